/* rover_world: the launch configuration of the Pioneer team (docs/method/formation.md,
 * sonar.md): the four worlds (open, obstacles, corridor, deadzone) as
 * lists of static obstacles, the robots' initial poses and the goal, the
 * team frame fixed from those initial poses, the Pioneer 2 DX footprint and
 * ground-truth clearance between footprints and obstacles.
 *
 * Everything is a deterministic function of (world, number of robots), so
 * the simulator, every rover daemon and the scenario derive the same layout
 * without talking to each other: this is how each robot knows its initial
 * pose in the shared team frame (and nothing else about the world).
 *
 * World frame: x forward (toward the goal), y left, metres. The rover
 * worlds sit at x > 4 m, clear of the PUMA work cell around the origin.
 * Team frame: origin at the mean initial position of the points O, axes
 * parallel to the world's (the team starts heading +x, toward the goal).
 */
#ifndef TANDEM_ROVER_WORLD_H
#define TANDEM_ROVER_WORLD_H

#include <stdint.h>

#include "pgrid.h"
#include "vec2.h"

#define ROVER_WORLD_ERR_ARG \
    (-1)                             /* NULL, n, spacing or formation out of
                                         range, a non-finite pose          */
#define ROVER_WORLD_ERR_UNKNOWN (-2) /* rover_world_id: no such world name */

/* Capacities, fixed at build time (VME style: no heap). The world's robots
 * (the layout's start poses, the simulator's fleet) may be set with
 * -DROVER_WORLD_MAX_ROBOTS=N; one team (one formation, one rover host's
 * batch, the TEAM and ROVERS_* messages) holds at most ROVER_TEAM_MAX,
 * the bound of those messages' arrays in lcmtypes/capacities. */
#ifndef ROVER_WORLD_MAX_ROBOTS
#define ROVER_WORLD_MAX_ROBOTS 10240 /* <= PGRID_MAX_ITEMS */
#endif
#define ROVER_TEAM_MAX 128
#define ROVER_WORLD_MAX_OBST 2048    /* a map's merged boxes (rover_map.h) */
#define ROVER_WORLD_ROW_MAX 10       /* robots per start row */
#define ROVER_WORLD_MAX_LANDMARKS 64 /* a robot's (= LOCALIZE_LANDMARKS_MAX), a map's, a file's */
/* A world's LED posts: a fleet's world (fleet.h) spreads more over its
 * area than any one robot uses (each takes the ROVER_WORLD_MAX_LANDMARKS
 * nearest its way, rover_world_landmarks_near). */
#define ROVER_WORLD_MAX_POSTS 1024
/* The camera reports landmark k (rover_world_config.landmark_m[k]) as beacon
 * target ROVER_LANDMARK_ID_BASE + k. Every robot id stays below it
 * (rover_world.c checks ROVER_WORLD_MAX_ROBOTS against it at build time):
 * at 1000 a fleet's robots 1000-1063 were seen as landmarks 0-63. */
#define ROVER_LANDMARK_ID_BASE 1000000

/* Pioneer 2 DX body (the chassis box, relative to the axle centre C). */
#define ROVER_BODY_LENGTH_M 0.44
#define ROVER_BODY_WIDTH_M 0.38
#define ROVER_BODY_OFFSET_M (-0.03) /* box centre is this far ahead of C */
/* O (the LED beacon, the camera) lies d behind C, signed: -0.15 puts it
 * 0.15 m AHEAD of the axle, where the seed's formation law has stable
 * heading dynamics in forward motion (docs/formation.md) */
#define ROVER_BEACON_D_M (-0.15)
/* The robot's hardware schedule, in simulator steps (1 ms): one frame of
 * encoders + sonar every 50 ms, one camera frame every 100 ms. A lockstep
 * controller at step k expects the frames of the last multiple of each. */
#define ROVER_SENSOR_PERIOD_STEPS 50
#define ROVER_CAMERA_PERIOD_STEPS 100

enum {
    ROVER_WORLD_OPEN = 0,
    ROVER_WORLD_OBSTACLES = 1,
    ROVER_WORLD_CORRIDOR = 2,
    ROVER_WORLD_DEADZONE = 3,
    ROVER_WORLD_COUNT = 4
};
/* A world read from a map file (rover_map.h): not one of the built-ins. */
#define ROVER_WORLD_FILE 100
enum { ROVER_OBST_BOX = 0, ROVER_OBST_CIRCLE = 1 };

typedef struct {
    int kind;          /* ROVER_OBST_* */
    double cx_m, cy_m; /* centre */
    double hx_m, hy_m; /* box half extents (box frame) */
    double angle_rad;  /* box orientation */
    double r_m;        /* circle radius */
    double height_m;   /* from the floor up */
} rover_obstacle;

typedef struct {
    int world; /* ROVER_WORLD_* */
    int n_robots;
    double spacing_m;                      /* start grid spacing */
    pose2 start_c[ROVER_WORLD_MAX_ROBOTS]; /* robot id k is index k-1 */
    double goal_m[2];                      /* world frame: where the goal formation stands */
    double goal_nominal_m[2];              /* the goal as given (goal_place moves goal_m) */
    int goal_fits;                         /* goal_place found room for the goal formation */
    pose2 team_origin;                     /* team frame in the world */
    int n_obst;
    rover_obstacle obst[ROVER_WORLD_MAX_OBST];
    double x_min_m, y_min_m, x_max_m, y_max_m; /* extent for plots/grids */
    /* LED landmarks at known places (world frame), at the height of the
     * robots' beacons: pairs 3.5 m either side of the way every 3 m from
     * behind the start to past the goal, and in the corridor world two
     * pairs on the corridor's inner faces (the funnel walls hide the
     * outer ones there). Not obstacles: the posts stand outside the space
     * the team drives through (sim/models/sim_rovers.c sees them as LEDs only). */
    int n_landmarks; /* at most ROVER_WORLD_MAX_LANDMARKS but in a fleet's world */
    double landmark_m[ROVER_WORLD_MAX_POSTS][2];
} rover_world_config;

/* "open" | "obstacles" | "corridor" | "deadzone" -> ROVER_WORLD_*, else
 * ROVER_WORLD_ERR_UNKNOWN. rover_world_name(ROVER_WORLD_FILE) is "file". */
int rover_world_id(const char *name);
const char *rover_world_name(int world);

/* Layout of `world` for n robots (1..ROVER_WORLD_MAX_ROBOTS), all heading
 * +x: up to ROVER_WORLD_ROW_MAX robots start in the slots of `formation`
 * (FORMATION_*, robot k in slot k-1, the frontmost at the same x for every
 * formation); larger teams on a grid of rows of ROVER_WORLD_ROW_MAX abreast,
 * spacing_m apart (> robot length). 0 ok, ROVER_WORLD_ERR_ARG bad input. */
int rover_world_layout(rover_world_config *w, int world, int n, double spacing_m, int formation);

/* Slot of the robot whose rank among the sorted team ids is `rank`, in a
 * formation of `type` (FORMATION_*) and n robots. Line: the rank itself
 * (slot 0 leftmost). Triangle and column: centre-out, so that the middle
 * robot of the line becomes the apex / the head of the column and its
 * neighbours fall in behind on their own side; going line -> triangle ->
 * column in a passage then needs no robot to cross another. ROVER_WORLD_ERR_ARG on bad
 * input. */
int rover_world_slot(int type, int n, int rank);

/* World <-> team frame (poses of any point). */
void rover_world_to_team(const rover_world_config *w, const pose2 *world_p, pose2 *team_p);
void rover_world_from_team(const rover_world_config *w, const pose2 *team_p, pose2 *world_p);
/* The same with the frame given by its origin in the world (a team of a
 * fleet, fleet.h: each team its own frame). */
void rover_frame_to(const pose2 *origin, const pose2 *world_p, pose2 *frame_p);
void rover_frame_from(const pose2 *origin, const pose2 *frame_p, pose2 *world_p);

/* Appends a box obstacle (centre, half extents in its frame, angle,
 * height) to w. 0, or ROVER_WORLD_ERR_ARG when w is NULL or holds
 * ROVER_WORLD_MAX_OBST already. */
int rover_world_add_box(rover_world_config *w, double cx, double cy, double hx, double hy,
                        double angle_rad, double height_m);

/* The centre of the chassis box of a robot whose axle centre C has pose
 * c: ROVER_BODY_OFFSET_M ahead of C along the heading (the footprint of
 * the clearance, the mates' boxes of the controller, the simulator's). */
void rover_body_centre_of_c(const pose2 *c, double xy_m[2]);
/* The same for a robot whose beacon point O has pose o (the pose the
 * truth and the team messages carry): C from O by unicycle_c_from_o with
 * ROVER_BEACON_D_M. */
void rover_body_centre_of_o(const pose2 *o, double xy_m[2]);

/* Signed distance from a point to an obstacle's outline (negative inside). */
double rover_obstacle_distance(const rover_obstacle *o, double x_m, double y_m);

/* Ground-truth clearance: for each alive robot (axle-centre poses c[i]),
 * the smallest distance between its footprint and any obstacle or other
 * alive robot's footprint (negative: overlapping). Footprint outlines are
 * sampled at corners and edge midpoints; the box-to-box distance is the
 * minimum of both directions. Dead robots get INFINITY. 0 ok, ROVER_WORLD_ERR_ARG bad. */
int rover_world_clearance(const rover_world_config *w, const pose2 *c, const int *alive, int n,
                          double *clearance_m);

/* The indexed computation's workspace (large: the caller keeps one). */
typedef struct {
    pgrid grid; /* the alive robots' body centres */
    double bx[ROVER_WORLD_MAX_ROBOTS], by[ROVER_WORLD_MAX_ROBOTS];
    int32_t near[ROVER_WORLD_MAX_ROBOTS];
} rover_clearance_work;

/* The same numbers as rover_world_clearance, bit for bit, with each
 * robot's mates taken from a grid of the body centres (pgrid.h) in discs
 * grown until no mate outside could be nearer: the cost per robot is set
 * by its neighbourhood, not by n (the obstacles are still all tested).
 * 0 ok, ROVER_WORLD_ERR_ARG bad input (work NULL too). */
int rover_world_clearance_indexed(const rover_world_config *w, const pose2 *c, const int *alive,
                                  int n, rover_clearance_work *work, double *clearance_m);

/* The posts a robot going from a to b (world frame) localizes on: the
 * indices of the ROVER_WORLD_MAX_LANDMARKS posts of w nearest the segment
 * a-b (ties to the lower index), ascending, into idx; all of them, 0..n-1,
 * when w holds no more. Returns their number, or ROVER_WORLD_ERR_ARG. */
int rover_world_landmarks_near(const rover_world_config *w, const double a[2], const double b[2],
                               int32_t idx[ROVER_WORLD_MAX_LANDMARKS]);

#endif
