/* carry_blocks: the stick of a carry run (docs/method/carry.md §8). A block
 * ARM:LINK:START_S:DURATION_S[:t3] is armed at START_S and inserted at the
 * first step after it at which that arm's tool moves (> 3 cm/s; in t3
 * > 10 cm/s) -- and, with ":t3", while the synchronised t3 runs -- so every
 * block meets a moving link; it is removed DURATION_S later. Blocks run one
 * after the other (one stick).
 *
 * While the stick is in: the contact force (from 0.1 s after contact, and
 * once settled), and in t3 the stops: the blocked arm's stop is the first
 * step after contact at which its s gained less than 0.1 mm over 10 ms; the
 * partner's stop the same test on its s; latency = partner stop - blocked
 * stop; lead = the partner's s minus its reference k_p s*.
 *
 * After removal: the arm that counts is the one the stick stopped, that is
 * touched or that reported BLOCKED while it was in (the arm it was pushed
 * into; if that one was not stopped, the other arm, whose way the stick
 * can stand in too; if neither, the stick stopped nothing and there is
 * nothing to resume: an arm it never stopped, waiting on its partner, is
 * the task's wait, not the stick's). When the stick comes out
 * while that arm runs a row
 * (its last event is not DONE), the arm has resumed at the first step at
 * which its tool is 5 mm from where it was at removal, or it reports
 * UNBLOCKED or DONE; resume_latency = that step - removal (or, when the
 * arm's daemon was killed by --fault and is down at the removal, - its
 * restart: it cannot resume before, and that wait is the kill's). The tool's
 * largest speed within LURCH_WINDOW_S of removal is the lurch.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "carry_scen.h"
#include "prng.h"
#include "tandem_action_event_t.h"
#include "tandem_sim_control_t.h"

#define MOVING_MPS 0.03    /* a block waits for its arm to move this fast ... */
#define MOVING_T3_MPS 0.10 /* ... or, in t3, this fast (cruise) */
#define CONTACT_N 0.5
#define LURCH_WINDOW_S 2.0
#define STOP_MPS 0.01
#define BLOCK_SETTLED_S 0.5 /* contact force "settled": this long after contact */
#define RESUME_MOVE_M 0.005 /* resumed: the tool is this far from where it was at removal */

int carry_block_parse(const char *s, block *b)
{
    char t3[8] = "";
    int n;
    memset(b, 0, sizeof *b);
    n = sscanf(s, "%d:%d:%lf:%lf:%7s", &b->arm, &b->link, &b->start_s, &b->dur_s, t3);
    if (n < 4 || b->arm < 1 || b->arm > 2 || b->link < 1 || b->link > 6 || !isfinite(b->start_s) ||
        b->start_s < 0.0 || !isfinite(b->dur_s) || b->dur_s <= 0.0 || b->dur_s > 3600.0 ||
        (n == 5 && strcmp(t3, "t3") != 0))
        return CARRY_SCEN_ERR_BLOCK;
    b->need_t3 = n == 5;
    return 0;
}

void carry_random_blocks(carry_blocks *bl, int k, uint64_t seed)
{
    prng_state r;
    double t = 5.0;
    int i;
    prng_seed(&r, seed * 104729u + 3u);
    for (i = 0; i < k && bl->n < MAX_BLOCKS; i++) {
        block *b = &bl->b[bl->n++];
        memset(b, 0, sizeof *b);
        b->arm = 1 + (int)(prng_uniform(&r) * 2.0);
        b->link = 2 + (int)(prng_uniform(&r) * 4.0);
        b->dur_s = 0.2 + 59.8 * prng_uniform(&r);
        b->need_t3 = i % 3 == 2;
        b->start_s = t;
        t += 2.0 + 10.0 * prng_uniform(&r);
    }
}

int carry_stick_in(const carry_blocks *bl)
{
    return bl->cur < bl->n && bl->b[bl->cur].in_s >= 0.0 && bl->b[bl->cur].out_s < 0.0;
}

/* The block armed: insert the stick once its arm moves (in t3 if asked);
 * skipped if that never happens within 300 s. */
static void block_arm(carry_state *r, carry_blocks *bl, block *b)
{
    const int a = b->arm - 1;
    if (r->t_s >= b->start_s && r->speed[a] > (b->need_t3 ? MOVING_T3_MPS : MOVING_MPS) &&
        (!b->need_t3 || carry_t3_running(r))) {
        carry_stick_command(r, TANDEM_SIM_CONTROL_T_INSERT_STICK, b->arm, b->link);
        b->in_s = r->t_s;
        b->during_t3 = carry_t3_running(r);
    } else if (r->t_s > b->start_s + 300.0) {
        b->done = 1; /* never met a moving arm: skipped */
        bl->cur++;
    }
}

/* In t3 after contact: the blocked arm's and the partner's stops and the
 * partner's lead over its reference. */
static void block_t3_stops(const carry_state *r, block *b)
{
    const int a = b->arm - 1, p = 1 - a;
    /* partner stop: its s advances by less than STOP_MPS * 10 ms
     * over the last 10 steps; lead over its reference k_p s* */
    const double l_max = fmax(r->s_f[0], r->s_f[1]);
    const double kb = r->s_f[a] / l_max, kp = r->s_f[p] / l_max;
    const double lead = r->s[p] - kp * (r->s[a] / kb);
    const double ds = r->s[p] - r->s_hist[p][(r->pending + 6) & 15];
    const double ds_self = r->s[a] - r->s_hist[a][(r->pending + 6) & 15];
    if (lead > b->lead_max_m)
        b->lead_max_m = lead;
    if (b->self_stop_s < 0.0 && ds_self < STOP_MPS * 0.010)
        b->self_stop_s = r->t_s;
    if (b->self_stop_s >= 0.0 && b->partner_stop_s < 0.0 && ds < STOP_MPS * 0.010)
        b->partner_stop_s = r->t_s;
}

/* The stick in: contact force, the t3 stops; out after the duration. */
static void block_in(carry_state *r, block *b)
{
    const int a = b->arm - 1;
    const double f = r->arm[a].max_contact_force_N;
    int k;
    for (k = 0; k < 2; k++)
        if (r->arm[k].max_contact_force_N > CONTACT_N ||
            r->last_event[k] == TANDEM_ACTION_EVENT_T_BLOCKED)
            b->stopped[k] = 1;
    if (f > b->max_force_N)
        b->max_force_N = f;
    if (f > CONTACT_N && b->contact_s < 0.0)
        b->contact_s = r->t_s;
    if (b->contact_s >= 0.0 && r->t_s - b->contact_s > 0.1 && f > 0.0) {
        b->force_sum_N += f;
        b->force_n++;
    }
    /* after the arm's blocked detector (0.3 s still) has switched the
     * law to leaning with the bias only */
    if (b->contact_s >= 0.0 && r->t_s - b->contact_s > BLOCK_SETTLED_S && f > 0.0) {
        b->force_late_sum_N += f;
        b->force_late_n++;
    }
    if (b->during_t3 && b->contact_s >= 0.0 && r->tr[0] == 3 && r->tr[1] == 3 && r->s_f[0] > 0.0 &&
        r->s_f[1] > 0.0)
        block_t3_stops(r, b);
    if (r->t_s >= b->in_s + b->dur_s) {
        const int o = b->stopped[a] || !b->stopped[1 - a] ? a : 1 - a;
        carry_stick_command(r, TANDEM_SIM_CONTROL_T_REMOVE_STICK, 0, 0);
        b->out_s = r->t_s;
        b->out_arm = o;
        memcpy(b->out_pos_m, r->arm[o].tool_position_m, sizeof b->out_pos_m);
        b->row_running_at_out = r->last_event[o] != TANDEM_ACTION_EVENT_T_DONE;
        b->resume_s = b->row_running_at_out && b->stopped[o] ? -1.0 : b->out_s;
        b->resume_from_s = b->out_s;
    }
}

/* The stick out: resume and lurch; the block is done once both are known,
 * and the next one starts no earlier than gap_after_s later. */
static void block_out(carry_state *r, carry_blocks *bl, block *b)
{
    const int a = b->out_arm;
    if (b->resume_s < 0.0 && r->arm_down[a]) {
        /* the arm's daemon is down (--fault): it cannot resume before it is
         * restarted, and the time it was down is the kill's, not the stick's */
        b->resume_from_s = r->t_s;
        memcpy(b->out_pos_m, r->arm[a].tool_position_m, sizeof b->out_pos_m);
        return;
    }
    if (b->resume_s < 0.0) {
        const int64_t out_step = (int64_t)(b->resume_from_s * 1000.0 + 0.5);
        double d[3];
        int i;
        for (i = 0; i < 3; i++)
            d[i] = r->arm[a].tool_position_m[i] - b->out_pos_m[i];
        if (sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) >= RESUME_MOVE_M ||
            r->unblocked_step[a] >= out_step || r->done_step[a] >= out_step)
            b->resume_s = r->t_s;
    }
    if (r->t_s <= b->out_s + LURCH_WINDOW_S || b->resume_s < 0.0) {
        if (r->speed[a] > b->lurch_mps && r->t_s <= b->out_s + LURCH_WINDOW_S)
            b->lurch_mps = r->speed[a];
        return;
    }
    b->done = 1;
    bl->cur++;
    if (bl->cur < bl->n && bl->b[bl->cur].start_s < r->t_s)
        bl->b[bl->cur].start_s = r->t_s + bl->gap_after_s;
}

void carry_block_step(carry_state *r, carry_blocks *bl)
{
    block *b;
    if (bl->cur >= bl->n)
        return;
    b = &bl->b[bl->cur];
    if (b->in_s < 0.0)
        block_arm(r, bl, b);
    else if (b->out_s < 0.0)
        block_in(r, b);
    else
        block_out(r, bl, b);
}
