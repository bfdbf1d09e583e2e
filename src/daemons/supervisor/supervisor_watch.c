/* supervisor_watch: what tandem-supervisor says about the cell: the
 * marking on PETRI_MARKING, the stall watchdog (stallwatch) and the
 * silence of an arm or of the simulator.
 */
#include <stdio.h>
#include <string.h>
#include "supervisor_daemon.h"
#include "tandem_petri_marking_t.h"
#include "tandem_sim_status_t.h"

#define SILENT_NS 1000000000LL /* wall time without a word: arm or simulator silent */
#define SILENT_STEPS 1000      /* the same in lockstep, in simulated steps */

/* ---- marking out ---------------------------------------------------------- */

void sup_publish_marking(supervisor_daemon *sv)
{
    tandem_petri_marking_t m;
    int8_t mk[PETRI_MAX_PLACES], run[PETRI_MAX_TRANSITIONS];
    int i;
    memset(&m, 0, sizeof m);
    for (i = 0; i < sv->pn->n_places; i++)
        mk[i] = (int8_t)sv->net.st.m[i];
    for (i = 0; i < sv->pn->n_transitions; i++)
        run[i] = (int8_t)petri_running(&sv->net, i);
    m.seq = sv->marking_seq++;
    m.utime = daemon_utime_now();
    m.step = sv->d.step;
    m.n_places = sv->pn->n_places;
    m.marking = mk;
    m.n_transitions = sv->pn->n_transitions;
    m.running = run;
    m.last_fired = sv->last_fired;
    m.fired_count = sv->net.fired_count;
    m.invariants_ok = (int8_t)petri_invariants_hold(&sv->net);
    m.dead = (int8_t)petri_dead(&sv->net);
    m.invariant_violations = sv->net.invariant_violations;
    m.deadlocks = sv->deadlocks;
    m.replans = sv->replans;
    m.detections = sv->detections;
    m.blockages = sv->blockages;
    m.workpiece_id = sv->wp_id;
    m.stalled = (int8_t)sv->stall.stalled;
    m.since_progress_s = sv->stall.idle_s;
    m.stall_limit_s = sv->stall.limit_s;
    m.stalls = sv->stall.stalls;
    m.arms_faulted = (int8_t)sv->arms_faulted;
    m.faults = sv->faults;
    m.arms_silent = (int8_t)sv->arms_silent;
    m.sim_silent = (int8_t)sv->sim_silent;
    m.rows_reissued = sv->rows_reissued;
    m.dones_recovered = sv->dones_recovered;
    m.resumed = (int8_t)sv->resumed;
    AUTH_PUBLISH(tandem_petri_marking_t, &sv->d.bus, sv->d.lcm, "PETRI_MARKING", &m);
}

/* ---- watchdogs ---------------------------------------------------------------- */

void sup_on_sim_status(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    supervisor_daemon *sv = u;
    tandem_sim_status_t m;
    (void)ch;
    if (!DAEMON_DECODE(&sv->d.msgs, tandem_sim_status_t, rb, &m))
        return;
    sv->stick_in = m.stick_inserted != 0;
    sv->sim_rx_ns = rtloop_now_ns();
    tandem_sim_status_t_decode_cleanup(&m);
}

/* A running row of an arm that is down, in a task whose net knows that
 * arm's health (taskdef_health): it waits for the arm, which the net
 * and the health status say, not on a stuck cell. */
static int waits_on_down_arm(const supervisor_daemon *sv, int t)
{
    int a;
    for (a = 0; a < 2; a++)
        if (sv->health.fault[a] >= 0 && ((sv->arms_faulted | sv->arms_silent) >> a & 1) &&
            (sup_row(sv, t)->arms & (a == 0 ? CARRY_ARM1 : CARRY_ARM2)))
            return 1;
    return 0;
}

/* Work is pending while a transition runs (but one waiting on an arm the
 * task knows is down) or one but the source (t1..t7 of the carry) and the
 * arms' health transitions may start. */
static int work_pending(const supervisor_daemon *sv)
{
    int t;
    for (t = 0; t < sv->pn->n_transitions; t++)
        if (t != sv->roles.source && !sup_health_transition(sv, t) &&
            ((petri_running(&sv->net, t) && !waits_on_down_arm(sv, t)) ||
             (petri_enabled(&sv->net, t) && (t != sv->roles.pick || sv->p1_bound))))
            return 1;
    return 0;
}

void sup_watch_stall(supervisor_daemon *sv)
{
    if (stallwatch_update(&sv->stall, sv->d.sim_time_s, sv->completed, work_pending(sv),
                          sv->stick_in) == 1) {
        sv->changed = 1;
        sv->dirty = 1;
        if (sv->stick_in)
            printf(
                "[%9.3f] STALLED: work pending, no transition completed, the stick in for %.1f s (longer than "
                "any block may last)\n",
                sv->d.sim_time_s, sv->stall.obstructed_s);
        else
            printf(
                "[%9.3f] STALLED: work pending, no transition completed for %.1f s with the stick out\n",
                sv->d.sim_time_s, sv->stall.limit_s);
        fflush(stdout);
    }
    sv->completed = 0;
}

void sup_watch_silence(supervisor_daemon *sv)
{
    const int64_t now = rtloop_now_ns();
    int a, arms = 0, sim;
    for (a = 0; a < 2; a++) {
        const arm_view *v = &sv->arm[a];
        const int64_t step = v->alive_step > v->step ? v->alive_step : v->step;
        const int64_t rx = v->alive_rx_ns > v->rx_ns ? v->alive_rx_ns : v->rx_ns;
        if (v->heard && (sv->d.lockstep ? sv->d.step - step > SILENT_STEPS : now - rx > SILENT_NS))
            arms |= 1 << a;
    }
    sim = !sv->d.lockstep && sv->sim_rx_ns > 0 && now - sv->sim_rx_ns > SILENT_NS;
    if (arms != sv->arms_silent || sim != sv->sim_silent) {
        printf("[%9.3f] silent: arm 1 %s, arm 2 %s, simulator %s\n", sv->d.sim_time_s,
               arms & 1 ? "SILENT" : "ok", arms & 2 ? "SILENT" : "ok", sim ? "SILENT" : "ok");
        fflush(stdout);
        sv->changed = 1;
    }
    sv->arms_silent = arms;
    sv->sim_silent = sim;
}
