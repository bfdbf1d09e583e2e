/* bench_arm: runs one arm-core routine N times on a fixed set of joint
 * vectors, for timing and for instruction counts per call:
 *   bench_arm ROUTINE [N]        ROUTINE = fk jac ik rne mass grav fd all
 *   valgrind --tool=callgrind build/bin/bench_arm rne 1000
 * Prints ns/call (wall clock, CLOCK_MONOTONIC).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "arm_dyn.h"
#include "arm_kin.h"

#define NSAMPLES 64

static double q_set[NSAMPLES][ARM_NJ], qd_set[NSAMPLES][ARM_NJ], T_set[NSAMPLES][16];
static volatile double sink;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void make_samples(const arm_model *m)
{
    unsigned long s = 1;
    int i, j;
    for (i = 0; i < NSAMPLES; i++) {
        for (j = 0; j < ARM_NJ; j++) {
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            q_set[i][j] = m->q_min_rad[j] + (m->q_max_rad[j] - m->q_min_rad[j]) *
                                                (double)(s >> 11) / 9007199254740992.0;
            qd_set[i][j] = 0.5 * (double)((long)(s >> 40) % 7 - 3);
        }
        arm_fk(m, NULL, q_set[i], T_set[i]);
    }
}

static double run(const arm_model *m, const char *name, long n)
{
    double out[36], t0;
    arm_ik_result r;
    long k;
    t0 = now_s();
    for (k = 0; k < n; k++) {
        const int i = (int)(k % NSAMPLES);
        if (strcmp(name, "fk") == 0)
            arm_fk(m, NULL, q_set[i], out);
        else if (strcmp(name, "jac") == 0)
            arm_jacobian(m, NULL, q_set[i], out);
        else if (strcmp(name, "ik") == 0) {
            arm_ik(m, NULL, T_set[i], &r);
            out[0] = r.branch[0].q_rad[0];
        } else if (strcmp(name, "rne") == 0)
            arm_rne(m, q_set[i], qd_set[i], qd_set[(i + 1) % NSAMPLES], NULL, NULL, out);
        else if (strcmp(name, "mass") == 0)
            arm_mass_matrix(m, q_set[i], NULL, out);
        else if (strcmp(name, "grav") == 0)
            arm_gravity(m, q_set[i], NULL, NULL, out);
        else if (strcmp(name, "fd") == 0)
            arm_forward_dynamics(m, q_set[i], qd_set[i], qd_set[(i + 1) % NSAMPLES], NULL, NULL,
                                 out);
        else
            return -1.0;
        sink += out[0];
    }
    return (now_s() - t0) / (double)n * 1e9;
}

int main(int argc, char **argv)
{
    static const char *const all[] = { "fk", "jac", "ik", "rne", "mass", "grav", "fd" };
    const arm_model *m = &arm_model_puma560;
    long n = 100000;
    size_t k;
    if (argc < 2 || argc > 3) {
        fprintf(stderr, "usage: bench_arm fk|jac|ik|rne|mass|grav|fd|all [N]\n");
        return 2;
    }
    if (argc == 3 && (n = strtol(argv[2], NULL, 10)) <= 0) {
        fprintf(stderr, "bench_arm: N must be a positive integer\n");
        return 2;
    }
    make_samples(m);
    for (k = 0; k < sizeof all / sizeof all[0]; k++) {
        if (strcmp(argv[1], "all") != 0 && strcmp(argv[1], all[k]) != 0)
            continue;
        printf("%-5s %10.1f ns/call  (%ld calls, puma560)\n", all[k], run(m, all[k], n), n);
        if (strcmp(argv[1], "all") != 0)
            return 0;
    }
    if (strcmp(argv[1], "all") != 0) {
        fprintf(stderr, "bench_arm: unknown routine '%s'\n", argv[1]);
        return 2;
    }
    return 0;
}
