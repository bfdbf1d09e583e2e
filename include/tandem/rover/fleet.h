/* fleet: many teams in one world (docs/formation.md, "Many teams in one
 * world"). T teams of K robots each, robot ids numbered team by team
 * (team t, 0-based, holds ids t K + 1 .. (t + 1) K), each team its own
 * formation, start area and goal, on an open world sized by T: the
 * teams' start areas side by side across the way (lanes, each as wide as
 * the team's formation plus a gap), all heading +x; more than
 * ROVER_FLEET_ROW_LANES teams in rows of that many lanes, each row
 * ROVER_FLEET_ROW_GAP_M past the goals of the row behind it (the world
 * grows along the way and across it alike, not across it alone: 300 teams
 * of 10 on 16 lanes of 19 rows, not one lane row 4 km wide). Each team's goal lies
 * ROVER_FLEET_GOAL_AHEAD_M ahead of its start, in its own lane (AHEAD) or,
 * with CROSS, in the lane of the neighbour it is paired with (lanes 0-1,
 * 2-3, ...: the two teams of a pair cross each other's way half-way;
 * an odd last team keeps its lane).
 *
 * Everything is a deterministic function of (teams, per_team, spacing,
 * formation, goals), like rover_world_layout: the simulator, every rover
 * daemon and the scenario derive the same fleet without talking. Each
 * team has its own team frame (rover_world.h: origin at the mean of its
 * robots' start points O, axes the world's), in which its messages, its
 * goal and its goal formation's heading (the goal's bearing from the
 * origin) are; a robot hears only its own team's messages
 * (rover_fleet_members, rover_ctl_set_team).
 */
#ifndef TANDEM_ROVER_FLEET_H
#define TANDEM_ROVER_FLEET_H

#include "rover_world.h"

#define ROVER_FLEET_ERR_ARG (-1) /* NULL, teams or per_team out of range, bad spacing */

/* Capacities (VME style, fixed at build time): a fleet of at most
 * ROVER_FLEET_MAX_TEAMS teams of at most ROVER_TEAM_MAX robots, and at
 * most ROVER_WORLD_MAX_ROBOTS robots in all. */
#define ROVER_FLEET_MAX_TEAMS 1024
/* Lanes in one row of teams (even: the pairs of CROSS stay in a row). */
#define ROVER_FLEET_ROW_LANES 16

/* The teams' goals (rover_fleet.goals). */
enum { ROVER_FLEET_GOALS_AHEAD = 0, ROVER_FLEET_GOALS_CROSS = 1 };

/* How far ahead of its start (the team's front row) each team's goal lies:
 * the open world's goal distance (rover_world.c). */
#define ROVER_FLEET_GOAL_AHEAD_M 12.0
/* Free space between two neighbouring teams' formations at the start. */
#define ROVER_FLEET_LANE_GAP_M 3.0
/* Free space between a row's goal formations and the start area of the
 * row ahead of it. */
#define ROVER_FLEET_ROW_GAP_M 6.0
/* LED posts along a lane's border stand at most this far apart where the
 * world's capacity allows: the camera's reach (sim_rovers_sense.c) */
#define ROVER_FLEET_POST_STEP_M 6.0

typedef struct {
    int teams, per_team;                     /* T, K */
    int goals;                               /* ROVER_FLEET_GOALS_* */
    double lane_m;                           /* lane pitch across the way (y) */
    int rows;                                /* rows of ROVER_FLEET_ROW_LANES lanes */
    double row_m;                            /* row pitch along the way (x) */
    double lane_y_m[ROVER_FLEET_MAX_TEAMS];  /* team t's lane centre (world frame) */
    double goal_m[ROVER_FLEET_MAX_TEAMS][2]; /* team t's goal (world frame) */
    pose2 origin[ROVER_FLEET_MAX_TEAMS];     /* team t's team frame in the world */
} rover_fleet;

/* The fleet's world: w as rover_world_layout's for the open world, with
 * the start poses of all teams * per_team robots (id k at index k - 1),
 * the extent and the LED landmarks (rows along the lanes' borders, at
 * most ROVER_FLEET_POST_STEP_M apart where ROVER_WORLD_MAX_POSTS allows)
 * covering every lane, w->team_origin
 * and w->goal_m team 0's; f the teams' lanes, frames and goals. 0, or ROVER_FLEET_ERR_ARG (teams 1..ROVER_FLEET_MAX_TEAMS,
 * per_team 1..ROVER_TEAM_MAX, their product at most ROVER_WORLD_MAX_ROBOTS,
 * goals one of ROVER_FLEET_GOALS_*). */
int rover_fleet_layout(rover_world_config *w, rover_fleet *f, int teams, int per_team,
                       double spacing_m, int formation, int goals);

/* Robot id's team (0-based), or ROVER_FLEET_ERR_ARG for an id outside the
 * fleet. */
int rover_fleet_team_of(const rover_fleet *f, int32_t id);

/* The ids of team t: lo..hi. ROVER_FLEET_ERR_ARG for a team outside the
 * fleet. */
int rover_fleet_members(const rover_fleet *f, int team, int32_t *lo, int32_t *hi);

/* Robot id's team frame in the world: its team's in a fleet, w's own
 * (w->team_origin) with f NULL or a single team. */
pose2 rover_fleet_frame_of(const rover_world_config *w, const rover_fleet *f, int32_t id);

/* "ahead" | "cross" -> ROVER_FLEET_GOALS_*, else ROVER_FLEET_ERR_ARG. */
int rover_fleet_goals_id(const char *name);
const char *rover_fleet_goals_name(int goals);

#endif
