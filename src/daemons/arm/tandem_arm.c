/* tandem-arm: continuous controller of one PUMA 560 ("MVME165" board).
 *
 * 1 kHz: reads ARMk_STATE, runs the core controller, publishes
 * ARMk_COMMAND (joint torques). Executes action rows from the supervisor
 * (ARMk_ACTION) segment by segment and reports ARM_EVENTS; between rows it
 * tracks fresh joint references (ARMk_JOINT_REF) if any arrive. Safe hold
 * (docs/method/lockstep.md §6): a stale state (> --stale-ms) engages the brakes; an invalid
 * row is rejected and the arm holds where it is with gravity compensation.
 *
 * All of its state is one arm_daemon (arm_daemon.h), created here in main
 * and handed to the cycle and to every handler. This file: inputs, the
 * cycle's dispatch between the controllers, commands and events out; the
 * controllers are arm_joint.c, arm_carry.c and arm_tdsd.c.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "arm_daemon.h"
#include "cartctl.h"
#include "cell.h"
#include "linalg.h"
#include "msg_check.h"
#include "options.h"
#include "arm_status.h"
#include "carry_status.h"
#include "shell_status.h"
#include "tandem_arm_command_t.h"

#define FAULT_CLEAR_S 0.5

/* Every event carries the running action and segment; Cartesian segments
 * add their progress (see cart_publish_event). */
void arm_event_fill(arm_daemon *ad, tandem_action_event_t *e, int ev, const char *detail)
{
    memset(e, 0, sizeof *e);
    e->seq = ad->ev_seq++;
    e->utime = daemon_utime_now();
    e->step = ad->st.step;
    e->action_id = ad->action_id;
    e->transition = ad->transition;
    e->arm = (int8_t)ad->arm;
    e->event = (int8_t)ev;
    e->segment = (int8_t)ad->cur_seg;
    e->detail = (char *)detail;
    e->last_done_action_id = ad->last_done_id;
    e->running = (int8_t)(ad->running && ev != TANDEM_ACTION_EVENT_T_DONE);
    e->holding_workpiece = ad->have_state ? ad->st.holding_workpiece : -1;
}

void arm_publish_event(arm_daemon *ad, int ev, const char *detail)
{
    tandem_action_event_t e;
    arm_event_fill(ad, &e, ev, detail);
    AUTH_PUBLISH(tandem_action_event_t, &ad->d.bus, ad->d.lcm, "ARM_EVENTS", &e);
}

/* ---- inputs --------------------------------------------------------------- */

static int state_valid(const arm_daemon *ad, const tandem_arm_state_t *s)
{
    return s->arm == ad->arm && s->step >= 0 && linalg_all_finite(s->q_rad, ARM_NJ) &&
           linalg_all_finite(s->qd_radps, ARM_NJ) && isfinite(s->sim_time_s);
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_daemon *ad = u;
    tandem_arm_state_t s;
    (void)ch;
    if (!DAEMON_DECODE(&ad->d.msgs, tandem_arm_state_t, rb, &s))
        return;
    if (!state_valid(ad, &s) ||
        step_gate_pass(&ad->state_gate, s.step, rtloop_now_ns()) != GUARD_OK) {
        ad->d.msgs.rejected++;
        return;
    }
    /* a backlog is of new steps: the simulator re-announces a step (same
     * state again) while it waits for a slow participant in lockstep */
    if (!ad->have_state || s.step > ad->st.step)
        arm_hold_note_state(ad);
    ad->st = s;
    ad->have_state = 1;
    ad->state_rx_ns = rtloop_now_ns();
    if (!ad->holding_set)
        arm_row_hold_at(ad, s.q_rad);
}

static int segment_valid(const arm_daemon *ad, const tandem_action_segment_t *g)
{
    switch (g->kind) {
    case TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN:
        return linalg_all_finite(g->position_m, 3) && linalg_all_finite(g->orientation_quat, 4) &&
               fabs(g->orientation_quat[0] * g->orientation_quat[0] +
                    g->orientation_quat[1] * g->orientation_quat[1] +
                    g->orientation_quat[2] * g->orientation_quat[2] +
                    g->orientation_quat[3] * g->orientation_quat[3] - 1.0) < 1e-3;
    case TANDEM_ACTION_SEGMENT_T_MOVE_JOINT:
        return arm_q_finite(g->q_rad) == 0 && arm_q_outside_limits(ad->model, g->q_rad) == 0;
    case TANDEM_ACTION_SEGMENT_T_GRASP:
    case TANDEM_ACTION_SEGMENT_T_RELEASE: return 1;
    default: return 0; /* Cartesian segments: see the event-referenced controller */
    }
}

static void row_take(arm_daemon *ad);

static void on_action(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_daemon *ad = u;
    tandem_action_row_t r;
    int i, ok;
    (void)ch;
    if (!DAEMON_DECODE(&ad->d.msgs, tandem_action_row_t, rb, &r))
        return;
    ok = action_row_check(&r, ad->arm, ROW_MAX_SEGMENTS) == MSG_OK && !ad->running &&
         !ad->row_in.have;
    for (i = 0; ok && i < r.n_segments; i++)
        ok = segment_valid(ad, &r.segments[i]);
    if (!ok) {
        ad->d.msgs.rejected++;
        if (r.arm == ad->arm) {
            /* the refusal names the refused row, not the one running */
            tandem_action_event_t e;
            arm_event_fill(ad, &e, TANDEM_ACTION_EVENT_T_REJECTED,
                           ad->running ? "busy" : "invalid row");
            e.action_id = r.action_id;
            e.transition = r.transition;
            AUTH_PUBLISH(tandem_action_event_t, &ad->d.bus, ad->d.lcm, "ARM_EVENTS", &e);
        }
        tandem_action_row_t_decode_cleanup(&r);
        return;
    }
    ad->row_in.row = r;
    memcpy(ad->row_in.seg, r.segments, sizeof(r.segments[0]) * (size_t)r.n_segments);
    ad->row_in.row.segments = ad->row_in.seg;
    ad->row_in.have = 1;
    tandem_action_row_t_decode_cleanup(&r);
    if (!ad->d.lockstep)
        row_take(ad);
}

/* A valid row starts here: at once in real time, in lockstep at the first
 * cycle after the step it was sent at (the supervisor answers that step
 * beside us, so whether it had arrived by then is a race). */
static void row_take(arm_daemon *ad)
{
    const tandem_action_row_t *r = &ad->row_in.row;
    ad->row_in.have = 0;
    arm_row_begin(ad, r);
    arm_cart_row_accept(ad, r);
    arm_tdsd_row_accept(ad, r);
    arm_publish_event(ad, TANDEM_ACTION_EVENT_T_STARTED, "");
}

/* ---- commands out and the cycle ------------------------------------------- */

static int state_stale(const arm_daemon *ad)
{
    if (!ad->have_state)
        return 1;
    if (ad->d.lockstep)
        return (double)(ad->d.step - ad->st.step) * DAEMON_SIM_DT_S > ad->stale_s;
    return (double)(rtloop_now_ns() - ad->state_rx_ns) * 1e-9 > ad->stale_s;
}

void arm_send_command(arm_daemon *ad, int mode, const double tau[ARM_NJ])
{
    tandem_arm_command_t c;
    memset(&c, 0, sizeof c);
    c.seq = ad->cmd_seq++;
    c.utime = daemon_utime_now();
    c.step = ad->st.step;
    c.arm = (int8_t)ad->arm;
    c.mode = (int8_t)mode;
    if (tau)
        memcpy(c.tau_Nm, tau, sizeof c.tau_Nm);
    c.gripper = (int8_t)arm_row_gripper_request(ad);
    arm_hold_note_command(ad);
    ad->last_cmd = c;
    ad->have_last_cmd = 1;
    AUTH_PUBLISH(tandem_arm_command_t, &ad->d.bus, ad->d.lcm, ad->cmd_ch, &c);
}

/* lockstep: the simulator announced again a step we answered (our
 * command or ack was lost on the way, and it waits for the command of
 * that step: sim_arms' ready): the same command again, which the
 * simulator takes once. */
static void repeat_command(daemon *d, void *user)
{
    arm_daemon *ad = user;
    (void)d;
    if (ad->have_last_cmd)
        AUTH_PUBLISH(tandem_arm_command_t, &ad->d.bus, ad->d.lcm, ad->cmd_ch, &ad->last_cmd);
}

/* Joint range and speed watchdog; 1 while the arm must hold on its brakes. */
static int joint_fault(arm_daemon *ad)
{
    const unsigned bits = arm_joint_faults(ad->model, ad->st.q_rad, ad->st.qd_radps);
    if (bits) {
        char detail[64];
        ad->fault_clear_s = 0.0;
        arm_hold_begin(ad, "joint fault");
        if (!ad->fault) {
            snprintf(detail, sizeof detail, "range 0x%02x speed 0x%02x", ARM_FAULT_RANGE(bits),
                     ARM_FAULT_SPEED(bits));
            arm_publish_event(ad, TANDEM_ACTION_EVENT_T_FAULT, detail);
            fprintf(stderr, "%s: FAULT %s: safe hold on the brakes\n", ad->d.name, detail);
        }
        ad->fault = 1;
    } else if (ad->fault) {
        ad->fault_clear_s += ad->d.period_s;
        if (ad->fault_clear_s >= FAULT_CLEAR_S) {
            ad->fault = 0; /* the protective stop (arm_hold.c) resumes the motion */
            arm_publish_event(ad, TANDEM_ACTION_EVENT_T_FAULT_CLEARED, "");
            fprintf(stderr, "%s: fault cleared\n", ad->d.name);
        }
    }
    return ad->fault;
}

/* The one writer of the shell's safe_hold: on, with the brakes commanded
 * this cycle, when there is a cause (why), off otherwise. 1 if braking. */
static int brakes(arm_daemon *ad, const char *why)
{
    ad->d.safe_hold = why != NULL;
    if (!why)
        return 0;
    snprintf(ad->d.status, sizeof ad->d.status, "safe hold: %s", why);
    arm_send_command(ad, TANDEM_ARM_COMMAND_T_MODE_BRAKE, NULL);
    return 1;
}

/* Inputs that stop every controller: a stale state (counted), a backlog
 * of states (arm_hold_check_gap). Either begins a protective stop. */
static const char *input_brake_cause(arm_daemon *ad)
{
    if (state_stale(ad)) {
        ad->d.msgs.stale++;
        arm_hold_begin(ad, "state stale");
        return "state stale";
    }
    return arm_hold_check_gap(ad) ? "states in a burst" : NULL;
}

/* The controllers in turn, each when it is the one to send the command:
 * the joint watchdog's brakes, the protective stop (arm_hold.c), a TDSD
 * segment, an event-referenced
 * Cartesian segment (again when a fallback joint move hands its segment
 * back), else joint space. */
static int cycle(daemon *d, void *user)
{
    arm_daemon *ad = user;
    if (!ad->have_state || (d->lockstep && ad->st.step != d->pending_step)) {
        /* lockstep: join once the first state is here; a state lost on the
         * way is waited for (the simulator announces the step again) rather
         * than answered from the previous one, which would break determinism */
        d->skip_ack = 1;
        return DAEMON_CONTINUE;
    }
    if (brakes(ad, input_brake_cause(ad)))
        return DAEMON_CONTINUE;
    if (d->lockstep && ad->row_in.have && ad->row_in.row.step < d->pending_step)
        row_take(ad);
    if (d->lockstep)
        arm_cart_partner_at(ad, d->pending_step);
    if (brakes(ad, joint_fault(ad) ? "joint FAULT" : NULL) || arm_hold_cycle(ad) ||
        arm_tdsd_cycle(ad) || arm_cart_cycle(ad) ||
        (arm_cart_fallback_cycle(ad, 0) && arm_cart_cycle(ad)))
        return DAEMON_CONTINUE;
    arm_joint_cycle(ad);
    return DAEMON_CONTINUE;
}

/* ---- command line and start-up check ---------------------------------------- */

/* --arm-model NAME: the model by its name */
static int parse_model(const char *prog, void *dest, char *value)
{
    const arm_model **model = dest;
    if (!(*model = arm_model_by_name(value))) {
        fprintf(stderr, "%s: --arm-model: '%s' is not puma560|seed002\n", prog, value);
        return OPTIONS_ERR_SAID;
    }
    return 0;
}

/* The defaults main sets and the help shows, written once. */
#define ARM_WN_DEFAULT_HZ 8
#define ARM_STALE_DEFAULT_MS 20
#define ARM_SPEED_FRAC_DEFAULT 0.5
#define TWO_PI 6.283185307179586

/* Into the arm_daemon main made; the values it holds before are the
 * defaults. --wn is stored as rad/s (times 2 pi), --stale-ms as s. */
static const option_entry arm_options[] = {
    { .name = "arm",
      .type = OPTION_INT,
      OPTION_AT(arm_daemon, arm),
      .min = 1,
      .max = 2,
      .meta = "N",
      .help = "which arm (required)" },
    { .name = "wn",
      .type = OPTION_DOUBLE,
      OPTION_AT(arm_daemon, gains.wn_radps),
      .min = 0.5,
      .max = 50.0,
      .scale = TWO_PI,
      .meta = "HZ",
      .help = "joint servo natural frequency in Hz",
      .def = OPTION_DEF(ARM_WN_DEFAULT_HZ) },
    { .name = "stale-ms",
      .type = OPTION_DOUBLE,
      OPTION_AT(arm_daemon, stale_s),
      .min = 1.0,
      .max = 1000.0,
      .scale = 1e-3,
      .meta = "MS",
      .help = "state older than this engages the brakes",
      .def = OPTION_DEF(ARM_STALE_DEFAULT_MS) },
    { .name = "speed-frac",
      .type = OPTION_DOUBLE,
      OPTION_AT(arm_daemon, speed_frac),
      .min = 0.01,
      .max = 1.0,
      .meta = "F",
      .help = "joint moves use this fraction of the motor speed",
      .def = OPTION_DEF(ARM_SPEED_FRAC_DEFAULT) },
    { .name = "arm-model",
      .type = OPTION_CALL,
      /* the option stores a pointer: its size is a pointer's */
      /* NOLINTNEXTLINE(bugprone-sizeof-expression) */
      OPTION_AT(arm_daemon, model),
      .call = parse_model,
      .meta = "NAME",
      .help = "puma560 or seed002 (must match tandem-sim's)",
      .def = "puma560" },
    { .name = "block-detect",
      .type = OPTION_CHOICE,
      OPTION_AT(arm_daemon, block_detect),
      .choices = options_on_off,
      .values = options_on_off_flags,
      .help =
          "off: the event-referenced law (eq. 6-7) alone, no blocked detector and no BLOCKED events",
      .def = "on" },
    { .name = NULL }
};

/* 0, or a negative options_parse result (--help, --version, bad options). */
static int parse_args(arm_daemon *ad, int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-arm",
        .usage = "usage: tandem-arm --arm 1|2 [options]\n"
                 "Continuous controller of one PUMA 560: computed-torque joint control with\n"
                 "gravity compensation; executes supervisor action rows; safe hold on stale\n"
                 "or invalid input.\n\n",
        .epilog = "\nThe control period (--period-ms) is 1 ms unless given.\n",
        .groups = { { arm_options, ad }, { options_daemon_common, &ad->d } },
        .n_groups = 2,
    };
    const int rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return rc;
    if (ad->arm == 0) {
        fprintf(stderr, "tandem-arm: --arm 1|2 is required\n");
        return OPTIONS_ERR_ARG;
    }
    return 0;
}

/* The constant tables this arm runs on, checked before it runs: its
 * model, the cell layout, the Cartesian controller's gains (cartseg
 * takes cartctl_gains_default; a row's own gains are checked as it
 * starts) and its option table. */
static int check_tables(const arm_daemon *ad)
{
    const char *prog = ad->d.name;
    cartctl_gains cg;
    cartctl_gains_default(&cg);
    if (daemon_check_table(
            prog, ad->model == &arm_model_seed002 ? "arm_model_seed002" : "arm_model_puma560",
            "arm_model_validate", arm_model_validate(ad->model), arm_model_strerror) != 0 ||
        daemon_check_table(prog, "cell_default", "cell_layout_validate",
                           cell_layout_validate(&cell_default), cell_strerror) != 0 ||
        daemon_check_table(prog, "cartctl_gains_default", "cartctl_gains_validate",
                           cartctl_gains_validate(&cg), cartctl_strerror) != 0 ||
        daemon_check_table(prog, "arm_options", "options_table_validate",
                           options_table_validate(arm_options), options_strerror) != 0)
        return DAEMON_ERR_TABLE;
    return 0;
}

int main(int argc, char **argv)
{
    static arm_daemon app;
    arm_daemon *ad = &app;
    daemon *d = &ad->d;
    int rc;
    char name[32];
    ad->model = &arm_model_puma560;
    ad->gains.wn_radps = TWO_PI * ARM_WN_DEFAULT_HZ;
    ad->stale_s = ARM_STALE_DEFAULT_MS * 1e-3;
    ad->speed_frac = ARM_SPEED_FRAC_DEFAULT;
    ad->block_detect = 1;
    daemon_defaults(d, "tandem-arm", 0.001);
    if ((rc = parse_args(ad, argc, argv)) < 0)
        return options_exit_status(rc);
    ad->gains.zeta = 1.0;
    step_gate_init(&ad->state_gate, 1000, 1000000000LL);
    arm_hold_init(ad);
    snprintf(name, sizeof name, "tandem-arm-%d", ad->arm);
    snprintf(d->name, sizeof d->name, "%s", name);
    snprintf(ad->state_ch, sizeof ad->state_ch, "ARM%d_STATE", ad->arm);
    snprintf(ad->cmd_ch, sizeof ad->cmd_ch, "ARM%d_COMMAND", ad->arm);
    snprintf(ad->action_ch, sizeof ad->action_ch, "ARM%d_ACTION", ad->arm);
    if (check_tables(ad) != 0)
        return 1;
    auth_bus_identity(&ad->d.bus, AUTH_ROLE_ARM, ad->arm, ad->arm);
    if (daemon_start(d) != 0)
        return 1;
    daemon_subscribe(d, "ARM_EVENTS", arm_cart_on_event, ad);
    daemon_subscribe(d, ad->state_ch, on_state, ad);
    daemon_subscribe(d, ad->action_ch, on_action, ad);
    snprintf(ad->jref.ch, sizeof ad->jref.ch, "ARM%d_JOINT_REF", ad->arm);
    daemon_subscribe(d, ad->jref.ch, arm_on_joint_ref, ad);
    d->repeat_fn = repeat_command;
    rc = daemon_run(d, cycle, ad);
    daemon_finish(d);
    return rc;
}
