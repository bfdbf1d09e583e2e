/* cell: const layout of the two-arm workcell (docs/method/carry.md §5, §5), the frame
 * helpers every program places the arms with, and cell_layout_validate,
 * which checks the layout fits together (no equation: geometry only); see
 * cell.h. */
#include "cell.h"
#include <math.h>
#include <stddef.h>
#include "vec3.h"

#define PI 3.14159265358979323846

const cell_layout cell_default = {
    .base_xyz_m = { { -0.60, 0.0, 0.0 }, { 0.60, 0.0, 0.0 } },
    .base_yaw_rad = { 0.0, PI },
    .table_center_m = { 0.0, 0.55, 0.175 },
    .table_size_m = { 1.80, 0.50, 0.05 }, /* top at z = 0.20 */
    .workpiece_size_m = { 0.30, 0.04, 0.04 },
    .workpiece_mass_kg = 0.5,
    .grasp_offset_m = 0.10,
    .grasp_tolerance_m = 0.02,
    .pick_center_m = { -0.60, 0.50, 0.22 },
    .pick_spread_m = { 0.05, 0.04 },
    .deliver_center_m = { 0.60, 0.50, 0.22 },
    .handover_center_m = { 0.0, 0.35, 0.45 },
    .approach_height_m = 0.13,
    .home_tool_m = { { -0.50, 0.50, 0.45 }, { 0.50, 0.50, 0.45 } },
    /* 0.18 m behind the delivery pose, arm 2's grasp point 0.68 m from its
     * base axis; arm 1 cannot reach it */
    .magazine_center_m = { 0.45, 0.68, 0.22 },
    /* 0.12 m behind the hand-over: its grasp points 6 grasp tolerances from
     * the first place's, where both arms keep more joint-range margin */
    .stand_b_center_m = { 0.0, 0.47, 0.45 },
};

/* Every number of the layout, group by group. */
static int numbers_finite(const cell_layout *c)
{
    const double *groups[] = { c->base_xyz_m[0],      c->base_xyz_m[1],      c->base_yaw_rad,
                               c->table_center_m,     c->table_size_m,       c->workpiece_size_m,
                               &c->workpiece_mass_kg, &c->grasp_offset_m,    &c->grasp_tolerance_m,
                               c->pick_center_m,      c->pick_spread_m,      c->deliver_center_m,
                               c->handover_center_m,  &c->approach_height_m, c->home_tool_m[0],
                               c->home_tool_m[1],     c->magazine_center_m,  c->stand_b_center_m };
    const int len[] = { 3, 3, CELL_ARMS, 3, 3, 3, 1, 1, 1, 3, 2, 3, 3, 1, 3, 3, 3, 3 };
    size_t g;
    int i;
    for (g = 0; g < sizeof groups / sizeof groups[0]; g++)
        for (i = 0; i < len[g]; i++)
            if (!isfinite(groups[g][i]))
                return 0;
    return 1;
}

static int positive(const double *v, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!(v[i] > 0.0))
            return 0;
    return 1;
}

/* A workpiece centred at p (+- spread in x, y) lies on the table top,
 * inside the table's footprint. */
static int rests_on_table(const cell_layout *c, const double p[3], const double spread[2])
{
    /* same tolerance the layout's own test uses for "resting on" */
    const double top = c->table_center_m[2] + 0.5 * c->table_size_m[2];
    int k;
    if (fabs(p[2] - 0.5 * c->workpiece_size_m[2] - top) > 1e-9)
        return 0;
    for (k = 0; k < 2; k++)
        if (fabs(p[k] - c->table_center_m[k]) + spread[k] + 0.5 * c->workpiece_size_m[k] >
            0.5 * c->table_size_m[k])
            return 0;
    return 1;
}

/* A bar centred at p is held above the table top. */
static int above_table(const cell_layout *c, const double p[3])
{
    return p[2] - 0.5 * c->workpiece_size_m[2] > c->table_center_m[2] + 0.5 * c->table_size_m[2];
}

/* The stand's two places hold two bars apart: no grasp point of one within
 * a grasp tolerance of the other's bar. */
static int stand_places_apart(const cell_layout *c)
{
    const double dx = c->stand_b_center_m[0] - c->handover_center_m[0];
    const double dy = c->stand_b_center_m[1] - c->handover_center_m[1];
    return hypot(dx, dy) > c->workpiece_size_m[1] + 2.0 * c->grasp_tolerance_m;
}

int cell_layout_validate(const cell_layout *c)
{
    static const double no_spread[2] = { 0.0, 0.0 };
    double arms_apart[3];
    if (!c)
        return CELL_ERR_ARG;
    if (!numbers_finite(c))
        return CELL_ERR_NONFINITE;
    if (!positive(c->table_size_m, 3) || !positive(c->workpiece_size_m, 3) ||
        !positive(&c->workpiece_mass_kg, 1) || !positive(&c->grasp_offset_m, 1) ||
        !positive(&c->grasp_tolerance_m, 1) || !positive(&c->approach_height_m, 1) ||
        c->pick_spread_m[0] < 0.0 || c->pick_spread_m[1] < 0.0)
        return CELL_ERR_RANGE;
    if (c->grasp_offset_m + c->grasp_tolerance_m > 0.5 * c->workpiece_size_m[0] ||
        !rests_on_table(c, c->pick_center_m, c->pick_spread_m) ||
        !rests_on_table(c, c->deliver_center_m, no_spread) ||
        !rests_on_table(c, c->magazine_center_m, no_spread) ||
        !above_table(c, c->handover_center_m) || !above_table(c, c->stand_b_center_m) ||
        !stand_places_apart(c))
        return CELL_ERR_INCONSISTENT;
    vec3_sub(arms_apart, c->base_xyz_m[1], c->base_xyz_m[0]);
    if (!(vec3_norm(arms_apart) > 0.0))
        return CELL_ERR_INCONSISTENT;
    return 0;
}

void cell_world_from_arm(const cell_layout *c, int a, double T[16])
{
    double R[9];
    const double z[3] = { 0.0, 0.0, 1.0 };
    rot_from_axis_angle(R, z, c->base_yaw_rad[a]);
    tf_from_rot_pos(T, R, c->base_xyz_m[a]);
}

void cell_tool_down_R(const cell_layout *c, int a, double R_arm[9])
{
    /* World tool-down: flange x along world x, z along -world z. */
    const double R_world[9] = { 1, 0, 0, 0, -1, 0, 0, 0, -1 };
    double T[16], Rb[9];
    cell_world_from_arm(c, a, T);
    tf_rot(Rb, T);
    rot_tmul(R_arm, Rb, R_world);
}

void cell_grasp_point(const cell_layout *c, int a, const double centre_world[3], double p_world[3])
{
    vec3_copy(p_world, centre_world);
    p_world[0] += (a == 0 ? -1.0 : 1.0) * c->grasp_offset_m;
}
