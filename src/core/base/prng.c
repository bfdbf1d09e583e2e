/* prng: splitmix64 (Steele, Lea, Flood 2014) with uniform and Gaussian
 * draws; drives the sonar range noise of docs/method/lockstep.md §3 deterministically.
 */
#include "prng.h"
#include "vec2.h"

#include <math.h>

void prng_seed(prng_state *r, uint64_t seed)
{
    r->s = seed;
}

uint64_t prng_u64(prng_state *r)
{
    uint64_t z = (r->s += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

double prng_uniform(prng_state *r)
{
    return (double)(prng_u64(r) >> 11) * (1.0 / 9007199254740992.0);
}

double prng_gauss(prng_state *r)
{
    /* 1 - u is in (0, 1], so the log is finite. */
    const double u1 = 1.0 - prng_uniform(r);
    const double u2 = prng_uniform(r);
    return sqrt(-2.0 * log(u1)) * cos(2.0 * VEC2_PI * u2);
}
