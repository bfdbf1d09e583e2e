/* The status codes of the rover domain's modules and the text of each
 * (status.h): <module>_strerror(rc) returns it, STATUS_UNKNOWN_TEXT for a
 * value that is no code of the module. Never NULL. */
#ifndef TANDEM_ROVER_STATUS_H
#define TANDEM_ROVER_STATUS_H

#include "status.h"
#include "unicycle.h"
#include "odometry.h"
#include "localize.h"
#include "sonar.h"
#include "behaviour.h"
#include "formation.h"
#include "team.h"
#include "rover_world.h"
#include "rover_ctl.h"
#include "rover_map.h"
#include "navfield.h"
#include "goal_place.h"
#include "slot_assign.h"
#include "fleet.h"

#define UNICYCLE_CODES(X) \
    X(0, "ok")            \
    X(UNICYCLE_ERR_ARG, "non-finite input (the output is 0)")
#define ODOMETRY_CODES(X) \
    X(0, "ok")            \
    X(ODOMETRY_ERR_ARG, "non-positive geometry or non-finite input")
#define LOCALIZE_CODES(X)                                                                        \
    X(0, "ok")                                                                                   \
    X(LOCALIZE_ERR_ARG, "NULL, non-finite input, a parameter out of range, an unknown landmark " \
                        "or a degenerate measurement")
#define SONAR_CODES(X) \
    X(0, "ok")         \
    X(SONAR_ERR_ARG,   \
      "NULL, non-finite or out-of-range input, an invalid model, or the primitive table full")
#define BEHAVIOUR_CODES(X) \
    X(0, "ok")             \
    X(BEHAVIOUR_ERR_ARG,   \
      "NULL, non-finite input, bad mode, a parameter out of range, or a pose at the singularity")
#define FORMATION_CODES(X)                                                        \
    X(0, "ok")                                                                    \
    X(FORMATION_ERR_ARG, "bad formation type, team size, slot, spacing or scale") \
    X(FORMATION_ERR_ABSENT, "the robot is not in the team")
#define TEAM_CODES(X)                                               \
    X(0, "ok")                                                      \
    X(TEAM_ERR_ARG, "NULL, non-finite input or an invalid message") \
    X(TEAM_ERR_FULL, "a new mate but TEAM_MAX are held")            \
    X(TEAM_ERR_UNKNOWN, "no such mate, or none to average")
#define ROVER_WORLD_CODES(X)                                                      \
    X(0, "ok")                                                                    \
    X(ROVER_WORLD_ERR_ARG,                                                        \
      "NULL, team size, spacing or formation out of range, or a non-finite pose") \
    X(ROVER_WORLD_ERR_UNKNOWN, "no world of that name")
#define ROVER_CTL_CODES(X)                                                   \
    X(ROVER_CTL_OK, "ok")                                                    \
    X(ROVER_CTL_ERR_ARG, "bad argument, parameter set or reading")           \
    X(ROVER_CTL_ERR_SNAPSHOT, "a snapshot of another robot or out of range") \
    X(ROVER_CTL_ERR_TEAM, "a team message from a robot of another team: not taken")
#define ROVER_MAP_CODES(X)                                                               \
    X(ROVER_MAP_OK, "ok")                                                                \
    X(ROVER_MAP_ERR_ARG, "bad argument")                                                 \
    X(ROVER_MAP_ERR_SIZE, "width and height must be 1..2048 cells (ROVER_MAP_MAX_SIDE)") \
    X(ROVER_MAP_ERR_RESOLUTION, "resolution must be finite and > 0, origin finite")      \
    X(ROVER_MAP_ERR_BOXES,                                                               \
      "the occupied cells merge into more than 2048 boxes (ROVER_WORLD_MAX_OBST)")       \
    X(ROVER_MAP_ERR_START, "a robot's start is off the map or on an obstacle")           \
    X(ROVER_MAP_ERR_GOAL, "the goal is off the map or on an obstacle")                   \
    X(ROVER_MAP_ERR_LANDMARKS,                                                           \
      "landmarks: not finite, or more than 64 (ROVER_WORLD_MAX_LANDMARKS)")              \
    X(ROVER_MAP_ERR_CELL, "a cell is neither free nor occupied")
#define NAVFIELD_CODES(X)                                                               \
    X(NAVFIELD_OK, "ok")                                                                \
    X(NAVFIELD_ERR_ARG, "NULL, bad parameters, or a world without extent")              \
    X(NAVFIELD_ERR_GOAL, "the goal is off the grid or nearer an obstacle than clear_m") \
    X(NAVFIELD_ERR_PASSES, "the relaxation did not settle within its bound")
#define GOAL_PLACE_CODES(X)                                            \
    X(GOAL_PLACE_OK, "ok")                                             \
    X(GOAL_PLACE_ERR_ARG, "NULL, bad formation, team size or spacing") \
    X(GOAL_PLACE_ERR_NO_FIT, "no place near the goal fits the goal formation: the goal kept")
#define ROVER_FLEET_CODES(X) \
    X(0, "ok")               \
    X(ROVER_FLEET_ERR_ARG,   \
      "NULL, teams, robots per team, their product or the goals out of range, or bad spacing")
#define SLOT_ASSIGN_CODES(X) \
    X(SLOT_ASSIGN_OK, "ok")  \
    X(SLOT_ASSIGN_ERR_ARG, "NULL, team size not 1..FORMATION_MAX_ROBOTS, or a position not finite")

const char *unicycle_strerror(int rc);
const char *odometry_strerror(int rc);
const char *localize_strerror(int rc);
const char *sonar_strerror(int rc);
const char *behaviour_strerror(int rc);
const char *formation_strerror(int rc);
const char *team_strerror(int rc);
const char *rover_world_strerror(int rc);
const char *rover_ctl_strerror(int rc);
const char *navfield_strerror(int rc);
const char *goal_place_strerror(int rc);
const char *slot_assign_strerror(int rc);
const char *rover_fleet_strerror(int rc);

#endif
