/* goal_place: where the team's goal formation stands
 * (docs/method/formation.md §15).
 *
 * The goal is the centre of the formation the team ends in: its slots lie
 * around it, headed along the bearing from the team origin to it. A goal
 * given near a wall, or a team larger than the room the goal has, puts a
 * slot inside an obstacle or off the map, where no robot can stand; the
 * robot sent there circles, and the team with it (the dead zone's goal is
 * 3.5 m behind the U's back wall: a column of eight has its rearmost slot
 * on that wall). So the layout places the goal formation where every slot
 * keeps GOAL_PLACE_CLEAR_M from every obstacle, the straight way to it
 * from the formation's centre too (one free area, not slots on both
 * sides of a wall), and lies that far inside the world's extent (a map's
 * edge; the box a built-in world's navigation grid covers, which reaches
 * past the goal as far as the formation does, rover_world_layout): at the
 * goal if it fits there, else at the nearest
 * point of a grid around it (at most the formation's radius plus one
 * spacing away) where it does. Every reader of the layout (simulator,
 * rover daemons, scenario criteria) derives the same goal from the same
 * world, team size and formation, so no message is needed.
 *
 * Pure computation, no allocation; bounded: at most
 * (2 GOAL_PLACE_RINGS + 1)^2 candidate goals, each checked against the
 * obstacles near the goal, and candidates are tried ring by ring so a
 * goal that fits returns after the first.
 */
#ifndef TANDEM_GOAL_PLACE_H
#define TANDEM_GOAL_PLACE_H

#include "rover_world.h"

/* A slot's clearance: the body's 0.32 m about its axle centre and the
 * 0.13 m margin its way is planned with (navfield_params_default's clear_m). */
#define GOAL_PLACE_CLEAR_M 0.45
#define GOAL_PLACE_STEP_M 0.1 /* the candidate grid, finer for small teams */
#define GOAL_PLACE_RINGS 40   /* candidate rings around the goal */

#define GOAL_PLACE_OK 0
#define GOAL_PLACE_ERR_ARG (-1)    /* NULL, bad formation or team size */
#define GOAL_PLACE_ERR_NO_FIT (-2) /* no candidate fits: the goal kept */

/* The radius of the formation's slots about its centre (m). */
double goal_place_radius_m(int formation, int n, double spacing_m);

/* 1 if the slots of `formation` for n robots, spacing_m apart, centred on
 * goal_m and headed from w's team origin toward it, and the ways to them
 * from goal_m, all keep GOAL_PLACE_CLEAR_M from w's obstacles and the
 * edges of its extent; else 0. */
int goal_place_fits(const rover_world_config *w, int formation, int n, double spacing_m,
                    const double goal_m[2]);

/* Places w's goal formation (above): w->goal_m moves to the nearest
 * candidate that fits, w->goal_nominal_m keeps the goal given and
 * w->goal_fits says whether one was found. GOAL_PLACE_OK (shift possibly
 * zero), GOAL_PLACE_ERR_NO_FIT (w->goal_m unchanged, goal_fits 0) or
 * GOAL_PLACE_ERR_ARG. */
int goal_place(rover_world_config *w, int formation, double spacing_m);

#endif
