/* tandem-sim: the ODE simulator daemon (SPEC.md §1, §5).
 * Owns the world and the clock; models (arms, rovers) plug in through
 * sim_model_ops. In lockstep it publishes step k, then waits until every
 * registered controller has answered k before stepping to k+1.
 */
#include "sim.h"
#include "arm_model.h"
#include "formation.h"
#include "options.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "tandem_clock_ack_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

typedef struct sim_app {
    sim_world  w;
    sim_config cfg;
    int64_t    max_steps;      /* 0 = run forever */
    int        expect;         /* lockstep: participants to wait for at start */
    const sim_model_ops *models[4];
    int        n_models;
    int        reset_pending;
    uint64_t   next_seed;
    int64_t answer_ns_avg;      /* lockstep: typical wall time to an answered step */
    /* options that are not stored as given */
    int        no_arms;        /* --no-arms: cfg.arms = 0 */
    int        world;          /* --world: index in options_world_names */
    int        arm_model;      /* --arm-model: index in options_arm_model_names, -1 not given */
} sim_app;

static sim_app app;

/* Lockstep: how long to wait for the answers before publishing the step
 * again (a datagram lost on a loaded host, not a dead participant). */
#define SIM_REANNOUNCE_NS 1000000LL       /* first repeat of an unanswered step */
#define SIM_REANNOUNCE_MAX_NS 32000000LL  /* back-off cap */

/* --friction V,C: both in [0, 100] */
static int parse_friction(const char *prog, void *dest, char *value)
{
    sim_config *cfg = dest;
    char *comma = strchr(value, ',');
    if (!comma) {
        fprintf(stderr, "%s: --friction: expected VISCOUS,COULOMB\n", prog);
        return OPTIONS_ERR_SAID;
    }
    *comma = '\0';
    if (parse_double_opt(prog, "--friction (viscous)", value, 0.0, 100.0, &cfg->arm_friction_viscous) < 0 ||
        parse_double_opt(prog, "--friction (Coulomb)", comma + 1, 0.0, 100.0, &cfg->arm_friction_coulomb) < 0)
        return OPTIONS_ERR_SAID;
    return 0;
}

/* --arm-q0 Q1,..,Q6: six angles in [-10, 10] rad (the joint ranges are
 * checked once the arm model is known) */
static int parse_q0(const char *prog, void *dest, char *value)
{
    sim_config *cfg = dest;
    char *tok = strtok(value, ",");
    int i;
    for (i = 0; i < ARM_NJ; i++, tok = strtok(NULL, ","))
        if (!tok || parse_double_opt(prog, "--arm-q0", tok, -10.0, 10.0, &cfg->arm1_q0_rad[i]) < 0) {
            if (!tok)
                fprintf(stderr, "%s: --arm-q0: expected 6 comma-separated angles (rad)\n", prog);
            return OPTIONS_ERR_SAID;
        }
    if (tok) {
        fprintf(stderr, "%s: --arm-q0: more than 6 angles\n", prog);
        return OPTIONS_ERR_SAID;
    }
    cfg->arm1_q0_set = 1;
    return 0;
}

static const option_entry sim_options[] = {
    { .name = "seed", .type = OPTION_INT, OPTION_AT(sim_app, w.seed), .min = 0, .max = 2147483647.0, .meta = "S",
      .help = "random seed (noise, workpiece stream)", .def = "1" },
    { .name = "steps", .type = OPTION_INT, OPTION_AT(sim_app, max_steps), .min = 0, .max = 2000000000.0,
      .meta = "N", .help = "stop after N steps (0 = run until stopped)", .def = "0" },
    { .name = "expect", .type = OPTION_INT, OPTION_AT(sim_app, expect), .min = 0, .max = SIM_MAX_PARTICIPANTS,
      .meta = "N", .help = "lockstep: wait for N controllers before the first step", .def = "0" },
    { .name = "timeout-ms", .type = OPTION_DOUBLE, OPTION_AT(sim_app, w.lockstep_timeout_s), .min = 10.0,
      .max = 600000.0, .scale = 1e-3, .meta = "MS", .help = "lockstep: drop a controller silent this long",
      .def = "2000" },
    { .name = "no-arms", .type = OPTION_FLAG, OPTION_AT(sim_app, no_arms), .help = "leave the PUMA pair out" },
    { .name = "workpieces", .type = OPTION_INT, OPTION_AT(sim_app, cfg.workpieces), .min = 0, .max = 100000,
      .meta = "N", .help = "workpieces to feed (0 = endless)", .def = "0" },
    { .name = "friction", .type = OPTION_CALL, OPTION_AT(sim_app, cfg), .call = parse_friction, .meta = "V,C",
      .help = "arm joint viscous (N m s/rad) and Coulomb (N m) friction, each 0..100", .def = "0,0" },
    { .name = "rovers", .type = OPTION_INT, OPTION_AT(sim_app, cfg.rovers), .min = 0, .max = 1000, .meta = "N",
      .help = "number of Pioneer robots", .def = "0" },
    { .name = "world", .type = OPTION_CHOICE, OPTION_AT(sim_app, world), .choices = options_world_names,
      .meta = "NAME", .help = "rover world", .def = "open" },
    { .name = "formation", .type = OPTION_CHOICE, OPTION_AT(sim_app, cfg.rover_formation),
      .choices = options_formation_names, .values = options_formation_values, .meta = "F",
      .help = "rover team's start formation", .def = "line" },
    { .name = "rover-batch", .type = OPTION_FLAG, OPTION_AT(sim_app, cfg.rover_batch),
      .help = "all robots' sensors in one message per tick (ROVERS_SENSORS, ROVERS_BEACONS) instead of "
              "ROVERk_SENSORS/_SONAR/_BEACONS" },
    { .name = "arm-model", .type = OPTION_CHOICE, OPTION_AT(sim_app, arm_model), .choices = options_arm_model_names,
      .meta = "NAME", .help = "arm 1's model (seed002: seed 002's arm)", .def = "puma560" },
    { .name = "arm-q0", .type = OPTION_CALL, OPTION_AT(sim_app, cfg), .call = parse_q0, .meta = "Q1,..,Q6",
      .help = "arm 1 starts at these joint angles (rad, -10..10) instead of home" },
    { .name = NULL }
};

static int parse_args(int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-sim",
        .usage = "usage: tandem-sim [options]\n"
                 "ODE simulator of the tandem world: two PUMA 560 arms with a table,\n"
                 "workpieces, vision camera and stick; Pioneer robots with sonar and\n"
                 "beacons. Steps at 1 kHz on the wall clock, or in lockstep.\n\n",
        .groups = { { sim_options, &app }, { options_daemon_common, &app.w.d } },
        .n_groups = 2,
    };
    int rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return rc;
    if (app.no_arms)
        app.cfg.arms = 0;
    snprintf(app.cfg.rover_world, sizeof app.cfg.rover_world, "%s", options_world_names[app.world]);
    if (app.arm_model >= 0)
        app.cfg.arm1_model = arm_model_by_name(options_arm_model_names[app.arm_model]);
    if (app.cfg.arm1_q0_set &&
        arm_q_outside_limits(app.cfg.arm1_model ? app.cfg.arm1_model : &arm_model_puma560, app.cfg.arm1_q0_rad)) {
        fprintf(stderr, "tandem-sim: --arm-q0: outside arm 1's joint ranges\n");
        return OPTIONS_ERR_ARG;
    }
    return 0;
}

/* ---- messages in ---------------------------------------------------------- */

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_clock_ack_t m;
    (void)ch; (void)u;
    if (!DAEMON_DECODE(&app.w.d.msgs, tandem_clock_ack_t, rb, &m))
        return;
    if (m.step < 0 || m.period_steps < 1 || m.period_steps > 100000 || m.name[0] == '\0' ||
        m.step > app.w.step) {
        app.w.d.msgs.rejected++;
    } else {
        sim_lockstep_on_ack(&app.w, m.name, m.step, m.period_steps, m.leaving);
    }
    tandem_clock_ack_t_decode_cleanup(&m);
}

static int control_valid(const tandem_sim_control_t *c)
{
    return c->command >= TANDEM_SIM_CONTROL_T_RESET && c->command <= TANDEM_SIM_CONTROL_T_QUIT &&
           all_finite(c->position_m, 3) && all_finite(c->axis, 3) &&
           isfinite(c->length_m) && isfinite(c->radius_m) && c->seed >= 0;
}

static void on_control(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_control_t m;
    int i, handled = 0;
    (void)ch; (void)u;
    if (!DAEMON_DECODE(&app.w.d.msgs, tandem_sim_control_t, rb, &m))
        return;
    if (!control_valid(&m)) {
        app.w.d.msgs.rejected++;
        goto out;
    }
    switch (m.command) {
    case TANDEM_SIM_CONTROL_T_PAUSE:  app.w.paused = 1; handled = 1; break;
    case TANDEM_SIM_CONTROL_T_RESUME: app.w.paused = 0; handled = 1; break;
    case TANDEM_SIM_CONTROL_T_QUIT:   daemon_request_stop(); handled = 1; break;
    case TANDEM_SIM_CONTROL_T_SET_SEED: app.next_seed = (uint64_t)m.seed; handled = 1; break;
    case TANDEM_SIM_CONTROL_T_RESET:
        app.next_seed = (uint64_t)m.seed;
        app.reset_pending = 1;
        handled = 1;
        break;
    default:
        for (i = 0; i < app.n_models && !handled; i++) {
            int rc = app.models[i]->control ? app.models[i]->control(&app.w, &m) : 0;
            if (rc < 0) {
                app.w.d.msgs.rejected++;
                handled = -1;
            } else if (rc > 0) {
                handled = 1;
            }
        }
    }
    if (handled == 0)
        app.w.d.msgs.rejected++;
out:
    tandem_sim_control_t_decode_cleanup(&m);
}

/* ---- messages out --------------------------------------------------------- */

static void publish_clock(void)
{
    tandem_sim_clock_t c;
    c.seq = app.w.clock_seq++;
    c.utime = daemon_utime_now();
    c.step = app.w.step;
    c.sim_time_s = app.w.time_s;
    c.mode = app.w.lockstep ? TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP : TANDEM_SIM_CLOCK_T_MODE_REALTIME;
    c.paused = (int8_t)app.w.paused;
    c.seed = (int64_t)app.w.seed;
    AUTH_PUBLISH(tandem_sim_clock_t, app.w.lcm, "SIM_CLOCK", &c);
}

static void publish_status(void)
{
    tandem_sim_status_t s;
    int i, n = 0;
    memset(&s, 0, sizeof s);
    for (i = 0; i < app.w.n_part; i++)
        n += app.w.part[i].active;
    s.seq = app.w.status_seq++;
    s.utime = daemon_utime_now();
    s.step = app.w.step;
    s.sim_time_s = app.w.time_s;
    s.mode = (int8_t)app.w.lockstep;
    s.paused = (int8_t)app.w.paused;
    s.n_participants = n;
    s.lockstep_timeouts = app.w.lockstep_timeouts;
    s.state_hash = (int64_t)sim_state_hash(&app.w);
    s.msgs_received = app.w.d.msgs.received;
    s.msgs_rejected = app.w.d.msgs.rejected;
    s.stale_commands = app.w.stale_commands;
    for (i = 0; i < app.n_models; i++)
        if (app.models[i]->status)
            app.models[i]->status(&app.w, &s);
    AUTH_PUBLISH(tandem_sim_status_t, app.w.lcm, "SIM_STATUS", &s);
}

/* ---- the step ------------------------------------------------------------- */

static int build_world(void)
{
    int i;
    if (sim_world_create(&app.w) != 0)
        return -1;
    for (i = 0; i < app.n_models; i++)
        if (app.models[i]->create(&app.w, &app.cfg) != 0) {
            fprintf(stderr, "tandem-sim: cannot create model '%s'\n", app.models[i]->name);
            return -1;
        }
    return 0;
}

static void destroy_world(void)
{
    int i;
    for (i = app.n_models - 1; i >= 0; i--)
        app.models[i]->destroy(&app.w);
    sim_world_destroy(&app.w);
}

static int active_participants(void);

/* Lockstep: every model has what it waits for at step k (its
 * controllers' commands, sim_model_ops.ready). */
static int models_ready(int64_t k)
{
    int i;
    for (i = 0; i < app.n_models; i++)
        if (app.models[i]->ready && !app.models[i]->ready(&app.w, k))
            return 0;
    return 1;
}

static void publish_step(void)
{
    int i;
    for (i = 0; i < app.n_models; i++)
        app.models[i]->after_step(&app.w);
    if (app.w.step % 100 == 0)
        publish_status();
    /* In lockstep the clock goes out when somebody must answer it (and
     * every 100 steps for a newcomer to join on): a team of 20 Hz rovers
     * does not need 1000 clocks a second, each received by every process
     * on the bus. */
    if (!app.w.lockstep || app.w.step % 100 == 0 || sim_lockstep_due(&app.w, app.w.step) ||
        active_participants() == 0)
        publish_clock();
}

static void advance(void)
{
    int i;
    for (i = 0; i < app.n_models; i++)
        app.models[i]->before_step(&app.w);
    sim_world_step(&app.w);
    publish_step();
}

static void maybe_reset(void)
{
    if (!app.reset_pending)
        return;
    app.reset_pending = 0;
    destroy_world();
    app.w.seed = app.next_seed;
    if (build_world() != 0) {
        daemon_request_stop();
        return;
    }
    fprintf(stderr, "tandem-sim: reset with seed %llu\n", (unsigned long long)app.w.seed);
    publish_step();
}

static int active_participants(void)
{
    int i, n = 0;
    for (i = 0; i < app.w.n_part; i++)
        n += app.w.part[i].active;
    return n;
}

/* Waits for the controllers due at the current step; bounded by the timeout. */
static void wait_for_answers(void)
{
    const int64_t t0 = rtloop_now_ns();
    /* the first repeat comes after a few typical answer times (at least
     * SIM_REANNOUNCE_NS): on a loaded machine a slow answer is not a lost one */
    int64_t last_pub = t0, again_ns = 4 * app.answer_ns_avg;
    if (again_ns < SIM_REANNOUNCE_NS) again_ns = SIM_REANNOUNCE_NS;
    if (again_ns > SIM_REANNOUNCE_MAX_NS) again_ns = SIM_REANNOUNCE_MAX_NS;
    while (!daemon_stop_requested()) {
        const int64_t now = rtloop_now_ns();
        const int starting = app.w.step == 0 && active_participants() < app.expect;
        if (!starting && !app.w.paused && sim_lockstep_ready(&app.w, app.w.step) &&
            (active_participants() == 0 || models_ready(app.w.step))) {
            /* answer time, averaged over ~64 waits, only of those answered
             * without a repeat (a lost message is not the machine's speed) */
            if (last_pub == t0)
                app.answer_ns_avg += (now - t0 - app.answer_ns_avg) / 64;
            return;
        }
        if (!starting && !app.w.paused && (double)(now - t0) * 1e-9 > app.w.lockstep_timeout_s) {
            if (sim_lockstep_drop_late(&app.w, app.w.step) == 0) {
                app.w.lockstep_timeouts++;
                fprintf(stderr, "tandem-sim: step %lld: a controller's output never came; going on\n",
                        (long long)app.w.step);
            }
            return;
        }
        /* Until everyone is there (or while paused), keep announcing the step
         * with its states, so a controller that starts late still sees them.
         * Otherwise re-announce on a short timer: a lost SIM_CLOCK, state or
         * ack then costs SIM_REANNOUNCE_NS, not the participant timeout
         * (participants answer a step they already answered again, without
         * running their cycle twice). */
        if (now - last_pub > ((starting || app.w.paused) ? 100000000LL : again_ns)) {
            publish_step();
            last_pub = now;
            /* a lost message is found at the first repeat; a controller
             * that is only slow (a loaded machine) should not be flooded */
            if (again_ns < SIM_REANNOUNCE_MAX_NS)
                again_ns *= 2;
        }
        lcm_handle_timeout(app.w.lcm, 1);   /* the re-announce timer's resolution */
        if (app.reset_pending)
            return;
    }
}

static int steps_done(void)
{
    return app.max_steps > 0 && app.w.step >= app.max_steps;
}

static void run_lockstep(void)
{
    publish_step();
    while (!daemon_stop_requested() && !steps_done()) {
        int64_t t0;
        wait_for_answers();
        if (app.reset_pending) {
            maybe_reset();
            continue;
        }
        if (daemon_stop_requested())
            break;
        t0 = rtloop_now_ns();
        advance();
        rtloop_record(&app.w.d.loop, t0);
        if (t0 - app.w.d.last_health_ns >= 1000000000LL) {
            app.w.d.last_health_ns = t0;
            daemon_publish_health(&app.w.d);
        }
    }
}

static void run_realtime(void)
{
    rtloop *l = &app.w.d.loop;
    l->next_ns = rtloop_now_ns() + l->period_ns;
    publish_step();
    while (!daemon_stop_requested() && !steps_done()) {
        rtloop_wait(l);
        daemon_drain(&app.w.d);
        maybe_reset();
        if (!app.w.paused)
            advance();
        else if (l->cycles % 100 == 0)
            publish_clock();
        rtloop_end_cycle(l);
        if (l->wake_ns - app.w.d.last_health_ns >= 1000000000LL) {
            app.w.d.last_health_ns = l->wake_ns;
            daemon_publish_health(&app.w.d);
        }
    }
}

int main(int argc, char **argv)
{
    int rc;
    memset(&app, 0, sizeof app);
    daemon_defaults(&app.w.d, "tandem-sim", SIM_DT_S);
    app.w.seed = 1;
    app.w.lockstep_timeout_s = 2.0;
    app.cfg.arms = 1;
    snprintf(app.cfg.rover_world, sizeof app.cfg.rover_world, "open");
    app.cfg.rover_formation = FORMATION_LINE;
    app.arm_model = -1;
    rc = parse_args(argc, argv);
    if (rc < 0)
        return options_exit_status(rc);
    app.w.lockstep = app.w.d.lockstep;
    app.w.d.period_s = SIM_DT_S;
    app.w.d.clock_source = 1;
    if (app.cfg.arms) {
        app.models[app.n_models++] = &sim_arms_ops;
        app.models[app.n_models++] = &sim_workpieces_ops;   /* after arms: needs their joints */
    }
    if (app.cfg.rovers > 0)
        app.models[app.n_models++] = &sim_rovers_ops;
    auth_bus_identity(AUTH_ROLE_SIM, 0, 0);
    if (daemon_start(&app.w.d) != 0)
        return 1;
    app.w.lcm = app.w.d.lcm;
    daemon_subscribe(&app.w.d, "SIM_ACK", on_ack, NULL);
    daemon_subscribe(&app.w.d, "SIM_CONTROL", on_control, NULL);
    if (build_world() != 0)
        return 1;
    if (app.w.lockstep)
        run_lockstep();
    else
        run_realtime();
    printf("tandem-sim: stopped at step %lld state_hash=%016llx rejected=%lld\n",
           (long long)app.w.step, (unsigned long long)sim_state_hash(&app.w),
           (long long)app.w.d.msgs.rejected);
    fflush(stdout);
    publish_status();
    destroy_world();           /* models unsubscribe: LCM must still be open */
    daemon_finish(&app.w.d);
    return 0;
}
