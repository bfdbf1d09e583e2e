// bench_tdsd_kdl: one TDSD step (tdsd_step, docs/method/tdsd.md) beside Orocos KDL's
// velocity IK solvers ChainIkSolverVel_wdls and ChainIkSolverVel_pinv on the
// same PUMA 560 chain, timed in the same run. Figures
// only, nothing asserted. C++ only because KDL is; the core is linked as C.
//   bench_tdsd_kdl [N]          ns/call of every variant (best of 10 rounds
//                               of N/10 calls)
//   bench_tdsd_kdl N MODE       only MODE (tdsd | tdsd_jac | wdls | pinv),
//                               N calls, for callgrind: (I(N2) - I(N1)) / (N2 - N1)
// Variants: "tdsd" = tdsd_step on a given Jacobian and pose (what the
// resolver costs), "tdsd_jac" = arm_fk_jacobian + tdsd_step (a whole
// tdsd_seg cycle's kinematics + resolver; KDL's solvers compute their
// Jacobian inside CartToJnt but no pose). 64 joint vectors uniform in the
// joint ranges, each with a random twist / pose error; the same set for all.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include <kdl/chain.hpp>
#include <kdl/chainiksolvervel_pinv.hpp>
#include <kdl/chainiksolvervel_wdls.hpp>
#include <kdl/frames.hpp>
#include <kdl/jntarray.hpp>

extern "C" {
#include "arm_kin.h"
#include "arm_model.h"
#include "tdsd.h"
#include "vec3.h"
}

static const int NS = 64;
static double q_set[NS][ARM_NJ], tw_set[NS][6];
static double J_set[NS][36], T_set[NS][16];
static tdsd_input in_set[NS];
static volatile double sink;

static KDL::Chain make_chain(const arm_model &m)
{
    KDL::Chain c;
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(KDL::Vector(0, 0, m.base_height_m))));
    for (int i = 0; i < ARM_NJ; i++)
        c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ),
                                  KDL::Frame::DH(m.a_m[i], m.alpha_rad[i], m.d_m[i], m.theta_offset_rad[i])));
    return c;
}

// best of 10 rounds of n/10 calls: robust against other load on a shared machine
template <class F> static double time_ns(long n, F f)
{
    const long per = n >= 10 ? n / 10 : 1;
    double best = 1e300;
    for (int round = 0; round < 10; round++) {
        auto t0 = std::chrono::steady_clock::now();
        for (long k = 0; k < per; k++)
            f((int)(k % NS));
        auto t1 = std::chrono::steady_clock::now();
        best = std::fmin(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / (double)per);
    }
    return best;
}

// resolver input of sample i from its pose and Jacobian
static void make_input(const arm_model &m, int i)
{
    tdsd_input &in = in_set[i];
    double R[9], dR[9], k[3];
    std::memset(&in, 0, sizeof in);
    std::memcpy(in.J1, J_set[i], sizeof in.J1);
    std::memcpy(in.Jw, J_set[i] + 18, sizeof in.Jw);
    in.orient = TDSD_ORIENT_FULL;
    tf_pos(in.p_m, T_set[i]);
    tf_rot(R, T_set[i]);
    std::memcpy(in.R, R, sizeof in.R);
    for (int r = 0; r < 3; r++) {
        in.v_d_mps[r] = tw_set[i][r];
        in.w_d_radps[r] = tw_set[i][3 + r];
        in.p_d_m[r] = in.p_m[r] + 0.001 * tw_set[i][r];
    }
    vec3_set(k, tw_set[i][3], tw_set[i][4], tw_set[i][5]);
    vec3_normalize(k, k);
    rot_from_axis_angle(dR, k, 0.01);
    rot_mul(in.R_d, dR, R);
    in.K_p = 20.0;
    in.K_o = 10.0;
    in.k_V = 10.0;
    tdsd_midrange_grad(in.grad_V, nullptr, q_set[i], m.q_min_rad, m.q_max_rad, 0x38u);
    std::memcpy(in.dq_max_radps, m.qd_max_radps, sizeof in.dq_max_radps);
    in.rate_cap = 1.0;
}

int main(int argc, char **argv)
{
    const arm_model &m = arm_model_puma560;
    const long n = argc > 1 ? std::atol(argv[1]) : 100000;
    const char *only = argc > 2 ? argv[2] : nullptr;
    if (n <= 0 || argc > 3) {
        std::fprintf(stderr, "usage: bench_tdsd_kdl [N [tdsd|tdsd_jac|wdls|pinv]]\n");
        return 2;
    }
    unsigned long s = 7;
    for (int i = 0; i < NS; i++) {
        for (int j = 0; j < ARM_NJ; j++) {
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            double u = (double)(s >> 11) / 9007199254740992.0;
            q_set[i][j] = m.q_min_rad[j] + (m.q_max_rad[j] - m.q_min_rad[j]) * u;
            s = s * 6364136223846793005UL + 1442695040888963407UL;
            u = (double)(s >> 11) / 9007199254740992.0;
            tw_set[i][j] = (j < 3 ? 0.2 : 0.5) * (2.0 * u - 1.0);   // m/s, rad/s
        }
        arm_fk_jacobian(&m, nullptr, q_set[i], T_set[i], J_set[i]);
        make_input(m, i);
    }

    KDL::Chain chain = make_chain(m);
    KDL::ChainIkSolverVel_wdls wdls(chain);   // defaults: eps 1e-5, maxiter 150, lambda 0
    KDL::ChainIkSolverVel_pinv pinv(chain);   // defaults: eps 1e-5, maxiter 150
    KDL::JntArray kq(ARM_NJ), kqd(ARM_NJ);
    KDL::Twist tw;
    auto load = [&](int i) {
        for (int j = 0; j < ARM_NJ; j++)
            kq(j) = q_set[i][j];
        // KDL: twist of the end-effector, reference point at the end-effector,
        // base-frame coordinates (as the core's geometric Jacobian)
        tw = KDL::Twist(KDL::Vector(tw_set[i][0], tw_set[i][1], tw_set[i][2]),
                        KDL::Vector(tw_set[i][3], tw_set[i][4], tw_set[i][5]));
    };
    tdsd_output out;
    auto run_tdsd = [&](int i) { tdsd_step(&in_set[i], &out); sink += out.dq_radps[0]; };
    auto run_tdsd_jac = [&](int i) {
        tdsd_input in = in_set[i];
        double T[16], J[36];
        arm_fk_jacobian(&m, nullptr, q_set[i], T, J);
        std::memcpy(in.J1, J, sizeof in.J1);
        std::memcpy(in.Jw, J + 18, sizeof in.Jw);
        tf_pos(in.p_m, T);
        tdsd_step(&in, &out);
        sink += out.dq_radps[0];
    };
    auto run_wdls = [&](int i) { load(i); wdls.CartToJnt(kq, tw, kqd); sink += kqd(0); };
    auto run_pinv = [&](int i) { load(i); pinv.CartToJnt(kq, tw, kqd); sink += kqd(0); };

    if (only) {
        if (!std::strcmp(only, "tdsd")) time_ns(n, run_tdsd);
        else if (!std::strcmp(only, "tdsd_jac")) time_ns(n, run_tdsd_jac);
        else if (!std::strcmp(only, "wdls")) time_ns(n, run_wdls);
        else if (!std::strcmp(only, "pinv")) time_ns(n, run_pinv);
        else { std::fprintf(stderr, "bench_tdsd_kdl: unknown mode '%s'\n", only); return 2; }
        return 0;
    }

    // cross-check: with a regular J, KDL pinv's 6-D solution must match J^-1 twist
    double maxdiff = 0.0;
    int nreg = 0;
    for (int i = 0; i < NS; i++) {
        double U[36], sv[6], V[36];
        (void)U; (void)sv; (void)V;
        load(i);
        pinv.CartToJnt(kq, tw, kqd);
        double r[6];
        for (int a = 0; a < 6; a++) {
            r[a] = -tw_set[i][a];
            for (int b = 0; b < 6; b++)
                r[a] += J_set[i][6 * a + b] * kqd(b);
        }
        double e = 0.0;
        for (int a = 0; a < 6; a++)
            e = std::fmax(e, std::fabs(r[a]));
        maxdiff = std::fmax(maxdiff, e);
        nreg++;
    }
    std::printf("PUMA 560, %d samples, %ld calls each; KDL pinv check max|J qd - twist| = %.1e over %d samples\n",
                NS, n, maxdiff, nreg);
    const double t_pinv = time_ns(n, run_pinv);
    const double t_wdls = time_ns(n, run_wdls);
    const double t_tdsd = time_ns(n, run_tdsd);
    const double t_tdsd_jac = time_ns(n, run_tdsd_jac);
    std::printf("  %-44s %8.1f ns\n", "KDL ChainIkSolverVel_pinv::CartToJnt", t_pinv);
    std::printf("  %-44s %8.1f ns\n", "KDL ChainIkSolverVel_wdls::CartToJnt", t_wdls);
    std::printf("  %-44s %8.1f ns   wdls/tdsd %.2fx  pinv/tdsd %.2fx\n", "tandem tdsd_step (J given)", t_tdsd,
                t_wdls / t_tdsd, t_pinv / t_tdsd);
    std::printf("  %-44s %8.1f ns   wdls/this %.2fx  pinv/this %.2fx\n", "tandem arm_fk_jacobian + tdsd_step", t_tdsd_jac,
                t_wdls / t_tdsd_jac, t_pinv / t_tdsd_jac);
    return 0;
}
