/* trig: sine and cosine without the 68040's trapped instructions
 * (docs/method/carry.md §3.4; see trig.h).
 *
 * x = n pi/2 + y, |y| <= pi/4, by Cody-Waite: pi/2 split into pio2_1 (its
 * first 33 bits, so n pio2_1 is exact for n < 2^20) and tails, the second
 * round taken when x is so close to a multiple of pi/2 that the first
 * loses more than 16 bits to cancellation (fdlibm's e_rem_pio2 "medium"
 * case). Then fdlibm's minimax polynomials (k_sin, k_cos), accurate to
 * about 2^-58 on [-pi/4, pi/4]. fdlibm also carries the rounding tail of
 * y into the kernels; it buys the last half ulp and costs a tenth of the
 * call, so it is left out: results stay within about one ulp of libm.
 */
#include "trig.h"

#include <math.h>

static const double PIO4 = 7.85398163397448278999e-01;   /* pi/4 rounded down */
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

/* sin(x), |x| <= pi/4, z = x^2 */
static double kernel_sin(double x, double z)
{
    const double v = z * x;
    const double r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    return x + v * (S1 + z * r);
}

/* cos(x), |x| <= pi/4, z = x^2: 1 - z/2 + z r, the 1 - z/2 split so that
 * its rounding error is added back */
static double kernel_cos(double z)
{
    const double w = z * z;
    const double r = z * (C1 + z * (C2 + z * C3)) + w * w * (C4 + z * (C5 + z * C6));
    const double hz = 0.5 * z, a = 1.0 - hz;
    return a + (((1.0 - a) - hz) + z * r);
}

void trig_sincos(double x_rad, double *s, double *c)
{
    double fn, r, w, y, z, sk, ck;
    long n;
    if (fabs(x_rad) <= PIO4) {
        /* already in the kernels' range (as fdlibm: no reduction) */
        z = x_rad * x_rad;
        *s = kernel_sin(x_rad, z);
        *c = kernel_cos(z);
        return;
    }
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
    y = r - w;
    if (n != 0 && fabs(y) < fabs(x_rad) * 0x1p-16) {
        /* near a multiple of pi/2: 33 more bits of pi/2 */
        const double t = r;
        w = fn * pio2_2;
        r = t - w;
        w = fn * pio2_2t - ((t - r) - w);
        y = r - w;
    }
    z = y * y;
    sk = kernel_sin(y, z);
    ck = kernel_cos(z);
    switch (n & 3) {
    case 0: *s = sk;  *c = ck;  break;
    case 1: *s = ck;  *c = -sk; break;
    case 2: *s = -sk; *c = -ck; break;
    default: *s = -ck; *c = sk; break;
    }
}
