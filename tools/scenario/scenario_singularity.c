/* tandem-scenario singularity: seed 002's S1 (SPEC.md §3, seed Fig. 3-6).
 *
 * The seed-002 arm moves its tool (the flange point, lg = 50 mm beyond the
 * wrist centre) on a straight line A -> B in 3.5 s (quintic time law)
 * with the tool frame held fixed: approach a = -x, o = +y, n = +z (base
 * frame: z up along the joint-1 axis, mounting surface at z = 0, shoulder
 * at z = 0.671 m).
 *
 *   A = (-0.047, -0.25, 0.40) m,  B = (-0.047, +0.25, 0.40) m.
 *
 * Why there: with that orientation the wrist centre is the tool point
 * + 50 mm along x, i.e. on the line x = +3 mm, y = -0.25 .. 0.25,
 * z = 0.40 m: it passes 3 mm from the joint-1 axis at mid-path (the
 * shoulder singularity), 0.271 m below the shoulder. This height and
 * orientation are where the seed-002 arm stays inside the SPEC §3 joint
 * ranges on the whole path on both sides of the axis (start branch
 * right-up-noflip: q = -89.3 17.5 140.4 -89.4 -89.7 22.1 deg); above the
 * shoulder the SPEC ranges of q2/q3 leave no in-range pose for this line.
 *
 * Task: position (priority 1) + full orientation (priority 2), no criterion.
 * Methods: tdsd (tdsd_step), pinv (rr_pinv_step, clipped), dls (rr_dls_step,
 * variable damping, clipped).
 */
#include <stdio.h>
#include <string.h>
#include "scenario.h"
#include "tdsd_scen.h"
#include "vec3.h"

static const char *const methods[] = { "tdsd", "pinv", "dls" };

static void usage(FILE *f)
{
    fprintf(f, "usage: tandem-scenario singularity [--method tdsd|pinv|dls] [--plant kin|ode]\n"
               "                                   [--servo-hz HZ] --out DIR\n"
               "Seed-002 arm, straight tool path A -> B whose wrist centre passes 3 mm from\n"
               "the joint-1 axis (shoulder singularity), 3.5 s, position + full orientation.\n"
               "  --method    tdsd (default) | pinv (clipped pseudo-inverse) | dls (damped)\n"
               "  --plant     kin (integrate dq at 1 kHz, default) | ode (tandem-sim +\n"
               "              tandem-arm tracking ARM1_JOINT_REF in lockstep)\n"
               "  --servo-hz  ode: tandem-arm joint servo bandwidth (default 15)\n"
               "Writes DIR/summary.json, series.csv, fig4_errors.png, fig5_joints.png,\n"
               "fig6_q1.png, fig8_joint_ranges.png.\n");
}

/* The S1 set-up (also used by test/test_tdsd_scenario.c through the same
 * numbers: keep them in step). */
static void setup(tdsd_scen *s)
{
    static const double R_d[9] = { 0, 0, -1,
                                   0, 1, 0,
                                   1, 0, 0 };   /* columns n = +z, o = +y, a = -x */
    memset(&s->cfg, 0, sizeof s->cfg);
    memset(&s->path, 0, sizeof s->path);
    s->cfg.model = &arm_model_seed002;
    arm_tool_none(&s->cfg.tool);                /* lg = 50 mm is d6 of the model */
    s->cfg.method = (tdsdrun_method)s->method_index;
    s->cfg.orient = TDSD_ORIENT_FULL;
    s->cfg.K_p = 20.0;
    s->cfg.K_o = 10.0;
    s->cfg.dls.lambda0 = 0.05;                  /* m/rad scale of the position rows */
    s->cfg.dls.eps = 0.05;
    s->cfg.T_recover_s = 0.5;
    s->cfg.dt_s = 0.001;
    s->cfg.settle_s = 1.0;
    s->cfg.region_m = 0.05;                     /* = lg: inside it the wrist lever rivals the shoulder's */
    s->path.n_wp = 2;
    vec3_set(s->path.wp_m[0], -0.047, -0.25, 0.40);
    vec3_set(s->path.wp_m[1], -0.047, 0.25, 0.40);
    s->path.seg_s[0] = 3.5;
    memcpy(s->path.R_d, R_d, sizeof R_d);
}

static int run(int argc, char **argv)
{
    tdsd_scen s;
    json_out j;
    memset(&s, 0, sizeof s);
    s.name = "singularity";
    switch (tdsd_scen_args(&s, argc, argv, methods, 3, usage)) {
    case 0: break;
    case 1: return 0;
    default: return 2;
    }
    setup(&s);
    if (tdsd_scen_start_pose(&s, "right-up-noflip") != 0)
        return 1;
    if (tdsd_scen_run(&s) != 0)
        return 1;
    if (json_open(&j, s.out, "summary.json") != 0)
        return 1;
    tdsd_scen_summary(&s, &j);
    json_str(&j, "A_m", "-0.047 -0.25 0.40");
    json_str(&j, "B_m", "-0.047 0.25 0.40");
    json_close(&j);
    tdsd_scen_plots(&s, "S1 shoulder singularity");
    printf("singularity %s (%s): max_pos_err %.3f mm, max_ori_err %.2f deg, speed ratio %.3f "
           "(demand %.3g), min Q1 %.3f at %.3f s, Q1 outside region %.3f, duration %.3f s -> %s\n",
           s.method, s.plant_ode ? "ode" : "kin", s.m.max_pos_err_m * 1e3,
           s.m.max_ori_err_rad * 57.29577951308232, s.m.max_speed_ratio, s.m.max_demand_ratio,
           s.m.min_Q1, s.m.t_min_Q1_s, s.m.min_Q1_outside, s.duration_s, s.out);
    return 0;
}

const scenario_def scenario_singularity = {
    "singularity",
    "seed 002 S1: straight path through the shoulder singularity (tdsd|pinv|dls)",
    run
};
