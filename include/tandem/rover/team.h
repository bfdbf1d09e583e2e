/* team: the table of team-mates built from their team messages (docs/method/
 * formation.md, distribution): heartbeat timeout, late joiners, the team
 * average reference R0 and fusion of camera beacon observations.
 *
 * Positions are of the point O (the beacon) in the team frame. Reference
 * R0: every alive member not announcing LEAVE, plus self, each extrapolated
 * to now along its reported (V, w) (at most timeout_s), averaged:
 * x0, y0, V0, w0 arithmetic, theta0 the circular mean atan2(sum sin, sum cos).
 *
 * Beacon fusion is a complementary filter on the OFFSET between where a
 * mate says it is (its own odometry: smooth but drifting) and where our
 * camera sees it (noisy but drift-free relative to us): each observation
 * moves the offset by alpha of the innovation, and the mate's fused
 * position is reported + offset. With alpha = 1 the last observation wins;
 * with alpha = 0 the camera is ignored.
 */
#ifndef TANDEM_TEAM_H
#define TANDEM_TEAM_H

#include <stdint.h>

#include "unicycle.h"
#include "vec2.h"

#define TEAM_ERR_ARG (-1)     /* NULL, non-finite input or invalid message */
#define TEAM_ERR_FULL (-2)    /* a new mate but TEAM_MAX are held          */
#define TEAM_ERR_UNKNOWN (-3) /* no such mate, or none to average          */

#define TEAM_MAX 128
#define TEAM_TIMEOUT_S_DEFAULT 1.0
#define TEAM_STILL_MPS 0.05 /* a mate slower than this counts as standing */

typedef struct {
    int32_t robot;
    double x_m, y_m, theta_rad; /* reported pose of O */
    double v_mps, w_radps;
    int formation; /* FORMATION_* */
    double scale;
    int announce; /* FORMATION_ANN_* */
    int32_t announce_seq;
    double t_s;              /* time heard, caller's clock */
    double off_x_m, off_y_m; /* camera correction (see above) */
    int observed;            /* number of beacon observations fused */
    double obs_t_s;          /* time of the last one */
    double obs_range_m;      /* and its range */
} team_member;

typedef struct {
    int32_t self_id;
    double timeout_s;
    int n;                   /* team-mates held (self not included) */
    team_member m[TEAM_MAX]; /* sorted by robot id */
} team_table;

int team_init(team_table *t, int32_t self_id, double timeout_s);

/* A team message (fields robot .. t_s; offsets are ignored). Returns 1 if
 * the robot was not known (a late joiner, or one back after a timeout:
 * re-slot), 0 if refreshed or ignored as older than what is held,
 * TEAM_ERR_ARG if invalid (non-finite, own id, bad formation/scale),
 * TEAM_ERR_FULL if the table is full. */
int team_update(team_table *t, const team_member *msg);

/* Drop every mate silent for more than timeout_s; returns how many. */
int team_expire(team_table *t, double now_s);

const team_member *team_find(const team_table *t, int32_t robot);

/* Sorted ids of the team including self (for formation_slot_of);
 * returns the count (at most cap). */
int team_ids(const team_table *t, int32_t *ids, int cap);

/* Fused position of a mate (reported + camera offset); TEAM_ERR_UNKNOWN if unknown. */
int team_position(const team_table *t, int32_t robot, double xy_m[2]);

/* Camera sees `robot`'s beacon at (range, bearing from our heading) from
 * our pose own_o (camera at O) at now_s. alpha in [0, 1]. TEAM_ERR_ARG on bad input
 * or unknown robot. */
int team_observe(team_table *t, int32_t robot, const pose2 *own_o, double range_m,
                 double bearing_rad, double alpha, double now_s);

/* Frame consensus. Each robot's position is dead reckoning with its own
 * drift e; a mate's camera offset is (where we see it) - (where it says it
 * is) = e_self - e_mate. team_mean_offset gives the mean offset over the
 * mates seen within max_age_s of now_s and max_range_m of us (a heading
 * error of ours turns the sighting about us by that angle: the farther the
 * mate, the larger the false offset) (returns how many; 0: off = 0); of a
 * mate on the move only the part across its heading counts (along it the
 * offset also holds the report's lag times its speed).
 * A robot that moves its own estimate by (dx, dy) calls team_shift_offsets
 * with the same (dx, dy): every sighting it makes from now on moves with
 * it, so the offsets it holds must too. */
int team_mean_offset(const team_table *t, double now_s, double max_age_s, double max_range_m,
                     double off_m[2]);
void team_shift_offsets(team_table *t, double dx_m, double dy_m);

/* Team-average reference R0 at now_s. self may be NULL (not counted);
 * self_left = 1 leaves self out of the average (own dead-zone escape).
 * Returns the number of robots averaged; TEAM_ERR_UNKNOWN if
 * none, TEAM_ERR_ARG on bad input. */
int team_reference(unicycle_state *ref, const team_table *t, const unicycle_state *self,
                   int self_left, double d_m, double now_s);

#endif
