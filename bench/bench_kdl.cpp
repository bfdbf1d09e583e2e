// bench_kdl: the same PUMA 560 chain in Orocos KDL and in the tandem core,
// timed in the same run (ns/call and ratio), plus the largest difference
// between the two results as a cross-check of the core's FK, Jacobian and
// RNE. C++ only because KDL is; the core is linked as plain C.
//   g++ -O2 -std=c++14 $(for d in include/tandem/*/; do printf -- "-I%s " $d; done) $(pkg-config --cflags orocos-kdl) bench/bench_kdl.cpp
//       build/lib/libtandem.a $(pkg-config --libs orocos-kdl) -lm -o build/bin/bench_kdl
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/chainjnttojacsolver.hpp>
#include <kdl/frames.hpp>
#include <kdl/jacobian.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>

#include "bench_pair.hpp"

extern "C" {
#include "arm_dyn.h"
#include "arm_kin.h"
#include "arm_model.h"
}

static double T_set[NS][16], q_set[NS][ARM_NJ], qd_set[NS][ARM_NJ], qdd_set[NS][ARM_NJ];
static volatile double sink;

static KDL::Chain make_chain(const arm_model &m)
{
    KDL::Chain c;
    c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None),
                              KDL::Frame(KDL::Vector(0, 0, m.base_height_m))));
    for (int i = 0; i < ARM_NJ; i++) {
        const double *I = m.inertia_kgm2[i];
        KDL::RigidBodyInertia rbi(m.mass_kg[i],
                                  KDL::Vector(m.com_m[i][0], m.com_m[i][1], m.com_m[i][2]),
                                  KDL::RotationalInertia(I[0], I[4], I[8], I[1], I[2], I[5]));
        // the rotor's reflected inertia as KDL's joint inertia (on the diagonal, as arm_rne)
        c.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::RotZ, 1.0, 0.0, m.armature_kgm2[i]),
                                  KDL::Frame::DH(m.a_m[i], m.alpha_rad[i], m.d_m[i],
                                                 m.theta_offset_rad[i]),
                                  rbi));
    }
    return c;
}

static void report(const char *what, double kdl_ns, double tandem_ns, double maxdiff)
{
    if (kdl_ns > 0)
        std::printf("%-22s kdl %8.1f ns  tandem %8.1f ns  kdl/tandem %5.2f  max|diff| %.2e\n",
                    what, kdl_ns, tandem_ns, kdl_ns / tandem_ns, maxdiff);
    else
        std::printf("%-22s kdl      n/a     tandem %8.1f ns\n", what, tandem_ns);
}

int main(int argc, char **argv)
{
    const arm_model &m = arm_model_puma560;
    const long n = argc > 1 ? std::atol(argv[1]) : 200000;
    if (n <= 0) {
        std::fprintf(stderr, "usage: bench_kdl [N]\n");
        return 2;
    }
    bench_samples(m, q_set, qd_set, qdd_set);

    KDL::Chain chain = make_chain(m);
    KDL::ChainFkSolverPos_recursive fk(chain);
    KDL::ChainJntToJacSolver jac(chain);
    KDL::ChainIdSolver_RNE rne(chain, KDL::Vector(0, 0, -ARM_GRAVITY_MPS2));
    KDL::ChainDynParam dyn(chain, KDL::Vector(0, 0, -ARM_GRAVITY_MPS2));
    KDL::JntSpaceInertiaMatrix kM(ARM_NJ);
    KDL::JntArray kq(ARM_NJ), kqd(ARM_NJ), kqdd(ARM_NJ), ktau(ARM_NJ);
    KDL::Frame kf;
    KDL::Jacobian kj(ARM_NJ);
    KDL::Wrenches fext(chain.getNrOfSegments(), KDL::Wrench::Zero());
    auto load = [&](int i) {
        for (int j = 0; j < ARM_NJ; j++) {
            kq(j) = q_set[i][j];
            kqd(j) = qd_set[i][j];
            kqdd(j) = qdd_set[i][j];
        }
    };

    // cross-check on every sample
    double dfk = 0, djac = 0, drne = 0, dmass = 0;
    for (int i = 0; i < NS; i++) {
        double T[16], J[36], tau[ARM_NJ], M[36];
        load(i);
        fk.JntToCart(kq, kf);
        jac.JntToJac(kq, kj);
        rne.CartToJnt(kq, kqd, kqdd, fext, ktau);
        dyn.JntToMass(kq, kM);
        arm_fk(&m, nullptr, q_set[i], T);
        arm_fk(&m, nullptr, q_set[i], T_set[i]);
        arm_mass_matrix(&m, q_set[i], nullptr, M);
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 6; c++)
                dmass = std::fmax(dmass, std::fabs(kM(r, c) - M[6 * r + c]));
        arm_jacobian(&m, nullptr, q_set[i], J);
        arm_rne(&m, q_set[i], qd_set[i], qdd_set[i], nullptr, nullptr, tau);
        for (int r = 0; r < 3; r++) {
            dfk = std::fmax(dfk, std::fabs(kf.p(r) - T[4 * r + 3]));
            for (int c = 0; c < 3; c++)
                dfk = std::fmax(dfk, std::fabs(kf.M(r, c) - T[4 * r + c]));
        }
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < 6; c++)
                djac = std::fmax(djac, std::fabs(kj(r, c) - J[6 * r + c]));
        for (int j = 0; j < ARM_NJ; j++)
            drne = std::fmax(drne, std::fabs(ktau(j) - tau[j]));
    }

    double out[36];
    arm_ik_result ikr;
    std::printf("PUMA 560, %ld calls each (best of %d batches), ns/call\n", n, BATCHES);
    double k1, t1, k2, t2, k3, t3, k5, t5, k4, t4;
    time_pair(n, [&](int i) { load(i); fk.JntToCart(kq, kf); sink += kf.p(0); },
              [&](int i) { arm_fk(&m, nullptr, q_set[i], out); sink += out[3]; }, &k1, &t1);
    report("FK", k1, t1, dfk);
    time_pair(n, [&](int i) { load(i); jac.JntToJac(kq, kj); sink += kj(0, 0); },
              [&](int i) { arm_jacobian(&m, nullptr, q_set[i], out); sink += out[0]; }, &k2, &t2);
    report("Jacobian", k2, t2, djac);
    time_pair(n, [&](int i) { load(i); rne.CartToJnt(kq, kqd, kqdd, fext, ktau); sink += ktau(0); },
              [&](int i) {
                  arm_rne(&m, q_set[i], qd_set[i], qdd_set[i], nullptr, nullptr, out);
                  sink += out[0];
              },
              &k3, &t3);
    report("RNE (inverse dyn.)", k3, t3, drne);
    time_pair(n, [&](int i) { load(i); dyn.JntToMass(kq, kM); sink += kM(0, 0); },
              [&](int i) { arm_mass_matrix(&m, q_set[i], nullptr, out); sink += out[0]; }, &k5, &t5);
    report("M(q) (KDL/CRBA)", k5, t5, dmass);
    time_pair(n, [&](int) {},
              [&](int i) { arm_ik(&m, nullptr, T_set[i], &ikr); sink += ikr.branch[0].q_rad[0]; },
              &k4, &t4);
    report("IK (all 8 branches)", 0, t4, 0);
    return 0;
}
