/* carry_bus: what a carry run (docs/method/carry.md §8) takes from the bus
 * every step -- the lockstep clock and answers, the arms' measured states
 * (tool speed and the run's health: range violations, range-stop onsets,
 * speed ratio, contact forces), the arms' events, the supervisor's marking,
 * the simulator's workpiece counts -- and what it puts on it: the stick
 * (SIM_CONTROL) and its own lockstep answer.
 */
#include <math.h>
#include <string.h>
#include "carry_scen.h"
#include "shared_run.h"
#include "arm_model.h"
#include "daemon.h"
#include "tandem_action_event_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

const char *const carry_daemon_fault_name[CARRY_DAEMONS] = { "sim", "arm1", "arm2", "supervisor" };
const char *const carry_daemon_lock_name[CARRY_DAEMONS] = { "tandem-sim", "tandem-arm-1",
                                                            "tandem-arm-2", "tandem-supervisor" };

static void on_sim_ack(const lcm_recv_buf_t *rb, const char *ch, const tandem_clock_ack_t *m,
                       void *u)
{
    int k;
    carry_state *r = u;
    (void)rb;
    (void)ch;
    for (k = 0; k < CARRY_DAEMONS; k++)
        if (!m->leaving && !strcmp(m->name, carry_daemon_lock_name[k]) && m->step > r->ack_step[k])
            r->ack_step[k] = m->step;
    if (r->hw && !m->leaving)
        hang_watch_heard(r->hw, m->name, scenario_wall_s());
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_clock_t *m, void *u)
{
    carry_state *r = u;
    (void)rb;
    (void)ch;
    if (m->mode == TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP && m->step >= 0) {
        r->pending = m->step;
        r->t_s = m->sim_time_s;
    }
    if (r->hw)
        hang_watch_heard(r->hw, carry_daemon_lock_name[0], scenario_wall_s());
}

/* Range violations (onsets per joint), joints on their range stops
 * (onsets of a joint within ARM_RANGE_TOL_RAD of a range end, or past
 * it), the least margin to a range end, speed ratio and contact forces. */
static void arm_health(carry_state *r, int a, const tandem_arm_state_t *m)
{
    const arm_model *pm = &arm_model_puma560;
    const unsigned range = ARM_FAULT_RANGE(arm_joint_faults(pm, m->q_rad, m->qd_radps));
    unsigned stop = 0;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        const double margin = fmin(m->q_rad[i] - pm->q_min_rad[i], pm->q_max_rad[i] - m->q_rad[i]);
        if ((range & (1u << i)) && !(r->range_bits[a] & (1u << i)))
            r->limit_violations++;
        if (margin <= ARM_RANGE_TOL_RAD)
            stop |= 1u << i;
        if ((stop & (1u << i)) && !(r->stop_bits[a] & (1u << i)))
            r->stop_onsets++;
        r->min_range_margin_rad = fmin(r->min_range_margin_rad, margin);
        r->max_speed_ratio = fmax(r->max_speed_ratio, fabs(m->qd_radps[i]) / pm->qd_max_radps[i]);
    }
    r->range_bits[a] = range;
    r->stop_bits[a] = stop;
    r->max_force_N = fmax(r->max_force_N, m->max_contact_force_N);
    r->max_force_10ms_N = fmax(r->max_force_10ms_N, m->max_contact_force_10ms_N);
}

static void on_arm(const lcm_recv_buf_t *rb, const char *ch, const tandem_arm_state_t *m, void *u)
{
    int a;
    carry_state *r = u;
    (void)rb;
    (void)ch;
    a = m->arm - 1;
    if (a == 0 || a == 1) {
        if (r->have_arm[a] && m->step > r->arm[a].step) {
            const double dt = (double)(m->step - r->arm[a].step) * 1e-3;
            const double dx = m->tool_position_m[0] - r->arm[a].tool_position_m[0];
            const double dy = m->tool_position_m[1] - r->arm[a].tool_position_m[1];
            const double dz = m->tool_position_m[2] - r->arm[a].tool_position_m[2];
            r->speed[a] = sqrt(dx * dx + dy * dy + dz * dz) / dt;
        }
        r->arm[a] = *m;
        r->have_arm[a] = 1;
        arm_health(r, a, m);
    }
}

/* A synchronised arm's progress as a fraction of its segment (a
 * restarted arm's segment is stretched, its s_f changes, its fraction
 * does not): how far it went back from its furthest, in metres. While the
 * stick is in it may push an arm, and with it the bar and the partner,
 * back along the path: that is the stick's doing, not counted (the
 * furthest is taken from where the stick left them). */
static void sync_backtrack(carry_state *r, int a, const tandem_action_event_t *e)
{
    double frac;
    if (e->sync_group <= 0 || !(e->s_f_m > 0.0))
        return;
    frac = e->s_m / e->s_f_m;
    if (e->action_id != r->sync_action[a] || e->segment != r->sync_seg[a]) {
        r->sync_action[a] = e->action_id;
        r->sync_seg[a] = e->segment;
        r->sync_frac_max[a] = frac;
    }
    if (r->status_stick)
        r->sync_frac_max[a] = frac;
    r->sync_frac_max[a] = fmax(r->sync_frac_max[a], frac);
    r->max_sync_backtrack_m = fmax(r->max_sync_backtrack_m,
                                   (r->sync_frac_max[a] - frac) * e->s_f_m);
}

static void on_event(const lcm_recv_buf_t *rb, const char *ch, const tandem_action_event_t *e,
                     void *u)
{
    carry_state *r = u;
    (void)rb;
    (void)ch;
    if ((e->arm == 1 || e->arm == 2) && e->event == TANDEM_ACTION_EVENT_T_PROGRESS) {
        r->s[e->arm - 1] = e->s_m;
        r->s_f[e->arm - 1] = e->s_f_m;
        r->tr[e->arm - 1] = e->transition;
        r->s_step[e->arm - 1] = e->step;
        sync_backtrack(r, e->arm - 1, e);
    } else if (e->arm == 1 || e->arm == 2) {
        r->last_event[e->arm - 1] = e->event;
        if (e->event == TANDEM_ACTION_EVENT_T_UNBLOCKED)
            r->unblocked_step[e->arm - 1] = e->step;
        if (e->event == TANDEM_ACTION_EVENT_T_DONE)
            r->done_step[e->arm - 1] = e->step;
    }
}

static void on_marking(const lcm_recv_buf_t *rb, const char *ch, const tandem_petri_marking_t *m,
                       void *u)
{
    int i;
    carry_state *r = u;
    (void)rb;
    (void)ch;
    if (m->n_places <= PETRI_MAX_PLACES && m->n_transitions <= PETRI_MAX_TRANSITIONS) {
        r->mk = *m;
        for (i = 0; i < m->n_places; i++)
            r->mk_marking[i] = m->marking[i];
        for (i = 0; i < m->n_transitions; i++)
            r->mk_running[i] = m->running[i];
        r->mk.marking = r->mk_marking;
        r->mk.running = r->mk_running;
        r->have_mk = 1;
    }
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *m,
                      void *u)
{
    carry_state *r = u;
    (void)rb;
    (void)ch;
    if (m->step > r->status_step) {
        r->status_step = m->step;
        r->status_stick = m->stick_inserted != 0;
    }
    r->delivered = m->workpieces_delivered;
    r->dropped = m->workpieces_dropped;
    r->spawned = m->workpieces_spawned;
}

AUTH_TYPED_HANDLER(tandem_clock_ack_t, raw_on_sim_ack, on_sim_ack)
AUTH_TYPED_HANDLER(tandem_sim_clock_t, raw_on_clock, on_clock)
AUTH_TYPED_HANDLER(tandem_arm_state_t, raw_on_arm, on_arm)
AUTH_TYPED_HANDLER(tandem_action_event_t, raw_on_event, on_event)
AUTH_TYPED_HANDLER(tandem_petri_marking_t, raw_on_marking, on_marking)
AUTH_TYPED_HANDLER(tandem_sim_status_t, raw_on_status, on_status)

void carry_send_control(carry_state *r, int cmd, int arm, int link)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.utime = 0;
    c.command = (int8_t)cmd;
    c.target = arm;
    c.link = link;
    c.length_m = cmd == TANDEM_SIM_CONTROL_T_INSERT_STICK ? 0.3 : 0.0;
    c.radius_m = cmd == TANDEM_SIM_CONTROL_T_INSERT_STICK ? 0.02 : 0.0;
    AUTH_PUBLISH(tandem_sim_control_t, r->bus, r->lcm, "SIM_CONTROL", &c);
}

void carry_stick_command(carry_state *r, int cmd, int arm, int link)
{
    r->stick_want = cmd == TANDEM_SIM_CONTROL_T_INSERT_STICK;
    r->stick_arm = arm;
    r->stick_link = link;
    r->stick_sent_step = r->pending;
    r->stick_tries = 0;
    carry_send_control(r, cmd, arm, link);
}

/* A status from this many steps after the command has seen it (the
 * simulator takes a command at the next step it runs). */
#define STICK_ACK_STEPS 20
/* A command the simulator refuses (no stick pose clears both arms) is not
 * lost: given up after this many tries. */
#define STICK_MAX_TRIES 20

void carry_stick_confirm(carry_state *r)
{
    if (r->stick_want < 0 || r->status_step < r->stick_sent_step + STICK_ACK_STEPS ||
        r->status_stick == r->stick_want)
        return;
    if (++r->stick_tries > STICK_MAX_TRIES) {
        fprintf(
            stderr,
            "tandem-scenario: the simulator does not take the stick command (%s) after %d tries: "
            "given up\n",
            r->stick_want ? "in" : "out", STICK_MAX_TRIES);
        r->stick_want = -1;
        return;
    }
    r->stick_resends++;
    fprintf(stderr,
            "tandem-scenario: the stick command (%s) was lost at %.3f s: sending it again\n",
            r->stick_want ? "in" : "out", r->t_s);
    r->stick_sent_step = r->pending;
    carry_send_control(
        r, r->stick_want ? TANDEM_SIM_CONTROL_T_INSERT_STICK : TANDEM_SIM_CONTROL_T_REMOVE_STICK,
        r->stick_arm, r->stick_link);
}

void carry_ack(carry_state *r, int64_t step, int leaving)
{
    scenario_ack(r->bus, r->lcm, &r->ack_seq, step, 1, leaving);
}

int carry_t3_running(const carry_state *r)
{
    return r->have_mk && r->mk.n_transitions > 2 && r->mk.running[2];
}

void carry_subscribe(carry_state *r)
{
    auth_bus_subscribe(r->bus, r->lcm, "SIM_CLOCK", raw_on_clock, r);
    auth_bus_subscribe(r->bus, r->lcm, "ARM1_STATE", raw_on_arm, r);
    auth_bus_subscribe(r->bus, r->lcm, "ARM2_STATE", raw_on_arm, r);
    auth_bus_subscribe(r->bus, r->lcm, "ARM_EVENTS", raw_on_event, r);
    auth_bus_subscribe(r->bus, r->lcm, "PETRI_MARKING", raw_on_marking, r);
    auth_bus_subscribe(r->bus, r->lcm, "SIM_STATUS", raw_on_status, r);
    auth_bus_subscribe(r->bus, r->lcm, "SIM_ACK", raw_on_sim_ack, r);
}
