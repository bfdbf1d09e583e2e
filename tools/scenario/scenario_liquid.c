/* tandem-scenario liquid: seed 002's S2 (SPEC.md §3, seed Fig. 7-8).
 *
 * The PUMA 560 (SPEC §3 joint ranges) carries a bucket upright from a to b
 * to c: straight segments of 3 s each, rest to rest (quintic), bucket
 * centre 0.10 m above the flange on its z axis, tool axis a = world +z.
 * Base frame: z up along the joint-1 axis, mounting surface z = 0.
 *
 *   a = 0.55 m at azimuth -100 deg, b = 0.55 m at 0 deg, c = 0.55 m at
 *   +100 deg, all at z = 0.60 m (0.07 m below the shoulder).
 *
 * The base turns about 200 deg in all; the chords stay >= 0.35 m from the
 * joint-1 axis (well clear of the shoulder singularity, d3 = 0.15 m).
 * At a the bucket is held with the gripper rolled to q6 = -100 deg (inside
 * its +-266 deg range; e.g. as it was picked off a shelf); both methods
 * start from that same joint vector (branch right-down-noflip:
 * q = -84.2 -67.9 12.5 0 55.4 -99.8 deg).
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
#include "vec3.h"

#define DEG (3.14159265358979323846 / 180.0)

static const char *const methods[] = { "tdsd", "full" };

static void usage(FILE *f)
{
    fprintf(f, "usage: tandem-scenario liquid [--method tdsd|full] [--plant kin|ode]\n"
               "                              [--servo-hz HZ] --out DIR\n"
               "PUMA 560 carries a bucket upright a -> b -> c (base turns ~200 deg).\n"
               "  --method    tdsd (default): position + tool axis + mid-range criterion\n"
               "              for q4..q6 | full: 6-D resolved rate (start orientation held)\n"
               "  --plant     kin (integrate dq at 1 kHz, default) | ode (tandem-sim +\n"
               "              tandem-arm tracking ARM1_JOINT_REF in lockstep)\n"
               "  --servo-hz  ode: tandem-arm joint servo bandwidth (default 15)\n"
               "Writes DIR/summary.json, series.csv, fig8_joint_ranges.png (seed Fig. 8),\n"
               "fig4_errors.png, fig5_joints.png, fig6_q1.png.\n");
}

static void setup(tdsd_scen *s)
{
    static const double az_deg[3] = { -100.0, 0.0, 100.0 };
    /* yaw 176 deg about +z: the roll that puts q6 at -100 deg at a */
    const double c = cos(176.0 * DEG), sn = sin(176.0 * DEG);
    const double R_d[9] = { c, -sn, 0, sn, c, 0, 0, 0, 1 };
    const double bucket[3] = { 0.0, 0.0, 0.10 };
    int i;
    memset(&s->cfg, 0, sizeof s->cfg);
    memset(&s->path, 0, sizeof s->path);
    s->cfg.model = &arm_model_puma560;
    arm_tool_offset(&s->cfg.tool, bucket);
    if (s->method_index == 0) {
        s->cfg.method = TDSDRUN_TDSD;
        s->cfg.orient = TDSD_ORIENT_AXIS;
        s->cfg.criterion_mask = 0x38;           /* q4, q5, q6 */
        s->cfg.k_V = 50.0;
    } else {
        s->cfg.method = TDSDRUN_PINV;
        s->cfg.orient = TDSD_ORIENT_FULL;
    }
    s->cfg.K_p = 20.0;
    s->cfg.K_o = 10.0;
    s->cfg.T_recover_s = 0.5;
    s->cfg.dt_s = 0.001;
    s->cfg.settle_s = 0.5;
    s->cfg.region_m = 0.0;                      /* no singular region on this path */
    s->path.n_wp = 3;
    for (i = 0; i < 3; i++)
        vec3_set(s->path.wp_m[i], 0.55 * cos(az_deg[i] * DEG), 0.55 * sin(az_deg[i] * DEG), 0.60);
    s->path.seg_s[0] = s->path.seg_s[1] = 3.0;
    memcpy(s->path.R_d, R_d, sizeof R_d);
}

static int run(int argc, char **argv)
{
    tdsd_scen s;
    json_out j;
    char buf[96];
    memset(&s, 0, sizeof s);
    s.name = "liquid";
    switch (tdsd_scen_args(&s, argc, argv, methods, 2, usage)) {
    case 0: break;
    case 1: return 0;
    default: return 2;
    }
    setup(&s);
    if (tdsd_scen_start_pose(&s, "right-down-noflip") != 0)
        return 1;
    if (tdsd_scen_run(&s) != 0)
        return 1;
    if (json_open(&j, s.out, "summary.json") != 0)
        return 1;
    tdsd_scen_summary(&s, &j);
    snprintf(buf, sizeof buf, "%.4f %.4f %.2f", s.path.wp_m[0][0], s.path.wp_m[0][1], s.path.wp_m[0][2]);
    json_str(&j, "a_m", buf);
    snprintf(buf, sizeof buf, "%.4f %.4f %.2f", s.path.wp_m[1][0], s.path.wp_m[1][1], s.path.wp_m[1][2]);
    json_str(&j, "b_m", buf);
    snprintf(buf, sizeof buf, "%.4f %.4f %.2f", s.path.wp_m[2][0], s.path.wp_m[2][1], s.path.wp_m[2][2]);
    json_str(&j, "c_m", buf);
    json_close(&j);
    tdsd_scen_plots(&s, "S2 liquid transport");
    printf("liquid %s (%s): max_tilt %.3f deg, joint_limit_violations %ld, q6 %.1f..%.1f deg "
           "(q6 excess %.1f deg), max_pos_err %.3f mm, speed ratio %.3f -> %s\n",
           s.method, s.plant_ode ? "ode" : "kin", s.m.max_tilt_rad / DEG, s.m.joint_limit_violations,
           s.m.q_lo_rad[5] / DEG, s.m.q_hi_rad[5] / DEG, s.m.max_excess_rad[5] / DEG,
           s.m.max_pos_err_m * 1e3, s.m.max_speed_ratio, s.out);
    return 0;
}

const scenario_def scenario_liquid = {
    "liquid",
    "seed 002 S2: bucket carried upright a -> b -> c, joints in range (tdsd|full)",
    run
};
