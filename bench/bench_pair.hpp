// bench_pair: what the arm baselines (bench_kdl, bench_pinocchio) share:
// the seeded sample set over the PUMA's joint ranges and the timing of two
// implementations in alternating batches. The machine is shared: each
// side's fastest batch is kept, so a burst of load elsewhere hits both
// sides alike and is then discarded rather than averaged in.
#ifndef TANDEM_BENCH_PAIR_HPP
#define TANDEM_BENCH_PAIR_HPP

#include <chrono>
#include <cmath>

extern "C" {
#include "arm_model.h"
}

static const int NS = 64;
static const int BATCHES = 200;

// q uniform in the ranges, qd in [-1, 1], qdd in [-2, 2] (a LCG, so every
// baseline sees the same samples)
static inline void bench_samples(const arm_model &m, double q[][ARM_NJ], double qd[][ARM_NJ],
                                 double qdd[][ARM_NJ])
{
    unsigned long s = 1;
    for (int i = 0; i < NS; i++)
        for (int j = 0; j < ARM_NJ; j++) {
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            double u = (double)(s >> 11) / 9007199254740992.0;
            q[i][j] = m.q_min_rad[j] + (m.q_max_rad[j] - m.q_min_rad[j]) * u;
            qd[i][j] = 2.0 * u - 1.0;
            qdd[i][j] = 4.0 * (1.0 - u) - 2.0;
        }
}

template <class F> static double time_ns(long n, F f)
{
    auto t0 = std::chrono::steady_clock::now();
    for (long k = 0; k < n; k++)
        f((int)(k % NS));
    auto t1 = std::chrono::steady_clock::now();
    return std::chrono::duration<double, std::nano>(t1 - t0).count() / (double)n;
}

template <class A, class B> static void time_pair(long n, A a, B b, double *a_ns, double *b_ns)
{
    const long nb = n / BATCHES > 0 ? n / BATCHES : 1;
    *a_ns = *b_ns = 1e300;
    for (int k = 0; k < BATCHES; k++) {
        *a_ns = std::fmin(*a_ns, time_ns(nb, a));
        *b_ns = std::fmin(*b_ns, time_ns(nb, b));
    }
}

#endif
