/* formation_bus: the formation scenario's side of the bus
 * (docs/method/formation.md §6). It is a lockstep participant answering
 * every FM_PERIOD steps, so it sees the simulator's ground truth
 * deterministically; the robots' ROVERk_STATE / ROVERS_STATE are kept by
 * step in a ring, and truth at step k is read with the states of the
 * cycle before (k - FM_PERIOD). The protocol counts (formation changes,
 * dead-zone escapes) are what the robots did, read from their states.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include "formation_scen.h"
#include "shared_run.h"
#include "run_key.h"
#include "daemon.h"
#include "tandem_clock_ack_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_sim_clock_t.h"

void fm_ack(fm_bus *bus, int64_t step)
{
    scenario_ack(bus->auth, bus->lcm, &bus->ack_seq, step, FM_PERIOD, 0);
}

int64_t fm_mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

int fm_bus_open(fm_bus *bus, const fm_cfg *cfg, hang_watch *hw)
{
    int k;
    bus->cfg = cfg;
    bus->hw = hw;
    bus->auth = run_key_bus();
    bus->clock_step = -1;
    bus->answered = -1;
    bus->last_truth_step = -1;
    for (k = 0; k <= FM_MAX; k++)
        bus->rover_ack[k] = -1;
    names_watch_init(&bus->names, "formation");
    names_watch_fleet(&bus->names, cfg->robots); /* every robot's states and truth */
    bus->lcm = lcm_create(cfg->url);
    if (!bus->lcm) {
        fprintf(stderr, "formation: cannot open LCM at %s\n", cfg->url);
        return 1;
    }
    return 0;
}

int fm_bus_handle(fm_bus *bus, int ms)
{
    const int rc = lcm_handle_timeout(bus->lcm, ms);
    if (rc < 0)
        return rc;
    /* a flood of channel names: a new handle */
    bus_names_watch(&bus->names, bus->auth, &bus->lcm, bus->cfg->url);
    return rc;
}

void fm_answer(fm_bus *bus, int ack)
{
    bus->answered = bus->clock_step;
    if (ack)
        fm_ack(bus, bus->clock_step);
}

void fm_answer_repeat(fm_bus *bus)
{
    if (!bus->clock_repeat)
        return;
    bus->clock_repeat = 0; /* our ack was lost: answer again */
    if (bus->answered >= 0)
        fm_ack(bus, bus->answered);
}

void fm_forget_ack(fm_bus *bus, int k)
{
    bus->rover_ack[k] = -1;
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_clock_t *m, void *u)
{
    fm_bus *bus = u;
    (void)rb;
    (void)ch;
    if (m->step < bus->clock_step)
        return;
    /* a step announced again: answered (our ack was lost), or not yet (we
     * wait for the robots' states): either way the ack of our last answered
     * step goes out, which also tells the simulator we are alive */
    if (m->step == bus->answered || m->step == bus->clock_step)
        bus->clock_repeat = 1;
    bus->clock_step = m->step;
    bus->sim_time = m->sim_time_s;
    bus->have_clock = 1;
    bus->last_clock_ns = fm_mono_ns();
    hang_watch_heard(bus->hw, "tandem-sim", scenario_wall_s()); /* a sign of life (--hang-s) */
}

/* When the last clock seen is a step everyone answers and nothing has
 * moved for a while, the simulator is waiting there: answer that step
 * again in case our ack was lost. (The simulator itself re-announces a
 * step whose answers are missing, sim_loop.c; only it may publish
 * SIM_CLOCK, auth_acl.c.) */
static void nudge(fm_bus *bus)
{
    const int64_t k = bus->clock_step;
    if (k % FM_PERIOD)
        return;
    fm_ack(bus, k);
}

void fm_quiet_from_now(fm_bus *bus)
{
    bus->last_clock_ns = fm_mono_ns();
}

void fm_nudge_if_quiet(fm_bus *bus)
{
    if (!bus->have_clock || fm_mono_ns() - bus->last_clock_ns <= 500000000LL)
        return;
    nudge(bus);
    bus->last_clock_ns = fm_mono_ns();
}

/* Robot m's state taken; 1 when it entered the dead zone with it. */
static int take_state(fm_bus *bus, const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    int entered;
    if (i < 0 || i >= bus->cfg->robots)
        return 0;
    entered = bus->have_state[i] && m->mode == TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE &&
              bus->mode[i] != TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE;
    bus->mode[i] = m->mode;
    bus->state_type[i] = m->formation;
    if (isfinite(m->formation_scale) && m->formation_scale > 0.0)
        bus->state_scale[i] = m->formation_scale;
    memcpy(bus->weight[i], m->weight, sizeof bus->weight[i]);
    {
        const pose2 team = { m->x_m, m->y_m, m->theta_rad };
        const fm_cfg *cfg = bus->cfg;
        const pose2 frame = rover_fleet_frame_of(&cfg->layout, cfg->teams > 1 ? &cfg->fleet : NULL,
                                                 m->robot);
        rover_frame_from(&frame, &team, &bus->est[i]);
    }
    bus->have_state[i] = 1;
    return entered;
}

static void ring_put(fm_bus *bus, const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    if (i < 0 || i >= bus->cfg->robots || m->step < 0)
        return;
    bus->ring[i][(m->step / FM_PERIOD) % FM_RING] = *m;
}

const tandem_rover_state_t *fm_ring_get(const fm_bus *bus, int i, int64_t k)
{
    const tandem_rover_state_t *m = &bus->ring[i][(k / FM_PERIOD) % FM_RING];
    return m->step == k && m->robot == i + 1 ? m : NULL;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_state_t *m,
                     void *u)
{
    fm_bus *bus = u;
    (void)rb;
    (void)ch;
    ring_put(bus, m);
}

static void on_states(const lcm_recv_buf_t *rb, const char *ch, const tandem_rovers_state_t *m,
                      void *u)
{
    int i;
    fm_bus *bus = u;
    (void)rb;
    (void)ch;
    for (i = 0; i < m->n; i++)
        ring_put(bus, &m->state[i]);
}

/* Truth at step k is taken with every live robot's state of the cycle
 * before; 0 while one of them is missing. *dz_entries: how many robots
 * entered the dead zone with the states taken. */
static int states_for_truth(fm_bus *bus, const fm_procs *pr, const tandem_rover_truth_t *m,
                            int *dz_entries)
{
    const fm_cfg *cfg = bus->cfg;
    const int64_t k = m->step - FM_PERIOD;
    int i;
    if (k < FM_PERIOD)
        return 1; /* robots start at their first period */
    for (i = 0; i < m->n; i++) {
        const int r = m->robot[i] - 1;
        if (m->alive[i] && r >= 0 && r < cfg->robots && !(pr->killed && r + 1 == cfg->kill_id) &&
            !fm_process_down(pr, r + 1, k) && !fm_ring_get(bus, r, k))
            return 0;
    }
    for (i = 0; i < cfg->robots; i++) {
        const tandem_rover_state_t *st = fm_ring_get(bus, i, k);
        if (st)
            *dz_entries += take_state(bus, st);
    }
    return 1;
}

/* A piece of a fleet's truth (robots m->robot[0] .. in id order) put in
 * its place; the whole step's truth once every robot's is in, NULL
 * before. A piece of a later step starts the step afresh. */
static const tandem_rover_truth_t *truth_gather(fm_bus *bus, const tandem_rover_truth_t *m)
{
    struct fm_truth_parts *p = &bus->parts;
    const int at = m->n > 0 ? m->robot[0] - 1 : -1, n = bus->cfg->robots;
    size_t k;
    if (at < 0 || at + m->n > n)
        return NULL;
    if (p->m.step == m->step && p->have > 0 && p->got_step[at] == m->step)
        return NULL; /* a piece announced again */
    if (p->m.step != m->step || p->have == 0) {
        p->m = *m;
        p->m.n = (int16_t)n;
        p->m.robot = p->robot;
        p->m.x_m = p->x_m;
        p->m.y_m = p->y_m;
        p->m.theta_rad = p->theta_rad;
        p->m.min_clearance_m = p->min_clearance_m;
        p->m.collisions = p->collisions;
        p->m.alive = p->alive;
        p->have = 0;
    }
    k = (size_t)m->n;
    memcpy(p->robot + at, m->robot, k * sizeof *m->robot);
    memcpy(p->x_m + at, m->x_m, k * sizeof *m->x_m);
    memcpy(p->y_m + at, m->y_m, k * sizeof *m->y_m);
    memcpy(p->theta_rad + at, m->theta_rad, k * sizeof *m->theta_rad);
    memcpy(p->min_clearance_m + at, m->min_clearance_m, k * sizeof *m->min_clearance_m);
    memcpy(p->collisions + at, m->collisions, k * sizeof *m->collisions);
    memcpy(p->alive + at, m->alive, k * sizeof *m->alive);
    p->got_step[at] = m->step;
    p->have += m->n;
    if (p->have < n)
        return NULL;
    p->have = 0;
    return &p->m;
}

/* ROVER_TRUTH: the --kill seen; with the robots' states of the cycle
 * before, the metrics. A team's truth is one message, a larger fleet's
 * gathered from its pieces first. */
static void on_truth(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_truth_t *piece,
                     void *u)
{
    fm_run *r = u;
    fm_bus *bus = &r->bus;
    const tandem_rover_truth_t *m = piece;
    int dz_entries = 0;
    (void)rb;
    (void)ch;
    fm_kill_truth(&r->procs, &r->cfg, piece);
    if (piece->n != r->cfg.robots && piece->step > bus->last_truth_step)
        m = truth_gather(bus, piece);
    if (!m || m->n != r->cfg.robots || m->step <= bus->last_truth_step ||
        !states_for_truth(bus, &r->procs, m, &dz_entries))
        return;
    bus->last_truth_step = m->step;
    fm_metrics_truth(&r->metrics, &r->cfg, bus, &r->procs, m, dz_entries);
}

/* SIM_ACK: the last step each rover process answered (--fault). */
static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const tandem_clock_ack_t *m, void *u)
{
    char *e;
    long k;
    fm_bus *bus = u;
    (void)rb;
    (void)ch;
    if (!m->leaving)
        hang_watch_heard(bus->hw, m->name, scenario_wall_s()); /* a sign of life (--hang-s) */
    if (m->leaving || strncmp(m->name, "tandem-rover-", 13) != 0)
        return;
    k = strtol(m->name + 13, &e, 10);
    if (*e || k < 1 || k > FM_MAX)
        return;
    if (m->step > bus->rover_ack[k])
        bus->rover_ack[k] = m->step;
}

AUTH_TYPED_HANDLER(tandem_clock_ack_t, raw_on_ack, on_ack)
AUTH_TYPED_HANDLER(tandem_sim_clock_t, raw_on_clock, on_clock)
AUTH_TYPED_HANDLER(tandem_rover_truth_t, raw_on_truth, on_truth)
AUTH_TYPED_HANDLER(tandem_rover_state_t, raw_on_state, on_state)
AUTH_TYPED_HANDLER(tandem_rovers_state_t, raw_on_states, on_states)

void fm_subscribe(fm_run *r)
{
    fm_bus *bus = &r->bus;
    auth_bus_subscribe_queue(bus->auth, bus->lcm, "SIM_CLOCK", raw_on_clock, bus, 0);
    auth_bus_subscribe_queue(bus->auth, bus->lcm, "ROVER_TRUTH", raw_on_truth, r, 100000);
    auth_bus_subscribe_queue(bus->auth, bus->lcm, "ROVER[0-9]+_STATE", raw_on_state, bus, 100000);
    auth_bus_subscribe_queue(bus->auth, bus->lcm, "ROVERS_STATE", raw_on_states, bus, 100000);
    auth_bus_subscribe_queue(bus->auth, bus->lcm, "SIM_ACK", raw_on_ack, bus, 100000);
}

void fm_unsubscribe(fm_run *r)
{
    auth_bus_unsubscribe_user(r->bus.auth, r->bus.lcm, &r->bus);
    auth_bus_unsubscribe_user(r->bus.auth, r->bus.lcm, r);
}
