/* trig: sine and cosine without the 68040's trapped instructions
 * (docs/method/carry.md §3.4; see trig.h).
 *
 * x = n pi/2 + y, |y| <= pi/4, by Cody-Waite: pi/2 split into pio2_1 (its
 * first 33 bits, so n pio2_1 is exact for n < 2^20) and tails, the second
 * round taken when x is so close to a multiple of pi/2 that the first
 * loses more than 16 bits to cancellation (fdlibm's e_rem_pio2 "medium"
 * case). y is carried as y0 + y1 (y1 the rounding tail) into fdlibm's
 * kernels (k_sin, k_cos, in the form without bit tricks), whose minimax
 * polynomials are accurate to about 2^-58 on [-pi/4, pi/4].
 */
#include "trig.h"

#include <math.h>

static const double invpio2 = 6.36619772367581382433e-01;
static const double pio2_1 = 1.57079632673412561417e+00;
static const double pio2_1t = 6.07710050650619224932e-11;
static const double pio2_2 = 6.07710050630396597660e-11;
static const double pio2_2t = 2.02226624879595063154e-21;

static const double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03,
                    S3 = -1.98412698298579493134e-04, S4 = 2.75573137070700676789e-06,
                    S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
static const double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03,
                    C3 = 2.48015872894767294178e-05, C4 = -2.75573143513906633035e-07,
                    C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;

/* sin(x + y), |x| <= pi/4, y the tail of x */
static double kernel_sin(double x, double y)
{
    const double z = x * x, v = z * x;
    const double r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    return x - ((z * (0.5 * y - v * r) - y) - v * S1);
}

/* cos(x + y), |x| <= pi/4 */
static double kernel_cos(double x, double y)
{
    const double z = x * x, w = z * z;
    const double r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    const double hz = 0.5 * z, a = 1.0 - hz;
    return a + (((1.0 - a) - hz) + (z * r - x * y));
}

void trig_sincos(double x_rad, double *s, double *c)
{
    double fn, r, w, y0, y1, sk, ck;
    long n;
    if (!(fabs(x_rad) < TRIG_REDUCE_MAX_RAD)) {
        *s = sin(x_rad);
        *c = cos(x_rad);
        return;
    }
    /* nearest n; the cast truncates (fmove.l in round-to-zero on the 68040, no trap) */
    n = (long)(x_rad * invpio2 + (x_rad >= 0.0 ? 0.5 : -0.5));
    fn = (double)n;
    r = x_rad - fn * pio2_1;   /* exact */
    w = fn * pio2_1t;
    y0 = r - w;
    if (n != 0 && fabs(y0) < fabs(x_rad) * 0x1p-16) {
        /* near a multiple of pi/2: 33 more bits of pi/2 */
        const double t = r;
        w = fn * pio2_2;
        r = t - w;
        w = fn * pio2_2t - ((t - r) - w);
        y0 = r - w;
    }
    y1 = (r - y0) - w;
    sk = kernel_sin(y0, y1);
    ck = kernel_cos(y0, y1);
    switch (n & 3) {
    case 0: *s = sk;  *c = ck;  break;
    case 1: *s = ck;  *c = -sk; break;
    case 2: *s = -sk; *c = -ck; break;
    default: *s = -ck; *c = sk; break;
    }
}
