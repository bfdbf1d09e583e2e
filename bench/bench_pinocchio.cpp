// bench_pinocchio: the same PUMA 560 in Pinocchio (PyPI `pin`, its C++
// headers and library) and in the tandem core, timed in the same run in
// alternating batches (best of each), with the largest difference of the
// results as a cross-check. C++ only because Pinocchio is; the core is
// linked as plain C. Built by tools/bench.sh when `pip install pin` has
// put Pinocchio in reach (its cmeel prefix, pinocchio-prefix below):
//   g++ -O3 -DNDEBUG -std=c++17 -I<prefix>/include $(for d in include/tandem/*/; do printf -- "-I%s " $d; done)
//       bench/bench_pinocchio.cpp build/lib/libtandem.a -L<prefix>/lib -lpinocchio_default
//       -Wl,-rpath,<prefix>/lib -lm -o build/bin/bench_pinocchio
// Pinocchio's joints sit on the DH frames i-1 (joint i turns about z_{i-1});
// joint i+1 is placed Tz(d_i) Tx(a_i) Rx(alpha_i) after joint i, and link
// i's inertia, given in DH frame i, is moved by that placement into joint
// i's frame. The flange is an operational frame on joint 6.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include <pinocchio/multibody.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/frames.hpp>
#include <pinocchio/algorithm/jacobian.hpp>
#include <pinocchio/algorithm/kinematics.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include "bench_pair.hpp"

extern "C" {
#include "arm_dyn.h"
#include "arm_kin.h"
#include "arm_model.h"
}

namespace pin = pinocchio;

static double q_set[NS][ARM_NJ], qd_set[NS][ARM_NJ], qdd_set[NS][ARM_NJ];
static volatile double sink;

static pin::SE3 dh_after_joint(const arm_model &m, int i)
{
    // Tz(d) Tx(a) Rx(alpha)
    const double ca = std::cos(m.alpha_rad[i]), sa = std::sin(m.alpha_rad[i]);
    Eigen::Matrix3d R;
    R << 1, 0, 0, 0, ca, -sa, 0, sa, ca;
    return pin::SE3(R, Eigen::Vector3d(m.a_m[i], 0.0, m.d_m[i]));
}

static pin::Model make_model(const arm_model &m, pin::FrameIndex *flange)
{
    pin::Model model;
    pin::JointIndex parent = 0;
    pin::SE3 place(Eigen::Matrix3d::Identity(), Eigen::Vector3d(0, 0, m.base_height_m));
    for (int i = 0; i < ARM_NJ; i++) {
        const double *I = m.inertia_kgm2[i];
        Eigen::Matrix3d Ic;
        Ic << I[0], I[1], I[2], I[3], I[4], I[5], I[6], I[7], I[8];
        const pin::Inertia in_link(m.mass_kg[i], Eigen::Vector3d(m.com_m[i][0], m.com_m[i][1], m.com_m[i][2]),
                                   Ic);
        const pin::SE3 after = dh_after_joint(m, i);
        parent = model.addJoint(parent, pin::JointModelRZ(), place, "j" + std::to_string(i + 1));
        model.appendBodyToJoint(parent, after.act(in_link), pin::SE3::Identity());
        place = after;
    }
    // the rotors' reflected inertia (arm_model.h armature_kgm2), which the
    // core adds to M's diagonal and J_i qdd_i to tau_i: Pinocchio's crba
    // and rnea do the same with model.armature
    model.armature = Eigen::Map<const Eigen::VectorXd>(m.armature_kgm2, ARM_NJ);
    model.gravity.linear(Eigen::Vector3d(0, 0, -ARM_GRAVITY_MPS2));
    *flange = model.addFrame(pin::Frame("flange", parent, 0, place, pin::OP_FRAME));
    return model;
}

static void report(const char *what, double p_ns, double t_ns, double maxdiff)
{
    std::printf("%-22s pinocchio %8.1f ns  tandem %8.1f ns  pinocchio/tandem %5.2f  max|diff| %.2e\n", what,
                p_ns, t_ns, p_ns / t_ns, maxdiff);
}

int main(int argc, char **argv)
{
    const arm_model &m = arm_model_puma560;
    const long n = argc > 1 ? std::atol(argv[1]) : 200000;
    if (n <= 0) {
        std::fprintf(stderr, "usage: bench_pinocchio [N]\n");
        return 2;
    }
    bench_samples(m, q_set, qd_set, qdd_set);
    pin::FrameIndex fid;
    const pin::Model model = make_model(m, &fid);
    pin::Data data(model);
    Eigen::VectorXd pq[NS], pqd[NS], pqdd[NS];
    for (int i = 0; i < NS; i++) {
        pq[i] = Eigen::Map<Eigen::VectorXd>(q_set[i], ARM_NJ);
        pqd[i] = Eigen::Map<Eigen::VectorXd>(qd_set[i], ARM_NJ);
        pqdd[i] = Eigen::Map<Eigen::VectorXd>(qdd_set[i], ARM_NJ);
    }
    pin::Data::Matrix6x Jp(6, ARM_NJ);

    // cross-check on every sample
    double dfk = 0, djac = 0, drne = 0, dmass = 0;
    for (int i = 0; i < NS; i++) {
        double T[16], J[36], tau[ARM_NJ], M[36];
        pin::forwardKinematics(model, data, pq[i]);
        pin::updateFramePlacement(model, data, fid);
        arm_fk(&m, nullptr, q_set[i], T);
        for (int r = 0; r < 3; r++) {
            dfk = std::fmax(dfk, std::fabs(data.oMf[fid].translation()(r) - T[4 * r + 3]));
            for (int c = 0; c < 3; c++)
                dfk = std::fmax(dfk, std::fabs(data.oMf[fid].rotation()(r, c) - T[4 * r + c]));
        }
        Jp.setZero();
        pin::computeFrameJacobian(model, data, pq[i], fid, pin::LOCAL_WORLD_ALIGNED, Jp);
        arm_jacobian(&m, nullptr, q_set[i], J);
        for (int r = 0; r < 6; r++)
            for (int c = 0; c < ARM_NJ; c++)
                djac = std::fmax(djac, std::fabs(Jp(r, c) - J[6 * r + c]));
        pin::rnea(model, data, pq[i], pqd[i], pqdd[i]);
        arm_rne(&m, q_set[i], qd_set[i], qdd_set[i], nullptr, nullptr, tau);
        for (int j = 0; j < ARM_NJ; j++)
            drne = std::fmax(drne, std::fabs(data.tau(j) - tau[j]));
        pin::crba(model, data, pq[i]);
        arm_mass_matrix(&m, q_set[i], nullptr, M);
        for (int r = 0; r < ARM_NJ; r++)
            for (int c = r; c < ARM_NJ; c++)   // crba fills the upper triangle
                dmass = std::fmax(dmass, std::fabs(data.M(r, c) - M[6 * r + c]));
    }

    std::printf("PUMA 560, %ld calls each (best of %d alternating batches), ns/call\n", n, BATCHES);
    double p_ns, t_ns;
    time_pair(n,
              [&](int i) {
                  pin::forwardKinematics(model, data, pq[i]);
                  pin::updateFramePlacement(model, data, fid);
                  sink = data.oMf[fid].translation()(0);
              },
              [&](int i) {
                  double T[16];
                  arm_fk(&m, nullptr, q_set[i], T);
                  sink = T[3];
              },
              &p_ns, &t_ns);
    report("FK", p_ns, t_ns, dfk);
    time_pair(n,
              [&](int i) {
                  pin::computeFrameJacobian(model, data, pq[i], fid, pin::LOCAL_WORLD_ALIGNED, Jp);
                  sink = Jp(0, 0);
              },
              [&](int i) {
                  double J[36];
                  arm_jacobian(&m, nullptr, q_set[i], J);
                  sink = J[0];
              },
              &p_ns, &t_ns);
    report("Jacobian", p_ns, t_ns, djac);
    time_pair(n,
              [&](int i) {
                  pin::rnea(model, data, pq[i], pqd[i], pqdd[i]);
                  sink = data.tau(0);
              },
              [&](int i) {
                  double tau[ARM_NJ];
                  arm_rne(&m, q_set[i], qd_set[i], qdd_set[i], nullptr, nullptr, tau);
                  sink = tau[0];
              },
              &p_ns, &t_ns);
    report("RNEA", p_ns, t_ns, drne);
    time_pair(n,
              [&](int i) {
                  pin::crba(model, data, pq[i]);
                  sink = data.M(0, 0);
              },
              [&](int i) {
                  double M[36];
                  arm_mass_matrix(&m, q_set[i], nullptr, M);
                  sink = M[0];
              },
              &p_ns, &t_ns);
    report("M(q) (CRBA)", p_ns, t_ns, dmass);
    return (dfk < 1e-9 && djac < 1e-9 && drne < 1e-9 && dmass < 1e-9) ? 0 : 1;
}
