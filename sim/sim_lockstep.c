/* sim_lockstep: who the simulator waits for (docs/method/lockstep.md §3, the lockstep protocol).
 * A controller registers by answering a step; it is then waited for on
 * every step that is a multiple of its period. A participant that does not
 * answer is waited for as long as it is alive, however slow (a loaded
 * machine, a stopped process): what it answers must not depend on the
 * wall clock. It is dropped only when dead (peer.h): its process gone, or
 * running and silent (no ack at all, not even the "still here" of a
 * participant waiting for an input) for the timeout, so a
 * dead or hung daemon cannot freeze the world (the drop is counted in
 * SIM_STATUS).
 */
#include "sim.h"
#include "rtloop.h"
#include <stdio.h>
#include <string.h>

static sim_participant *find(sim_world *w, const char *name)
{
    int i;
    for (i = 0; i < w->n_part; i++)
        if (strcmp(w->part[i].name, name) == 0)
            return &w->part[i];
    return NULL;
}

/* Every first answer to the current step counts, a re-announced one too:
 * counting only the answers that came before the first re-announce would
 * keep a slow participant's average below its real answer time for good
 * (its every answer re-announced, none counted), and each re-announce
 * resends every robot's frames. */
static void note_answer_time(sim_participant *p, int64_t answer_ns)
{
    if (answer_ns < 0)
        return;
    if (p->answer_ns_avg == 0)
        p->answer_ns_avg = answer_ns;
    else
        p->answer_ns_avg += (answer_ns - p->answer_ns_avg) / 16;
}

void sim_lockstep_on_ack(sim_world *w, const char *name, int64_t step, int32_t period, int leaving,
                         int32_t pid)
{
    sim_participant *p = find(w, name);
    if (!p) {
        if (leaving || w->n_part >= SIM_MAX_PARTICIPANTS)
            return;
        p = &w->part[w->n_part++];
        memset(p, 0, sizeof *p);
        snprintf(p->name, sizeof p->name, "%s", name);
        p->last_ack = -1;
        p->first_ack = step;
        p->peer.heard_ns = rtloop_now_ns();
        fprintf(stderr, "tandem-sim: lockstep participant '%s' joined (every %d steps)\n", name,
                (int)period);
    }
    if (leaving) {
        if (p->active)
            fprintf(stderr, "tandem-sim: lockstep participant '%s' left\n", name);
        p->active = 0;
        return;
    }
    /* a dropped participant's "still here" (a step it answered before)
     * does not bring it back; answering a new step does */
    if (!p->active && step <= p->last_ack)
        return;
    if (!p->active)
        p->first_ack = step; /* back (a restarted controller): owes from here */
    p->active = 1;
    peer_heard(&p->peer, pid, rtloop_now_ns());
    if (step == w->step && step > p->last_ack)
        note_answer_time(p, p->peer.heard_ns - w->step_announced_ns);
    p->period_steps = period < 1 ? 1 : period;
    if (step > p->last_ack)
        p->last_ack = step;
}

int64_t sim_lockstep_owed_step(const sim_world *w, const char *name, int64_t k)
{
    int i;
    for (i = 0; i < w->n_part; i++) {
        const sim_participant *p = &w->part[i];
        int64_t due;
        if (strcmp(p->name, name) != 0)
            continue;
        if (!p->active)
            return -1;
        due = k - k % p->period_steps;
        return due >= p->first_ack ? due : -1;
    }
    return -1;
}

int sim_lockstep_ready(const sim_world *w, int64_t k)
{
    int i;
    for (i = 0; i < w->n_part; i++) {
        const sim_participant *p = &w->part[i];
        if (p->active && k % p->period_steps == 0 && p->last_ack < k)
            return 0;
    }
    return 1;
}

int sim_lockstep_due(const sim_world *w, int64_t k)
{
    int i;
    for (i = 0; i < w->n_part; i++)
        if (w->part[i].active && k % w->part[i].period_steps == 0)
            return 1;
    return 0;
}

static int is_late(const sim_participant *p, int64_t k)
{
    return p->active && k % p->period_steps == 0 && p->last_ack < k;
}

int sim_lockstep_late(const sim_world *w, int64_t k)
{
    int i;
    for (i = 0; i < w->n_part; i++)
        if (is_late(&w->part[i], k))
            return 1;
    return 0;
}

int64_t sim_lockstep_answer_ns(const sim_world *w, int64_t k)
{
    int64_t longest = 0;
    int i;
    for (i = 0; i < w->n_part; i++) {
        const sim_participant *p = &w->part[i];
        if (p->active && k % p->period_steps == 0 && p->answer_ns_avg > longest)
            longest = p->answer_ns_avg;
    }
    return longest;
}

int sim_lockstep_drop_dead(sim_world *w, int64_t k)
{
    const int64_t now = rtloop_now_ns();
    const int64_t silent_ns = (int64_t)(w->lockstep_timeout_s * 1e9);
    int i, n = 0;
    for (i = 0; i < w->n_part; i++) {
        sim_participant *p = &w->part[i];
        if (!is_late(p, k) || !peer_dead(&p->peer, now, silent_ns))
            continue;
        fprintf(stderr,
                "tandem-sim: lockstep participant '%s' (pid %ld) did not answer step %lld and is "
                "%s; dropped\n",
                p->name, (long)p->peer.pid, (long long)k,
                peer_proc_of(p->peer.pid) == PEER_PROC_GONE ? "gone" : "silent");
        p->active = 0;
        w->lockstep_timeouts++;
        n++;
    }
    return n;
}

int sim_lockstep_robot_hosted(const sim_world *w, int32_t id)
{
    int i, named = 0;
    for (i = 0; i < w->n_part; i++) {
        long lo, hi;
        if (!peer_rover_range(w->part[i].name, &lo, &hi) || id < lo || id > hi)
            continue;
        if (w->part[i].active)
            return 1;
        named = 1;
    }
    return !named;
}
