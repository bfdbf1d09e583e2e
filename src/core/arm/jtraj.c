/* jtraj: quintic rest-to-rest joint trajectory for tandem-arm's joint moves
 * (home, park; no equation of docs/method/: the standard quintic blend),
 * s(tau) = 10 tau^3 - 15 tau^4 + 6 tau^5. Peak of ds/dtau is 15/8 and of
 * d2s/dtau2 is 10/sqrt(3), which gives the shortest duration meeting the
 * speed and acceleration bounds.
 *
 * The controlled stop of a protective stop (docs/method/carry.md §7.4):
 * constant deceleration per joint from the measured speed to rest, in
 * closed form so that the reference is the same whatever the cycle's
 * period (a reference integrated cycle by cycle drifts with late cycles).
 */
#include "jtraj.h"
#include <math.h>

#define QUINTIC_PEAK_VEL 1.875
#define QUINTIC_PEAK_ACC 5.773502691896258

int jtraj_plan(jtraj *t, const arm_model *m, const double q0[ARM_NJ], const double q1[ARM_NJ],
               double speed_frac, double qdd_max_radps2)
{
    int i;
    double T = 0.0;
    if (arm_q_finite(q0) != 0 || arm_q_finite(q1) != 0 ||
        !(speed_frac > 0.0 && speed_frac <= 1.0) || !(qdd_max_radps2 > 0.0) ||
        !isfinite(qdd_max_radps2))
        return JTRAJ_ERR_ARG;
    for (i = 0; i < ARM_NJ; i++) {
        const double dq = fabs(q1[i] - q0[i]);
        const double t_vel = QUINTIC_PEAK_VEL * dq / (speed_frac * m->qd_max_radps[i]);
        const double t_acc = sqrt(QUINTIC_PEAK_ACC * dq / qdd_max_radps2);
        if (t_vel > T)
            T = t_vel;
        if (t_acc > T)
            T = t_acc;
        t->q0[i] = q0[i];
        t->q1[i] = q1[i];
    }
    t->duration_s = T;
    return 0;
}

void jtraj_at(const jtraj *t, double t_s, double q[ARM_NJ], double qd[ARM_NJ], double qdd[ARM_NJ])
{
    double tau, s, ds, dds;
    int i;
    if (t->duration_s <= 0.0) {
        tau = 1.0;
    } else {
        tau = t_s / t->duration_s;
        tau = tau < 0.0 ? 0.0 : (tau > 1.0 ? 1.0 : tau);
    }
    s = tau * tau * tau * (10.0 - 15.0 * tau + 6.0 * tau * tau);
    if (t->duration_s > 0.0 && tau > 0.0 && tau < 1.0) {
        /* one division, not three: a divide is 38 clocks on the 68040 */
        const double inv_T = 1.0 / t->duration_s;
        ds = 30.0 * tau * tau * (1.0 - tau) * (1.0 - tau) * inv_T;
        dds = 60.0 * tau * (1.0 - tau) * (1.0 - 2.0 * tau) * (inv_T * inv_T);
    } else {
        ds = 0.0;
        dds = 0.0;
    }
    for (i = 0; i < ARM_NJ; i++) {
        const double dq = t->q1[i] - t->q0[i];
        q[i] = t->q0[i] + s * dq;
        qd[i] = ds * dq;
        qdd[i] = dds * dq;
    }
}

int jtraj_stop_plan(jtraj_stop *s, const double q0_rad[ARM_NJ], const double qd0_radps[ARM_NJ],
                    double decel_radps2)
{
    int i;
    const int q_ok = arm_q_finite(q0_rad) == 0;
    for (i = 0; i < ARM_NJ; i++) {
        s->q0_rad[i] = q_ok ? q0_rad[i] : 0.0;
        s->qd0_radps[i] = 0.0;
    }
    s->decel_radps2 = 1.0;
    s->duration_s = 0.0;
    if (!q_ok || arm_q_finite(qd0_radps) != 0 || !(decel_radps2 > 0.0) || !isfinite(decel_radps2))
        return JTRAJ_ERR_STOP;
    s->decel_radps2 = decel_radps2;
    for (i = 0; i < ARM_NJ; i++) {
        const double t_i = fabs(qd0_radps[i]) / decel_radps2;
        s->qd0_radps[i] = qd0_radps[i];
        if (t_i > s->duration_s)
            s->duration_s = t_i;
    }
    return 0;
}

void jtraj_stop_at(const jtraj_stop *s, double t_s, double q[ARM_NJ], double qd[ARM_NJ],
                   double qdd[ARM_NJ])
{
    const double t = t_s > 0.0 ? t_s : 0.0;
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        const double v = s->qd0_radps[i];
        const double a = v > 0.0 ? -s->decel_radps2 : (v < 0.0 ? s->decel_radps2 : 0.0);
        const double t_i = fabs(v) / s->decel_radps2;
        const double tt = t < t_i ? t : t_i;
        q[i] = s->q0_rad[i] + v * tt + 0.5 * a * tt * tt;
        qd[i] = t < t_i ? v + a * tt : 0.0;
        qdd[i] = t < t_i ? a : 0.0;
    }
}

int jtraj_at_rest(const double qd_radps[ARM_NJ], double tol_radps)
{
    int i;
    for (i = 0; i < ARM_NJ; i++)
        if (!(fabs(qd_radps[i]) < tol_radps))
            return 0;
    return 1;
}
