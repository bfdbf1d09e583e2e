/* sim_loop: tandem-sim's messages and its step (docs/method/lockstep.md §1, §3). The
 * models' hooks run in the order of sim_app.models (before_step, the ODE
 * step, after_step). In lockstep the simulator publishes step k, then
 * waits until every registered controller has answered k (and every
 * model has the commands it waits for) before stepping to k+1; in real
 * time it steps on the wall clock.
 */
#include "sim_app.h"
#include "rover_batch.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "tandem_clock_ack_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

/* Lockstep: how long to wait for the answers before publishing the step
 * again (a datagram lost on a loaded host, not a dead participant). */
#define SIM_REANNOUNCE_NS 1000000LL      /* first repeat of an unanswered step */
#define SIM_REANNOUNCE_MAX_NS 32000000LL /* back-off cap, unless a fleet's answers take longer */
/* Lockstep: how often a late participant's process is looked at (alive,
 * stopped, gone: sim_lockstep_drop_dead). */
#define SIM_LIVENESS_CHECK_NS 50000000LL

static int active_participants(const sim_world *w)
{
    int i, n = 0;
    for (i = 0; i < w->n_part; i++)
        n += w->part[i].active;
    return n;
}

/* ---- messages in ---------------------------------------------------------- */

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    sim_app *app = u;
    tandem_clock_ack_t m;
    (void)ch;
    if (!DAEMON_DECODE(&app->w.d.msgs, tandem_clock_ack_t, rb, &m))
        return;
    if (m.step < 0 || m.period_steps < 1 || m.period_steps > 100000 || m.name[0] == '\0' ||
        m.step > app->w.step) {
        app->w.d.msgs.rejected++;
    } else {
        sim_lockstep_on_ack(&app->w, m.name, m.step, m.period_steps, m.leaving, m.pid);
    }
    tandem_clock_ack_t_decode_cleanup(&m);
}

static int control_valid(const tandem_sim_control_t *c)
{
    return c->command >= TANDEM_SIM_CONTROL_T_RESET && c->command <= TANDEM_SIM_CONTROL_T_QUIT &&
           linalg_all_finite(c->position_m, 3) && linalg_all_finite(c->axis, 3) &&
           isfinite(c->length_m) && isfinite(c->radius_m) && c->seed >= 0;
}

static void on_control(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    sim_app *app = u;
    tandem_sim_control_t m;
    int i, handled = 0;
    (void)ch;
    if (!DAEMON_DECODE(&app->w.d.msgs, tandem_sim_control_t, rb, &m))
        return;
    if (!control_valid(&m)) {
        app->w.d.msgs.rejected++;
        goto out;
    }
    switch (m.command) {
    case TANDEM_SIM_CONTROL_T_PAUSE:
        app->w.paused = 1;
        handled = 1;
        break;
    case TANDEM_SIM_CONTROL_T_RESUME:
        app->w.paused = 0;
        handled = 1;
        break;
    case TANDEM_SIM_CONTROL_T_QUIT:
        daemon_request_stop();
        handled = 1;
        break;
    case TANDEM_SIM_CONTROL_T_SET_SEED:
        app->next_seed = (uint64_t)m.seed;
        handled = 1;
        break;
    case TANDEM_SIM_CONTROL_T_RESET:
        app->next_seed = (uint64_t)m.seed;
        app->reset_pending = 1;
        handled = 1;
        break;
    default:
        for (i = 0; i < app->n_models && !handled; i++) {
            const sim_model *md = &app->models[i];
            int rc = md->ops->control ? md->ops->control(md->state, &app->w, &m) : 0;
            if (rc < 0) {
                app->w.d.msgs.rejected++;
                handled = -1;
            } else if (rc > 0) {
                handled = 1;
            }
        }
    }
    if (handled == 0)
        app->w.d.msgs.rejected++;
out:
    tandem_sim_control_t_decode_cleanup(&m);
}

void sim_subscribe(sim_app *app)
{
    daemon_subscribe(&app->w.d, "SIM_ACK", on_ack, app);
    daemon_subscribe(&app->w.d, "SIM_CONTROL", on_control, app);
}

/* ---- messages out --------------------------------------------------------- */

static void publish_clock(sim_app *app)
{
    tandem_sim_clock_t c;
    c.seq = app->w.clock_seq++;
    c.utime = daemon_utime_now();
    c.step = app->w.step;
    c.sim_time_s = app->w.time_s;
    c.mode = app->w.lockstep ? TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP : TANDEM_SIM_CLOCK_T_MODE_REALTIME;
    c.paused = (int8_t)app->w.paused;
    c.seed = (int64_t)app->w.seed;
    AUTH_PUBLISH(tandem_sim_clock_t, &app->w.d.bus, app->w.d.lcm, "SIM_CLOCK", &c);
}

uint64_t sim_app_state_hash(const sim_app *app)
{
    uint64_t h = sim_state_hash(&app->w);
    int i;
    for (i = 0; i < app->n_models; i++)
        if (app->models[i].ops->hash)
            h = app->models[i].ops->hash(app->models[i].state, h);
    return h;
}

void sim_publish_status(sim_app *app)
{
    tandem_sim_status_t s;
    int i;
    memset(&s, 0, sizeof s);
    s.seq = app->w.status_seq++;
    s.utime = daemon_utime_now();
    s.step = app->w.step;
    s.sim_time_s = app->w.time_s;
    s.mode = (int8_t)app->w.lockstep;
    s.paused = (int8_t)app->w.paused;
    s.n_participants = active_participants(&app->w);
    s.lockstep_timeouts = app->w.lockstep_timeouts;
    s.state_hash = (int64_t)sim_app_state_hash(app);
    s.msgs_received = app->w.d.msgs.received;
    s.msgs_rejected = app->w.d.msgs.rejected;
    s.stale_commands = app->w.stale_commands;
    for (i = 0; i < app->n_models; i++)
        if (app->models[i].ops->status)
            app->models[i].ops->status(app->models[i].state, &app->w, &s);
    AUTH_PUBLISH(tandem_sim_status_t, &app->w.d.bus, app->w.d.lcm, "SIM_STATUS", &s);
}

/* ---- the step ------------------------------------------------------------- */

int sim_build_world(sim_app *app)
{
    int i;
    if (sim_world_create(&app->w) != 0)
        return SIM_ERR_CREATE;
    for (i = 0; i < app->n_models; i++)
        if (app->models[i].ops->create(app->models[i].state, &app->w, &app->cfg) != 0) {
            fprintf(stderr, "tandem-sim: cannot create model '%s'\n", app->models[i].ops->name);
            return SIM_ERR_CREATE;
        }
    return 0;
}

void sim_destroy_world(sim_app *app)
{
    int i;
    for (i = app->n_models - 1; i >= 0; i--)
        app->models[i].ops->destroy(app->models[i].state, &app->w);
    sim_world_destroy(&app->w);
}

/* Lockstep: every model has what it waits for at step k (its
 * controllers' commands, sim_model_ops.ready). */
static int models_ready(const sim_app *app, int64_t k)
{
    int i;
    for (i = 0; i < app->n_models; i++)
        if (app->models[i].ops->ready &&
            !app->models[i].ops->ready(app->models[i].state, &app->w, k))
            return 0;
    return 1;
}

static void publish_step(sim_app *app)
{
    int i;
    for (i = 0; i < app->n_models; i++)
        app->models[i].ops->after_step(app->models[i].state, &app->w);
    if (app->w.step % 100 == 0)
        sim_publish_status(app);
    /* In lockstep the clock goes out when somebody must answer it (and
     * every 100 steps for a newcomer to join on): a team of 20 Hz rovers
     * does not need 1000 clocks a second, each received by every process
     * on the bus. */
    if (!app->w.lockstep || app->w.step % 100 == 0 || sim_lockstep_due(&app->w, app->w.step) ||
        active_participants(&app->w) == 0)
        publish_clock(app);
}

static void advance(sim_app *app)
{
    int i;
    for (i = 0; i < app->n_models; i++)
        app->models[i].ops->before_step(app->models[i].state, &app->w);
    sim_world_step(&app->w);
    publish_step(app);
}

static void maybe_reset(sim_app *app)
{
    if (!app->reset_pending)
        return;
    app->reset_pending = 0;
    sim_destroy_world(app);
    app->w.seed = app->next_seed;
    if (sim_build_world(app) != 0) {
        daemon_request_stop();
        return;
    }
    fprintf(stderr, "tandem-sim: reset with seed %llu\n", (unsigned long long)app->w.seed);
    publish_step(app);
}

/* Every participant answered, yet a model's input for the step did not
 * come within the timeout (sim_model_ops.ready): go on without it. */
static void give_up_waiting(sim_world *w)
{
    w->lockstep_timeouts++;
    fprintf(stderr, "tandem-sim: step %lld: a controller's output never came; going on\n",
            (long long)w->step);
}

/* Waits for the controllers due at the current step. A late participant
 * is waited for while it is alive (however slow: a loaded machine must
 * not change the run) and dropped once dead (sim_lockstep_drop_dead); the
 * wall-clock timeout bounds only the wait for a model's input after every
 * participant answered. */
static void wait_for_answers(sim_app *app)
{
    const int64_t t0 = rtloop_now_ns();
    /* the first repeat comes after a few typical answer times of those due
     * (at least SIM_REANNOUNCE_NS): on a loaded machine a slow answer is
     * not a lost one, and the steps nobody answers must not pull the
     * typical time down (a 20 Hz rover host is due one step in 50) */
    const int64_t answer_ns = sim_lockstep_answer_ns(&app->w, app->w.step);
    int64_t last_pub = t0, again_ns = 4 * answer_ns, last_check = t0, answered_ns = -1,
            again_max_ns = SIM_REANNOUNCE_MAX_NS;
    app->w.step_announced_ns = t0;
    if (again_ns < SIM_REANNOUNCE_NS)
        again_ns = SIM_REANNOUNCE_NS;
    if (again_ns > SIM_REANNOUNCE_MAX_NS)
        again_ns = SIM_REANNOUNCE_MAX_NS;
    /* a repeat sends the step's every frame again, a fleet's megabytes to
     * every host: repeated faster than the hosts answer, it is work added
     * to the work they are behind with (10,000 robots on 4 hosts, each
     * 0.1-1 s a step, were sent each step every 32 ms and never caught up).
     * So for a fleet of more than one batch of frames (BATCH_MAX robots),
     * where a typical answer itself takes longer than the 32 ms cap, the
     * first repeat and the back-off are 4 of them while answers are due
     * (a repeat at 32 ms still came 3 times a step at 10,000 robots, and
     * the repeated frames were most of the hosts' and the simulator's
     * CPU: 1.30 against 0.75 us a robot-step); a cell and a team (a lost
     * datagram, 10 % loss; a flood's handle renewals) keep the short
     * schedule as it was */
    if (app->cfg.rovers > BATCH_MAX && answer_ns > SIM_REANNOUNCE_MAX_NS)
        again_ns = again_max_ns = 4 * answer_ns;
    while (!daemon_stop_requested()) {
        const int64_t now = rtloop_now_ns();
        const int starting = app->w.step == 0 && active_participants(&app->w) < app->expect;
        const int waiting = !starting && !app->w.paused;
        const int late = sim_lockstep_late(&app->w, app->w.step);
        if (waiting && !late &&
            (active_participants(&app->w) == 0 || models_ready(app, app->w.step))) {
            return;
        }
        if (waiting && late && now - last_check > SIM_LIVENESS_CHECK_NS) {
            last_check = now;
            if (sim_lockstep_drop_dead(&app->w, app->w.step) > 0)
                continue;
        }
        if (waiting && !late && answered_ns < 0) {
            answered_ns = now;
            /* every participant answered: what is missing is an output
             * lost on the way, not work under way, and the repair must
             * come well within the timeout: back to the short schedule */
            again_max_ns = SIM_REANNOUNCE_MAX_NS;
            if (again_ns > again_max_ns)
                again_ns = again_max_ns;
        }
        if (waiting && !late && (double)(now - answered_ns) * 1e-9 > app->w.lockstep_timeout_s) {
            give_up_waiting(&app->w);
            return;
        }
        /* Until everyone is there (or while paused), keep announcing the step
         * with its states, so a controller that starts late still sees them.
         * Otherwise re-announce on a short timer: a lost SIM_CLOCK, state or
         * ack then costs SIM_REANNOUNCE_NS, not the participant timeout
         * (participants answer a step they already answered again, without
         * running their cycle twice). */
        if (now - last_pub > ((starting || app->w.paused) ? 100000000LL : again_ns)) {
            publish_step(app);
            last_pub = now;
            app->w.lockstep_reannounced += !starting && !app->w.paused;
            /* a lost message is found at the first repeat; a controller
             * that is only slow (a loaded machine) should not be flooded */
            if (again_ns < again_max_ns)
                again_ns = 2 * again_ns < again_max_ns ? 2 * again_ns : again_max_ns;
        }
        lcm_handle_timeout(app->w.d.lcm, 1); /* the re-announce timer's resolution */
        /* health goes on while waiting: a simulator held by a silent
         * controller is alive, and its health says so (a scenario takes a
         * daemon without health for hung) */
        daemon_health_tick(&app->w.d, now);
        /* a long wait (the start, a pause) under a flood of channel names:
         * the new handle is subscribed before the old one is read for the
         * last time, so no answer is lost */
        daemon_names_watch(&app->w.d);
        if (app->reset_pending)
            return;
    }
}

static int steps_done(const sim_app *app)
{
    return app->max_steps > 0 && app->w.step >= app->max_steps;
}

void sim_run_lockstep(sim_app *app)
{
    publish_step(app);
    while (!daemon_stop_requested() && !steps_done(app)) {
        int64_t t0;
        wait_for_answers(app);
        if (app->reset_pending) {
            maybe_reset(app);
            continue;
        }
        if (daemon_stop_requested())
            break;
        /* the bound on LCM's table of channel names: here, with every
         * answer to this step in and the next step not announced yet, a
         * renewed handle has nothing in flight to lose; the step, the
         * participants and the held commands are the world's, not LCM's */
        daemon_names_watch(&app->w.d);
        t0 = rtloop_now_ns();
        advance(app);
        rtloop_record(&app->w.d.loop, t0);
        daemon_health_tick(&app->w.d, t0);
    }
}

void sim_run_realtime(sim_app *app)
{
    rtloop *l = &app->w.d.loop;
    l->next_ns = rtloop_now_ns() + l->period_ns;
    publish_step(app);
    while (!daemon_stop_requested() && !steps_done(app)) {
        rtloop_wait(l);
        daemon_drain(&app->w.d);
        maybe_reset(app);
        if (!app->w.paused)
            advance(app);
        else if (l->cycles % 100 == 0)
            publish_clock(app);
        rtloop_end_cycle(l);
        daemon_health_tick(&app->w.d, l->wake_ns);
        daemon_names_watch(&app->w.d); /* after the step, as the daemons do */
    }
}
