/* sonar: ray casting against a fixed-capacity 2.5-D world and the Pioneer
 * 2 DX front-ring transducer model (docs/method/sonar.md).
 *
 * World: up to SONAR_MAX_PRIMS primitives, each a 2-D shape extruded over
 * [z_min, z_max] (infinities allowed): oriented boxes (axis-aligned is
 * angle 0), circles (cylinders) and line segments (thin walls, two-sided).
 * sonar_world_build() makes a uniform grid (at most SONAR_GRID_MAX^2 cells,
 * in any shape: a long row of robots gets cells as fine as a square map,
 * SONAR_GRID_MAX_REFS prim references); sonar_cast walks it with a
 * 2-D DDA and stops at the first cell whose far edge lies beyond the best
 * hit. Without a built grid (or if it did not fit) it scans every prim with
 * a bounding-circle reject.
 *
 * Transducer model: 8 transducers (table order -90 -50 -30 -10 10 30 50 90
 * deg, index 0 = right), mounted as on a Pioneer 2 DX front ring, positions
 * relative to the axle centre C. A reading casts rays_per_cone rays evenly
 * across the cone; the nearest echo wins. A ray whose incidence angle
 * (between the ray and the surface normal) exceeds specular_max_rad is
 * reflected away (no echo from it). The winner gets Gaussian noise from
 * the caller's PRNG and is clamped to [range_min, range_max]; no echo at all
 * reads range_max (as sonar_scan_t does).
 * Firing sequence: as on the Pioneer, one transducer fires every
 * fire_period_s (40 ms: 25 firings per second for the ring, so each
 * transducer is refreshed every 0.32 s), in ARIA order left to right, i.e.
 * table indices 7, 6, ..., 0 (sonar_p2dx_fire_order).
 */
#ifndef TANDEM_SONAR_H
#define TANDEM_SONAR_H

#include <stdint.h>

#include "prng.h"
#include "rover_world.h"
#include "vec2.h"

#define SONAR_ERR_ARG \
    (-1) /* NULL, non-finite or out-of-range input, an
                               invalid model, or the primitive table full */

#ifndef SONAR_MAX_PRIMS /* a map's boxes and the robots */
#define SONAR_MAX_PRIMS (ROVER_WORLD_MAX_OBST + ROVER_WORLD_MAX_ROBOTS)
#endif
#define SONAR_N 8
#define SONAR_MAX_RAYS 32
#define SONAR_GRID_MAX 64         /* the grid holds SONAR_GRID_MAX^2 cells */
#define SONAR_MANY_PRIMS 256      /* above: grid cells of about one prim each */
#define SONAR_GRID_MAX_REFS 32768 /* < 65536: cell_start and refs are uint16 */

enum { SONAR_PRIM_BOX = 0, SONAR_PRIM_CIRCLE = 1, SONAR_PRIM_SEGMENT = 2 };

typedef struct {
    int kind;
    double ax, ay; /* box/circle centre; segment end a */
    double bx, by; /* box half extents; segment end b */
    double c, s;   /* box orientation cos, sin */
    double r;      /* circle radius */
    double z_min, z_max;
    double bcx, bcy, br;   /* bounding circle */
    double x0, y0, x1, y1; /* bounding box */
} sonar_prim;

typedef struct {
    int n;
    sonar_prim p[SONAR_MAX_PRIMS];
    int built; /* grid valid for the current prims */
    double gx0, gy0, cell_m;
    int nx, ny;
    uint16_t cell_start[SONAR_GRID_MAX * SONAR_GRID_MAX + 1];
    uint16_t refs[SONAR_GRID_MAX_REFS];
} sonar_world;

typedef struct {
    double t_m;           /* distance along the ray */
    double nx, ny;        /* unit surface normal facing the ray */
    double incidence_rad; /* angle between -ray and normal, [0, pi/2] */
    int prim;
} sonar_hit;

void sonar_world_init(sonar_world *w);
/* Each returns the prim index, or SONAR_ERR_ARG (full, or invalid: non-finite,
 * non-positive size, z_min > z_max, NaN). Adding invalidates the grid. */
int sonar_world_add_box(sonar_world *w, double cx, double cy, double half_x, double half_y,
                        double angle_rad, double z_min, double z_max);
int sonar_world_add_aabb(sonar_world *w, double x0, double y0, double x1, double y1, double z_min,
                         double z_max);
int sonar_world_add_circle(sonar_world *w, double cx, double cy, double r, double z_min,
                           double z_max);
int sonar_world_add_segment(sonar_world *w, double ax, double ay, double bx, double by,
                            double z_min, double z_max);
/* Build the broad-phase grid. 0 ok, 1 did not fit (casts scan linearly). */
int sonar_world_build(sonar_world *w);

/* One ray from (ox, oy) at height z, direction dir_rad, up to max_m.
 * Returns 1 with *hit filled, 0 for no hit, SONAR_ERR_ARG on bad input. Starting
 * inside a primitive is a hit at t = 0. */
int sonar_cast(sonar_hit *hit, const sonar_world *w, double ox, double oy, double z_m,
               double dir_rad, double max_m);
/* Same result without the grid (every prim tested); for tests and timing. */
int sonar_cast_brute(sonar_hit *hit, const sonar_world *w, double ox, double oy, double z_m,
                     double dir_rad, double max_m);

/* Slab test of the line through (ox, oy) with direction (dx, dy) against
 * a box (centre cx, cy, half extents hx, hy, heading given by its cosine c
 * and sine s): *t_in, *t_out the line parameters where it enters and
 * leaves the box, n_in the outward normal (box frame) of the face it
 * enters by (0, 0 if no face bounds the entry). 1 if the line meets the
 * box, 0 if it misses. Shared by the sonar and the controller's mate mask. */
int sonar_line_box(double ox, double oy, double dx, double dy, double cx, double cy, double hx,
                   double hy, double c, double s, double *t_in, double *t_out, double n_in[2]);

typedef struct {
    double x_m, y_m;  /* mounting position relative to C, robot frame */
    double angle_rad; /* bearing, CCW from the heading */
} sonar_transducer;

extern const sonar_transducer sonar_p2dx_front[SONAR_N];
extern const int sonar_p2dx_fire_order[SONAR_N];

typedef struct {
    double range_min_m;      /* 0.1 */
    double range_max_m;      /* 5.0 */
    double cone_rad;         /* full cone width, 25 deg */
    int rays_per_cone;       /* 5 (1..SONAR_MAX_RAYS) */
    double noise_sd_m;       /* 0.01 */
    double specular_max_rad; /* 0 = no specular loss; e.g. 70 deg to enable */
    double height_m;         /* transducer height above the floor, 0.2 */
    double fire_period_s;    /* 0.04 */
} sonar_model;

void sonar_model_default(sonar_model *m);
int sonar_model_validate(const sonar_model *m);

/* Reading of transducer k for a robot whose axle centre C has pose c.
 * rng may be NULL (no noise). Returns 1 echo, 0 none (range = max), SONAR_ERR_ARG bad. */
int sonar_fire(double *range_m, const sonar_world *w, const sonar_model *m, const pose2 *c, int k,
               prng_state *rng);
/* All eight, in table order (noise drawn in table order). Returns the
 * number of echoes or SONAR_ERR_ARG. */
int sonar_ring(double range_m[SONAR_N], const sonar_world *w, const sonar_model *m, const pose2 *c,
               prng_state *rng);
/* Transducer that fires in the slot containing time t_s (t_s >= 0). */
int sonar_fired_index(double t_s, const sonar_model *m);

#endif
