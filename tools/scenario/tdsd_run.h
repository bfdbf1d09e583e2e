/* tdsd_run: the part of the TDSD scenarios (singularity, liquid; docs/method/
 * tdsd.md §8 S1/S2) that is pure computation: the tool path, one resolver step
 * (tdsd_step or a resolved-rate baseline) from a joint vector, the measures
 * of docs/method/lockstep.md §8, and the kinematic plant (joint rates integrated
 * at 1 kHz). The ODE plant (tdsd_ode.c) calls the same step on the measured
 * state. No I/O, no allocation: test/unit/tdsd/test_tdsd_scenario.c links it with the
 * core alone.
 */
#ifndef TANDEM_TDSD_RUN_H
#define TANDEM_TDSD_RUN_H

#include "arm_model.h"
#include "tdsd.h"

#define TDSDRUN_MAX_WP 4

typedef enum {
    TDSDRUN_TDSD = 0, /* tdsd_step: task priority + speed distribution */
    TDSDRUN_PINV = 1, /* rr_pinv_step: 6-D (or 5-D) pseudo-inverse, clipped */
    TDSDRUN_DLS = 2   /* rr_dls_step: damped least squares, clipped */
} tdsdrun_method;

/* Straight segments through the waypoints, each rest-to-rest with a quintic
 * time law over seg_s[i] nominal seconds; the tool frame R_d is constant.
 * The path parameter s is in nominal seconds, 0 .. tdsdrun_path_length_s. */
typedef struct tdsdrun_path {
    int n_wp;
    double wp_m[TDSDRUN_MAX_WP][3];
    double seg_s[TDSDRUN_MAX_WP - 1];
    double R_d[9];
} tdsdrun_path;

double tdsdrun_path_length_s(const tdsdrun_path *p);
/* p_d(s) and dp_d/ds (the feed-forward at path rate 1). */
void tdsdrun_path_eval(const tdsdrun_path *p, double s, double p_m[3], double v_mps[3]);

typedef struct tdsdrun_cfg {
    const arm_model *model;
    arm_tool tool;
    tdsdrun_method method;
    tdsd_orient_mode orient; /* FULL (S1, liquid full) or AXIS (liquid tdsd) */
    double K_p, K_o;         /* 1/s */
    unsigned criterion_mask; /* tdsd_midrange_grad joints (0 = no criterion) */
    double k_V;
    rr_dls_params dls;
    double T_recover_s; /* path rate re-accelerates 0 -> 1 in this time */
    double dt_s;        /* control period */
    double settle_s;    /* run on this long after the path's end */
    double region_m;    /* "singular region": wrist centre closer than
                                    this to the joint-1 axis (metrics only) */
    double speed_frac;  /* joint speeds planned up to this share of
                                    qd_max (0 = 1.0); the metrics use qd_max */
} tdsdrun_cfg;

typedef struct tdsdrun_state {
    double t_s;          /* controller time */
    double s;            /* path parameter (nominal seconds) */
    double lambda;       /* last path rate */
    double t_path_end_s; /* when s reached the end, -1 before */
} tdsdrun_state;

typedef struct tdsdrun_sample {
    double t_s, s, lambda, Q1, Q2;
    double p_d_m[3], p_m[3];
    double pos_err_m;
    double ori_err_rad;             /* angle of R_d R^T (full orientation error) */
    double tilt_rad;                /* angle between the tool axis a and a_d */
    double dq_radps[ARM_NJ];        /* the command (within the limits) */
    double dq_demand_radps[ARM_NJ]; /* baselines: before clipping; tdsd: = dq */
    double sigma_min_J;             /* smallest singular value of the 6x6 J */
    double wrist_axis_m;            /* wrist centre's distance from the joint-1 axis */
    int time_scaled;
    int status; /* TDSD_OK or the resolver's error */
} tdsdrun_sample;

void tdsdrun_init(tdsdrun_state *st);
/* One control step at joint vector q: resolves dq (sample->dq_radps) for the
 * path reference at st->s, then advances st->s by lambda * dt and st->t_s
 * by dt. Returns the resolver status (dq zeroed on error). */
int tdsdrun_step(const tdsdrun_cfg *c, const tdsdrun_path *p, tdsdrun_state *st,
                 const double q_rad[ARM_NJ], tdsdrun_sample *out);
/* 1 when the path is done and settle_s has passed. */
int tdsdrun_finished(const tdsdrun_cfg *c, const tdsdrun_state *st);

/* Measures (docs/method/lockstep.md §8). */
typedef struct tdsdrun_metrics {
    double region_m;
    long n;
    double max_pos_err_m, sum_sq_pos_err;
    double max_ori_err_rad, max_tilt_rad;
    double max_speed_ratio;  /* max_i,t |qd_i| / qd_max_i of the joint rates given */
    double max_demand_ratio; /* same for the unclipped demand */
    double min_Q1, t_min_Q1_s;
    double min_Q1_outside;                /* min Q1 while the wrist is outside the region */
    double t_region_in_s, t_region_out_s; /* first / last step inside, -1 if never */
    double min_wrist_axis_m;
    double t_ori_recovered_s; /* last time the orientation error was > 0.5 deg */
    double ori_err_end_rad, tilt_end_rad;
    long joint_limit_violations;   /* steps with some joint outside its range */
    double max_excess_rad[ARM_NJ]; /* how far each joint went outside its range */
    double q_lo_rad[ARM_NJ], q_hi_rad[ARM_NJ];
    double min_lambda;
    long resolver_errors;
} tdsdrun_metrics;

void tdsdrun_metrics_init(tdsdrun_metrics *m, double region_m);
/* qd: the joint rates the arm really ran (command for kin, measured for
 * ode); q: the joint vector the sample was taken at. */
void tdsdrun_metrics_add(tdsdrun_metrics *m, const arm_model *model, const tdsdrun_sample *s,
                         const double q_rad[ARM_NJ], const double qd_radps[ARM_NJ]);

typedef void (*tdsdrun_sample_fn)(void *user, const tdsdrun_sample *s, const double q_rad[ARM_NJ]);

/* Kinematic plant: q += dq dt from q0 until tdsdrun_finished or t_max_s.
 * on_sample (may be NULL) sees every step. Returns the path duration
 * (time s reached its end, or t_max_s). q0 is left unchanged. */
double tdsdrun_kin(const tdsdrun_cfg *c, const tdsdrun_path *p, const double q0_rad[ARM_NJ],
                   double t_max_s, tdsdrun_metrics *m, tdsdrun_sample_fn on_sample, void *user);

#endif
