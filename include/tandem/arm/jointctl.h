/* jointctl: joint-space computed-torque control with gravity compensation
 * (the arm's inner loop and its safe hold, docs/method/carry.md §3, §7):
 *   tau = M(q) (qdd_d + Kv (qd_d - qd) + Kp (q_d - q)) + C(q, qd) qd + g(q)
 * saturated to the motor torque limits. Gains are natural frequency and
 * damping ratio, the same for every joint (M decouples the joints).
 */
#ifndef TANDEM_JOINTCTL_H
#define TANDEM_JOINTCTL_H

#include "arm_dyn.h"
#include "arm_model.h"

#define JOINTCTL_ERR_ARG \
    (-1) /* non-finite reference, negative gains, or
                                  the inverse dynamics refused the state  */

typedef struct jointctl_gains {
    double wn_radps; /* closed-loop natural frequency */
    double zeta;     /* damping ratio */
} jointctl_gains;

/* Torque for the reference (q_d, qd_d, qdd_d). 0 ok, JOINTCTL_ERR_ARG bad input.
 * saturated (may be NULL) is set to 1 if any joint hit its torque limit. */
int jointctl_torque(const arm_model *m, const arm_payload *payload, const jointctl_gains *g,
                    const double q[ARM_NJ], const double qd[ARM_NJ], const double q_d[ARM_NJ],
                    const double qd_d[ARM_NJ], const double qdd_d[ARM_NJ], double tau_Nm[ARM_NJ],
                    int *saturated);

/* Torque limit clamp shared by every controller. Returns 1 if any clamped. */
int jointctl_saturate(const arm_model *m, double tau_Nm[ARM_NJ]);

#endif
