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

void fm_ack(fm_state *fm, int64_t step)
{
    scenario_ack(run_key_bus(), fm->lcm, &fm->ack_seq, step, FM_PERIOD, 0);
}

int64_t fm_mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_clock_t *m, void *u)
{
    fm_state *fm = u;
    (void)rb;
    (void)ch;
    if (m->step < fm->clock_step)
        return;
    /* a step announced again: answered (our ack was lost), or not yet (we
     * wait for the robots' states): either way the ack of our last answered
     * step goes out, which also tells the simulator we are alive */
    if (m->step == fm->answered || m->step == fm->clock_step)
        fm->clock_repeat = 1;
    fm->clock_step = m->step;
    fm->sim_time = m->sim_time_s;
    fm->have_clock = 1;
    fm->last_clock_ns = fm_mono_ns();
    hang_watch_heard(&fm->hw, "tandem-sim", scenario_wall_s()); /* a sign of life (--hang-s) */
}

/* When the last clock seen is a step everyone answers and nothing has
 * moved for a while, the simulator is waiting there: answer that step
 * again in case our ack was lost. (The simulator itself re-announces a
 * step whose answers are missing, sim_loop.c; only it may publish
 * SIM_CLOCK, auth_acl.c.) */
void fm_nudge(fm_state *fm)
{
    const int64_t k = fm->clock_step;
    if (k % FM_PERIOD)
        return;
    fm_ack(fm, k);
}

static void take_state(fm_state *fm, const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    if (i < 0 || i >= fm->robots)
        return;
    if (fm->have_state[i] && m->mode == TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE &&
        fm->mode[i] != TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE)
        fm->escapes++;
    fm->mode[i] = m->mode;
    fm->state_type[i] = m->formation;
    if (isfinite(m->formation_scale) && m->formation_scale > 0.0)
        fm->state_scale[i] = m->formation_scale;
    memcpy(fm->weight[i], m->weight, sizeof fm->weight[i]);
    {
        const pose2 team = { m->x_m, m->y_m, m->theta_rad };
        rover_world_from_team(&fm->layout, &team, &fm->est[i]);
    }
    fm->have_state[i] = 1;
}

static void ring_put(fm_state *fm, const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    if (i < 0 || i >= fm->robots || m->step < 0)
        return;
    fm->ring[i][(m->step / FM_PERIOD) % FM_RING] = *m;
}

const tandem_rover_state_t *fm_ring_get(const fm_state *fm, int i, int64_t k)
{
    const tandem_rover_state_t *m = &fm->ring[i][(k / FM_PERIOD) % FM_RING];
    return m->step == k && m->robot == i + 1 ? m : NULL;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_state_t *m,
                     void *u)
{
    fm_state *fm = u;
    (void)rb;
    (void)ch;
    ring_put(fm, m);
}

static void on_states(const lcm_recv_buf_t *rb, const char *ch, const tandem_rovers_state_t *m,
                      void *u)
{
    int i;
    fm_state *fm = u;
    (void)rb;
    (void)ch;
    for (i = 0; i < m->n; i++)
        ring_put(fm, &m->state[i]);
}

int fm_process_down(const fm_state *fm, int id, int64_t k)
{
    return id >= 1 && id <= FM_MAX && k > fm->down_after[id] && k < fm->up_at[id];
}

int fm_states_for_truth(fm_state *fm, const tandem_rover_truth_t *m)
{
    const int64_t k = m->step - FM_PERIOD;
    int i;
    if (k < FM_PERIOD)
        return 1; /* robots start at their first period */
    for (i = 0; i < m->n; i++) {
        const int r = m->robot[i] - 1;
        if (m->alive[i] && r >= 0 && r < fm->robots && !(fm->killed && r + 1 == fm->kill_id) &&
            !fm_process_down(fm, r + 1, k) && !fm_ring_get(fm, r, k))
            return 0;
    }
    for (i = 0; i < fm->robots; i++) {
        const tandem_rover_state_t *st = fm_ring_get(fm, i, k);
        if (st)
            take_state(fm, st);
    }
    return 1;
}

/* SIM_ACK: the last step each rover process answered (--fault). */
static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const tandem_clock_ack_t *m, void *u)
{
    char *e;
    long k;
    fm_state *fm = u;
    (void)rb;
    (void)ch;
    if (!m->leaving)
        hang_watch_heard(&fm->hw, m->name, scenario_wall_s()); /* a sign of life (--hang-s) */
    if (m->leaving || strncmp(m->name, "tandem-rover-", 13) != 0)
        return;
    k = strtol(m->name + 13, &e, 10);
    if (*e || k < 1 || k > FM_MAX)
        return;
    if (m->step > fm->rover_ack[k])
        fm->rover_ack[k] = m->step;
}

AUTH_TYPED_HANDLER(tandem_clock_ack_t, raw_on_ack, on_ack)
AUTH_TYPED_HANDLER(tandem_sim_clock_t, raw_on_clock, on_clock)
AUTH_TYPED_HANDLER(tandem_rover_truth_t, raw_on_truth, fm_on_truth)
AUTH_TYPED_HANDLER(tandem_rover_state_t, raw_on_state, on_state)
AUTH_TYPED_HANDLER(tandem_rovers_state_t, raw_on_states, on_states)

void fm_subscribe(fm_state *fm)
{
    auth_bus_subscribe_queue(run_key_bus(), fm->lcm, "SIM_CLOCK", raw_on_clock, fm, 0);
    auth_bus_subscribe_queue(run_key_bus(), fm->lcm, "ROVER_TRUTH", raw_on_truth, fm, 100000);
    auth_bus_subscribe_queue(run_key_bus(), fm->lcm, "ROVER[0-9]+_STATE", raw_on_state, fm, 100000);
    auth_bus_subscribe_queue(run_key_bus(), fm->lcm, "ROVERS_STATE", raw_on_states, fm, 100000);
    auth_bus_subscribe_queue(run_key_bus(), fm->lcm, "SIM_ACK", raw_on_ack, fm, 100000);
}

void fm_unsubscribe(fm_state *fm)
{
    auth_bus_unsubscribe_user(run_key_bus(), fm->lcm, fm);
}
