/* trig: sine, cosine, atan2 and exp without the 68040's trapped
 * instructions (docs/method/puma.md §1; see trig.h).
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

static const double PIO4 = 7.85398163397448278999e-01; /* pi/4 rounded down */
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

/* sin(x), |x| <= pi/4, z = x^2. Both kernels inline: their two Horner
 * chains are independent and overlap where the FPU can (on the host
 * trig_sincos was latency-bound while it called kernel_cos). */
static inline double kernel_sin(double x, double z)
{
    const double v = z * x;
    const double r = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
    return x + v * (S1 + z * r);
}

/* cos(x), |x| <= pi/4, z = x^2: 1 - z/2 + z r, the 1 - z/2 split so that
 * its rounding error is added back */
static inline double kernel_cos(double z)
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
    r = x_rad - fn * pio2_1; /* exact */
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
    case 0:
        *s = sk;
        *c = ck;
        break;
    case 1:
        *s = ck;
        *c = -sk;
        break;
    case 2:
        *s = -sk;
        *c = -ck;
        break;
    default:
        *s = -ck;
        *c = sk;
        break;
    }
}

/* ---- atan2 ---------------------------------------------------------------- */

/* atan of 0.5, 1, 1.5 and infinity, each as a head and a tail */
static const double atan_hi[4] = { 4.63647609000806093515e-01, 7.85398163397448278999e-01,
                                   9.82793723247329054082e-01, 1.57079632679489655800e+00 };
static const double atan_lo[4] = { 2.26987774529616870924e-17, 3.06161699786838301793e-17,
                                   1.39033110312309984516e-17, 6.12323399573676603587e-17 };
static const double aT[11] = { 3.33333333333329318027e-01, -1.99999999998764832476e-01,
                               1.42857142725034663711e-01, -1.11111104054623557880e-01,
                               9.09088713343650656196e-02, -7.69187620504482999495e-02,
                               6.66107313738753120669e-02, -5.83357013379057348645e-02,
                               4.97687799461593236017e-02, -3.65315727442169155270e-02,
                               1.62858201153657823623e-02 };
static const double PI_HI = 3.1415926535897931160e+00, PI_LO = 1.2246467991473531772e-16;

/* atan(t), t >= 0 finite: reduced to |x| <= 7/16 around 0, 0.5, 1, 1.5 or
 * infinity (fdlibm s_atan), then an odd polynomial of degree 23 */
static double atan_nonneg(double t)
{
    double x = t, z, w, s1, s2;
    int id;
    if (t < 0.4375) {
        id = -1;
    } else if (t < 1.1875) {
        if (t < 0.6875) {
            id = 0;
            x = (2.0 * t - 1.0) / (2.0 + t);
        } else {
            id = 1;
            x = (t - 1.0) / (t + 1.0);
        }
    } else if (t < 2.4375) {
        id = 2;
        x = (t - 1.5) / (1.0 + 1.5 * t);
    } else {
        id = 3;
        x = -1.0 / t;
    }
    z = x * x;
    w = z * z;
    s1 = z * (aT[0] + w * (aT[2] + w * (aT[4] + w * (aT[6] + w * (aT[8] + w * aT[10])))));
    s2 = w * (aT[1] + w * (aT[3] + w * (aT[5] + w * (aT[7] + w * aT[9]))));
    if (id < 0)
        return x - x * (s1 + s2);
    return atan_hi[id] - ((x * (s1 + s2) - atan_lo[id]) - x);
}

double trig_atan2(double y, double x)
{
    double a;
    if (!isfinite(x) || !isfinite(y))
        return atan2(y, x);
    if (y == 0.0)
        return (x > 0.0 || (x == 0.0 && !signbit(x))) ? y : (signbit(y) ? -PI_HI : PI_HI);
    if (x == 0.0)
        return y > 0.0 ? atan_hi[3] : -atan_hi[3];
    a = atan_nonneg(fabs(y / x));
    if (x < 0.0)
        a = PI_HI - (a - PI_LO);
    return y < 0.0 ? -a : a;
}

/* ---- exp -------------------------------------------------------------------- */

static const double ln2_hi = 6.93147180369123816490e-01, ln2_lo = 1.90821492927058770002e-10;
static const double inv_ln2 = 1.44269504088896338700e+00;
static const double P1 = 1.66666666666666019037e-01, P2 = -2.77777777770155933842e-03,
                    P3 = 6.61375632143793436117e-05, P4 = -1.65339022054652515390e-06,
                    P5 = 4.13813679705723846039e-08;

double trig_exp(double x)
{
    double hi, lo, r, t, c, y, p2;
    long k, e;
    if (!(fabs(x) <= 700.0))
        return exp(x);
    k = (long)(x * inv_ln2 + (x >= 0.0 ? 0.5 : -0.5));
    hi = x - (double)k * ln2_hi; /* exact */
    lo = (double)k * ln2_lo;
    r = hi - lo;
    t = r * r;
    c = r - t * (P1 + t * (P2 + t * (P3 + t * (P4 + t * P5))));
    y = 1.0 - ((lo - (r * c) / (2.0 - c)) - hi);
    /* y 2^k; |k| <= 1010, so every power below is exact and finite */
    p2 = k >= 0 ? 2.0 : 0.5;
    for (e = k >= 0 ? k : -k; e != 0; e >>= 1) {
        if (e & 1)
            y *= p2;
        p2 *= p2;
    }
    return y;
}
