/* rover_ctl_internal: NOT PART OF THE PUBLIC INTERFACE. The functions the
 * formation controller's own files (rover_ctl*.c) share with one another;
 * everything outside src/core/rover/rover_ctl*.c uses rover_ctl.h only.
 *   rover_ctl.c          init, the step's orchestration, its outputs
 *   rover_ctl_params.c   defaults and rover_ctl_params_validate
 *   rover_ctl_inputs.c   encoders, sonar, camera, team messages, own pose,
 *                        frame consensus, the mate mask
 *   rover_ctl_guard.c    collision guard, passage width, rearmost test
 *   rover_ctl_escape.c   the escape's state table, dead-zone escape,
 *                        giving way and waiting for outranking mates; the
 *                        one writer of the escape's state (c->esc)
 *   rover_ctl_mates.c    the priority order, the wait set, mates' chassis
 *                        by the team table: turning, backing and driving
 *                        clear of them
 *   rover_ctl_teams.c    robots of other teams seen by the camera, and
 *                        standing for those of outranking teams
 */
#ifndef TANDEM_ROVER_CTL_INTERNAL_H
#define TANDEM_ROVER_CTL_INTERNAL_H

#include "rover_ctl.h"

/* Another team's robot `id` seen by the camera at range / bearing from
 * own O pose o at t_s: kept (rover_ctl_teams.c). */
void rover_ctl_stranger_seen(rover_ctl_state *c, int32_t id, const pose2 *o, double range_m,
                             double bearing_rad, double t_s);
/* 1 if the robot is to stand this period for a robot of an outranking
 * team (one with lower ids) near ahead; bounded by stranger_hold_max_s
 * (rover_ctl_teams.c). */
int rover_ctl_stranger_wait(rover_ctl_state *c, const pose2 *o, double t_s, double dt_s);

/* Own pose of O, localized or dead-reckoned (rover_ctl_inputs.c). */
void rover_ctl_own_pose(const rover_ctl_state *c, pose2 *o);

/* Moves the own frame toward the team's (rover_ctl_inputs.c). */
void rover_ctl_frame_consensus(rover_ctl_state *c, double t_s, double dt_s);

/* Slower than this, a turn is a turn on the spot (a mate's, as the team
 * table reports it, or our own command). */
#define ROVER_SPIN_V_MPS 0.05

/* The circle a robot's chassis sweeps turning on the spot: its corners'
 * reach round the axle C, 0.314 m (rover_ctl_mates.c). */
double rover_ctl_turn_reach_m(void);

/* Every echo of the sonar ring lies at least 5 cm outside that circle
 * (rover_ctl_guard.c). */
int rover_ctl_spin_clear(const double range_m[BEH_SONAR_N]);

/* That, and with a map the map's clearance at the axle C as far outside
 * the circle: the walls behind, which no transducer sees (rover_ctl_guard.c). */
int rover_ctl_spin_free(const rover_ctl_state *c, const pose2 *o);

/* With a map, turning at w_radps would move a chassis corner toward a
 * wall the map puts within 5 cm of it: 1, else 0 (rover_ctl_guard.c). */
int rover_ctl_turn_grazes(const rover_ctl_state *c, const pose2 *o, double w_radps);

/* With a map, backing 0.1 m straight keeps the chassis's rear edge 5 cm
 * from every wall of the map it comes toward: 1, else 0
 * (rover_ctl_guard.c). */
int rover_ctl_back_clear_of_map(const rover_ctl_state *c, const pose2 *o);

/* The collision guard's speed rule alone; returns the nearest echo in the
 * way (rover_ctl_guard.c). */
double rover_ctl_guard_speed(unicycle_cmd *u, const double range_m[BEH_SONAR_N],
                             const rover_ctl_params *p);

/* Passage width for the passage protocol: INFINITY open, NAN unknown
 * (rover_ctl_guard.c). masked: the ranges with mates masked (keep_m 0). */
double rover_ctl_passage_width(const rover_ctl_state *c, const pose2 *o, const unicycle_state *ref,
                               const sonar_groups *gw, const double masked[BEH_SONAR_N]);

/* 1 if this robot is the last of the team toward the goal (it alone may
 * restore the formation after a passage). */
int rover_ctl_is_rearmost(const rover_ctl_state *c, const pose2 *o);

/* Dead-zone escape and give-way state machine: 1 while escaping, with its
 * command in *u (rover_ctl_escape.c). gw: sonar groups with mates masked
 * (walls only), g: with near mates kept (avoidance). */
int rover_ctl_escape_step(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                          const pose2 *o, const double goal[2], double t_s, double dt_s,
                          unicycle_cmd *u);

/* The announcement own team messages carry now: the escape table's for
 * the phase, else the passage protocol's (rover_ctl_escape.c). */
int rover_ctl_own_announce(const rover_ctl_state *c);

/* The priority order and the mates' chassis by the team table
 * (rover_ctl_mates.c); o: own O pose. */
/* 1 if robot (announce_a, id_a) outranks robot (announce_b, id_b): LEAVE
 * before GIVE_WAY before the rest, then the lower id. A strict total
 * order on distinct ids. */
int rover_ctl_outranks(int announce_a, int32_t id_a, int announce_b, int32_t id_b);
/* 1 if walls (gw: mates masked) are within follow_dist_m + walls_near_m
 * on some side. */
int rover_ctl_walls_near(const sonar_groups *gw, const rover_ctl_params *p);
/* The mates this robot waits for: those that outrank it and conflict with
 * it (docs/method/formation.md §10); their ids in wait[], the count
 * returned. */
int rover_ctl_wait_set(const rover_ctl_state *c, const pose2 *o, const sonar_groups *gw, double t_s,
                       int32_t wait[TEAM_MAX]);
/* 1 if mate m at mate_xy_m heads our way (we lie ahead of its heading). */
int rover_ctl_mate_coming(const team_member *m, const double mate_xy_m[2], const pose2 *o);
/* The id of a mate whose chassis lies within our turning circle, or whose
 * circle meets ours while it turns on the spot and outranks us; else 0. */
int32_t rover_ctl_spin_hits_mate(const rover_ctl_state *c, const pose2 *o);
/* 1 if turning the way dir (+1 left) sweeps our chassis into a mate's
 * within the next 0.6 rad. */
int rover_ctl_turn_sweeps_mate(const rover_ctl_state *c, const pose2 *o, int dir);
/* 1 if our chassis lies in mate's way: its turning circle or the lane it
 * sweeps driving ahead_m on. */
int rover_ctl_in_way_of(const rover_ctl_state *c, const pose2 *o, int32_t mate, double ahead_m);
/* 1 if backing reach_m along our crumbs keeps our chassis clear of every
 * mate's. */
int rover_ctl_crumbs_clear(const rover_ctl_state *c, const pose2 *o, double reach_m);
/* 1 if a mate's chassis reaches into the lane ours sweeps driving ahead_m
 * straight on. */
int rover_ctl_mate_in_lane(const rover_ctl_state *c, const pose2 *o, double ahead_m);
/* Which mates rover_ctl_cmd_sweeps_mate looks at. */
typedef enum {
    ROVER_SWEEP_ANY = 0,   /* every mate */
    ROVER_SWEEP_WAITED = 1 /* the mates of our wait set */
} rover_sweep_mates;

/* The id of a mate (of those `which` names) whose chassis ours would
 * sweep into (or come nearer to, touching it already) flying u for the
 * next second (arcs and turns on the spot included), else 0. */
int32_t rover_ctl_cmd_sweeps_mate(const rover_ctl_state *c, const pose2 *o, const unicycle_cmd *u,
                                  rover_sweep_mates which);
/* The id of an outranking mate that flying u for the next second meets,
 * the mate flying on at the speed and turn rate of the team table, else
 * 0 (rover_ctl_mates.c). */
int32_t rover_ctl_cmd_meets_mate(const rover_ctl_state *c, const pose2 *o, const unicycle_cmd *u);

#endif
