/* tdsd_setup: S1 and S2 of seed 002 (docs/method/tdsd.md); why these numbers: see
 * docs/tdsd.md and the comments below.
 *
 * Base frame of both arms: z up along the joint-1 axis, mounting surface at
 * z = 0 (seed-002 shoulder at z = 0.671 m, PUMA 560 at 0.6718 m).
 */
#include "tdsd_setup.h"
#include "arm_kin.h"
#include "vec3.h"
#include <math.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

static int start_pose(const tdsdrun_cfg *c, const tdsdrun_path *p, const char *branch,
                      double q0[ARM_NJ])
{
    double T[16];
    arm_ik_result r;
    const int b = arm_ik_branch_from_name(branch);
    tf_from_rot_pos(T, p->R_d, p->wp_m[0]);
    if (b < 0 || arm_ik(c->model, &c->tool, T, &r) != 0 || r.branch[b].status != ARM_IK_OK)
        return TDSD_SETUP_ERR_START;
    memcpy(q0, r.branch[b].q_rad, sizeof(double) * ARM_NJ);
    return 0;
}

/* S1. Tool = the flange point (lg = 50 mm beyond the wrist centre, the
 * model's d6), frame held fixed: a = -x, o = +y, n = +z. Path A -> B,
 * straight, 3.5 s quintic:
 *   A = (-0.047, -0.25, 0.40) m,  B = (-0.047, +0.25, 0.40) m.
 * With that frame the wrist centre is the tool point + 50 mm along x, i.e.
 * on x = +3 mm: it passes 3 mm from the joint-1 axis at mid-path (shoulder
 * singularity), 0.271 m below the shoulder. Height and frame were chosen
 * where the seed-002 arm stays inside the docs/method/tdsd.md ranges along the whole
 * line on both sides of the axis; above the shoulder the seed-002 ranges of
 * q2/q3 leave no in-range pose for such a line. */
int tdsd_setup_singularity(tdsdrun_cfg *c, tdsdrun_path *p, tdsdrun_method method,
                           double q0_rad[ARM_NJ])
{
    static const double R_d[9] = {
        0, 0, -1, 0, 1, 0, 1, 0, 0
    }; /* columns n = +z, o = +y, a = -x */
    memset(c, 0, sizeof *c);
    memset(p, 0, sizeof *p);
    c->model = &arm_model_seed002;
    arm_tool_none(&c->tool);
    c->method = method;
    c->orient = TDSD_ORIENT_FULL;
    c->K_p = 20.0;
    c->K_o = 10.0;
    c->dls.lambda0 = 0.05; /* m/rad, the scale of the position rows */
    c->dls.eps = 0.05;
    c->T_recover_s = 0.5;
    c->dt_s = 0.001;
    c->settle_s = 1.0;
    c->region_m = 0.05; /* = lg: inside, the wrist's lever rivals q1's */
    p->n_wp = 2;
    vec3_set(p->wp_m[0], -0.047, -0.25, 0.40);
    vec3_set(p->wp_m[1], -0.047, 0.25, 0.40);
    p->seg_s[0] = 3.5;
    memcpy(p->R_d, R_d, sizeof R_d);
    return start_pose(c, p, "right-up-noflip", q0_rad);
}

/* S2. Bucket centre 0.10 m above the flange on z6, tool axis a = +z (up).
 * a, b, c: 0.55 m from the joint-1 axis at azimuth -100, 0, +100 deg,
 * z = 0.60 m; 3 s per straight segment, rest to rest. The base turns about
 * 200 deg; the chords stay >= 0.35 m from the axis (clear of the shoulder
 * singularity, d3 = 0.15 m). At a the gripper is rolled so that q6 = -100
 * deg (yaw 176 deg; inside +-266 deg): both methods start there. full holds
 * that roll about the vertical, so q6 follows the base rotation out of its
 * range; tdsd leaves the roll free and the criterion spends it on q6. */
int tdsd_setup_liquid(tdsdrun_cfg *c, tdsdrun_path *p, int full, double q0_rad[ARM_NJ])
{
    static const double az_deg[3] = { -100.0, 0.0, 100.0 };
    const double cy = cos(176.0 * DEG), sy = sin(176.0 * DEG);
    const double bucket[3] = { 0.0, 0.0, 0.10 };
    int i;
    memset(c, 0, sizeof *c);
    memset(p, 0, sizeof *p);
    c->model = &arm_model_puma560;
    arm_tool_offset(&c->tool, bucket);
    if (!full) {
        c->method = TDSDRUN_TDSD;
        c->orient = TDSD_ORIENT_AXIS;
        c->criterion_mask = 0x38; /* q4, q5, q6 */
        c->k_V = 50.0;
    } else {
        c->method = TDSDRUN_PINV;
        c->orient = TDSD_ORIENT_FULL;
    }
    c->K_p = 20.0;
    c->K_o = 10.0;
    c->T_recover_s = 0.5;
    c->dt_s = 0.001;
    c->settle_s = 0.5;
    c->region_m = 0.0; /* no singular region on this path */
    p->n_wp = 3;
    for (i = 0; i < 3; i++)
        vec3_set(p->wp_m[i], 0.55 * cos(az_deg[i] * DEG), 0.55 * sin(az_deg[i] * DEG), 0.60);
    p->seg_s[0] = p->seg_s[1] = 3.0;
    p->R_d[0] = cy;
    p->R_d[1] = -sy;
    p->R_d[2] = 0.0;
    p->R_d[3] = sy;
    p->R_d[4] = cy;
    p->R_d[5] = 0.0;
    p->R_d[6] = 0.0;
    p->R_d[7] = 0.0;
    p->R_d[8] = 1.0;
    return start_pose(c, p, "right-down-noflip", q0_rad);
}
