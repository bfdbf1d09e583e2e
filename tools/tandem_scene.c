/* tandem-scene: prints the static geometry of the simulated world as JSON,
 * straight from the core's const tables (arm_model, cell, rover_world,
 * formation, sonar), so that viewers and plotting scripts draw the same
 * arms, table, obstacles, goal and formation slots the controllers use
 * instead of keeping their own copies of the numbers.
 *
 *   tandem-scene [--world NAME | --world-file PATH [--start X,Y,THETA] [--goal X,Y]]
 *                [--rovers N] [--formation F] [--arm1 MODEL] [--urdf]
 * A world file that gives no layout is refused (exit 2), which is how
 * tools/tandem-run checks one before it starts anything.
 *
 * --urdf writes the cell as URDF instead (both arms, the table, a Pioneer),
 * for tools that read robot descriptions (RViz, Foxglove, PyBullet ...).
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "arm_model.h"
#include "cell.h"
#include "formation.h"
#include "odometry.h"
#include "rover_world.h"
#include "sonar.h"
#include "options.h"
#include "world_file.h"

static void json_array(const char *key, const double *v, int n, const char *sep)
{
    int i;
    printf("\"%s\": [", key);
    for (i = 0; i < n; i++)
        printf("%s%.10g", i ? ", " : "", v[i]);
    printf("]%s", sep);
}

static void print_arm_model(const char *key, const arm_model *m)
{
    printf("\"%s\": {\"name\": \"%s\", \"base_height_m\": %.10g, ", key, m->name, m->base_height_m);
    json_array("a_m", m->a_m, ARM_NJ, ", ");
    json_array("d_m", m->d_m, ARM_NJ, ", ");
    json_array("alpha_rad", m->alpha_rad, ARM_NJ, ", ");
    json_array("theta_offset_rad", m->theta_offset_rad, ARM_NJ, "");
    printf("},\n");
}

static void print_cell(const cell_layout *c)
{
    int a;
    printf("\"cell\": {\"tool_length_m\": %.10g, \"arm_base_T\": [", CELL_TOOL_LENGTH_M);
    for (a = 0; a < CELL_ARMS; a++) {
        double T[16];
        int i;
        cell_world_from_arm(c, a, T);
        printf("%s[", a ? ", " : "");
        for (i = 0; i < 16; i++)
            printf("%s%.10g", i ? ", " : "", T[i]);
        printf("]");
    }
    printf("],\n  ");
    json_array("table_center_m", c->table_center_m, 3, ", ");
    json_array("table_size_m", c->table_size_m, 3, ", ");
    json_array("workpiece_size_m", c->workpiece_size_m, 3, ", ");
    printf("\"grasp_offset_m\": %.10g, ", c->grasp_offset_m);
    json_array("pick_center_m", c->pick_center_m, 3, ", ");
    json_array("handover_center_m", c->handover_center_m, 3, ", ");
    json_array("deliver_center_m", c->deliver_center_m, 3, "");
    printf("},\n");
}

static void print_obstacle(const rover_obstacle *o, const char *sep)
{
    printf("    {\"kind\": \"%s\", \"c_m\": [%.10g, %.10g], \"half_m\": [%.10g, %.10g], "
           "\"angle_rad\": %.10g, \"r_m\": %.10g, \"height_m\": %.10g}%s\n",
           o->kind == ROVER_OBST_CIRCLE ? "circle" : "box", o->cx_m, o->cy_m, o->hx_m, o->hy_m,
           o->angle_rad, o->r_m, o->height_m, sep);
}

static void print_rover_world(const rover_world_config *w)
{
    int i;
    printf("\"rover_world\": {\"name\": \"%s\", \"n_robots\": %d, ", rover_world_name(w->world),
           w->n_robots);
    json_array("goal_m", w->goal_m, 2, ", ");
    printf("\"team_origin\": [%.10g, %.10g, %.10g], ", w->team_origin.x_m, w->team_origin.y_m,
           w->team_origin.theta_rad);
    printf("\"extent_m\": [%.10g, %.10g, %.10g, %.10g],\n  \"landmarks_m\": [", w->x_min_m,
           w->y_min_m, w->x_max_m, w->y_max_m);
    for (i = 0; i < w->n_landmarks; i++)
        printf("%s[%.10g, %.10g]", i ? ", " : "", w->landmark_m[i][0], w->landmark_m[i][1]);
    printf("],\n  \"starts\": [");
    for (i = 0; i < w->n_robots; i++)
        printf("%s[%.10g, %.10g, %.10g]", i ? ", " : "", w->start_c[i].x_m, w->start_c[i].y_m,
               w->start_c[i].theta_rad);
    printf("],\n  \"obstacles\": [\n");
    for (i = 0; i < w->n_obst; i++)
        print_obstacle(&w->obst[i], i + 1 < w->n_obst ? "," : "");
    printf("  ]},\n");
}

static void print_rover_body(void)
{
    sonar_model sm;
    int k;
    sonar_model_default(&sm);
    printf(
        "\"rover\": {\"body_length_m\": %.10g, \"body_width_m\": %.10g, \"body_offset_m\": %.10g, "
        "\"beacon_d_m\": %.10g,\n  \"sonar_cone_rad\": %.10g, \"sonar_range_max_m\": %.10g, "
        "\"sonar\": [",
        ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, ROVER_BODY_OFFSET_M, ROVER_BEACON_D_M, sm.cone_rad,
        sm.range_max_m);
    for (k = 0; k < SONAR_N; k++)
        printf("%s[%.10g, %.10g, %.10g]", k ? ", " : "", sonar_p2dx_front[k].x_m,
               sonar_p2dx_front[k].y_m, sonar_p2dx_front[k].angle_rad);
    printf("]},\n");
}

/* Slot offsets (scale 1) of every formation type for n robots, indexed by
 * the robot's rank among the team ids (the controllers' assignment). */
static void print_slots(int n)
{
    static const char *names[] = { "line", "triangle", "column" };
    formation_fsm_params p;
    int t, r;
    formation_fsm_params_default(&p);
    printf("\"formation\": {\"spacing_m\": %.10g", p.spacing_m);
    for (t = 0; t < 3; t++) {
        printf(", \"%s\": [", names[t]);
        for (r = 0; r < n; r++) {
            double xy[2] = { 0.0, 0.0 };
            formation_slot_xy(xy, t, n, rover_world_slot(t, n, r), p.spacing_m, 1.0);
            printf("%s[%.10g, %.10g]", r ? ", " : "", xy[0], xy[1]);
        }
        printf("]");
    }
    printf("}\n");
}

/* ---- URDF ----------------------------------------------------------------
 * Each arm is its DH chain as the core computes it (arm_model.h): link
 * armK_link<i> is DH frame i (link0 = frame 0, base_height_m above the
 * mounting surface armK_base), joint i a revolute joint about z of frame
 * i-1 whose origin turns by theta_offset_i, followed by a fixed joint
 * Tz(d_i) Tx(a_i) Rx(alpha_i) from the massless armK_q<i> to armK_link<i>;
 * link i carries its mass, centre of mass and inertia, given in frame i by
 * the table. So the URDF's forward kinematics are the core's, exactly. */

/* URDF's rpy (R = Rz(yaw) Ry(pitch) Rx(roll)) of a row-major 4x4. */
static void rpy_of(const double T[16], double rpy[3])
{
    rpy[0] = atan2(T[9], T[10]);
    rpy[1] = atan2(-T[8], sqrt(T[0] * T[0] + T[4] * T[4]));
    rpy[2] = atan2(T[4], T[0]);
}

static void urdf_origin(double x, double y, double z, double r, double p, double yw)
{
    printf("    <origin xyz=\"%.17g %.17g %.17g\" rpy=\"%.17g %.17g %.17g\"/>\n", x, y, z, r, p,
           yw);
}

static void urdf_fixed(const char *parent, const char *child, const char *name, const double T[16])
{
    double rpy[3];
    rpy_of(T, rpy);
    printf(
        "  <joint name=\"%s\" type=\"fixed\">\n    <parent link=\"%s\"/>\n    <child link=\"%s\"/>\n",
        name, parent, child);
    urdf_origin(T[3], T[7], T[11], rpy[0], rpy[1], rpy[2]);
    printf("  </joint>\n");
}

static void urdf_box_link(const char *name, double mass_kg, const double at[3],
                          const double size[3], const char *material)
{
    const double k = mass_kg / 12.0;
    printf("  <link name=\"%s\">\n", name);
    printf("    <inertial>\n  ");
    urdf_origin(at[0], at[1], at[2], 0, 0, 0);
    printf("      <mass value=\"%.17g\"/>\n", mass_kg);
    printf(
        "      <inertia ixx=\"%.17g\" ixy=\"0\" ixz=\"0\" iyy=\"%.17g\" iyz=\"0\" izz=\"%.17g\"/>\n",
        k * (size[1] * size[1] + size[2] * size[2]), k * (size[0] * size[0] + size[2] * size[2]),
        k * (size[0] * size[0] + size[1] * size[1]));
    printf("    </inertial>\n");
    printf("    <visual>\n  ");
    urdf_origin(at[0], at[1], at[2], 0, 0, 0);
    printf("      <geometry><box size=\"%.17g %.17g %.17g\"/></geometry>\n"
           "      <material name=\"%s\"/>\n    </visual>\n",
           size[0], size[1], size[2], material);
    printf("    <collision>\n  ");
    urdf_origin(at[0], at[1], at[2], 0, 0, 0);
    printf("      <geometry><box size=\"%.17g %.17g %.17g\"/></geometry>\n    </collision>\n",
           size[0], size[1], size[2]);
    printf("  </link>\n");
}

/* A cylinder of a link's visual body: centre xyz, axis z turned by roll then pitch. */
static void urdf_cylinder(double x, double y, double z, double roll, double pitch, double radius,
                          double length, const char *material)
{
    printf("    <visual>\n  ");
    urdf_origin(x, y, z, roll, pitch, 0);
    printf("      <geometry><cylinder radius=\"%.17g\" length=\"%.17g\"/></geometry>\n"
           "      <material name=\"%s\"/>\n    </visual>\n",
           radius, length, material);
}

/* Display sizes of the arms' bodies (no controller uses them): the
 * shoulder and elbow joints and links, then the wrist's. */
#define URDF_HOUSING_R_M                       \
    {                                          \
        0.075, 0.075, 0.065, 0.05, 0.045, 0.04 \
    }
#define URDF_HOUSING_L_M                   \
    {                                      \
        0.18, 0.18, 0.16, 0.11, 0.10, 0.08 \
    }
#define URDF_LINK_R_M                        \
    {                                        \
        0.05, 0.05, 0.045, 0.04, 0.035, 0.03 \
    }
#define URDF_PEDESTAL_R_M 0.09
#define URDF_MIN_SEGMENT_M 1e-6

/* Link i's body, in frame i: the housing of joint i on its axis (z of
 * frame i-1, which is Rx(-alpha) Tx(-a) Tz(-d) from frame i), the segment
 * along that axis over d_i and the one along x_i over a_i. These are the
 * sticks the DH chain draws, given a radius; zero-length ones are left out. */
static void urdf_dh_link(int k, int i, const arm_model *m)
{
    static const double housing_r[ARM_NJ] = URDF_HOUSING_R_M, housing_l[ARM_NJ] = URDF_HOUSING_L_M;
    static const double link_r[ARM_NJ] = URDF_LINK_R_M;
    const double *c = m->com_m[i], *I = m->inertia_kgm2[i];
    const double a = m->a_m[i], d = m->d_m[i], al = m->alpha_rad[i], sa = sin(al), ca = cos(al);
    char material[16];
    snprintf(material, sizeof material, "arm%d", k);
    printf("  <link name=\"arm%d_link%d\">\n    <inertial>\n  ", k, i + 1);
    urdf_origin(c[0], c[1], c[2], 0, 0, 0);
    printf("      <mass value=\"%.17g\"/>\n", m->mass_kg[i]);
    printf(
        "      <inertia ixx=\"%.17g\" ixy=\"%.17g\" ixz=\"%.17g\" iyy=\"%.17g\" iyz=\"%.17g\" izz=\"%.17g\"/>\n",
        I[0], I[1], I[2], I[4], I[5], I[8]);
    printf("    </inertial>\n");
    urdf_cylinder(-a, -sa * d, -ca * d, -al, 0, housing_r[i], housing_l[i], "joint");
    if (fabs(d) > URDF_MIN_SEGMENT_M)
        urdf_cylinder(-a, -0.5 * sa * d, -0.5 * ca * d, -al, 0, link_r[i], fabs(d), material);
    if (fabs(a) > URDF_MIN_SEGMENT_M)
        urdf_cylinder(-0.5 * a, 0, 0, 0, 1.5707963267948966, link_r[i], fabs(a), material);
    printf("  </link>\n");
}

static void urdf_arm(int k, const arm_model *m, const double base_T[16])
{
    char parent[32], child[32], name[32];
    double T[16] = { 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1 };
    int i;
    char material[16];
    snprintf(material, sizeof material, "arm%d", k);
    /* the pedestal from the mounting surface up to frame 0 */
    printf("  <link name=\"arm%d_base\">\n", k);
    urdf_cylinder(0, 0, 0.5 * m->base_height_m, 0, 0, URDF_PEDESTAL_R_M, m->base_height_m,
                  material);
    printf("  </link>\n  <link name=\"arm%d_link0\"/>\n", k);
    snprintf(child, sizeof child, "arm%d_base", k);
    snprintf(name, sizeof name, "arm%d_mount", k);
    urdf_fixed("world", child, name, base_T);
    arm_base_frame(m, T);
    snprintf(parent, sizeof parent, "arm%d_base", k);
    snprintf(child, sizeof child, "arm%d_link0", k);
    snprintf(name, sizeof name, "arm%d_base_height", k);
    urdf_fixed(parent, child, name, T);
    for (i = 0; i < ARM_NJ; i++) {
        printf("  <link name=\"arm%d_q%d\"/>\n", k, i + 1);
        urdf_dh_link(k, i, m);
        printf("  <joint name=\"arm%d_joint%d\" type=\"revolute\">\n"
               "    <parent link=\"arm%d_link%d\"/>\n    <child link=\"arm%d_q%d\"/>\n",
               k, i + 1, k, i, k, i + 1);
        urdf_origin(0, 0, 0, 0, 0, m->theta_offset_rad[i]);
        printf(
            "    <axis xyz=\"0 0 1\"/>\n"
            "    <limit lower=\"%.17g\" upper=\"%.17g\" effort=\"%.17g\" velocity=\"%.17g\"/>\n  </joint>\n",
            m->q_min_rad[i], m->q_max_rad[i], m->tau_max_Nm[i], m->qd_max_radps[i]);
        printf("  <joint name=\"arm%d_dh%d\" type=\"fixed\">\n"
               "    <parent link=\"arm%d_q%d\"/>\n    <child link=\"arm%d_link%d\"/>\n",
               k, i + 1, k, i + 1, k, i + 1);
        urdf_origin(m->a_m[i], 0, m->d_m[i], m->alpha_rad[i], 0, 0);
        printf("  </joint>\n");
    }
    printf("  <link name=\"arm%d_tool\"/>\n", k);
    T[3] = T[7] = 0.0;
    T[11] = CELL_TOOL_LENGTH_M;
    snprintf(parent, sizeof parent, "arm%d_link6", k);
    snprintf(child, sizeof child, "arm%d_tool", k);
    snprintf(name, sizeof name, "arm%d_tool_joint", k);
    urdf_fixed(parent, child, name, T);
}

/* Sim-only numbers of the Pioneer's bodies (sim/models/sim_rovers.c: the
 * controllers never use them); its sizes are the core's. */
#define PIONEER_CHASSIS_KG 8.0
#define PIONEER_CHASSIS_H_M 0.20
#define PIONEER_CHASSIS_Z_M 0.15
#define PIONEER_WHEEL_KG 0.5
#define PIONEER_WHEEL_W_M 0.04

/* One Pioneer at the team frame's origin: pioneer_base is its axle centre C
 * on the floor, the chassis box ahead of it, two wheels on continuous joints. */
static void urdf_pioneer(const rover_world_config *w)
{
    const double r = ODOMETRY_P2DX_WHEEL_RADIUS_M, track = ODOMETRY_P2DX_AXLE_TRACK_M;
    const double at[3] = { ROVER_BODY_OFFSET_M, 0.0, PIONEER_CHASSIS_Z_M };
    const double size[3] = { ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, PIONEER_CHASSIS_H_M };
    const double c = cos(w->team_origin.theta_rad), s = sin(w->team_origin.theta_rad);
    const double T[16] = { c, -s, 0, w->team_origin.x_m, s, c, 0, w->team_origin.y_m, 0, 0, 1, 0, 0,
                           0, 0,  1 };
    const double k = PIONEER_WHEEL_KG / 12.0;
    int side;
    urdf_box_link("pioneer_base", PIONEER_CHASSIS_KG, at, size, "pioneer");
    urdf_fixed("world", "pioneer_base", "pioneer_start", T);
    for (side = 0; side < 2; side++) {
        const char *nm = side == 0 ? "left" : "right";
        printf(
            "  <link name=\"pioneer_%s_wheel\">\n    <inertial>\n      <mass value=\"%.17g\"/>\n"
            "      <inertia ixx=\"%.17g\" ixy=\"0\" ixz=\"0\" iyy=\"%.17g\" iyz=\"0\" izz=\"%.17g\"/>\n"
            "    </inertial>\n    <visual>\n  ",
            nm, PIONEER_WHEEL_KG, k * (3 * r * r + PIONEER_WHEEL_W_M * PIONEER_WHEEL_W_M),
            k * 6 * r * r, k * (3 * r * r + PIONEER_WHEEL_W_M * PIONEER_WHEEL_W_M));
        urdf_origin(0, 0, 0, -1.5707963267948966, 0, 0);
        printf("      <geometry><cylinder radius=\"%.17g\" length=\"%.17g\"/></geometry>\n"
               "      <material name=\"wheel\"/>\n    </visual>\n  </link>\n",
               r, PIONEER_WHEEL_W_M);
        printf("  <joint name=\"pioneer_%s_wheel_joint\" type=\"continuous\">\n"
               "    <parent link=\"pioneer_base\"/>\n    <child link=\"pioneer_%s_wheel\"/>\n",
               nm, nm);
        urdf_origin(0, side == 0 ? 0.5 * track : -0.5 * track, r, 0, 0, 0);
        printf("    <axis xyz=\"0 1 0\"/>\n  </joint>\n");
    }
}

/* The colours viewers draw with: the browser viewer's, so a screenshot and
 * its pixel check (tools/viewer/view_check.py) match whatever a URDF names. */
static void print_urdf_materials(void)
{
    static const struct {
        const char *name;
        double rgba[4];
    } mats[] = {
        { "arm1", { 1.0, 0.502, 0.0, 1.0 } },   { "arm2", { 0.118, 0.431, 1.0, 1.0 } },
        { "joint", { 0.3, 0.3, 0.3, 1.0 } },    { "table", { 0.588, 0.471, 0.353, 1.0 } },
        { "pioneer", { 0.75, 0.1, 0.1, 1.0 } }, { "wheel", { 0.1, 0.1, 0.1, 1.0 } },
    };
    size_t i;
    for (i = 0; i < sizeof mats / sizeof mats[0]; i++)
        printf("  <material name=\"%s\"><color rgba=\"%.4g %.4g %.4g %.4g\"/></material>\n",
               mats[i].name, mats[i].rgba[0], mats[i].rgba[1], mats[i].rgba[2], mats[i].rgba[3]);
}

static void print_urdf(const arm_model *arm1, const cell_layout *c, const rover_world_config *w)
{
    const arm_model *models[CELL_ARMS] = { arm1, &arm_model_puma560 };
    const double *tc = c->table_center_m, zero[3] = { 0.0, 0.0, 0.0 };
    const double T_table[16] = { 1, 0, 0, tc[0], 0, 1, 0, tc[1], 0, 0, 1, tc[2], 0, 0, 0, 1 };
    int a;
    printf(
        "<?xml version=\"1.0\"?>\n<!-- Generated by tandem-scene (option urdf) from the core's tables "
        "(arm_model, cell, rover_world): do not edit. -->\n<robot name=\"tandem_cell\">\n");
    print_urdf_materials();
    printf("  <link name=\"world\"/>\n");
    for (a = 0; a < CELL_ARMS; a++) {
        double B[16];
        cell_world_from_arm(c, a, B);
        urdf_arm(a + 1, models[a], B);
    }
    /* the table top is fixed: a nominal mass, for parsers that want one */
    urdf_box_link("table", 100.0, zero, c->table_size_m, "table");
    urdf_fixed("world", "table", "table_fixed", T_table);
    urdf_pioneer(w);
    printf("</robot>\n");
}

typedef struct scene_options {
    int world, formation, arm1; /* indices in the options_*_names lists */
    long n;
    world_opts wopt;
    int urdf;
} scene_options;

static const option_entry scene_table[] = {
    { .name = "world",
      .type = OPTION_CHOICE,
      OPTION_AT(scene_options, world),
      .choices = options_world_names,
      .meta = "NAME",
      .help = "rover world",
      .def = "open" },
    WORLD_FILE_OPTIONS(scene_options, wopt),
    { .name = "rovers",
      .type = OPTION_INT,
      OPTION_AT(scene_options, n),
      .min = 1,
      .max = ROVER_WORLD_MAX_ROBOTS,
      .meta = "N",
      .help = "robots in the team",
      .def = "3" },
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(scene_options, formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .meta = "F",
      .help = "formation of the slots' team",
      .def = "line" },
    { .name = "arm1",
      .type = OPTION_CHOICE,
      OPTION_AT(scene_options, arm1),
      .choices = options_arm_model_names,
      .meta = "MODEL",
      .help = "arm 1's tables",
      .def = "puma560" },
    { .name = "urdf",
      .type = OPTION_FLAG,
      OPTION_AT(scene_options, urdf),
      .help = "write the cell as URDF (both arms' DH chains with limits, masses and inertias, "
              "the table, a Pioneer at the team's start) instead of JSON" },
    OPTION_HELP_ENTRY(0),
    OPTION_VERSION_ENTRY,
    { .name = NULL }
};

int main(int argc, char **argv)
{
    scene_options o = { 0, FORMATION_LINE, 0, 3, { 0, NULL, NULL, NULL }, 0 };
    const option_program prog = {
        .name = "tandem-scene",
        .usage =
            "usage: tandem-scene [--world NAME | --world-file PATH] [--rovers N] [--formation F] [--arm1 MODEL] [--urdf]\n"
            "Prints the static geometry of the tandem world as JSON on stdout: the arm\n"
            "DH tables, the work cell (arm bases, table, workpieces), the rover world\n"
            "(obstacles, goal, team frame), the Pioneer body and sonar ring and the\n"
            "formation slots, all from the same tables the controllers use.\n"
            "With --urdf: the cell as URDF (arms, table, a Pioneer) instead.\n\n",
        .groups = { { scene_table, &o } },
        .n_groups = 1,
    };
    const arm_model *arm1;
    int world, formation, rc;
    long n;
    static rover_world_config w; /* large: keep it off the stack */
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    world = rover_world_id(options_world_names[o.world]);
    formation = o.formation;
    arm1 = arm_model_by_name(options_arm_model_names[o.arm1]);
    n = o.n;
    o.wopt.world = world;
    if (world_opts_layout(&w, &o.wopt, (int)n, 1.0, formation, "tandem-scene") != 0)
        return 2;
    if (o.urdf) {
        print_urdf(arm1, &cell_default, &w);
        return 0;
    }
    printf("{\n");
    print_arm_model("arm1_model", arm1);
    print_arm_model("arm2_model", &arm_model_puma560);
    print_cell(&cell_default);
    print_rover_world(&w);
    print_rover_body();
    print_slots((int)n);
    printf("}\n");
    return 0;
}
