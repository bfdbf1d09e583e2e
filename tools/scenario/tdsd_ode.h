/* tdsd_ode: the --plant ode of the TDSD scenarios. Starts tandem-sim and
 * tandem-arm (arm 1) in lockstep on a private LCM URL, joins the lockstep
 * as "tandem-scenario", resolves TDSD (tdsdrun_step) from the measured
 * ARM1_STATE every step and publishes ARM1_JOINT_REF, which tandem-arm
 * tracks with its computed-torque joint controller.
 */
#ifndef TANDEM_TDSD_ODE_H
#define TANDEM_TDSD_ODE_H

#include "tdsd_run.h"

typedef struct tdsd_ode_opts {
    const char *out_dir; /* child logs go here (ode_*.log) */
    double servo_hz;     /* tandem-arm --wn */
    double settle_s;     /* hold q0 this long before the path starts */
    double t_max_s;      /* controller-time cap */
} tdsd_ode_opts;

/* Same contract as tdsdrun_kin (metrics from the measured q and qd; samples
 * timed from the path start). Returns the path duration, or
 * TDSD_ODE_ERR_RUN (negative) if the simulation could not be run. */
#define TDSD_ODE_ERR_RUN \
    (-1) /* no LCM, the children did not start or died,
                                  or the wall-time limit (said on stderr) */
double tdsd_ode_run(const tdsdrun_cfg *c, const tdsdrun_path *p, const double q0_rad[ARM_NJ],
                    const tdsd_ode_opts *o, tdsdrun_metrics *m, tdsdrun_sample_fn on_sample,
                    void *user);

#endif
