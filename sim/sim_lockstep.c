/* sim_lockstep: who the simulator waits for (docs/method/lockstep.md §3, the lockstep protocol).
 * A controller registers by answering a step; it is then waited for on
 * every step that is a multiple of its period. A participant that stops
 * answering is dropped after a wall-clock timeout so a dead daemon cannot
 * freeze the world (and the drop is counted in SIM_STATUS).
 */
#include "sim.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static sim_participant *find(sim_world *w, const char *name)
{
    int i;
    for (i = 0; i < w->n_part; i++)
        if (strcmp(w->part[i].name, name) == 0)
            return &w->part[i];
    return NULL;
}

void sim_lockstep_on_ack(sim_world *w, const char *name, int64_t step, int32_t period, int leaving)
{
    sim_participant *p = find(w, name);
    if (!p) {
        if (leaving || w->n_part >= SIM_MAX_PARTICIPANTS)
            return;
        p = &w->part[w->n_part++];
        memset(p, 0, sizeof *p);
        snprintf(p->name, sizeof p->name, "%s", name);
        p->last_ack = -1;
        fprintf(stderr, "tandem-sim: lockstep participant '%s' joined (every %d steps)\n",
                name, (int)period);
    }
    if (leaving) {
        if (p->active)
            fprintf(stderr, "tandem-sim: lockstep participant '%s' left\n", name);
        p->active = 0;
        return;
    }
    p->active = 1;
    p->period_steps = period < 1 ? 1 : period;
    if (step > p->last_ack)
        p->last_ack = step;
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

int sim_lockstep_drop_late(sim_world *w, int64_t k)
{
    int i, n = 0;
    for (i = 0; i < w->n_part; i++) {
        sim_participant *p = &w->part[i];
        if (p->active && k % p->period_steps == 0 && p->last_ack < k) {
            fprintf(stderr, "tandem-sim: lockstep participant '%s' did not answer step %lld; dropped\n",
                    p->name, (long long)k);
            p->active = 0;
            w->lockstep_timeouts++;
            n++;
        }
    }
    return n;
}

/* The robots a participant's name says it hosts: 1 and *lo..*hi for
 * "tandem-rover-K" / "tandem-rover-A-B" (tandem-rover's lockstep name). */
static int rover_host_range(const char *name, long *lo, long *hi)
{
    static const char prefix[] = "tandem-rover-";
    char *end;
    if (strncmp(name, prefix, sizeof prefix - 1) != 0)
        return 0;
    *lo = strtol(name + sizeof prefix - 1, &end, 10);
    *hi = *lo;
    if (*end == '-')
        *hi = strtol(end + 1, &end, 10);
    return *end == '\0' && *lo >= 1 && *hi >= *lo;
}

int sim_lockstep_robot_hosted(const sim_world *w, int32_t id)
{
    int i, named = 0;
    for (i = 0; i < w->n_part; i++) {
        long lo, hi;
        if (!rover_host_range(w->part[i].name, &lo, &hi) || id < lo || id > hi)
            continue;
        if (w->part[i].active)
            return 1;
        named = 1;
    }
    return !named;
}
