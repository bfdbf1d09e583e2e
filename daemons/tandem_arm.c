/* tandem-arm: continuous controller of one PUMA 560 ("MVME165" board).
 *
 * 1 kHz: reads ARMk_STATE, runs the core controller, publishes
 * ARMk_COMMAND (joint torques). Executes action rows from the supervisor
 * (ARMk_ACTION) segment by segment and reports ARM_EVENTS. Safe hold
 * (SPEC.md §7): a stale state (> --stale-ms) engages the brakes; an invalid
 * row is rejected and the arm holds where it is with gravity compensation.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "arm_kin.h"
#include "jointctl.h"
#include "jtraj.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"

#define ROW_MAX_SEGMENTS 8
#define JOINT_DONE_TOL_RAD 0.005
#define JOINT_DONE_SPEED_RADPS 0.02

typedef struct arm_ctl {
    int    arm;                       /* 1 or 2 */
    const arm_model *model;
    jointctl_gains gains;
    double stale_s;
    double speed_frac;
    /* latest valid state */
    tandem_arm_state_t st;
    int    have_state;
    int64_t state_rx_ns;              /* wall time it arrived (real-time staleness) */
    /* what the arm is doing */
    double hold_q[ARM_NJ];
    int    holding_set;
    tandem_action_segment_t seg[ROW_MAX_SEGMENTS];
    int    n_seg, cur_seg;
    int32_t action_id, transition;
    int    running;
    jtraj  traj;
    double seg_t0_s;
    int    gripper;                   /* command to send this cycle */
    int64_t cmd_seq, ev_seq;
    char   state_ch[16], cmd_ch[16], action_ch[16];
} arm_ctl;

static arm_ctl C;

static void usage(void)
{
    printf("usage: tandem-arm --arm 1|2 [options]\n"
           "Continuous controller of one PUMA 560: computed-torque joint control with\n"
           "gravity compensation; executes supervisor action rows; safe hold on stale\n"
           "or invalid input.\n\n"
           "  --arm N           which arm, 1 or 2 (required)\n"
           "  --wn HZ           joint servo natural frequency in Hz (default 8)\n"
           "  --stale-ms MS     state older than this engages the brakes (default 20)\n"
           "  --speed-frac F    joint moves use this fraction of the motor speed (default 0.5)\n"
           DAEMON_COMMON_HELP);
}

static void publish_event(daemon *d, int ev, const char *detail)
{
    tandem_action_event_t e;
    memset(&e, 0, sizeof e);
    e.seq = C.ev_seq++;
    e.utime = daemon_utime_now();
    e.step = C.st.step;
    e.action_id = C.action_id;
    e.transition = C.transition;
    e.arm = (int8_t)C.arm;
    e.event = (int8_t)ev;
    e.segment = (int8_t)C.cur_seg;
    e.detail = (char *)detail;
    tandem_action_event_t_publish(d->lcm, "ARM_EVENTS", &e);
}

/* ---- inputs --------------------------------------------------------------- */

static int state_valid(const tandem_arm_state_t *s)
{
    return s->arm == C.arm && s->step >= 0 && all_finite(s->q_rad, ARM_NJ) &&
           all_finite(s->qd_radps, ARM_NJ) && isfinite(s->sim_time_s) &&
           (!C.have_state || s->step >= C.st.step);
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_arm_state_t s;
    (void)ch;
    d->msgs.received++;
    if (tandem_arm_state_t_decode(rb->data, 0, rb->data_size, &s) < 0) {
        d->msgs.rejected++;
        return;
    }
    if (!state_valid(&s)) {
        d->msgs.rejected++;
        return;
    }
    C.st = s;
    C.have_state = 1;
    C.state_rx_ns = rtloop_now_ns();
    if (!C.holding_set) {
        memcpy(C.hold_q, s.q_rad, sizeof C.hold_q);
        C.holding_set = 1;
    }
}

static int segment_valid(const tandem_action_segment_t *g)
{
    switch (g->kind) {
    case TANDEM_ACTION_SEGMENT_T_MOVE_JOINT:
        return arm_q_finite(g->q_rad) == 0 && arm_q_outside_limits(C.model, g->q_rad) == 0;
    case TANDEM_ACTION_SEGMENT_T_GRASP:
    case TANDEM_ACTION_SEGMENT_T_RELEASE:
        return 1;
    default:
        return 0;   /* Cartesian segments: see the event-referenced controller */
    }
}

static void on_action(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    daemon *d = u;
    tandem_action_row_t r;
    int i, ok;
    (void)ch;
    d->msgs.received++;
    if (tandem_action_row_t_decode(rb->data, 0, rb->data_size, &r) < 0) {
        d->msgs.rejected++;
        return;
    }
    ok = r.arm == C.arm && r.n_segments > 0 && r.n_segments <= ROW_MAX_SEGMENTS && !C.running;
    for (i = 0; ok && i < r.n_segments; i++)
        ok = segment_valid(&r.segments[i]);
    if (!ok) {
        d->msgs.rejected++;
        if (r.arm == C.arm) {
            const int32_t id = C.action_id, t = C.transition;
            C.action_id = r.action_id;
            C.transition = r.transition;
            publish_event(d, TANDEM_ACTION_EVENT_T_REJECTED, C.running ? "busy" : "invalid row");
            C.action_id = id;
            C.transition = t;
        }
        tandem_action_row_t_decode_cleanup(&r);
        return;
    }
    memcpy(C.seg, r.segments, sizeof(r.segments[0]) * (size_t)r.n_segments);
    C.n_seg = r.n_segments;
    C.cur_seg = -1;
    C.action_id = r.action_id;
    C.transition = r.transition;
    C.running = 1;
    tandem_action_row_t_decode_cleanup(&r);
    publish_event(d, TANDEM_ACTION_EVENT_T_STARTED, "");
}

/* ---- segments ------------------------------------------------------------- */

static void start_segment(daemon *d)
{
    const tandem_action_segment_t *g;
    C.cur_seg++;
    if (C.cur_seg >= C.n_seg) {
        C.running = 0;
        publish_event(d, TANDEM_ACTION_EVENT_T_DONE, "");
        return;
    }
    g = &C.seg[C.cur_seg];
    C.seg_t0_s = C.st.sim_time_s;
    if (g->kind == TANDEM_ACTION_SEGMENT_T_MOVE_JOINT)
        jtraj_plan(&C.traj, C.model, C.hold_q, g->q_rad, C.speed_frac, 2.0);
    else
        C.gripper = g->kind == TANDEM_ACTION_SEGMENT_T_GRASP ? TANDEM_ARM_COMMAND_T_GRIP_CLOSE
                                                            : TANDEM_ARM_COMMAND_T_GRIP_OPEN;
}

/* Reference for this cycle; returns 1 when the segment is complete. */
static int segment_reference(double q_d[ARM_NJ], double qd_d[ARM_NJ], double qdd_d[ARM_NJ])
{
    const tandem_action_segment_t *g = &C.seg[C.cur_seg];
    const double t = C.st.sim_time_s - C.seg_t0_s;
    int i, done = 1;
    if (g->kind != TANDEM_ACTION_SEGMENT_T_MOVE_JOINT) {
        memcpy(q_d, C.hold_q, sizeof C.hold_q);
        memset(qd_d, 0, sizeof(double) * ARM_NJ);
        memset(qdd_d, 0, sizeof(double) * ARM_NJ);
        return t >= 0.2;   /* the fingers take 0.2 s to close or open */
    }
    jtraj_at(&C.traj, t, q_d, qd_d, qdd_d);
    if (t < C.traj.duration_s)
        return 0;
    for (i = 0; i < ARM_NJ; i++)
        if (fabs(C.st.q_rad[i] - q_d[i]) > JOINT_DONE_TOL_RAD || fabs(C.st.qd_radps[i]) > JOINT_DONE_SPEED_RADPS)
            done = 0;
    if (done)
        memcpy(C.hold_q, q_d, sizeof C.hold_q);
    return done;
}

/* ---- the cycle ------------------------------------------------------------ */

static int state_stale(const daemon *d)
{
    if (!C.have_state)
        return 1;
    if (d->lockstep)
        return (double)(d->step - C.st.step) * DAEMON_SIM_DT_S > C.stale_s;
    return (double)(rtloop_now_ns() - C.state_rx_ns) * 1e-9 > C.stale_s;
}

static void send_command(daemon *d, int mode, const double tau[ARM_NJ])
{
    tandem_arm_command_t c;
    memset(&c, 0, sizeof c);
    c.seq = C.cmd_seq++;
    c.utime = daemon_utime_now();
    c.step = C.st.step;
    c.arm = (int8_t)C.arm;
    c.mode = (int8_t)mode;
    if (tau)
        memcpy(c.tau_Nm, tau, sizeof c.tau_Nm);
    c.gripper = (int8_t)C.gripper;
    tandem_arm_command_t_publish(d->lcm, C.cmd_ch, &c);
    C.gripper = TANDEM_ARM_COMMAND_T_GRIP_KEEP;
}

static void cycle(daemon *d, void *user)
{
    double q_d[ARM_NJ], qd_d[ARM_NJ] = { 0 }, qdd_d[ARM_NJ] = { 0 }, tau[ARM_NJ];
    arm_payload payload, *pl = NULL;
    (void)user;
    if (state_stale(d)) {
        if (C.have_state)
            d->msgs.stale++;
        d->safe_hold = 1;
        snprintf(d->status, sizeof d->status, "safe hold: state stale");
        send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return;
    }
    d->safe_hold = 0;
    memcpy(q_d, C.hold_q, sizeof q_d);
    if (C.running) {
        if (C.cur_seg < 0)
            start_segment(d);
        if (C.running && segment_reference(q_d, qd_d, qdd_d)) {
            start_segment(d);
            if (C.running)
                segment_reference(q_d, qd_d, qdd_d);
        }
    }
    if (C.st.holding_workpiece >= 0) {
        const double com[3] = { 0.0, 0.0, 0.10 };
        arm_payload_point(&payload, 0.5, com);
        pl = &payload;
    }
    if (jointctl_torque(C.model, pl, &C.gains, C.st.q_rad, C.st.qd_radps, q_d, qd_d, qdd_d, tau, NULL) != 0) {
        send_command(d, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
        return;
    }
    snprintf(d->status, sizeof d->status, C.running ? "action %d segment %d" : "holding",
             (int)C.action_id, C.cur_seg);
    send_command(d, TANDEM_ARM_COMMAND_T_MODE_TORQUE, tau);
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        { "arm", required_argument, 0, 'a' },
        { "wn", required_argument, 0, 'w' },
        { "stale-ms", required_argument, 0, 's' },
        { "speed-frac", required_argument, 0, 'f' },
        DAEMON_COMMON_OPTIONS,
        { 0, 0, 0, 0 }
    };
    daemon d;
    int c, rc;
    long arm = 0;
    double hz = 8.0, ms = 20.0;
    char name[32];
    memset(&C, 0, sizeof C);
    C.speed_frac = 0.5;
    daemon_defaults(&d, "tandem-arm", 0.001);
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        rc = daemon_parse_common(&d, c, optarg);
        if (rc == 2) { usage(); return 0; }
        if (rc < 0) return 2;
        if (rc == 1) continue;
        switch (c) {
        case 'a': if (parse_int_opt("tandem-arm", "--arm", optarg, 1, 2, &arm) < 0) return 2; break;
        case 'w': if (parse_double_opt("tandem-arm", "--wn", optarg, 0.5, 50.0, &hz) < 0) return 2; break;
        case 's': if (parse_double_opt("tandem-arm", "--stale-ms", optarg, 1.0, 1000.0, &ms) < 0) return 2; break;
        case 'f': if (parse_double_opt("tandem-arm", "--speed-frac", optarg, 0.01, 1.0, &C.speed_frac) < 0) return 2; break;
        default: usage(); return 2;
        }
    }
    if (optind < argc || arm == 0) {
        fprintf(stderr, "tandem-arm: %s\n", arm == 0 ? "--arm 1|2 is required" : "unexpected argument");
        return 2;
    }
    C.arm = (int)arm;
    C.model = &arm_model_puma560;
    C.gains.wn_radps = 6.283185307179586 * hz;
    C.gains.zeta = 1.0;
    C.stale_s = ms * 1e-3;
    snprintf(name, sizeof name, "tandem-arm-%d", C.arm);
    snprintf(d.name, sizeof d.name, "%s", name);
    snprintf(C.state_ch, sizeof C.state_ch, "ARM%d_STATE", C.arm);
    snprintf(C.cmd_ch, sizeof C.cmd_ch, "ARM%d_COMMAND", C.arm);
    snprintf(C.action_ch, sizeof C.action_ch, "ARM%d_ACTION", C.arm);
    if (daemon_start(&d) != 0)
        return 1;
    lcm_subscribe(d.lcm, C.state_ch, on_state, &d);
    lcm_subscribe(d.lcm, C.action_ch, on_action, &d);
    rc = daemon_run(&d, cycle, NULL);
    daemon_finish(&d);
    return rc;
}
