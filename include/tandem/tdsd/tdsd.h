/* tdsd: task decomposition + speed distribution (docs/method/tdsd.md, eq. 8, 11-13)
 * for a 6-joint arm, plus the resolved-rate baselines (plain pseudo-inverse
 * and damped least squares, both clipped per joint).
 *
 * Arm-agnostic: the caller supplies the Jacobian rows (from its own
 * kinematics, e.g. the geometric Jacobian rows vx vy vz wx wy wz), the
 * desired and actual tool pose and the path feed-forward; tdsd_step returns
 * joint rates that never exceed dq_max.
 *
 * Time scaling contract ("path rate"): v_d_mps and w_d_radps are the path
 * feed-forward at path rate 1 (d p_d / dt when the path parameter advances
 * at its nominal speed). tdsd_step picks lambda in [0, rate_cap] and uses
 *     y1' = lambda v_d + K_p e_p,   y2' = lambda w_d + K_o e_o.
 * The caller must advance its path parameter by lambda * dt (not dt), so the
 * reference p_d, R_d moves exactly as fast as the feed-forward says; the
 * tool then stays on the path and crosses a singularity slowly. rate_cap is
 * the caller's path-rate input: 1 for nominal speed, 0 to hold, or a ramp
 * (e.g. min(1, lambda_prev + dt / T_recover)) to re-accelerate smoothly.
 */
#ifndef TANDEM_TDSD_H
#define TANDEM_TDSD_H

#define TDSD_NJ 6

/* tdsd_step's fast path (docs/method/tdsd.md §3a) runs where the position
 * block and the orientation block of the LQ factor of [J1; J2] each have
 * ||L||_F ||L^-1||_F at most this (an upper bound on sigma_max / sigma_min)
 * and at most 1 / pinv_rtol; elsewhere the SVD resolution runs. */
#define TDSD_FAST_COND_MAX 1e6
/* The cheaper of the two fast paths, the U D U^T factor of J J^T
 * (docs/method/tdsd.md §3a), runs where the product of the two blocks'
 * bounds is at most this: its rounding grows like their square. */
#define TDSD_GRAM_COND_MAX 1e3

/* tdsd_output.fast: which resolution ran */
#define TDSD_PATH_SVD 0  /* the SVD of §3 (tdsd_step_svd, singular or near) */
#define TDSD_PATH_LQ 1   /* LQ of [J1; J2] by Gram-Schmidt (§3a) */
#define TDSD_PATH_GRAM 2 /* U D U^T of J J^T (§3a), well conditioned */

enum {
    TDSD_OK = 0,
    TDSD_ERR_ARG = -1,    /* non-finite or out-of-range input; out->dq is zeroed */
    TDSD_ERR_NUMERIC = -2 /* linear algebra failure (should not happen); dq zeroed */
};

/* Second-priority task. */
typedef enum {
    TDSD_ORIENT_NONE = 0, /* position only (3 rows); dq2 = 0 */
    TDSD_ORIENT_FULL = 1, /* J2 = Jw (3 rows), e_o of eq. 13 */
    TDSD_ORIENT_AXIS = 2  /* tool axis a only (2 rows): J2 = [n^T; o^T] Jw,
                             e2 = [n.(a x a_d), o.(a x a_d)]; rotation about
                             a is left free (docs/method/tdsd.md §8 S2, "liquid transport") */
} tdsd_orient_mode;

typedef struct {
    double J1[3 * TDSD_NJ]; /* position Jacobian, rows vx vy vz (m/rad) */
    double Jw[3 * TDSD_NJ]; /* angular Jacobian, rows wx wy wz (1) */
    tdsd_orient_mode orient;
    double v_d_mps[3];            /* p_d' at path rate 1 */
    double p_d_m[3];              /* desired tool position p_d */
    double p_m[3];                /* actual tool position p */
    double w_d_radps[3];          /* desired angular velocity at path rate 1 */
    double R_d[9];                /* desired tool frame, row-major, columns n_d o_d a_d */
    double R[9];                  /* actual tool frame, columns n o a */
    double K_p;                   /* position feedback gain (1/s), >= 0 */
    double K_o;                   /* orientation feedback gain (1/s), >= 0 */
    double grad_V[TDSD_NJ];       /* gradient of the criterion V(q) (priority 3) */
    double k_V;                   /* criterion gain k (dq3 ascends V for k > 0) */
    double dq_max_radps[TDSD_NJ]; /* joint speed limits, > 0 */
    double rate_cap;              /* path-rate input in [0, 1] (see above) */
    double pinv_rtol;             /* rank cut of every pseudo-inverse, [0,1);
                                    0 selects LINALG_PINV_RTOL */
} tdsd_input;

typedef struct {
    double dq_radps[TDSD_NJ]; /* the command: dq1 + Q1 dq2 + Q2 dq3 */
    double dq1[TDSD_NJ];      /* J1+ y1' (after time scaling) */
    double dq2[TDSD_NJ];      /* (J2 P1)+ (y2' - J2 dq1), before Q1 */
    double dq3[TDSD_NJ];      /* (P1 - (J2P1)+(J2P1)) k grad V, before Q2 */
    double Q1, Q2;            /* speed-distribution factors in [0, 1] */
    double lambda;            /* path rate used, in [0, rate_cap] */
    double fb_scale;          /* 1, or < 1 when even lambda = 0 could not
                                    keep J1+ K_p e_p inside the limits: then
                                    dq1 = fb_scale J1+ K_p e_p (direction kept) */
    int time_scaled;          /* lambda < rate_cap or fb_scale < 1 */
    int n_clipped;            /* baselines: joints saturated. TDSD: joints
                                    the final exact-limit guard cut by more
                                    than 1e-6 relative (rounding stays below;
                                    nonzero means a bug) */
    double sigma_min_J1;      /* smallest singular value of J1; on the fast
                                    path (fast = 1) a lower bound on it,
                                    1 / ||L11^-1||_F */
    double sigma_max_J1;      /* largest; fast path: upper bound ||L11||_F */
    int fast;                 /* TDSD_PATH_GRAM, _LQ (fast paths) or _SVD */
    int rank_J1;              /* under the pinv tolerance */
    int rank_J2P1;            /* TDSD: rank of J2 P1; baselines: of [J1;J2] */
    int n2;                   /* rows of task 2 (0, 2 or 3) */
    double e_p[3];            /* p_d - p */
    double e_o[3];            /* first n2 entries: orientation error used */
    double y1[3];             /* y1' demanded (after scaling) */
    double y2[3];             /* y2' demanded (first n2 entries) */
    double damping;           /* rr_dls_step: damping lambda used; else 0 */
} tdsd_output;

/* One control cycle of TDSD. Returns TDSD_OK, or a negative code with
 * out->dq_radps zeroed (safe: hold). Guarantees |dq_i| <= dq_max_i.
 * Resolves by the U D U^T factor of the Gram matrix of [J1; J2] where the
 * product of the two blocks' condition bounds is at most
 * TDSD_GRAM_COND_MAX, by the LQ factor (modified Gram-Schmidt) where each
 * is at most TDSD_FAST_COND_MAX, by the SVD of tdsd_step_svd elsewhere;
 * they agree to rounding (docs/method/tdsd.md §3a gives the identities and
 * the bounds). */
int tdsd_step(const tdsd_input *in, tdsd_output *out);
/* tdsd_step without its pass over the inputs, for a caller whose inputs
 * are valid by construction (every entry finite, orient one of the modes,
 * K_p, K_o >= 0, rate_cap in [0, 1], pinv_rtol in [0, 1), dq_max > 0):
 * tdsd_seg_step, which builds them from a checked reference and segment,
 * so that no input is checked twice a cycle. Invalid inputs are then
 * undefined behaviour of the result, not an error code. */
int tdsd_step_unchecked(const tdsd_input *in, tdsd_output *out);
/* The same step, always by the SVD (the generic path; the fast path's
 * test oracle). */
int tdsd_step_svd(const tdsd_input *in, tdsd_output *out);

/* e_o = 1/2 (n x n_d + o x o_d + a x a_d) (eq. 13); equals sin(theta) k
 * when R_d = Rot(k, theta) R. */
void tdsd_orientation_error(double e_o[3], const double R_d[9], const double R[9]);
/* Tool-axis error for TDSD_ORIENT_AXIS: e2 = [n.(a x a_d), o.(a x a_d)];
 * |e2| = sin of the angle between a and a_d. */
void tdsd_axis_error(double e2[2], const double R_d[9], const double R[9]);
/* The 2 x 6 tool-axis Jacobian J2 = [n^T Jw; o^T Jw]: the rates of the
 * angular velocity components that tilt the tool axis a. */
void tdsd_axis_jacobian(double J2[2 * TDSD_NJ], const double Jw[3 * TDSD_NJ], const double R[9]);

/* Criterion of docs/method/tdsd.md §8 S2, for the joints whose bit is set in joint_mask
 * (bit i = joint i+1; S2 uses 0x38 = joints 4..6):
 *   V(q) = -sum ((q_i - mid_i) / (max_i - min_i))^2,  mid = (min+max)/2
 *   dV/dq_i = -2 (q_i - mid_i) / (max_i - min_i)^2.
 * V may be NULL. Returns TDSD_ERR_ARG unless every used max_i > min_i and
 * all values are finite. */
int tdsd_midrange_grad(double grad_V[TDSD_NJ], double *V, const double q_rad[TDSD_NJ],
                       const double q_min_rad[TDSD_NJ], const double q_max_rad[TDSD_NJ],
                       unsigned joint_mask);

/* The same gradient with the ranges taken once (a control cycle divides
 * nothing): dV/dq_i = k_i (q_i - mid_i), k_i = -2 / (max_i - min_i)^2, for
 * the joints of the mask (0 elsewhere). tdsd_midrange_init checks the
 * ranges as tdsd_midrange_grad does (TDSD_ERR_ARG); tdsd_midrange_grad_at
 * takes q as given (the caller's q is finite). */
typedef struct {
    double mid_rad[TDSD_NJ];
    double k_per_rad2[TDSD_NJ];
    unsigned mask;
} tdsd_midrange;
int tdsd_midrange_init(tdsd_midrange *c, const double q_min_rad[TDSD_NJ],
                       const double q_max_rad[TDSD_NJ], unsigned joint_mask);
void tdsd_midrange_grad_at(const tdsd_midrange *c, const double q_rad[TDSD_NJ],
                           double grad_V[TDSD_NJ]);

/* Baseline 1: full resolved rate dq = J+ [y1'; y2'] with J = [J1; J2]
 * (J2 per in->orient: 6 rows for FULL), plain pseudo-inverse (in->pinv_rtol),
 * then each joint saturated to +-dq_max independently (this distorts the
 * direction of motion; that is what the baseline shows). No time scaling:
 * lambda = rate_cap. grad_V and k_V are ignored. */
int rr_pinv_step(const tdsd_input *in, tdsd_output *out);

/* Damping rule for rr_dls_step (Nakamura & Hanafusa 1986 variable damping):
 *   lambda^2 = lambda0^2 (1 - (sigma_min / eps)^2)  if sigma_min < eps,
 *   lambda^2 = 0                                     otherwise,
 * sigma_min = smallest singular value of the stacked J. eps <= 0 selects
 * constant damping lambda = lambda0 (Wampler 1986). */
typedef struct {
    double lambda0; /* >= 0, same units as sigma (m/rad for position rows) */
    double eps;     /* singular-region size */
} rr_dls_params;

/* Baseline 2: dq = J^T (J J^T + lambda^2 I)^-1 [y1'; y2'], then the same
 * per-joint saturation. out->damping reports lambda. */
int rr_dls_step(const tdsd_input *in, const rr_dls_params *dls, tdsd_output *out);

#endif
