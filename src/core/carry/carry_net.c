/* carry_net: the two-arm carry task of docs/method/carry.md §5 (Petri net: N-, N+, the
 * vision source with its inhibitor arc, P-invariants, gamma0) and the
 * lookup table of docs/method/carry.md §6. Gains were tuned on the erlaw point-mass
 * loop (test/unit/carry/test_carry_net.c): a 1 kHz operational-space
 * computed-torque arm behaves like X'' = u. carry_table_validate checks the
 * lookup table against itself and against the net.
 */
#include "carry_net.h"
#include <math.h>

#include <stddef.h>

#define T CARRY_N_TRANSITIONS
/*                                   t1 t2 t3 t4 t5 t6 t7 tv */
static const int8_t N_MINUS[CARRY_N_PLACES * T] = {
    /* p1 */ 1, 0, 0, 0, 0, 0, 0, 0,
    /* p2 */ 0, 0, 1, 0, 0, 0, 0, 0,
    /* p3 */ 1, 0, 0, 0, 0, 0, 0, 0,
    /* p4 */ 0, 1, 0, 0, 0, 0, 0, 0,
    /* p5 */ 0, 0, 1, 0, 0, 0, 0, 0,
    /* p6 */ 0, 0, 0, 1, 0, 0, 0, 0,
    /* p7 */ 0, 0, 0, 0, 0, 1, 0, 0,
    /* p8 */ 0, 0, 0, 0, 1, 0, 0, 0,
    /* p9 */ 0, 0, 0, 0, 0, 0, 1, 0,
};
static const int8_t N_PLUS[CARRY_N_PLACES * T] = {
    /* p1 */ 0, 0, 0, 0, 0, 0, 0, 1,
    /* p2 */ 0, 0, 0, 0, 0, 0, 1, 0,
    /* p3 */ 0, 0, 0, 0, 0, 1, 0, 0,
    /* p4 */ 1, 0, 0, 0, 0, 0, 0, 0,
    /* p5 */ 0, 1, 0, 0, 0, 0, 0, 0,
    /* p6 */ 0, 0, 1, 0, 0, 0, 0, 0,
    /* p7 */ 0, 0, 0, 1, 0, 0, 0, 0,
    /* p8 */ 0, 0, 0, 1, 0, 0, 0, 0,
    /* p9 */ 0, 0, 0, 0, 1, 0, 0, 0,
};
/* vision may add a token to p1 only while p1 is empty */
static const int8_t N_INHIBIT[CARRY_N_PLACES * T] = {
    /* p1 */ 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0,          0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
    0,          0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
};
#undef T
static const uint8_t GAMMA0[CARRY_N_PLACES] = { 1, 1, 1, 0, 0, 0, 0, 0, 0 };
static const int8_t INVARIANTS[CARRY_N_INVARIANTS * CARRY_N_PLACES] = {
    0, 0, 1, 1, 1, 1, 1, 0, 0, /* arm 1: p3+p4+p5+p6+p7 = 1 */
    0, 1, 0, 0, 0, 1, 0, 1, 1, /* arm 2: p2+p6+p8+p9 = 1    */
};

const petri_net carry_net = {
    CARRY_N_PLACES, CARRY_N_TRANSITIONS, N_MINUS,    N_PLUS, N_INHIBIT,
    GAMMA0,         CARRY_N_INVARIANTS,  INVARIANTS,
};

/* Gains: free moves at 0.25 m/s; fine moves near the workpiece slower,
 * with the bias fading over the last ~5 cm (k1/k2) instead of ~10 cm.
 * k0 = 0.2 m/s^2 starts the arm from rest well above the residual
 * acceleration error of a good computed-torque model; a synchronised
 * partner of a blocked arm leads it by at most
 * (a_m + k_v v_m + k0)/k_p (about 7 cm at cruise, k0/k_p = 2 mm at rest). */
#define FREE                                        \
    {                                               \
        0.25, 0.5, 4.0, 100.0, 20.0, 0.2, 5.0, 50.0 \
    }
#define FINE                                          \
    {                                                 \
        0.10, 0.3, 4.0, 100.0, 20.0, 0.15, 5.0, 100.0 \
    }
#define SYNC                                        \
    {                                               \
        0.20, 0.4, 4.0, 100.0, 20.0, 0.2, 5.0, 50.0 \
    }

#define MOVE(p)                        \
    {                                  \
        CARRY_SEG_MOVE, CARRY_POSE_##p \
    }
#define GRASP                            \
    {                                    \
        CARRY_SEG_GRASP, CARRY_POSE_NONE \
    }
#define RELEASE                            \
    {                                      \
        CARRY_SEG_RELEASE, CARRY_POSE_NONE \
    }
#define IDLE         \
    {                \
        0, 0,        \
        {            \
            {        \
                0, 0 \
            }        \
        }            \
    }
#define NOPOSE CARRY_POSE_NONE

const erlaw_gains carry_rot_gains = { 0.5, 1.0, 8.0, 100.0, 20.0, 0.2, 5.0, 20.0 };

const carry_row carry_table[CARRY_N_TRANSITIONS] = {
    { "t1 arm 1 home -> above workpiece",
      CARRY_ARM1,
      { CARRY_POSE_ABOVE_WORKPIECE, NOPOSE },
      { CARRY_GRIP_NONE, CARRY_GRIP_NONE },
      FREE,
      0,
      { { 1, 0, { MOVE(ABOVE_WORKPIECE) } }, IDLE } },
    { "t2 arm 1 descends, grasps, lifts",
      CARRY_ARM1,
      { CARRY_POSE_ABOVE_WORKPIECE, NOPOSE },
      { CARRY_GRIP_CLOSE, CARRY_GRIP_NONE },
      FINE,
      0,
      { { 3, 0, { MOVE(AT_WORKPIECE), GRASP, MOVE(ABOVE_WORKPIECE) } }, IDLE } },
    { "t3 both arms to the hand-over (synchronised)",
      CARRY_ARM1 | CARRY_ARM2,
      { CARRY_POSE_HANDOVER_1, CARRY_POSE_HANDOVER_2 },
      { CARRY_GRIP_NONE, CARRY_GRIP_NONE },
      SYNC,
      1,
      { { 1, 0, { MOVE(HANDOVER_1) } }, { 1, 0, { MOVE(HANDOVER_2) } } } },
    { "t4 hand-over: arm 2 grasps, then arm 1 releases",
      CARRY_ARM1 | CARRY_ARM2,
      { NOPOSE, NOPOSE },
      { CARRY_GRIP_OPEN, CARRY_GRIP_CLOSE },
      FINE,
      0,
      { { 1, 1, { RELEASE } }, { 1, 0, { GRASP } } } },
    { "t5 arm 2 to the release pose",
      CARRY_ARM2,
      { NOPOSE, CARRY_POSE_RELEASE_POSE },
      { CARRY_GRIP_NONE, CARRY_GRIP_NONE },
      FREE,
      0,
      { IDLE, { 2, 0, { MOVE(ABOVE_RELEASE), MOVE(RELEASE_POSE) } } } },
    { "t6 arm 1 back home",
      CARRY_ARM1,
      { CARRY_POSE_HOME_1, NOPOSE },
      { CARRY_GRIP_NONE, CARRY_GRIP_NONE },
      FREE,
      0,
      { { 2, 0, { MOVE(CLEAR_1), MOVE(HOME_1) } }, IDLE } },
    { "t7 arm 2 releases and goes home",
      CARRY_ARM2,
      { NOPOSE, CARRY_POSE_HOME_2 },
      { CARRY_GRIP_NONE, CARRY_GRIP_OPEN },
      FREE,
      0,
      { IDLE, { 3, 0, { RELEASE, MOVE(ABOVE_RELEASE), MOVE(HOME_2) } } } },
    { "vision locates a workpiece",
      0u,
      { NOPOSE, NOPOSE },
      { CARRY_GRIP_NONE, CARRY_GRIP_NONE },
      FREE,
      0,
      { IDLE, IDLE } },
};

static const char *const POSE_NAMES[CARRY_N_POSES] = {
    "NONE",           "HOME_1",       "ABOVE_WORKPIECE",  "AT_WORKPIECE",
    "HANDOVER_1",     "CLEAR_1",      "HOME_2",           "HANDOVER_2",
    "ABOVE_RELEASE",  "RELEASE_POSE", "ABOVE_HANDOVER_1", "ABOVE_HANDOVER_2",
    "ABOVE_MAGAZINE", "AT_MAGAZINE",  "STAND_B_1",        "ABOVE_STAND_B_1",
    "CLEAR_B_1",      "STAND_B_2",    "ABOVE_STAND_B_2",
};

/* The arm whose tool each pose of the cell is computed for (0, 1): the
 * supervisor resolves HOME_1 ... CLEAR_1, ABOVE_HANDOVER_1 and the _B_1
 * poses on arm 1's side of the bar and the rest on arm 2's, and test_cell
 * checks each inside that arm's joint ranges; the other arm is not known
 * to reach it. */
static const int8_t POSE_ARM[CARRY_N_POSES] = {
    [CARRY_POSE_NONE] = -1,
    [CARRY_POSE_HOME_1] = 0,
    [CARRY_POSE_ABOVE_WORKPIECE] = 0,
    [CARRY_POSE_AT_WORKPIECE] = 0,
    [CARRY_POSE_HANDOVER_1] = 0,
    [CARRY_POSE_CLEAR_1] = 0,
    [CARRY_POSE_HOME_2] = 1,
    [CARRY_POSE_HANDOVER_2] = 1,
    [CARRY_POSE_ABOVE_RELEASE] = 1,
    [CARRY_POSE_RELEASE_POSE] = 1,
    [CARRY_POSE_ABOVE_HANDOVER_1] = 0,
    [CARRY_POSE_ABOVE_HANDOVER_2] = 1,
    [CARRY_POSE_ABOVE_MAGAZINE] = 1,
    [CARRY_POSE_AT_MAGAZINE] = 1,
    [CARRY_POSE_STAND_B_1] = 0,
    [CARRY_POSE_ABOVE_STAND_B_1] = 0,
    [CARRY_POSE_CLEAR_B_1] = 0,
    [CARRY_POSE_STAND_B_2] = 1,
    [CARRY_POSE_ABOVE_STAND_B_2] = 1,
};

const carry_row *carry_row_of(int t)
{
    return (t >= 0 && t < CARRY_N_TRANSITIONS) ? &carry_table[t] : NULL;
}

/* Field i of a gain set, in erlaw_gains order. */
static double gain_field(const erlaw_gains *g, int i)
{
    const double v[CARRY_N_GAINS] = { g->v_m, g->a_m, g->u_m, g->k_p, g->k_v, g->k0, g->k1, g->k2 };
    return v[i];
}

int carry_gains_bounds(double lo[CARRY_N_GAINS], double hi[CARRY_N_GAINS])
{
    int t, i, n = 0;
    for (t = 0; t < CARRY_N_TRANSITIONS; t++) {
        const erlaw_gains *g = &carry_table[t].lin;
        if (erlaw_gains_validate(g) != 0)
            continue; /* the vision transition moves no arm */
        for (i = 0; i < CARRY_N_GAINS; i++) {
            const double v = gain_field(g, i);
            lo[i] = (n == 0 || v < lo[i]) ? v : lo[i];
            hi[i] = (n == 0 || v > hi[i]) ? v : hi[i];
        }
        n++;
    }
    return n > 0 ? 0 : CARRY_NET_ERR_NO_GAINS;
}

int carry_gains_within_table(const erlaw_gains *g, int allow_zero)
{
    double lo[CARRY_N_GAINS], hi[CARRY_N_GAINS];
    int i;
    if (!g || carry_gains_bounds(lo, hi) != 0)
        return 0;
    for (i = 0; i < CARRY_N_GAINS; i++) {
        const double v = gain_field(g, i);
        if (!isfinite(v) || v > hi[i] || (v < lo[i] && !(allow_zero && v == 0.0)))
            return 0;
    }
    return 1;
}

static int pose_ok(int pose)
{
    return pose >= 0 && pose < CARRY_N_POSES;
}

static int grip_ok(int grip)
{
    return grip == CARRY_GRIP_NONE || grip == CARRY_GRIP_CLOSE || grip == CARRY_GRIP_OPEN;
}

/* One segment: 0, CARRY_NET_ERR_RANGE or _INCONSISTENT (a move goes to a
 * pose, a grasp or release has none). */
static int segment_check(const carry_segment *s)
{
    if (!pose_ok(s->pose))
        return CARRY_NET_ERR_RANGE;
    switch (s->kind) {
    case CARRY_SEG_MOVE: return s->pose != CARRY_POSE_NONE ? 0 : CARRY_NET_ERR_INCONSISTENT;
    case CARRY_SEG_GRASP:
    case CARRY_SEG_RELEASE: return s->pose == CARRY_POSE_NONE ? 0 : CARRY_NET_ERR_INCONSISTENT;
    default: return CARRY_NET_ERR_RANGE;
    }
}

/* Arm a's plan in row r: its segments, and the row's claims about it (in
 * arms, target pose, net gripper action, waiting for the partner). Sets
 * *moves if the plan has a Cartesian move. */
static int plan_check(const carry_row *r, int a, int *moves)
{
    const carry_arm_plan *pl = &r->plan[a];
    const carry_arm_plan *partner = &r->plan[1 - a];
    const int in_row = (r->arms & (a == 0 ? CARRY_ARM1 : CARRY_ARM2)) != 0;
    int k, last_pose = CARRY_POSE_NONE, last_grip = CARRY_GRIP_NONE;
    if (pl->n_segments < 0 || pl->n_segments > CARRY_MAX_SEGMENTS)
        return CARRY_NET_ERR_SIZE;
    if (!pose_ok(r->target_pose[a]) || !grip_ok(r->gripper[a]) ||
        (pl->after_partner != 0 && pl->after_partner != 1))
        return CARRY_NET_ERR_RANGE;
    for (k = 0; k < pl->n_segments; k++) {
        const int rc = segment_check(&pl->seg[k]);
        if (rc != 0)
            return rc;
        if (pl->seg[k].kind == CARRY_SEG_MOVE) {
            last_pose = pl->seg[k].pose;
            *moves = 1;
        } else {
            last_grip = pl->seg[k].kind == CARRY_SEG_GRASP ? CARRY_GRIP_CLOSE : CARRY_GRIP_OPEN;
        }
    }
    if (in_row != (pl->n_segments > 0) || r->target_pose[a] != last_pose ||
        r->gripper[a] != last_grip ||
        (pl->after_partner && (partner->n_segments == 0 || partner->after_partner)))
        return CARRY_NET_ERR_INCONSISTENT;
    return 0;
}

/* Transition t has an input place (is not a source). */
static int has_input(const petri_net *net, int t)
{
    int i;
    for (i = 0; i < net->n_places; i++)
        if (net->n_minus[i * net->n_transitions + t])
            return 1;
    return 0;
}

static int row_check(const carry_row *r, const petri_net *net, int t, int health)
{
    int a, rc, moves = 0;
    if (!r->name || (r->arms & ~(CARRY_ARM1 | CARRY_ARM2)) != 0 || r->sync_group < 0)
        return CARRY_NET_ERR_RANGE;
    for (a = 0; a < 2; a++)
        if ((rc = plan_check(r, a, &moves)) != 0)
            return rc;
    if (r->sync_group > 0 && r->arms != (CARRY_ARM1 | CARRY_ARM2))
        return CARRY_NET_ERR_INCONSISTENT;
    if (moves && erlaw_gains_validate(&r->lin) != 0)
        return CARRY_NET_ERR_GAINS;
    if (health)
        return r->arms == 0 && has_input(net, t) ? 0 : CARRY_NET_ERR_NET;
    if ((r->arms != 0) != has_input(net, t))
        return CARRY_NET_ERR_NET;
    return 0;
}

int carry_table_validate(const carry_row *rows, int n_rows, const petri_net *net)
{
    return carry_table_validate_health(rows, n_rows, net, 0);
}

int carry_table_validate_health(const carry_row *rows, int n_rows, const petri_net *net,
                                uint32_t health)
{
    int t, rc;
    if (!rows || !net)
        return CARRY_NET_ERR_ARG;
    if (petri_net_validate(net) != 0)
        return CARRY_NET_ERR_NET;
    if (n_rows != net->n_transitions)
        return CARRY_NET_ERR_SIZE;
    for (t = 0; t < n_rows; t++)
        if ((rc = row_check(&rows[t], net, t, (int)(health >> t & 1u))) != 0)
            return rc;
    return 0;
}

const char *carry_pose_name(int pose)
{
    return (pose >= 0 && pose < CARRY_N_POSES) ? POSE_NAMES[pose] : "?";
}

int carry_pose_arm(int pose)
{
    return (pose >= 0 && pose < CARRY_N_POSES) ? POSE_ARM[pose] : -1;
}

int carry_pose_from_vision(int pose)
{
    return pose == CARRY_POSE_ABOVE_WORKPIECE || pose == CARRY_POSE_AT_WORKPIECE;
}
