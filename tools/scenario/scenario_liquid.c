/* tandem-scenario liquid: seed 002's S2 (docs/method/tdsd.md, seed Fig. 7-8).
 *
 * The PUMA 560 (docs/method/tdsd.md joint ranges) carries a bucket upright from a to b
 * to c (straight segments, 3 s each, rest to rest); the base turns about
 * 200 deg. a, b, c, the start pose and why: tools/scenario/tdsd_setup.c
 * and docs/tdsd.md.
 *
 * tdsd: position (3 rows) + tool axis (2 rows, TDSD_ORIENT_AXIS) and the S2
 * criterion V = -sum_{4..6} ((q_i - mid_i)/(max_i - min_i))^2 in the
 * remaining freedom (the rotation about the bucket's axis, which the tool
 * point on z6 makes exactly a q6 motion). full: 6-D resolved rate with the
 * complete start orientation held (clipped pseudo-inverse): it must keep the
 * gripper's roll about the vertical, so q6 winds on by the base rotation.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "scenario.h"
#include "tdsd_scen.h"
#include "tdsd_setup.h"

#define DEG (3.14159265358979323846 / 180.0)

static const char *const methods[] = { "tdsd", "full", NULL };

static const tdsd_scen_usage usage = {
    "usage: tandem-scenario liquid [--method tdsd|full] [--plant kin|ode]\n"
    "                              [--servo-hz HZ] --out DIR\n"
    "PUMA 560 carries a bucket upright a -> b -> c (base turns ~200 deg).\n\n",
    methods,
    "tdsd: position + tool axis + mid-range criterion for q4..q6; full: 6-D resolved rate (start orientation held)",
    "Writes DIR/summary.json, series.csv, fig8_joint_ranges.png (seed Fig. 8),\n"
    "fig4_errors.png, fig5_joints.png, fig6_q1.png.\n"
};
static int run(int argc, char **argv)
{
    tdsd_scen s;
    json_out j;
    memset(&s, 0, sizeof s);
    s.name = "liquid";
    switch (tdsd_scen_args(&s, argc, argv, &usage)) {
    case 0: break;
    case 1: return 0;
    default: return 2;
    }
    if (tdsd_setup_liquid(&s.cfg, &s.path, s.method_index == 1, s.q0_rad) != 0) {
        fprintf(stderr, "tandem-scenario liquid: start pose a not reachable in range\n");
        return 1;
    }
    if (tdsd_scen_run(&s) != 0)
        return 1;
    if (json_open(&j, s.out, "summary.json") != 0)
        return 1;
    tdsd_scen_summary(&s, &j);
    json_point(&j, "a_m", s.path.wp_m[0], "%.4f %.4f %.2f");
    json_point(&j, "b_m", s.path.wp_m[1], "%.4f %.4f %.2f");
    json_point(&j, "c_m", s.path.wp_m[2], "%.4f %.4f %.2f");
    tdsd_scen_finish(&s, &j);
    tdsd_scen_plots(&s, "S2 liquid transport");
    printf("liquid %s (%s): max_tilt %.3f deg, joint_limit_violations %ld, q6 %.1f..%.1f deg "
           "(q6 excess %.1f deg), max_pos_err %.3f mm, speed ratio %.3f -> %s\n",
           s.method, s.plant_ode ? "ode" : "kin", s.m.max_tilt_rad / DEG,
           s.m.joint_limit_violations, s.m.q_lo_rad[5] / DEG, s.m.q_hi_rad[5] / DEG,
           s.m.max_excess_rad[5] / DEG, s.m.max_pos_err_m * 1e3, s.m.max_speed_ratio, s.out);
    return tdsd_scen_exit(&s);
}

const scenario_def scenario_liquid = {
    "liquid", "seed 002 S2: bucket carried upright a -> b -> c, joints in range (tdsd|full)", run
};
