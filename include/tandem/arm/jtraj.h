/* jtraj: smooth joint-space point-to-point trajectory (quintic, rest to
 * rest) whose duration respects every joint's speed and an acceleration
 * budget, used for joint moves (home, park) by tandem-arm; and the
 * controlled stop that ends every protective stop (docs/method/carry.md
 * §7.4): each joint brought from its measured speed to rest at a constant
 * deceleration, after which a move is planned again from where the arm
 * stands (jtraj_plan).
 */
#ifndef TANDEM_JTRAJ_H
#define TANDEM_JTRAJ_H

#include "arm_model.h"

#define JTRAJ_ERR_ARG \
    (-1) /* non-finite q0/q1, speed_frac outside (0, 1]
                                 or qdd_max <= 0                          */
#define JTRAJ_ERR_STOP \
    (-2) /* jtraj_stop_plan: non-finite q0/qd0, or the
                                 deceleration not finite and > 0          */

/* The joint moves' acceleration budget: tandem-arm plans every joint move
 * with it, and its protective stop decelerates at it, so a stop asks no
 * joint for more than the move it interrupts did. */
#define JTRAJ_MOVE_QDD_RADPS2 2.0

typedef struct jtraj {
    double q0[ARM_NJ];
    double q1[ARM_NJ];
    double duration_s;
} jtraj;

/* Plans q0 -> q1 with peak speed <= speed_frac * qd_max and peak
 * acceleration <= qdd_max_radps2 on every joint. 0 ok, JTRAJ_ERR_ARG bad input. */
int jtraj_plan(jtraj *t, const arm_model *m, const double q0[ARM_NJ], const double q1[ARM_NJ],
               double speed_frac, double qdd_max_radps2);
/* Position, velocity, acceleration at time t_s (clamped to [0, duration]). */
void jtraj_at(const jtraj *t, double t_s, double q[ARM_NJ], double qd[ARM_NJ], double qdd[ARM_NJ]);

/* Controlled stop from (q0, qd0): joint i decelerates at decel_radps2
 * until it rests, at t_i = |qd0_i| / a (docs/method/carry.md §7.4):
 *   qd_i(t) = qd0_i - sgn(qd0_i) a min(t, t_i)
 *   q_i(t)  = q0_i + qd0_i min(t, t_i) - sgn(qd0_i) a min(t, t_i)^2 / 2  */
typedef struct jtraj_stop {
    double q0_rad[ARM_NJ];
    double qd0_radps[ARM_NJ];
    double decel_radps2;
    double duration_s; /* max_i t_i: every joint at rest from then on */
} jtraj_stop;

/* 0 ok; JTRAJ_ERR_STOP bad input (then s is a stop at rest at q0 if q0 is
 * finite, else zeroed). */
int jtraj_stop_plan(jtraj_stop *s, const double q0_rad[ARM_NJ], const double qd0_radps[ARM_NJ],
                    double decel_radps2);
/* Position, velocity, acceleration of the stop at t_s >= 0 after it began
 * (t_s < 0 is taken as 0). */
void jtraj_stop_at(const jtraj_stop *s, double t_s, double q[ARM_NJ], double qd[ARM_NJ],
                   double qdd[ARM_NJ]);
/* 1 if every |qd_i| < tol_radps: the arm counts as at rest this cycle. */
int jtraj_at_rest(const double qd_radps[ARM_NJ], double tol_radps);

#endif
