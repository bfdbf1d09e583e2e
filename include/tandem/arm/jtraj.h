/* jtraj: smooth joint-space point-to-point trajectory (quintic, rest to
 * rest) whose duration respects every joint's speed and an acceleration
 * budget. Used for joint moves (home, park) by tandem-arm (issue: PUMA pair).
 */
#ifndef TANDEM_JTRAJ_H
#define TANDEM_JTRAJ_H

#include "arm_model.h"

#define JTRAJ_ERR_ARG (-1)  /* non-finite q0/q1, speed_frac outside (0, 1]
                               or qdd_max <= 0                            */

typedef struct jtraj {
    double q0[ARM_NJ];
    double q1[ARM_NJ];
    double duration_s;
} jtraj;

/* Plans q0 -> q1 with peak speed <= speed_frac * qd_max and peak
 * acceleration <= qdd_max_radps2 on every joint. 0 ok, JTRAJ_ERR_ARG bad input. */
int  jtraj_plan(jtraj *t, const arm_model *m, const double q0[ARM_NJ], const double q1[ARM_NJ],
                double speed_frac, double qdd_max_radps2);
/* Position, velocity, acceleration at time t_s (clamped to [0, duration]). */
void jtraj_at(const jtraj *t, double t_s, double q[ARM_NJ], double qd[ARM_NJ], double qdd[ARM_NJ]);

#endif
