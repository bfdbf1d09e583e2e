/* cell: const layout of the two-arm workcell (SPEC.md §2.4, §5); see cell.h. */
#include "cell.h"
#include <math.h>
#include "vec3.h"

#define PI 3.14159265358979323846

const cell_layout cell_default = {
    .base_xyz_m = { { -0.60, 0.0, 0.0 }, { 0.60, 0.0, 0.0 } },
    .base_yaw_rad = { 0.0, PI },
    .table_center_m = { 0.0, 0.55, 0.175 },
    .table_size_m = { 1.80, 0.50, 0.05 },        /* top at z = 0.20 */
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
};

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
