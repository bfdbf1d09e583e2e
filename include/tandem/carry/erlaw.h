/* erlaw: event-referenced control law for one straight segment
 * (docs/method/carry.md §3, eq. 6-7), its orientation channel, external (synchronised)
 * references, and the time-referenced baseline.
 *
 * Output is the commanded operational-space acceleration (linear in m/s^2,
 * angular in rad/s^2). Turning it into joint torques (computed torque with
 * the arm's dynamic model) is the arm daemon's job; erlaw knows no arm.
 *
 *   u = A_d(s_ref) e + k_v (V_d(s_ref) e - V) + k_p (X_d(s_ref) - X) + p_bias
 *   p_bias = e k0 / (1 + exp(k1 - k2 (s_f - s)))
 *
 * s is always the *measured* progress (projection of X on the segment,
 * clamped to [0, s_f]); p_bias uses it. s_ref selects the reference:
 *   ERLAW_REF_MEASURED  s_ref = s                  (event law, eq. 6)
 *   ERLAW_REF_EXTERNAL  s_ref = min(k_i s*, s)     (synchronised, docs/method/carry.md §4)
 *   ERLAW_REF_TIME      s_ref = s_d(t), advancing with the clock from the
 *                       segment start              (baseline, docs/method/carry.md §8)
 *   ERLAW_REF_BLOCKED   s_ref = s, planned motion dropped, the pose
 *                       across e held where the block was detected
 *                       (erlaw_line_hold / erlaw_rot_hold); s_ext unused
 *
 * While blocked under the event law, s stops, so every term stops:
 * u = A_d(s) e + k_v V_d(s) e + p_bias(s) (plus feedback on V = 0), i.e.
 * bounded by a_m + k_v v_m + k0 whatever the block duration. Once the
 * block is detected, ERLAW_REF_BLOCKED drops the planned motion and keeps
 * the law's start-up form with the references frozen at the measured
 * pose X_h (set by erlaw_line_hold when the block is detected):
 *   u = k0 e - k_v V + k_p (X_h - X),
 * so the demand is the bias along the path (its full start-up value k0,
 * not eq. 7's faded p_bias(s): released near the goal, the arm must still
 * move on at k0 / k_v) plus a hold of the pose where the block was
 * detected, in every direction (docs/method/carry.md §3: no error builds up). The pose
 * held is the measured one, not the planned line: an obstacle that
 * deflected the arm (a pinned proximal link: the other joints carry the
 * tool on, off the line) is not fought, and a contact near a joint axis
 * is not loaded with the lever-arm multiple of a cross-track error. Along
 * e the hold and the bias balance k_p |X_h - X| = k0 a few mm ahead of
 * X_h (cartseg's CARTSEG_UNBLOCK_EPS_M reads that creep as the release).
 * The bias moves the arm on when
 * the obstacle goes (as it starts the arm at s0).
 *
 * External reference (a synchronised action, docs/method/carry.md §4): s_ext = k_i s*.
 * With min semantics k_i s* <= s_i, and an arm never chases a reference
 * ahead of itself: s_ref = min(clamp(s_ext), s). An arm with s_ref = s
 * defines s* (it is the laggard): plain eq. 6 at its own s, bias included.
 * An arm ahead of its reference (s_ref < s) is a follower and tracks the
 * reference *as it moves*:
 *   u = A_ref e + k_vf (V_ref e - V) + k_pf (X_d(s_ref + g) - X)
 *   V_ref = d s_ref/dt  (first-order filtered difference of s_ext,
 *                        ERLAW_REF_RATE_TAU_S, clamped to |.| <= 2 v_m)
 *   A_ref = rho^2 A_d(s_ref),  rho = clamp(V_ref / V_d(s_ref), 0, 1)
 * (A_ref: a reference moving along the profile at rho times its planned
 * pace has acceleration rho^2 A_d, neglecting d rho/dt.) No bias: it
 * belongs to the arm that defines s*. Instead the follower keeps a fixed
 * gap g = ERLAW_FOLLOW_GAP_M (1 mm) ahead of its reference: it makes the
 * roles unambiguous (without it a follower at rest sits exactly on its
 * reference, flips to laggard on rounding, takes the bias, flips back,
 * and the arms' blocked detectors cannot tell the held arm from the
 * blocked one); cartseg treats an arm more than 0.5 mm ahead of its
 * reference as held, not blocked. When s* stops, V_ref -> 0 and
 * A_ref -> 0 within a few ms and the follower brakes as a critically
 * damped tracker of a fixed point: k_pf = max(k_p, w^2), k_vf = max(k_v, 2 w), w =
 * ERLAW_SYNC_OMEGA_RADPS. From speed v0 its speed falls below eps when
 * (1 - w t) e^(-w t) = eps / v0, i.e. t = 0.88 / w for eps / v0 = 1/20
 * (29 ms at w = 30 rad/s), and it overshoots its rest point by at most
 * v0 / (e w) (2.5 mm from 0.2 m/s): lead <= g + v0 / (e w); it then
 * backs onto its rest point (at up to ~0.15 v0). With the row's
 * k_p = 100, k_v = 20 alone (w = 10) the stop would take 88 ms.
 *
 * Short segments (k2 s_f < 2 k1): eq. 7 would already be fading at s = 0
 * and the bias might not start the arm, so k2 is raised to 2 k1 / s_f
 * (bias ~k0 at the start, k0 / (1 + e^k1) at the goal, as for long ones).
 *
 * Along the path, X_d is taken at the measured s, so eq. 6 has no
 * position term there: a constant unmodelled acceleration d opposing the
 * motion leaves the arm at rest about d / (k_v sqrt(u_m)) short of s_f
 * (near the end V_d ~ sqrt(u_m) (s_f - s) and p_bias ~ 0). Choose the
 * done tolerance accordingly.
 *
 * Orientation channel: rotation R0 -> R1 about the fixed world axis n of
 * R1 R0^T by theta_f (must be < pi). Measured progress: theta =
 * n . log(R R0^T) clamped; reference R_d = Rot(n, theta_ref) R0; the
 * "position error" is the world rotation vector log(R_d R^T).
 */
#ifndef TANDEM_ERLAW_H
#define TANDEM_ERLAW_H

#include "sprofile.h"

#define ERLAW_ERR_ARG \
    (-1) /* NULL, non-finite input, invalid gains, bad
                               reference mode, or dt < 0                  */

/* One set of limits and gains (one row of the lookup table, docs/method/carry.md §6).
 * For the orientation channel read m as rad. */
typedef struct {
    double v_m; /* m/s                       */
    double a_m; /* m/s^2                     */
    double u_m; /* da/ds limit, 1/s^2        */
    double k_p; /* 1/s^2                     */
    double k_v; /* 1/s                       */
    double k0;  /* m/s^2: bias magnitude     */
    double k1;  /* -: bias turn-off offset   */
    double k2;  /* 1/m: bias turn-off slope  */
} erlaw_gains;

typedef enum {
    ERLAW_REF_MEASURED = 0,
    ERLAW_REF_EXTERNAL = 1,
    ERLAW_REF_TIME = 2,
    ERLAW_REF_BLOCKED = 3 /* detected block: start-up form at s */
} erlaw_ref;

/* Follower of an external reference: tracking bandwidth (rad/s) and the
 * time constant of the reference-rate filter (s). */
#define ERLAW_SYNC_OMEGA_RADPS 30.0
#define ERLAW_REF_RATE_TAU_S 0.004
/* A follower rests this far ahead of its reference (see above). */
#define ERLAW_FOLLOW_GAP_M 0.001

/* The time-referenced baseline advances s_d(t) with speed
 * max(V_d(s_d), ERLAW_TIME_V_FLOOR_FRAC * v_peak) (see sprofile_advance). */
#define ERLAW_TIME_V_FLOOR_FRAC 0.05

/* State of one channel (one segment, translation or rotation). */
typedef struct {
    sprofile prof;
    erlaw_gains g;
    double k2_eff;     /* k2, raised to 2 k1 / s_f on short segments  */
    double e[3];       /* unit direction / rotation axis              */
    double s_time_m;   /* s_d(t) of the time-referenced baseline      */
    double t_s;        /* time since the segment start                */
    double s_ext_prev; /* last external reference (clamped)           */
    double v_ext;      /* its filtered rate V_ref                     */
    int ext_seen;      /* s_ext_prev holds a value                    */
    double s_resume_m; /* erlaw_channel_resume: where the arm stood   */
    int resumed;       /* the resume ramp caps V_d and A_d            */
} erlaw_channel;

typedef struct {
    erlaw_channel ch;
    double p0_m[3];
    double x_hold_m[3]; /* pose held across e while blocked (init: p0) */
} erlaw_line;

typedef struct {
    erlaw_channel ch;
    double R0[9];
    double R_hold[9]; /* orientation held while blocked (init: R0)   */
} erlaw_rot;

typedef struct {
    double u[3];     /* commanded acceleration (m/s^2 or rad/s^2)  */
    double s_m;      /* measured progress                          */
    double s_ref_m;  /* reference progress used                    */
    double x_err[3]; /* X_d - X (or log(R_d R^T))                  */
    double a_d, v_d; /* reference acceleration and speed used
                           (planned at s_ref; A_ref, V_ref for a follower) */
    double bias;     /* |p_bias|                                   */
    int follower;    /* 1: tracking an external reference ahead of it */
} erlaw_out;

/* 0 if every field is finite, the limits > 0 and k_p, k_v, k0, k2 >= 0;
 * else ERLAW_ERR_ARG. */
int erlaw_gains_validate(const erlaw_gains *g);

/* Segment p0 -> p1. A zero-length segment is valid (holds p0). 0 / ERLAW_ERR_ARG. */
int erlaw_line_init(erlaw_line *l, const double p0_m[3], const double p1_m[3],
                    const erlaw_gains *g);
/* Measured progress: projection of x on the segment, clamped to [0, s_f]. */
double erlaw_line_s(const erlaw_line *l, const double x_m[3]);
/* Pose held across the path under ERLAW_REF_BLOCKED (call it with the
 * measured tool point when the block is detected). 0 / ERLAW_ERR_ARG. */
int erlaw_line_hold(erlaw_line *l, const double x_m[3]);
/* One control cycle. s_ext_m is used only with ERLAW_REF_EXTERNAL (it is
 * clamped to [0, s_f], then to the measured s); dt_s advances the baseline
 * clock (ERLAW_REF_TIME), the reference-rate estimate and the segment
 * time. Returns 0, or ERLAW_ERR_ARG on bad input (out->u is then 0). */
int erlaw_line_step(erlaw_line *l, const double x_m[3], const double v_mps[3], erlaw_ref ref,
                    double s_ext_m, double dt_s, erlaw_out *out);

/* Orientation move R0 -> R1 (rotation matrices, row-major). 0 / ERLAW_ERR_ARG. */
int erlaw_rot_init(erlaw_rot *r, const double R0[9], const double R1[9], const erlaw_gains *g);
/* Measured rotated angle about the move's axis, clamped to [0, theta_f]. */
double erlaw_rot_angle(const erlaw_rot *r, const double R[9]);
/* Orientation held (across the move's axis) under ERLAW_REF_BLOCKED. */
int erlaw_rot_hold(erlaw_rot *r, const double R[9]);
int erlaw_rot_step(erlaw_rot *r, const double R[9], const double w_radps[3], erlaw_ref ref,
                   double s_ext_rad, double dt_s, erlaw_out *out);

/* Protective-stop resume (docs/method/carry.md §7.4): the arm stands at
 * measured progress s_r after a hold (a block released, a frozen or late
 * controller, a fault) and the planned motion is taken up from there as
 * from a start: V_d and A_d are those of the profile at s - s_r wherever
 * that is the slower, so the arm never sees a speed demand it has no
 * planned acceleration for (eq. 6 from rest at cruise: k_v v_m, ten
 * times a_m with the carry rows). Not for a follower (it tracks its
 * reference's rate, itself capped so) nor the time baseline. */
void erlaw_channel_resume(erlaw_channel *c, double s_r);

/* Segment length s_f (m or rad) of a channel. */
double erlaw_channel_length(const erlaw_channel *c);

/* Done: s within tol_s of s_f and |speed| below tol_v. */
int erlaw_done(double s_m, double s_f_m, double speed, double tol_s, double tol_v);

/* Blocked detection: s has not advanced by more than eps_s for longer
 * than t_block_s while motion was commanded. */
typedef struct {
    double s_best_m;
    double t_still_s;
} erlaw_block;

void erlaw_block_reset(erlaw_block *b, double s_m);
/* Returns 1 while blocked, 0 otherwise. commanding = 0 (e.g. at the goal)
 * resets the still timer. */
int erlaw_block_update(erlaw_block *b, double s_m, int commanding, double dt_s, double eps_s,
                       double t_block_s);

#endif
