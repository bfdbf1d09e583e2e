/* sprofile: minimum-time jerk-limited speed profile in the path-length
 * domain (docs/method/carry.md §2, eq. 2-4).
 *
 * The profile is a function of the travelled path length s in [0, s_f],
 * not of time: a(s) is piecewise linear with slopes +-u_m (u = da/ds),
 * w(s) = v(s)^2 is its integral (dw/ds = 2a). v(0) = v(s_f) = 0 and
 * a(0) = a(s_f) = 0.
 *
 * Units are free: the same code serves translation (m, m/s, m/s^2, 1/s^2
 * for u_m) and orientation moves referenced by the rotated angle (rad,
 * rad/s, rad/s^2, 1/s^2). Names say _m for brevity; read "length unit".
 *
 * Short segments (s4 < s3 in eq. 4): the acceleration phase length D is
 * cut to s_f/2, the peak acceleration to min(a_m, u_m D/2) and the peak
 * w follows from D and the peak acceleration in closed form, so the
 * profile stays continuous and ends at rest exactly at s_f.
 */
#ifndef TANDEM_SPROFILE_H
#define TANDEM_SPROFILE_H

#define SPROFILE_ERR_ARG (-1) /* NULL, not finite, s_f < 0 or a limit <= 0 */

typedef struct {
    double s_f_m;   /* segment length                                 */
    double u_m;     /* da/ds limit                                    */
    double a_peak;  /* peak |a| actually used (<= a_m)                */
    double w_peak;  /* peak v^2 actually used (<= v_m^2)              */
    double d_acc_m; /* length of the acceleration (and deceleration)
                           phase; s3 - s0 in eq. 4                        */
    double x1_m;    /* a_peak / u_m: end of the jerk phase (x = s - s0) */
    double w_x1;    /* a_peak^2 / u_m: w there (every evaluation used to
                           divide for both)                               */
} sprofile;

/* Plan a profile. s_f_m >= 0 and v_m, a_m, u_m > 0, all finite.
 * s_f_m = 0 gives the all-zero profile. Returns 0 or SPROFILE_ERR_ARG (bad input;
 * *p is then the zero profile). */
int sprofile_plan(sprofile *p, double s_f_m, double v_m, double a_m, double u_m);

/* Planned acceleration and speed at path length s (clamped to [0, s_f]).
 * Either output may be NULL. */
void sprofile_at(const sprofile *p, double s_m, double *a_d, double *v_d);

/* Planned peak speed (sqrt(w_peak)). */
double sprofile_v_peak(const sprofile *p);

/* Time integration for a time-referenced baseline: advance a reference
 * path length s by dt along ds/dt = max(v(s), v_floor) (RK4, one step),
 * clamped to [0, s_f]. The pure profile has v ~ sqrt(u_m) s near both
 * ends, so without a floor s(t) would never leave 0 nor reach s_f in
 * finite time; v_floor plays the role that p_bias plays in the event law.
 * Call once per control cycle from s = 0 at the segment start: no table,
 * no allocation. */
double sprofile_advance(const sprofile *p, double s_m, double dt_s, double v_floor);
/* The same step from s_m in [0, s_f] for a caller that has just evaluated
 * its first stage, rate_s = max(v(s_m), v_floor) (v_floor >= 0): one
 * profile evaluation fewer, the same result. Other arguments: as
 * sprofile_advance. */
double sprofile_advance_at(const sprofile *p, double s_m, double rate_s, double dt_s,
                           double v_floor);

#endif
