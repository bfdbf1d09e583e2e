/* tandem-scenario singularity: seed 002's S1 (docs/method/tdsd.md, seed Fig. 3-6).
 *
 * The seed-002 arm moves its tool on a straight line A -> B in 3.5 s with
 * the tool frame held; the wrist centre passes 3 mm from the joint-1 axis.
 * A, B and why: tools/scenario/tdsd_setup.c and docs/tdsd.md.
 *
 * Task: position (priority 1) + full orientation (priority 2), no criterion.
 * Methods: tdsd (tdsd_step), pinv (rr_pinv_step, clipped), dls (rr_dls_step,
 * variable damping, clipped).
 */
#include <stdio.h>
#include <string.h>
#include "scenario.h"
#include "tdsd_scen.h"
#include "tdsd_setup.h"

static const char *const methods[] = { "tdsd", "pinv", "dls", NULL };

static const tdsd_scen_usage usage = {
    "usage: tandem-scenario singularity [--method tdsd|pinv|dls] [--plant kin|ode]\n"
    "                                   [--servo-hz HZ] --out DIR\n"
    "Seed-002 arm, straight tool path A -> B whose wrist centre passes 3 mm from\n"
    "the joint-1 axis (shoulder singularity), 3.5 s, position + full orientation.\n\n",
    methods, "tdsd: the seed's method (tdsd_step); pinv: clipped pseudo-inverse; dls: damped",
    "Writes DIR/summary.json, series.csv, fig4_errors.png, fig5_joints.png,\n"
    "fig6_q1.png, fig8_joint_ranges.png.\n"
};
static int run(int argc, char **argv)
{
    tdsd_scen s;
    json_out j;
    memset(&s, 0, sizeof s);
    s.name = "singularity";
    switch (tdsd_scen_args(&s, argc, argv, &usage)) {
    case 0: break;
    case 1: return 0;
    default: return 2;
    }
    if (tdsd_setup_singularity(&s.cfg, &s.path, (tdsdrun_method)s.method_index, s.q0_rad) != 0) {
        fprintf(stderr, "tandem-scenario singularity: start pose A not reachable in range\n");
        return 1;
    }
    if (tdsd_scen_run(&s) != 0)
        return 1;
    if (json_open(&j, s.out, "summary.json") != 0)
        return 1;
    tdsd_scen_summary(&s, &j);
    json_point(&j, "A_m", s.path.wp_m[0], "%.3f %.3f %.3f");
    json_point(&j, "B_m", s.path.wp_m[1], "%.3f %.3f %.3f");
    tdsd_scen_finish(&s, &j);
    tdsd_scen_plots(&s, "S1 shoulder singularity");
    printf("singularity %s (%s): max_pos_err %.3f mm, max_ori_err %.2f deg, speed ratio %.3f "
           "(demand %.3g), min Q1 %.3f at %.3f s, Q1 outside region %.3f, duration %.3f s -> %s\n",
           s.method, s.plant_ode ? "ode" : "kin", s.m.max_pos_err_m * 1e3,
           s.m.max_ori_err_rad * 57.29577951308232, s.m.max_speed_ratio, s.m.max_demand_ratio,
           s.m.min_Q1, s.m.t_min_Q1_s, s.m.min_Q1_outside, s.duration_s, s.out);
    return tdsd_scen_exit(&s);
}

const scenario_def scenario_singularity = {
    "singularity", "seed 002 S1: straight path through the shoulder singularity (tdsd|pinv|dls)",
    run
};
