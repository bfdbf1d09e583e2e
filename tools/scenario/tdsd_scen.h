/* tdsd_scen: command line, plant selection, CSV, summary.json and plots
 * shared by `tandem-scenario singularity` and `tandem-scenario liquid`
 * (docs/method/tdsd.md §8 S1/S2, §6). The scenario files only choose the arm, the
 * path, the start pose and the method.
 */
#ifndef TANDEM_TDSD_SCEN_H
#define TANDEM_TDSD_SCEN_H

#include <stdio.h>
#include "scenario.h"
#include "tdsd_run.h"

typedef struct tdsd_scen {
    const char *name;   /* "singularity" | "liquid" */
    const char *method; /* the --method name */
    int method_index;   /* index into the scenario's method list */
    int plant_ode;
    const char *out;
    int out_given;   /* --out seen */
    double servo_hz; /* --plant ode: tandem-arm --wn */
    tdsdrun_cfg cfg;
    tdsdrun_path path;
    double q0_rad[ARM_NJ];
    tdsdrun_metrics m;
    double duration_s; /* path duration (time scaling included) */
    double wall_s;
} tdsd_scen;

/* What a TDSD scenario tells its --help: synopsis and description, its
 * methods (NULL-terminated, the first is the default) and what they are,
 * and what it writes. */
typedef struct tdsd_scen_usage {
    const char *usage;
    const char *const *methods;
    const char *method_help;
    const char *epilog;
} tdsd_scen_usage;

/* Failures of a TDSD scenario's steps (0 = ok; each said on stderr). */
#define TDSD_SCEN_ERR_ARG (-1) /* bad usage */
#define TDSD_SCEN_ERR_IO (-2)  /* DIR or a file in it not made */
#define TDSD_SCEN_ERR_RUN (-3) /* the plant did not run (--plant ode: the children) */

/* Parses --method M --plant kin|ode --out DIR [--servo-hz HZ] into s and
 * creates DIR. Returns 0 ok, 1 if --help was printed, TDSD_SCEN_ERR_ARG
 * or TDSD_SCEN_ERR_IO. */
int tdsd_scen_args(tdsd_scen *s, int argc, char **argv, const tdsd_scen_usage *u);
/* Runs the chosen plant from s->q0_rad, writing DIR/series.csv. 0 ok,
 * TDSD_SCEN_ERR_IO or TDSD_SCEN_ERR_RUN. */
int tdsd_scen_run(tdsd_scen *s);
/* The keys both scenarios report (summary.json is left open for more). */
/* Success criteria of a TDSD scenario run: tool position error within
 * TDSD_POS_TOL_* (kinematic plant: 0.1 mm; ODE plant: 2 mm), no joint
 * past its range, no joint faster than its limit, and for the liquid the
 * tool axis within 1 deg of vertical. Appends the failed ones to buf;
 * returns how many failed. */
#define TDSD_POS_TOL_KIN_M 0.0001
#define TDSD_POS_TOL_ODE_M 0.002
#define TDSD_TILT_TOL_RAD 0.017453292519943295
/* --plant ode plans joint speeds up to this share of qd_max */
#define TDSD_ODE_SPEED_FRAC 0.9
int tdsd_scen_criteria(const tdsd_scen *s, char *buf, size_t cap);
/* Adds exit_reason and failed_criteria, closes the summary; returns the
 * number of failed criteria. */
int tdsd_scen_finish(const tdsd_scen *s, json_out *j);
/* Prints the verdict line; exit status 0 (all met) or 3. */
int tdsd_scen_exit(const tdsd_scen *s);
void tdsd_scen_summary(const tdsd_scen *s, json_out *j);
/* DIR/plots.gp -> fig4_errors.png, fig5_joints.png, fig6_q1.png,
 * fig8_joint_ranges.png. 0 ok, TDSD_SCEN_ERR_IO, or SCENARIO_ERR_IO (gnuplot). */
int tdsd_scen_plots(const tdsd_scen *s, const char *title);
#endif
