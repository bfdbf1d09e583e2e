/* prng: tiny deterministic pseudo-random generator (splitmix64) for sensor
 * noise models. The caller owns the state, so runs are reproducible for a
 * given seed and several robots can have independent streams.
 */
#ifndef TANDEM_PRNG_H
#define TANDEM_PRNG_H

#include <stdint.h>

typedef struct {
    uint64_t s;
} prng_state;

void prng_seed(prng_state *r, uint64_t seed);
uint64_t prng_u64(prng_state *r);
/* Uniform in [0, 1), 53-bit resolution. */
double prng_uniform(prng_state *r);
/* Standard normal N(0, 1) (Box-Muller, one value per call). */
double prng_gauss(prng_state *r);

#endif
