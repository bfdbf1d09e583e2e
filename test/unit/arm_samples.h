/* arm_samples: reproducible random joint vectors for the arm tests, drawn
 * from the core's prng so every test uses one generator. */
#ifndef TANDEM_TEST_ARM_SAMPLES_H
#define TANDEM_TEST_ARM_SAMPLES_H

#include "arm_model.h"
#include "prng.h"

/* Uniform inside the model's joint ranges. */
static inline void random_q(const arm_model *m, prng_state *s, double q[ARM_NJ])
{
    int j;
    for (j = 0; j < ARM_NJ; j++)
        q[j] = m->q_min_rad[j] + (m->q_max_rad[j] - m->q_min_rad[j]) * prng_uniform(s);
}

/* Uniform in [-scale, scale] per joint. */
static inline void random_vec(prng_state *s, double scale, double v[ARM_NJ])
{
    int j;
    for (j = 0; j < ARM_NJ; j++)
        v[j] = scale * (2.0 * prng_uniform(s) - 1.0);
}

#endif
