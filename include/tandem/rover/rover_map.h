/* rover_map: a world given as an occupancy grid (docs/method/sonar.md
 * §8, "Worlds from occupancy maps"): the grid, its occupied cells merged into
 * axis-aligned boxes (the obstacles the simulator and the sonar ray cast
 * see), and the launch configuration built on it (the team placed in its
 * formation slots around a start pose, the goal, the LED landmarks).
 *
 * The grid is what the file says, read outside the core (the YAML + PGM
 * reader of the daemon shell, world_file.h): cell (i, j) is column i from
 * the left, row j from the BOTTOM (y grows with j), its lower-left corner
 * at (origin_x_m + i res, origin_y_m + j res). Capacities are named
 * constants; a map that needs more is refused with the limit's code.
 */
#ifndef TANDEM_ROVER_MAP_H
#define TANDEM_ROVER_MAP_H

#include "navfield.h"
#include "rover_world.h"
#include "vec2.h"

#define ROVER_MAP_OK 0
#define ROVER_MAP_ERR_ARG (-1)        /* NULL, n, spacing or formation out of range */
#define ROVER_MAP_ERR_SIZE (-2)       /* width or height < 1 or > ROVER_MAP_MAX_SIDE */
#define ROVER_MAP_ERR_RESOLUTION (-3) /* resolution not finite and > 0, origin not finite */
#define ROVER_MAP_ERR_BOXES (-4)      /* the occupied cells need more than the box capacity */
#define ROVER_MAP_ERR_START \
    (-5) /* start not finite, or a robot's body off the map or on an obstacle */
#define ROVER_MAP_ERR_GOAL (-6) /* goal not finite, off the map or in an occupied cell */
#define ROVER_MAP_ERR_LANDMARKS \
    (-7)                        /* a landmark not finite, or more than ROVER_WORLD_MAX_LANDMARKS */
#define ROVER_MAP_ERR_CELL (-8) /* a cell value other than FREE or OCCUPIED */

#define ROVER_MAP_MAX_SIDE 2048 /* cells along x or y */
#define ROVER_MAP_MAX_CELLS (2048L * 2048L)
#define ROVER_MAP_WALL_HEIGHT_M 0.5 /* the boxes' height (the built-in walls') */
#define ROVER_MAP_LANDMARKS_AUTO (-1)

enum { ROVER_MAP_FREE = 0, ROVER_MAP_OCCUPIED = 1 };

typedef struct {
    int width, height;                       /* cells */
    double resolution_m;                     /* cell side */
    double origin_x_m, origin_y_m;           /* lower-left corner of cell (0, 0) */
    unsigned char cell[ROVER_MAP_MAX_CELLS]; /* [j * width + i], ROVER_MAP_FREE/OCCUPIED */
} rover_map;

/* What the file adds to the grid (its tandem: section, or the options). */
typedef struct {
    pose2 start; /* the team reference's start (mean of the O points), heading */
    double goal_m[2];
    int n_landmarks; /* ROVER_MAP_LANDMARKS_AUTO: placed by rover_world_from_map */
    double landmark_m[ROVER_WORLD_MAX_LANDMARKS][2];
} rover_map_site;

const char *rover_map_strerror(int rc);

/* Size, resolution, origin and every cell value. ROVER_MAP_OK or the code. */
int rover_map_validate(const rover_map *m);

/* 1 if (x, y) lies in an occupied cell or off the map, else 0. */
int rover_map_blocked(const rover_map *m, double x_m, double y_m);

/* Greedy merge of the occupied cells into axis-aligned boxes: row by row
 * from the bottom, each run of occupied cells not yet covered grows
 * upward while the whole run is occupied and uncovered. Every occupied
 * cell ends in exactly one box, no free cell in any. Boxes as rover
 * obstacles (ROVER_OBST_BOX, angle 0, ROVER_MAP_WALL_HEIGHT_M high).
 * m is used as scratch and restored. ROVER_MAP_OK, ROVER_MAP_ERR_BOXES
 * (more than cap; *n = cap), or a validation code. */
int rover_map_merge(rover_map *m, rover_obstacle *box, int cap, int *n);

/* The launch configuration on map m: the obstacles are the merged boxes;
 * robots in their slots of `formation` as rover_world_layout places them,
 * moved so that the team reference (mean O) is at s->start, all heading
 * s->start.theta_rad (the team frame is the start pose); goal and
 * landmarks from s (auto: see rover_map_auto_landmarks). Every robot's
 * body must lie on the map clear of the boxes and the goal on a free
 * cell. w->world is ROVER_WORLD_FILE. ROVER_MAP_OK or the code (w zeroed). */
int rover_world_from_map(rover_world_config *w, rover_map *m, const rover_map_site *s, int n,
                         double spacing_m, int formation);

/* LED posts along the way: pairs either side of the polyline
 * way[0..n_way-1] (the start, the way's turns, the goal), across its
 * local direction, every 3 m of its length from 3 m before way[0] to 3 m
 * past its end (the step grows if they would exceed
 * ROVER_WORLD_MAX_LANDMARKS): each 3.5 m out, or where a wall stands
 * nearer, 0.15 m before it on the way's side (never beyond a wall; a
 * corridor's posts stand on its floor by its walls); none where the
 * way's point is not free. A way of one point (a start on the goal) runs
 * along heading_rad. Returns how many (into lm); 0 for no way or more
 * than ROVER_MAP_WAY_MAX points. */
#define ROVER_MAP_WAY_MAX 256
int rover_map_landmarks_along(const rover_map *m, const double (*way)[2], int n_way,
                              double heading_rad, double lm[ROVER_WORLD_MAX_LANDMARKS][2]);
/* w's posts along the way field f (built on w) takes from the team's
 * start to the goal (navfield_polyline, in w's world frame), so a
 * corridor's bends have posts in sight; w unchanged where that way has
 * no leg. Returns w->n_landmarks. */
int rover_map_landmarks_on_way(rover_world_config *w, const rover_map *m, const navfield *f);
/* rover_map_landmarks_along the straight line from start to goal (the
 * way of a map on which no navigation function was built). */
int rover_map_auto_landmarks(const rover_map *m, const pose2 *start, const double goal_m[2],
                             double lm[ROVER_WORLD_MAX_LANDMARKS][2]);

#endif
