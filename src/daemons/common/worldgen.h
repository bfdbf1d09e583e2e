/* worldgen: random rover worlds as occupancy maps (docs/formation.md,
 * "Generated worlds"): convex clutter, U / V / L pockets (traps),
 * corridors with bends and narrowings, and mixes of them, each with the
 * team's start and goal, kept only if a search finds a way for the robot
 * body from every robot's start to the goal on the map inflated by the
 * body's radius plus a margin, wide enough for the team in column.
 * Host only (tandem-worldgen, tandem-scenario formation --world random).
 */
#ifndef TANDEM_WORLDGEN_H
#define TANDEM_WORLDGEN_H

#include <stdint.h>
#include "rover_map.h"

/* status codes; their texts: WORLDGEN_CODES (shell_status.h) */
#define WORLDGEN_OK 0
#define WORLDGEN_ERR_ARG (-1)    /* kind, size or robots out of range */
#define WORLDGEN_ERR_NO_WAY (-2) /* no attempt gave a passable world */
#define WORLDGEN_ERR_MEMORY (-3)

enum {
    WORLDGEN_CLUTTER = 0,
    WORLDGEN_TRAPS = 1,
    WORLDGEN_CORRIDOR = 2,
    WORLDGEN_MIXED = 3,
    WORLDGEN_KINDS = 4
};

#define WORLDGEN_RESOLUTION_M 0.1
#define WORLDGEN_ATTEMPTS 64 /* sub-seeds tried before giving up */
/* The robot body's radius about C (half the chassis diagonal plus the
 * box's offset) and the margin the way must leave on each side of it. */
#define WORLDGEN_BODY_RADIUS_M 0.32
#define WORLDGEN_MARGIN_M 0.25

typedef struct worldgen_params {
    int kind; /* WORLDGEN_* */
    uint64_t seed;
    double width_m, height_m; /* the map (a wall round it) */
    int robots;               /* team size: the start area holds it */
    int formation;            /* the start formation (FORMATION_*) */
} worldgen_params;

/* the text of a WORLDGEN_* code (shell_status.h), STATUS_UNKNOWN_TEXT for another value */
const char *worldgen_strerror(int rc);
/* "clutter" | "traps" | "corridor" | "mixed" -> WORLDGEN_*, else WORLDGEN_ERR_ARG. */
int worldgen_kind(const char *name);
const char *worldgen_kind_name(int kind);

/* A world into m and s (landmarks auto). *attempt: the sub-seed index that
 * gave it (0 = the seed itself). WORLDGEN_OK or a code. */
int worldgen_make(rover_map *m, rover_map_site *s, const worldgen_params *p, int *attempt);

/* 1 if every robot of a team of n (in `formation`) placed at s->start can
 * reach s->goal_m and every slot of the formation placed at the goal
 * (headed along the bearing of the goal from the start) on m inflated by
 * clearance_m (BFS, 8-connected), 0 if not (or the layout is refused). */
int worldgen_passable(rover_map *m, const rover_map_site *s, int n, int formation,
                      double clearance_m);

#endif
