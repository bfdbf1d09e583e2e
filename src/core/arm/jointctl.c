/* jointctl: computed-torque joint control (docs/method/carry.md §3 inner loop, §7 hold):
 *   tau = M(q) (qdd_d + Kv (qd_d - qd) + Kp (q_d - q)) + C(q, qd) qd + g(q)
 * evaluated as one RNE pass with the servo acceleration, then clamped to
 * the torque limits (jointctl_clamp, shared by every controller). */
#include "jointctl.h"
#include <math.h>

static const double gravity_down[3] = { 0.0, 0.0, -9.81 };

int jointctl_saturate(const arm_model *m, double tau_Nm[ARM_NJ])
{
    int i, hit = 0;
    for (i = 0; i < ARM_NJ; i++) {
        const double lim = m->tau_max_Nm[i];
        if (tau_Nm[i] > lim) {
            tau_Nm[i] = lim;
            hit = 1;
        }
        if (tau_Nm[i] < -lim) {
            tau_Nm[i] = -lim;
            hit = 1;
        }
    }
    return hit;
}

int jointctl_torque(const arm_model *m, const arm_payload *payload, const jointctl_gains *g,
                    const double q[ARM_NJ], const double qd[ARM_NJ], const double q_d[ARM_NJ],
                    const double qd_d[ARM_NJ], const double qdd_d[ARM_NJ], double tau_Nm[ARM_NJ],
                    int *saturated)
{
    double a[ARM_NJ];
    const double kp = g->wn_radps * g->wn_radps, kv = 2.0 * g->zeta * g->wn_radps;
    int i, hit;
    if (!q_d || !qd_d || !qdd_d || !(kp >= 0.0) || !(kv >= 0.0))
        return JOINTCTL_ERR_ARG;
    for (i = 0; i < ARM_NJ; i++)
        a[i] = qdd_d[i] + kv * (qd_d[i] - qd[i]) + kp * (q_d[i] - q[i]);
    /* RNE with the servo acceleration is M a + C qd + g in one pass. It
     * checks a finite, and a is finite only if q_d, qd_d and qdd_d are
     * (inf - inf, 0 inf and NaN anything are NaN): they are checked once. */
    if (arm_rne(m, q, qd, a, gravity_down, payload, tau_Nm) != 0)
        return JOINTCTL_ERR_ARG;
    hit = jointctl_saturate(m, tau_Nm);
    if (saturated)
        *saturated = hit;
    return 0;
}
