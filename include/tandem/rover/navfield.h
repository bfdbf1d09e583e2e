/* navfield: a navigation function over a world's free space, and the
 * point to steer for on it (docs/method/formation.md §14).
 *
 * A grid laid over the world holds, for every cell, its centre's clearance
 * (distance to the nearest obstacle) and the length of the shortest
 * 8-connected way from the cell centre to the goal for a disc of radius
 * clear_m, each step's length weighted by 1 + pen_gain (1 - c / prefer_m)
 * where the way passes at a clearance c below prefer_m (a way through the
 * middle of a passage costs less than one along its wall).
 *
 * Why steepest descent cannot stall (the local minima of a reactive goal
 * behaviour, a pocket facing the team, a wall with one gap): the value is a
 * shortest-path length on a graph with positive weights, so every finite
 * cell but the goal's has a neighbour on its shortest way whose value is
 * smaller by that step's weight; descent from any cell joined to the goal
 * reaches it in fewer steps than there are cells.
 *
 * navfield_waypoint returns the goal itself wherever the straight way to it
 * keeps los_m from every obstacle, so in the open the seed's goal behaviour
 * is flown unchanged; elsewhere the farthest point of the descent, within
 * look_m, that is seen straight. Pure computation, fixed capacity (the
 * cells grow coarser when a world needs more than NAVFIELD_MAX_CELLS), no
 * allocation; the build is bounded by the cells and obstacles, a query by
 * look_m and the world's size.
 */
#ifndef TANDEM_ROVER_NAVFIELD_H
#define TANDEM_ROVER_NAVFIELD_H

#include "rover_world.h"
#include "vec2.h"

#define NAVFIELD_OK 0
#define NAVFIELD_ERR_ARG (-1) /* NULL, bad parameters, a world without extent */
#define NAVFIELD_ERR_GOAL \
    (-2) /* the goal's cell is off the grid or nearer an obstacle than clear_m */
#define NAVFIELD_ERR_PASSES (-3) /* the relaxation did not settle within its bound */

/* navfield_waypoint's answers (>= 0) */
#define NAVFIELD_DIRECT 0  /* the goal, seen straight */
#define NAVFIELD_DESCENT 1 /* a point of the descent */
#define NAVFIELD_NO_WAY 2  /* no way from here: the goal (the seed's behaviour) */

#ifndef NAVFIELD_MAX_CELLS
#define NAVFIELD_MAX_CELLS (512L * 512L)
#endif

typedef struct {
    double clear_m;     /* cells nearer an obstacle than this are not passable (body + margin) */
    double los_m;       /* a straight way is seen clear if it keeps this from every obstacle */
    double prefer_m;    /* ways nearer an obstacle than this cost more ... */
    double pen_gain;    /* ... up to (1 + pen_gain) times their length */
    double look_m;      /* the waypoint lies at most this far along the descent ... */
    double min_ahead_m; /* ... and at least this far, where the descent is that long */
    double cell_min_m;  /* the finest cell side (coarser when the world needs more cells) */
} navfield_params;

typedef struct {
    navfield_params p;
    int nx, ny;
    double cell_m;                     /* cell side */
    double x0_m, y0_m;                 /* world frame: the lower-left corner of cell (0, 0) */
    pose2 frame;                       /* the callers' frame in the world (the team frame) */
    long goal_cell;                    /* j * nx + i */
    float clear_m[NAVFIELD_MAX_CELLS]; /* centre to the nearest obstacle, capped */
    float way_m[NAVFIELD_MAX_CELLS];   /* weighted way to the goal; INFINITY: none */
} navfield;

void navfield_params_default(navfield_params *p);
/* NAVFIELD_OK, or NAVFIELD_ERR_ARG for a value not finite, not positive
 * where it must be, or los_m / prefer_m below clear_m's half / clear_m. */
int navfield_params_validate(const navfield_params *p);

/* The field of world w (its obstacles, extent, goal and team frame).
 * NAVFIELD_OK or a NAVFIELD_ERR_* code (the field is then unusable). */
int navfield_build(navfield *f, const navfield_params *p, const rover_world_config *w);

/* The way field again for another clear_m, the clearances kept (what a
 * search for the widest passable disc needs); clear_m at most prefer_m
 * and at most twice los_m. NAVFIELD_OK or a NAVFIELD_ERR_* code. */
int navfield_relax(navfield *f, double clear_m);

/* The weighted way from the world point (x, y) to the goal (the cell's
 * value); INFINITY off the grid or where there is none. */
double navfield_way_m(const navfield *f, double x_m, double y_m);

/* A lower bound on the distance from `at` (the callers' frame) to the
 * nearest obstacle: its cell centre's clearance less half the cell's
 * diagonal (no obstacle is nearer the point than that), capped as the
 * clearances are. -INFINITY off the grid, or on NULL or non-finite input. */
double navfield_clearance_m(const navfield *f, const double at_m[2]);

/* A tighter lower bound than navfield_clearance_m (the best of the nine
 * cells round the point's, each centre's clearance less its distance to
 * the point), and in slope the way the clearance grows there (the cells'
 * central differences, per metre, the callers' frame; away from the
 * nearest obstacle, about unit length where one is within the cap; 0 off
 * the grid). -INFINITY off the grid, or on NULL or non-finite input
 * (slope NULL: nothing written). */
double navfield_clearance_slope_m(const navfield *f, const double at_m[2], double slope[2]);

/* The way to the goal from `from` (the callers' frame): from the cell
 * navfield_waypoint would descend from (its own, or for a point nearer an
 * obstacle than clear_m, a robot beside a wall, the one within reach with
 * the least way plus the straight distance to it), that cell's way plus
 * the straight distance to its centre. So from any point p, and any q that
 * p reaches straight (within the reach, no nearer an obstacle than p or
 * clear_m / 2), way(p) <= way(q) + |pq| + the distance from q to its
 * cell's centre. INFINITY where no cell near is joined to the goal, or on
 * NULL or non-finite input. How far along the way a robot is, the same
 * measure round any bend. */
double navfield_way_from(const navfield *f, const double from_m[2]);

/* The point to steer for from `from` toward `goal` (both in the callers'
 * frame, f->frame): NAVFIELD_DIRECT and out = goal when the straight way
 * is clear; NAVFIELD_DESCENT and a point of the field's descent; or
 * NAVFIELD_NO_WAY and out = goal where no cell near `from` is joined to
 * the goal. `goal` should lie near the field's goal (a slot of the
 * formation placed at it). NAVFIELD_ERR_ARG on NULL or non-finite input. */
int navfield_waypoint(const navfield *f, const double from_m[2], const double goal_m[2],
                      double out_m[2]);

/* The way from `from` to `goal` (the callers' frame) as a polyline:
 * `from`, then the points navfield_waypoint steers for in turn until the
 * goal is seen straight, then the goal (also where there is no way, or
 * the cap cuts it short). Each point is at least a metre along the
 * descent, so at most cap points. How many (0 on NULL, non-finite input
 * or cap < 2). */
int navfield_polyline(const navfield *f, const double from_m[2], const double goal_m[2],
                      double (*way)[2], int cap);

/* The passages on the way ahead: what the sonar's passage test measures
 * (left + right + the robot's width, docs/method/formation.md §9), read
 * from the map along the descent. At every cell of the descent the free
 * width across the way's direction, from the first obstacle on its left
 * to the first on its right, each looked for up to side_m (a cell with a
 * side open beyond side_m has none); also along lines tilted up to 45 deg
 * from the way's normal, projected on it (a gap in a thin wall crossed
 * aslant), the least of them. */
typedef struct {
    double ahead_m;  /* the narrowest width is taken this far along the way */
    double side_m;   /* each side's obstacle looked for this far */
    double below_m;  /* the way narrower than this is measured ... */
    double beyond_m; /* ... over ahead_m and this much further */
} navfield_passage_query;

typedef struct {
    double narrowest_m; /* INFINITY: no passage within ahead_m (or no way) */
    double below_len_m; /* how much of the way looked at is narrower than below_m:
                           a gap in a thin wall is short, a corridor long */
} navfield_passage;

/* The passages on the descent from `from` (the callers' frame).
 * NAVFIELD_OK, or NAVFIELD_ERR_ARG on NULL or non-finite input (out
 * unchanged). Bounded: (ahead_m + beyond_m) / cell steps, 4 side_m /
 * cell samples on each of 9 lines per step. */
int navfield_passage_ahead(const navfield *f, const double from_m[2],
                           const navfield_passage_query *q, navfield_passage *out);

#endif
