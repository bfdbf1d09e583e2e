/* bench_carry: cost of the carry task's two real-time steps.
 *   supervisor step: enable scan (petri_select) + one firing (start or
 *     completion) + P-invariant check, cycling the carry net forever;
 *   arm control cycle: cartseg_step (FK + Jacobian + Jdot qd, erlaw law,
 *     damped inverse, RNE with the held bar, torque clamp) on a PUMA 560
 *     tool-down pose of arm 1's cell, plus its parts.
 *
 *   bench_carry                 all figures (ns per call, wall clock, best
 *                               of 20 batches); with
 *                               valgrind in PATH also instructions per
 *                               call: callgrind (2N calls - N calls) / N
 *   bench_carry MODE N          MODE = sup | cycle | kin | jdot | law | inv | rne
 *                               (N calls only; for callgrind)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <math.h>

#include "arm_dyn.h"
#include "arm_kin.h"
#include "carry_net.h"
#include "cartseg.h"
#include "cell.h"
#include "erlaw.h"
#include "linalg.h"
#include "petri.h"
#include "stallwatch.h"
#include "vec3.h"

#define NSAMPLES 64

static volatile double sink;
static petri net;
static stallwatch stall;
static double sup_t_s;
static cartseg seg;
static arm_tool tool;
static arm_payload bar;
static double T_wb[16], q_set[NSAMPLES][ARM_NJ], qd_set[NSAMPLES][ARM_NJ];

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* One supervisor step: the daemon's enable scan, then start the chosen
 * transition (or, with none enabled, complete the lowest running one, as a
 * completion event would), then the invariant check it does on change and
 * its stall watch (with the pending-work scan). */
static int sup_step(void)
{
    int t = petri_select(&net), completed = 0, pending = 0;
    if (t >= 0) {
        petri_start(&net, t);
    } else {
        for (t = 0; t < carry_net.n_transitions; t++)
            if (petri_running(&net, t)) {
                petri_complete(&net, t);
                completed = 1;
                break;
            }
    }
    for (t = 0; t < carry_net.n_transitions && !pending; t++)
        pending = petri_running(&net, t) || petri_enabled(&net, t);
    sup_t_s += 0.01;
    stallwatch_update(&stall, sup_t_s, completed, pending, 0);
    return petri_invariants_hold(&net);
}

static int setup(void)
{
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    const double q_ref[ARM_NJ] = { 0.0, 0.6, 2.9, 0.0, -0.4, 0.0 };
    const double com[3] = { 0.1, 0.0, CELL_TOOL_LENGTH_M };
    double Rb[9], T[16], p[3], Tinv[16], R1[9], p1[3], q0[ARM_NJ];
    arm_ik_result r;
    unsigned long s = 1;
    int i, j;
    if (stallwatch_init(&stall, 30.0) != 0 || petri_init(&net, &carry_net) != 0)
        return -1;
    arm_tool_offset(&tool, off);
    arm_payload_point(&bar, cell_default.workpiece_mass_kg, com);
    cell_world_from_arm(&cell_default, 0, T_wb);
    tf_inverse(Tinv, T_wb);
    tf_apply(p, Tinv, cell_default.home_tool_m[0]);
    cell_tool_down_R(&cell_default, 0, Rb);
    tf_from_rot_pos(T, Rb, p);
    if (arm_ik(&arm_model_puma560, &tool, T, &r) != 0)
        return -1;
    memcpy(q0, r.branch[arm_ik_nearest(&r, q_ref)].q_rad, sizeof q0);
    vec3_set(R1, 1, 0, 0);
    vec3_set(R1 + 3, 0, -1, 0);
    vec3_set(R1 + 6, 0, 0, -1);
    vec3_copy(p1, cell_default.home_tool_m[0]);
    p1[0] -= 0.2;
    p1[2] -= 0.1;
    if (cartseg_start(&seg, &arm_model_puma560, &tool, T_wb, q0, p1, R1, &carry_table[0].lin,
                      ERLAW_REF_MEASURED) != 0)
        return -1;
    /* states near the segment: +-0.05 rad, +-0.5 rad/s */
    for (i = 0; i < NSAMPLES; i++)
        for (j = 0; j < ARM_NJ; j++) {
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            q_set[i][j] = q0[j] + 0.1 * ((double)(s >> 11) / 9007199254740992.0 - 0.5);
            qd_set[i][j] = 1.0 * ((double)(s >> 40) / 16777216.0 - 0.5);
        }
    return 0;
}

static void run(const char *mode, long n)
{
    long k;
    for (k = 0; k < n; k++) {
        const int i = (int)(k % NSAMPLES);
        const double *q = q_set[i], *qd = qd_set[i];
        if (strcmp(mode, "sup") == 0) {
            sink = sup_step();
        } else if (strcmp(mode, "cycle") == 0) {
            cartseg_out o;
            /* the daemon's joint watchdog, then the segment law */
            sink = arm_joint_faults(&arm_model_puma560, q, qd);
            cartseg_step(&seg, &arm_model_puma560, &tool, &bar, q, qd, -1.0, 1e-3, &o);
            sink = o.tau_Nm[0];
        } else if (strcmp(mode, "kin") == 0) {
            cartctl_state st;
            cartctl_state_at(&arm_model_puma560, &tool, q, qd, &st);
            sink = st.J[7];
        } else if (strcmp(mode, "jdot") == 0) {
            double jd[6];
            cartctl_jdot_qd(&arm_model_puma560, &tool, q, qd, jd);
            sink = jd[0];
        } else if (strcmp(mode, "law") == 0) {
            erlaw_out eo;
            double x[3] = { 0.3, 0.1, 0.4 }, v[3] = { 0.1, 0.0, 0.0 };
            x[0] += 1e-3 * (double)i;
            erlaw_line_step(&seg.line, x, v, ERLAW_REF_MEASURED, 0.0, 1e-3, &eo);
            sink = eo.u[0];
        } else if (strcmp(mode, "inv") == 0) {
            cartctl_state st;
            cartctl_out co;
            const double a[3] = { 0.1, 0.0, -0.1 };
            cartctl_state_at(&arm_model_puma560, &tool, q, qd, &st);
            cartctl_qdd(&arm_model_puma560, &tool, &seg.cg, q, qd, &st, a, seg.R_d_base, &co);
            sink = co.qdd[0];
        } else if (strcmp(mode, "rne") == 0) {
            double tau[ARM_NJ];
            arm_rne(&arm_model_puma560, q, qd, qd_set[(i + 1) % NSAMPLES], NULL, &bar, tau);
            sink = tau[0];
        }
    }
}

/* Best of 20 batches: on shared cores the mean measures the neighbours
 * (preemption), the minimum the code. */
static double ns_per_call(const char *mode, long n)
{
    const long batch = n / 20;
    double best = 1e30;
    int b;
    run(mode, batch); /* warm-up */
    for (b = 0; b < 20; b++) {
        const double t0 = now_s();
        run(mode, batch);
        best = fmin(best, (now_s() - t0) / (double)batch * 1e9);
    }
    return best;
}

/* Instructions per call under callgrind, or -1 without valgrind. */
static long instr_per_call(const char *self, const char *mode, long n)
{
    long ir[2] = { -1, -1 };
    int r;
    for (r = 0; r < 2; r++) {
        char cmd[1024], line[512];
        FILE *p;
        snprintf(cmd, sizeof cmd,
                 "valgrind --tool=callgrind --callgrind-out-file=/dev/null '%s' %s %ld 2>&1", self,
                 mode, n * (r + 1));
        /* NOLINTNEXTLINE(cert-env33-c): the command is this benchmark's own, built above */
        p = popen(cmd, "r");
        if (!p)
            return -1;
        while (fgets(line, sizeof line, p)) {
            const char *c = strstr(line, "Collected : ");
            if (c)
                ir[r] = strtol(c + 12, NULL, 10);
        }
        pclose(p);
    }
    return ir[0] > 0 && ir[1] > ir[0] ? (ir[1] - ir[0]) / n : -1;
}

int main(int argc, char **argv)
{
    static const char *const parts[] = { "kin", "jdot", "law", "inv", "rne" };
    static const char *const part_names[] = {
        "kinematics: FK + Jacobian + twist (cartctl_state_at)",
        "Jdot qd: kinematics pass + analytic (cartctl_jdot_qd)",
        "event law eq. 6-7 (erlaw_line_step)",
        "kinematics + damped inverse -> qdd (cartctl_qdd)",
        "dynamics: RNE with the held bar (arm_rne)",
    };
    /* NOLINTNEXTLINE(cert-env33-c): asks the shell whether valgrind is installed */
    const int have_vg = system("valgrind --version >/dev/null 2>&1") == 0;
    double sup_ns, cyc_ns;
    long sup_ir = -1, cyc_ir = -1;
    size_t i;
    if (setup() != 0) {
        fprintf(stderr, "bench_carry: set-up failed\n");
        return 1;
    }
    if (argc == 3) {
        run(argv[1], strtol(argv[2], NULL, 10));
        return 0;
    }
    sup_ns = ns_per_call("sup", 2000000);
    cyc_ns = ns_per_call("cycle", 200000);
    if (have_vg) {
        sup_ir = instr_per_call(argv[0], "sup", 1000);
        cyc_ir = instr_per_call(argv[0], "cycle", 1000);
    }
    printf("  supervisor step (enable scan + fire + invariant check): %7.1f ns", sup_ns);
    if (sup_ir > 0)
        printf(", %ld instructions", sup_ir);
    printf("\n  arm control cycle (cartseg_step, PUMA 560 + bar):      %7.3f us", cyc_ns * 1e-3);
    if (cyc_ir > 0)
        printf(", %ld instructions", cyc_ir);
    printf("  = %.2f%% of the 1 ms period (target < 5 us)\n", cyc_ns * 1e-6 * 100.0);
    printf("  parts of the cycle:\n");
    for (i = 0; i < sizeof parts / sizeof parts[0]; i++) {
        long ir = have_vg ? instr_per_call(argv[0], parts[i], 1000) : -1;
        printf("    %-55s %7.3f us", part_names[i], ns_per_call(parts[i], 200000) * 1e-3);
        if (ir > 0)
            printf(", %ld instructions", ir);
        printf("\n");
    }
    return 0;
}
