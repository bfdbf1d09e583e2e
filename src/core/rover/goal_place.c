/* goal_place: the goal formation placed where every slot is free
 * (docs/method/formation.md §15; see goal_place.h). No equation: a
 * nearest-first search over a grid of candidate goals. */
#include "goal_place.h"

#include <math.h>
#include <stddef.h>

#include "formation.h"

double goal_place_radius_m(int formation, int n, double spacing_m)
{
    double s[FORMATION_MAX_ROBOTS][2], r = 0.0;
    int k;
    if (n < 1 || n > FORMATION_MAX_ROBOTS ||
        formation_slots_xy(s, formation, n, spacing_m, 1.0) != 0)
        return NAN;
    for (k = 0; k < n; k++)
        r = fmax(r, hypot(s[k][0], s[k][1]));
    return r;
}

/* The obstacles a slot of any candidate can come within GOAL_PLACE_CLEAR_M
 * of: those nearer the goal than reach_m. Their count. */
static int near_obstacles(const rover_world_config *w, const double goal_m[2], double reach_m,
                          uint16_t *near)
{
    int k, n = 0;
    for (k = 0; k < w->n_obst; k++)
        if (rover_obstacle_distance(&w->obst[k], goal_m[0], goal_m[1]) <= reach_m)
            near[n++] = (uint16_t)k;
    return n;
}

static int point_clear(const rover_world_config *w, const uint16_t *near, int n_near,
                       const double p[2])
{
    int k;
    /* a map ends where it was drawn; a built-in world's extent is what
     * the navigation function's grid covers */
    if (p[0] < w->x_min_m + GOAL_PLACE_CLEAR_M || p[0] > w->x_max_m - GOAL_PLACE_CLEAR_M ||
        p[1] < w->y_min_m + GOAL_PLACE_CLEAR_M || p[1] > w->y_max_m - GOAL_PLACE_CLEAR_M)
        return 0;
    for (k = 0; k < n_near; k++)
        if (rover_obstacle_distance(&w->obst[near[k]], p[0], p[1]) < GOAL_PLACE_CLEAR_M)
            return 0;
    return 1;
}

/* The straight way from the formation's centre g to its slot at offset
 * d keeps the clearance too, sampled every half step: the formation is
 * one free area, not slots on both sides of a wall (the nearest free
 * point for the dead zone's rear slot is inside the U, behind its back
 * wall from the goal). */
static int way_clear(const rover_world_config *w, const uint16_t *near, int n_near,
                     const double g[2], const double d[2])
{
    const long n = (long)ceil(hypot(d[0], d[1]) / (0.5 * GOAL_PLACE_STEP_M));
    long i;
    for (i = 0; i <= n; i++) {
        const double f = n > 0 ? (double)i / (double)n : 0.0;
        const double p[2] = { g[0] + f * d[0], g[1] + f * d[1] };
        if (!point_clear(w, near, n_near, p))
            return 0;
    }
    return 1;
}

/* Every slot s (formation frame) around g, headed from the team origin,
 * and the way to it from g. Slots first: most candidates fail there. */
static int slots_clear(const rover_world_config *w, const uint16_t *near, int n_near,
                       const double (*s)[2], int n, const double g[2])
{
    const double h = atan2(g[1] - w->team_origin.y_m, g[0] - w->team_origin.x_m);
    double d[FORMATION_MAX_ROBOTS][2];
    int k;
    for (k = 0; k < n; k++) {
        double p[2];
        vec2_rotate(d[k], s[k][0], s[k][1], h);
        p[0] = g[0] + d[k][0];
        p[1] = g[1] + d[k][1];
        if (!point_clear(w, near, n_near, p))
            return 0;
    }
    for (k = 0; k < n; k++)
        if (!way_clear(w, near, n_near, g, d[k]))
            return 0;
    return 1;
}

static int slots_of(double (*s)[2], int formation, int n, double spacing_m)
{
    return n >= 1 && n <= FORMATION_MAX_ROBOTS &&
           formation_slots_xy(s, formation, n, spacing_m, 1.0) == 0;
}

int goal_place_fits(const rover_world_config *w, int formation, int n, double spacing_m,
                    const double goal_m[2])
{
    double s[FORMATION_MAX_ROBOTS][2];
    uint16_t near[ROVER_WORLD_MAX_OBST];
    double r;
    if (!w || !goal_m || !slots_of(s, formation, n, spacing_m))
        return 0;
    r = goal_place_radius_m(formation, n, spacing_m);
    return slots_clear(w, near, near_obstacles(w, goal_m, r + GOAL_PLACE_CLEAR_M, near),
                       (const double(*)[2])s, n, goal_m);
}

/* The nearest candidate (i, j) steps from the goal that fits, ring by
 * ring (ring r: max(|i|, |j|) = r, no nearer than r steps), the first
 * found among equals; 0 and *bi, *bj set, or -1. */
static int nearest_fit(const rover_world_config *w, const uint16_t *near, int n_near,
                       const double (*s)[2], int n, double step_m, int *bi, int *bj)
{
    long best = -1;
    int r, i, j;
    for (r = 0; r <= GOAL_PLACE_RINGS && (best < 0 || (long)r * r <= best); r++)
        for (j = -r; j <= r; j++)
            for (i = -r; i <= r; i += (j == -r || j == r || r == 0) ? 1 : 2 * r) {
                const long d2 = (long)i * i + (long)j * j;
                const double g[2] = { w->goal_nominal_m[0] + i * step_m,
                                      w->goal_nominal_m[1] + j * step_m };
                if (d2 > (long)GOAL_PLACE_RINGS * GOAL_PLACE_RINGS || (best >= 0 && d2 >= best))
                    continue;
                if (slots_clear(w, near, n_near, s, n, g)) {
                    best = d2;
                    *bi = i;
                    *bj = j;
                }
            }
    return best < 0 ? -1 : 0;
}

int goal_place(rover_world_config *w, int formation, double spacing_m)
{
    double s[FORMATION_MAX_ROBOTS][2];
    uint16_t near[ROVER_WORLD_MAX_OBST];
    double r, shift_max, step;
    int n_near, bi = 0, bj = 0;
    if (!w)
        return GOAL_PLACE_ERR_ARG;
    w->goal_nominal_m[0] = w->goal_m[0];
    w->goal_nominal_m[1] = w->goal_m[1];
    w->goal_fits = 0;
    if (!slots_of(s, formation, w->n_robots, spacing_m))
        return GOAL_PLACE_ERR_ARG;
    r = goal_place_radius_m(formation, w->n_robots, spacing_m);
    /* a formation moved further than its own size is not at the goal */
    shift_max = r + spacing_m;
    step = fmax(GOAL_PLACE_STEP_M, shift_max / GOAL_PLACE_RINGS);
    n_near = near_obstacles(w, w->goal_m, r + shift_max + GOAL_PLACE_CLEAR_M, near);
    w->goal_fits = nearest_fit(w, near, n_near, (const double(*)[2])s, w->n_robots, step, &bi,
                               &bj) == 0;
    if (!w->goal_fits)
        return GOAL_PLACE_ERR_NO_FIT;
    w->goal_m[0] = w->goal_nominal_m[0] + bi * step;
    w->goal_m[1] = w->goal_nominal_m[1] + bj * step;
    return GOAL_PLACE_OK;
}
