/* The texts of the rover domain's status codes (rover_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "rover_status.h"

STATUS_STRERROR(unicycle_strerror, UNICYCLE_CODES)
STATUS_STRERROR(odometry_strerror, ODOMETRY_CODES)
STATUS_STRERROR(localize_strerror, LOCALIZE_CODES)
STATUS_STRERROR(sonar_strerror, SONAR_CODES)
STATUS_STRERROR(behaviour_strerror, BEHAVIOUR_CODES)
STATUS_STRERROR(formation_strerror, FORMATION_CODES)
STATUS_STRERROR(team_strerror, TEAM_CODES)
STATUS_STRERROR(rover_world_strerror, ROVER_WORLD_CODES)
STATUS_STRERROR(rover_ctl_strerror, ROVER_CTL_CODES)
STATUS_STRERROR(rover_map_strerror, ROVER_MAP_CODES)
STATUS_STRERROR(navfield_strerror, NAVFIELD_CODES)
STATUS_STRERROR(goal_place_strerror, GOAL_PLACE_CODES)
STATUS_STRERROR(slot_assign_strerror, SLOT_ASSIGN_CODES)
STATUS_STRERROR(rover_fleet_strerror, ROVER_FLEET_CODES)
