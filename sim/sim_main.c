/* tandem-sim: the ODE simulator daemon (SPEC.md §1, §5).
 * Owns the world and the clock; models (arms, rovers) plug in through
 * sim_model_ops. In lockstep it publishes step k, then waits until every
 * registered controller has answered k before stepping to k+1.
 */
#include "sim.h"
#include "arm_model.h"
#include "formation.h"
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
} sim_app;

static sim_app app;

/* Lockstep: how long to wait for the answers before publishing the step
 * again (a datagram lost on a loaded host, not a dead participant). */
#define SIM_REANNOUNCE_NS 1000000LL       /* first repeat of an unanswered step */
#define SIM_REANNOUNCE_MAX_NS 32000000LL  /* back-off cap */

static void usage(void)
{
    printf("usage: tandem-sim [options]\n"
           "ODE simulator of the tandem world: two PUMA 560 arms with a table,\n"
           "workpieces, vision camera and stick; Pioneer robots with sonar and\n"
           "beacons. Steps at 1 kHz on the wall clock, or in lockstep.\n\n"
           "  --seed S          random seed (noise, workpiece stream); default 1\n"
           "  --steps N         stop after N steps (0 = run until stopped)\n"
           "  --expect N        lockstep: wait for N controllers before the first step\n"
           "  --timeout-ms MS   lockstep: drop a controller silent this long (default 2000)\n"
           "  --no-arms         leave the PUMA pair out\n"
           "  --workpieces N    workpieces to feed (0 = endless, default)\n"
           "  --friction V,C    arm joint viscous (N m s/rad) and Coulomb (N m) friction\n"
           "  --rovers N        number of Pioneer robots (default 0)\n"
           "  --world NAME      rover world: open | obstacles | corridor | deadzone\n"
           "  --formation F     rover team's start formation: line (default) | triangle | column\n"
           "  --rover-batch     all robots' sensors in one message per tick (ROVERS_SENSORS,\n"
           "                    ROVERS_BEACONS) instead of ROVERk_SENSORS/_SONAR/_BEACONS\n"
           "  --arm-model NAME  arm 1 is puma560 (default) or seed002 (seed 002's arm)\n"
           "  --arm-q0 Q1,..,Q6 arm 1 starts at these joint angles (rad) instead of home\n"
           DAEMON_COMMON_HELP);
}

static int parse_args(int argc, char **argv)
{
    static const struct option opts[] = {
        { "seed", required_argument, 0, 's' },
        { "steps", required_argument, 0, 'n' },
        { "expect", required_argument, 0, 'e' },
        { "timeout-ms", required_argument, 0, 't' },
        { "no-arms", no_argument, 0, 'A' },
        { "workpieces", required_argument, 0, 'W' },
        { "friction", required_argument, 0, 'f' },
        { "rovers", required_argument, 0, 'r' },
        { "world", required_argument, 0, 'w' },
        { "formation", required_argument, 0, 'F' },
        { "rover-batch", no_argument, 0, 'B' },
        { "arm-model", required_argument, 0, 'M' },
        { "arm-q0", required_argument, 0, 'Q' },
        DAEMON_COMMON_OPTIONS,
        { 0, 0, 0, 0 }
    };
    int c, i;
    long v;
    double ms;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        int rc = daemon_parse_common(&app.w.d, c, optarg);
        if (rc == 2) {
            usage();
            exit(0);
        }
        if (rc < 0)
            return -1;
        if (rc == 1)
            continue;
        switch (c) {
        case 's':
            if (parse_int_opt("tandem-sim", "--seed", optarg, 0, 2147483647L, &v) < 0) return -1;
            app.w.seed = (uint64_t)v;
            break;
        case 'n':
            if (parse_int_opt("tandem-sim", "--steps", optarg, 0, 2000000000L, &v) < 0) return -1;
            app.max_steps = v;
            break;
        case 'e':
            if (parse_int_opt("tandem-sim", "--expect", optarg, 0, SIM_MAX_PARTICIPANTS, &v) < 0) return -1;
            app.expect = (int)v;
            break;
        case 't':
            if (parse_double_opt("tandem-sim", "--timeout-ms", optarg, 10.0, 600000.0, &ms) < 0) return -1;
            app.w.lockstep_timeout_s = ms * 1e-3;
            break;
        case 'A':
            app.cfg.arms = 0;
            break;
        case 'W':
            if (parse_int_opt("tandem-sim", "--workpieces", optarg, 0, 100000L, &v) < 0) return -1;
            app.cfg.workpieces = (int)v;
            break;
        case 'f': {
            char *comma = strchr(optarg, ',');
            if (!comma) {
                fprintf(stderr, "tandem-sim: --friction: expected VISCOUS,COULOMB\n");
                return -1;
            }
            *comma = '\0';
            if (parse_double_opt("tandem-sim", "--friction (viscous)", optarg, 0.0, 100.0, &app.cfg.arm_friction_viscous) < 0 ||
                parse_double_opt("tandem-sim", "--friction (Coulomb)", comma + 1, 0.0, 100.0, &app.cfg.arm_friction_coulomb) < 0)
                return -1;
            break;
        }
        case 'r':
            if (parse_int_opt("tandem-sim", "--rovers", optarg, 0, 1000L, &v) < 0) return -1;
            app.cfg.rovers = (int)v;
            break;
        case 'w':
            if (strcmp(optarg, "open") && strcmp(optarg, "obstacles") &&
                strcmp(optarg, "corridor") && strcmp(optarg, "deadzone")) {
                fprintf(stderr, "tandem-sim: --world: '%s' is not open|obstacles|corridor|deadzone\n", optarg);
                return -1;
            }
            snprintf(app.cfg.rover_world, sizeof app.cfg.rover_world, "%s", optarg);
            break;
        case 'F':
            if (!strcmp(optarg, "line")) app.cfg.rover_formation = FORMATION_LINE;
            else if (!strcmp(optarg, "triangle")) app.cfg.rover_formation = FORMATION_TRIANGLE;
            else if (!strcmp(optarg, "column")) app.cfg.rover_formation = FORMATION_COLUMN;
            else {
                fprintf(stderr, "tandem-sim: --formation: '%s' is not line|triangle|column\n", optarg);
                return -1;
            }
            break;
        case 'B':
            app.cfg.rover_batch = 1;
            break;
        case 'M':
            if (!(app.cfg.arm1_model = arm_model_by_name(optarg))) {
                fprintf(stderr, "tandem-sim: --arm-model: '%s' is not puma560|seed002\n", optarg);
                return -1;
            }
            break;
        case 'Q': {
            char *tok = strtok(optarg, ",");
            for (i = 0; i < ARM_NJ; i++, tok = strtok(NULL, ","))
                if (!tok || parse_double_opt("tandem-sim", "--arm-q0", tok, -10.0, 10.0, &app.cfg.arm1_q0_rad[i]) < 0) {
                    if (!tok)
                        fprintf(stderr, "tandem-sim: --arm-q0: expected 6 comma-separated angles (rad)\n");
                    return -1;
                }
            if (tok) {
                fprintf(stderr, "tandem-sim: --arm-q0: more than 6 angles\n");
                return -1;
            }
            app.cfg.arm1_q0_set = 1;
            break;
        }
        default:
            usage();
            return -1;
        }
    }
    if (app.cfg.arm1_q0_set &&
        arm_q_outside_limits(app.cfg.arm1_model ? app.cfg.arm1_model : &arm_model_puma560, app.cfg.arm1_q0_rad)) {
        fprintf(stderr, "tandem-sim: --arm-q0: outside arm 1's joint ranges\n");
        return -1;
    }
    if (optind < argc) {
        fprintf(stderr, "tandem-sim: unexpected argument '%s'\n", argv[optind]);
        return -1;
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
    memset(&app, 0, sizeof app);
    daemon_defaults(&app.w.d, "tandem-sim", SIM_DT_S);
    app.w.seed = 1;
    app.w.lockstep_timeout_s = 2.0;
    app.cfg.arms = 1;
    snprintf(app.cfg.rover_world, sizeof app.cfg.rover_world, "open");
    app.cfg.rover_formation = FORMATION_LINE;
    if (parse_args(argc, argv) != 0)
        return 2;
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
