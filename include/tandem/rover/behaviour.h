/* behaviour: the four seed-003 behaviours and their blending (docs/method/
 * formation.md; seed eqs. 2, 5-11 with the corrections of docs/method/formation.md).
 *
 * Poses passed in are poses of the tracked point O (the beacon, the robot's
 * origin) with the robot heading; O lies at the signed distance d behind
 * the axle centre C (d < 0: ahead of it; unicycle.h). Every law below holds
 * for either sign; the seed's formation law is stable in forward motion
 * only with O ahead (d < 0, docs/formation.md), which is the default.
 * Index order of the behaviours (and of every weight array) follows the
 * rover_state_t message: BEH_GOAL, BEH_FORMATION, BEH_AVOID, BEH_EXCEPTION
 * (the seed numbers them W2, W3, W4, W1).
 *
 * Sonar ring (8 front transducers, table order -90 -50 -30 -10 10 30 50 90
 * deg, CCW positive, so index 0 is right and 7 is left) grouped as
 *   right = {0}, right-front = {1, 2}, front = {3, 4},
 *   left-front = {5, 6}, left = {7}; a group reads the minimum of its members.
 */
#ifndef TANDEM_BEHAVIOUR_H
#define TANDEM_BEHAVIOUR_H

#include "unicycle.h"
#include "vec2.h"

#define BEHAVIOUR_ERR_ARG \
    (-1) /* NULL, non-finite input, bad mode or a
                                   parameter out of range; also the pose too
                                   near eq. 5's singularity (r cos phi = d)
                                   and weights that do not sum above 0     */

enum { BEH_GOAL = 0, BEH_FORMATION = 1, BEH_AVOID = 2, BEH_EXCEPTION = 3, BEH_COUNT = 4 };

enum {
    BEH_BLEND_WEIGHTED = 0,    /* seed eq. 11 */
    BEH_BLEND_SUBSUMPTION = 1, /* Brooks: one behaviour wins by priority */
    BEH_BLEND_VECSUM = 2       /* Arkin: equal-weight vector sum */
};

#define BEH_SONAR_N 8

typedef struct {
    double d_m;       /* O behind C, signed (< 0: ahead); |d| > 0 */
    double v_max_mps; /* eq. 6 (goal) and avoid/exception limits */
    double w_max_radps;
    double v_fm_max_mps; /* eq. 10 (formation) */
    double w_fm_max_radps;
    int sat_mode;              /* UNICYCLE_SAT_*; default CLIP (the seed) */
    double a1, a2;             /* move-to-goal closed loop r' = -a1 r, phi' = -a2 phi */
    double goal_tol_m;         /* r below this: at goal, stop */
    double goal_margin_m;      /* keep r cos phi - d above this (eq. 5 singular at 0) */
    double b1, b2;             /* keep-formation l' = b1 (l_d - l), phi' = b2 (phi_d - phi) */
    double d_s_m;              /* single-robot safety distance */
    double k_v;                /* avoid: V = k S_F (1/s) */
    double k_s;                /* avoid: w = k_s (S_LF - S_RF) (rad/s per m) */
    int d_st_lateral;          /* 0: the seed's d_st (l_d cos phi_d); 1: lateral |l_d sin phi_d| */
    double d_st_rear_max_m;    /* a slot's distance behind R0 counts in d_st up to this */
    double v_k_mps, w_k_radps; /* dead-zone escape, eq. 2 */
    double dead_zone_time_s;   /* dead-zone condition must hold this long */
    double passage_safety_m;   /* narrow passage: L + R + width < D + this */
    double robot_width_m;
    double k2, k3, k4;              /* eq. 11 weights */
    double d_r_m;                   /* allowed deviation from the slot */
    double form_near_m, form_far_m; /* slot distance band over which slot tracking
                                     * hands over from pose tracking to pursuit
                                     * (behaviour_slot_track) */
} behaviour_params;

/* Defaults (Pioneer 2 DX-like):
 *   d -0.15 m (O ahead of C); V_max 0.5 m/s, w_max 1.0 rad/s (both eq. 6 and eq. 10);
 *   a1 0.4, a2 1.0; goal_tol 0.3 m, goal_margin 0.05 m; b1 0.5, b2 1.0;
 *   d_s 0.6 m; k_v 0.3 1/s, k_s 0.8; d_st_rear_max 1.0 m (one spacing);
 *   V_k 0.0 m/s, w_k 0.6 rad/s, 2 s;
 *   passage safety 0.3 m, width 0.38 m; k2 1, k3 1, k4 1, d_r 0.3 m;
 *   form_near 0.3 m, form_far 0.8 m. */
void behaviour_params_default(behaviour_params *p);
/* 0 if every parameter is finite and in range, else BEHAVIOUR_ERR_ARG. */
int behaviour_params_validate(const behaviour_params *p);

typedef struct {
    double front_m, left_front_m, right_front_m, left_m, right_m;
    double min_m; /* minimum over all eight */
} sonar_groups;

/* Group the eight ranges (non-finite or negative ranges read as 0, i.e.
 * "obstacle here", the safe reading). */
void behaviour_sonar_groups(sonar_groups *g, const double range_m[BEH_SONAR_N]);

/* ---- move to goal (eq. 5 corrected, eq. 6) ---------------------------- */
enum { BEH_GOAL_DRIVE = 0, BEH_GOAL_TURN = 1, BEH_GOAL_REACHED = 2 };
/* r = |G - O|, phi = bearing of G from O minus heading. */
void behaviour_goal_polar(double *r_m, double *phi_rad, const pose2 *o, const double goal_m[2]);
/* Unsaturated eq. 5: requires r cos phi - d != 0 (returns BEHAVIOUR_ERR_ARG if too near). */
int behaviour_goal_raw(unicycle_cmd *u, double r_m, double phi_rad, double d_m, double a1,
                       double a2);
/* Saturated move-to-goal. Returns BEH_GOAL_DRIVE (eq. 5 + 6),
 * BEH_GOAL_TURN (r cos phi - d <= margin but r > goal_tol: turn in place
 * toward the goal, V = 0, w = sat(a2 phi)), BEH_GOAL_REACHED (r <= goal_tol:
 * U = 0), or BEHAVIOUR_ERR_ARG on bad input (U = 0). */
int behaviour_goal(unicycle_cmd *u, const pose2 *o, const double goal_m[2],
                   const behaviour_params *p);
/* The turn on the spot toward a target at bearing phi (the BEH_GOAL_TURN
 * branch): V = 0, w = sat(a2 phi). */
void behaviour_goal_face(unicycle_cmd *u, double phi_rad, const behaviour_params *p);

/* ---- keep formation (docs/method/formation.md §3: A, B, gamma; eq. 10) ------------------------ */
/* (l, phi) of O_i relative to O_0 in R0's frame. */
void behaviour_formation_polar(double *l_m, double *phi_rad, const pose2 *o,
                               const unicycle_state *ref);
/* Distance from the ideal slot, R_d = sqrt(l^2 + l_d^2 - 2 l l_d cos(phi - phi_d)). */
double behaviour_slot_error(double l_m, double phi_rad, double l_d_m, double phi_d_rad);
/* Unsaturated V_i, w_i. */
void behaviour_formation_raw(unicycle_cmd *u, double l_m, double phi_rad, double gamma_rad,
                             double l_d_m, double phi_d_rad, double v0_mps, double w0_radps,
                             double d_m, double b1, double b2);
/* Saturated keep-formation; R_d_m (may be NULL) receives the slot error.
 * BEHAVIOUR_ERR_ARG on bad input (U = 0). */
int behaviour_formation(unicycle_cmd *u, double *R_d_m, const pose2 *o, const unicycle_state *ref,
                        double l_d_m, double phi_d_rad, const behaviour_params *p);

/* The seed's law as flown (ROVER_LAW_SEED): behaviour_formation with V
 * floored at 0 (the Pioneer has no rear sonar; a robot ahead of its slot
 * slows down and waits). With O ahead of the axle (d < 0) the law's
 * heading dynamics are stable in forward motion, theta_i' =
 * -(V0 / |d|) sin(theta_i - theta0) on the slot; with O behind (d > 0)
 * they are the mirror image and unstable (docs/formation.md). R_d_m as in
 * behaviour_formation. BEHAVIOUR_ERR_ARG on bad input (U = 0). */
int behaviour_formation_seed(unicycle_cmd *u, double *R_d_m, const pose2 *o,
                             const unicycle_state *ref, double l_d_m, double phi_d_rad,
                             const behaviour_params *p);

/* Slot tracking (the comparison law, ROVER_LAW_KANAYAMA). With O behind
 * the axle the seed law swings the tail to move O sideways and, with
 * V >= 0, its internal heading dynamics are unstable (theta' ~
 * (V / d) sin theta: a time constant of d / V ~ 0.3 s); this law steers
 * the NOSE whatever the sign of d: Kanayama pose tracking of the slot pose (slot position,
 * team heading; V = V0 cos e_th + b1 e_x, w = w0 + V0 (4 e_y + 2 sin e_th),
 * V0 floored at 0.1 m/s for steering), handing over linearly between
 * form_near_m and form_far_m from the slot to pursuit of the slot point
 * when the slot is ahead (V = (V0 + b1 dist) cos(bearing),
 * w = w0 + b2 bearing). V is never negative: a robot ahead of its slot
 * waits for it. Saturated as eq. 10. BEHAVIOUR_ERR_ARG on bad input (U = 0). */
int behaviour_slot_track(unicycle_cmd *u, const pose2 *o, const unicycle_state *ref, double l_d_m,
                         double phi_d_rad, const behaviour_params *p);
/* behaviour_slot_track, with R_d_m (may be NULL) the seed law's slot error
 * (used by the eq. 11 weight). */
int behaviour_formation_track(unicycle_cmd *u, double *R_d_m, const pose2 *o,
                              const unicycle_state *ref, double l_d_m, double phi_d_rad,
                              const behaviour_params *p);

/* ---- avoid obstacles -------------------------------------------------- */
/* d_st = d_s + (D/2 - l_d cos phi_d), never below d_s. */
double behaviour_d_st(const behaviour_params *p, double width_D_m, double l_d_m, double phi_d_rad);
/* If min(F, LF, RF) > d_st: (v_now, 0), returns 0. Else V = k S_F,
 * w = k_s (S_LF - S_RF) limited to +-w_max (the seed writes min(., w_max),
 * we clamp both signs), V limited to V_max; returns 1. */
int behaviour_avoid(unicycle_cmd *u, const sonar_groups *g, double v_now_mps, double d_st_m,
                    const behaviour_params *p);

/* ---- exceptions (eq. 2) ------------------------------------------------ */
typedef struct {
    double blocked_s; /* time the dead-zone condition has held */
    int active;       /* escaping */
    int entries;      /* n: number of dead-zone entries so far */
} behaviour_exception;

void behaviour_exception_init(behaviour_exception *e);
/* Dead-zone detector and escape. Condition: front, left and right all < d_s.
 * Enter when it has held for dead_zone_time_s (entries++); while active,
 * U = (V_k, +w_k) on odd entries, (V_k, -w_k) on even. Leave (and clear
 * the timer) as soon as the front reads > d_s (the heading is free); when
 * not active, any direction > d_s clears the timer. Returns 1 while active
 * (announce ANNOUNCE_LEAVE), 0 otherwise, BEHAVIOUR_ERR_ARG on bad input. */
int behaviour_exception_step(behaviour_exception *e, unicycle_cmd *u, const sonar_groups *g,
                             double dt_s, const behaviour_params *p);
/* Narrow passage: left + right + robot width < formation width D + safety. */
int behaviour_passage_narrow(const sonar_groups *g, double width_D_m, const behaviour_params *p);

/* ---- blending (eq. 11) and baselines ------------------------------------ */
typedef struct {
    unicycle_cmd u[BEH_COUNT]; /* each behaviour's command */
    int exception_active;
    int avoid_active; /* obstacle within d_st (min(F,LF,RF) <= d_st) */
    double R_d_m;     /* slot error */
    double d_st_m;
    double min_range_m; /* min of all sonar ranges */
} behaviour_inputs;

typedef struct {
    unicycle_cmd u;               /* blended command */
    double weight_raw[BEH_COUNT]; /* W_i before normalisation */
    double weight[BEH_COUNT];     /* W_i / sum W (sums to 1; log these) */
    int winner;                   /* largest normalised weight (lowest index on ties) */
} behaviour_blender;

/* Weighted (eq. 11): exception -> W = (0,0,0,1); else W_goal = k2,
 * W_form = k3 R_d / d_r, W_avoid = k4 d_st / min range.
 * Subsumption: exception > avoid (if avoid_active) > formation
 * (if R_d > d_r) > goal, one-hot. Vecsum: exception alone if active, else
 * goal, formation and avoid with equal weights. Returns BEHAVIOUR_ERR_ARG on bad mode or
 * non-finite input (U = 0). */
int behaviour_blend(behaviour_blender *out, const behaviour_inputs *in, int mode,
                    const behaviour_params *p);

#endif
