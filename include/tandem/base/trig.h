/* trig: sine and cosine together, atan2 and exp in plain double
 * arithmetic, for the control cycles (docs/method/puma.md §1).
 *
 * Why: the 68040 has no sine or cosine in hardware; libm's fsin/fcos/fsincos
 * trap to the FPSP software package (hundreds of clocks each). This is the
 * fdlibm kernel pair on [-pi/4, pi/4] after a Cody-Waite reduction by
 * pi/2: a few multiplications and additions, within one ulp of libm.
 */
#ifndef TANDEM_TRIG_H
#define TANDEM_TRIG_H

/* |x| below this is reduced here (n <= 2^19 quarter turns); above it, and
 * for a non-finite x, libm's sin and cos answer (never in a control cycle:
 * joint angles are a few radians). */
#define TRIG_REDUCE_MAX_RAD 823549.6

/* sin(x_rad) and cos(x_rad); neither pointer may be NULL. */
void trig_sincos(double x_rad, double *s, double *c);

/* atan2(y, x) in (-pi, pi], as libm's for finite arguments (fdlibm's
 * s_atan polynomial after its four-interval reduction); a non-finite
 * argument goes to libm. glibc's on the 68040 traps three times. */
double trig_atan2(double y, double x);

/* exp(x) (fdlibm's e_exp: x = k ln2 + r, a rational approximation on
 * |r| <= ln2/2, 2^k by squaring); |x| > 700 and non-finite x go to libm. */
double trig_exp(double x);

#endif
