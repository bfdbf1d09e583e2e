/* tandem-scene: prints the static geometry of the simulated world as JSON,
 * straight from the core's const tables (arm_model, cell, rover_world,
 * formation, sonar), so that viewers and plotting scripts draw the same
 * arms, table, obstacles, goal and formation slots the controllers use
 * instead of keeping their own copies of the numbers.
 *
 *   tandem-scene [--world NAME | --world-file PATH [--start X,Y,THETA] [--goal X,Y]]
 *                [--rovers N] [--formation F] [--arm1 MODEL]
 * A world file that gives no layout is refused (exit 2), which is how
 * tools/tandem-run checks one before it starts anything.
 */
#include <stdio.h>
#include <string.h>
#include "arm_model.h"
#include "cell.h"
#include "formation.h"
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
    printf("\"rover_world\": {\"name\": \"%s\", \"n_robots\": %d, ", rover_world_name(w->world), w->n_robots);
    json_array("goal_m", w->goal_m, 2, ", ");
    printf("\"team_origin\": [%.10g, %.10g, %.10g], ", w->team_origin.x_m, w->team_origin.y_m,
           w->team_origin.theta_rad);
    printf("\"extent_m\": [%.10g, %.10g, %.10g, %.10g],\n  \"landmarks_m\": [", w->x_min_m, w->y_min_m,
           w->x_max_m, w->y_max_m);
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
    printf("\"rover\": {\"body_length_m\": %.10g, \"body_width_m\": %.10g, \"body_offset_m\": %.10g, "
           "\"beacon_d_m\": %.10g,\n  \"sonar_cone_rad\": %.10g, \"sonar_range_max_m\": %.10g, "
           "\"sonar\": [", ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, ROVER_BODY_OFFSET_M, ROVER_BEACON_D_M,
           sm.cone_rad, sm.range_max_m);
    for (k = 0; k < SONAR_N; k++)
        printf("%s[%.10g, %.10g, %.10g]", k ? ", " : "", sonar_p2dx_front[k].x_m, sonar_p2dx_front[k].y_m,
               sonar_p2dx_front[k].angle_rad);
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

typedef struct scene_options {
    int  world, formation, arm1;   /* indices in the options_*_names lists */
    long n;
    world_opts wopt;
} scene_options;

static const option_entry scene_table[] = {
    { .name = "world", .type = OPTION_CHOICE, OPTION_AT(scene_options, world), .choices = options_world_names,
      .meta = "NAME", .help = "rover world", .def = "open" },
    WORLD_FILE_OPTIONS(scene_options, wopt),
    { .name = "rovers", .type = OPTION_INT, OPTION_AT(scene_options, n), .min = 1, .max = ROVER_WORLD_MAX_ROBOTS,
      .meta = "N", .help = "robots in the team", .def = "3" },
    { .name = "formation", .type = OPTION_CHOICE, OPTION_AT(scene_options, formation),
      .choices = options_formation_names, .values = options_formation_values, .meta = "F",
      .help = "formation of the slots' team", .def = "line" },
    { .name = "arm1", .type = OPTION_CHOICE, OPTION_AT(scene_options, arm1), .choices = options_arm_model_names,
      .meta = "MODEL", .help = "arm 1's tables", .def = "puma560" },
    { .name = "help", .type = OPTION_HELP, .help = "this text" },
    { .name = "version", .type = OPTION_VERSION, .help = "program version" },
    { .name = NULL }
};

int main(int argc, char **argv)
{
    scene_options o = { 0, FORMATION_LINE, 0, 3, { 0, NULL, NULL, NULL } };
    const option_program prog = {
        .name = "tandem-scene",
        .usage = "usage: tandem-scene [--world NAME | --world-file PATH] [--rovers N] [--formation F] [--arm1 MODEL]\n"
                 "Prints the static geometry of the tandem world as JSON on stdout: the arm\n"
                 "DH tables, the work cell (arm bases, table, workpieces), the rover world\n"
                 "(obstacles, goal, team frame), the Pioneer body and sonar ring and the\n"
                 "formation slots, all from the same tables the controllers use.\n\n",
        .groups = { { scene_table, &o } }, .n_groups = 1,
    };
    const arm_model *arm1;
    int world, formation, rc;
    long n;
    static rover_world_config w;   /* large: keep it off the stack */
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    world = rover_world_id(options_world_names[o.world]);
    formation = o.formation;
    arm1 = arm_model_by_name(options_arm_model_names[o.arm1]);
    n = o.n;
    o.wopt.world = world;
    if (world_opts_layout(&w, &o.wopt, (int)n, 1.0, formation, "tandem-scene") != 0) return 2;
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
