/* rover_ctl: one Pioneer's distributed formation controller (SPEC.md
 * section 4), the whole per-robot algorithm behind tandem-rover:
 *   odometry from wheel encoders only (pose of O in the team frame),
 *   team table from team messages (1 s heartbeat) and beacon fusion,
 *   team-average reference R0, slot by sorted id, the four behaviours and
 *   the blend (eq. 11 or a baseline), the narrow-passage protocol, the
 *   dead-zone escape, and a safe stop on stale sensors.
 *
 * Dead-zone escape: the seed turns with alternating +-w_k until the front
 * is free (behaviour_exception_step). Turning alone leaves the robot facing
 * out of the trap with the goal still behind it, and the goal behaviour
 * drives it straight back in; so after the turn the robot follows the
 * obstacle boundary (wall on the side it turned away from) until it is
 * closer to its goal than where it was trapped and the way to the goal is
 * free (the leave rule of Bug2). The robot announces LEAVE on entry (the
 * team reference leaves it out) and REJOIN when done.
 *
 * Announcements: a robot broadcasts the announcement it originated last
 * (code, seq) in every team message until it makes another, so a lost
 * message costs nothing; mates adopt it through formation_fsm_on_announce.
 */
#ifndef TANDEM_ROVER_CTL_H
#define TANDEM_ROVER_CTL_H

#include <stdint.h>

#include "behaviour.h"
#include "formation.h"
#include "odometry.h"
#include "team.h"

/* Values match rover_state_t MODE_*. */
enum { ROVER_MODE_FORMATION = 0, ROVER_MODE_DEAD_ZONE = 1, ROVER_MODE_CHANGING = 2,
       ROVER_MODE_AT_GOAL = 3, ROVER_MODE_SAFE_STOP = 4 };
enum { ROVER_ESC_NONE = 0, ROVER_ESC_TURN = 1, ROVER_ESC_FOLLOW = 2 };

typedef struct {
    behaviour_params_t beh;
    formation_fsm_params_t fsm;
    int    blend_mode;          /* BEH_BLEND_* */
    int    formation;           /* nominal FORMATION_* */
    double team_timeout_s;      /* heartbeat: 1 s */
    double beacon_alpha;        /* team_observe gain */
    double stale_s;             /* sensors older than this: safe stop */
    double team_period_s;       /* team messages: 0.1 s (10 Hz) */
    double wheel_radius_m, axle_track_m;
    double follow_dist_m;       /* escape: wall distance kept */
    double follow_v_mps;
    double follow_w_radps;
    double escape_max_s;        /* give up following after this long */
    double passage_sense_max_m; /* side readings beyond: no passage wall */
    double mate_keep_m;         /* a mate's echo nearer than this stays an obstacle */
    double passage_front_min_m; /* a passage needs the front open this far */
    double passage_hold_s;      /* front blocked: last width kept this long (0: no hold) */
    double v_change_mps;
    double guard_m, guard_stop_m; /* collision guard: slow below, stop at (front echo) */
    double goal_heading_gain;   /* R0 heading toward the goal bearing, 0..1 (see .c) */        /* speed cap while shrinking / changing type */
    double sonar_max_m;         /* range reported for a masked (mate) echo */
} rover_ctl_params_t;

/* One received team message (fields of team_msg_t). */
typedef struct {
    team_member_t m;            /* robot .. announce_seq; t_s = receive time */
    double goal_m[2];
} rover_team_msg_t;

typedef struct {
    unicycle_cmd_t u;           /* drive command */
    int    mode;                /* ROVER_MODE_* */
    int    send_team;           /* 1: publish `team` now */
    team_member_t team;         /* own team message (x, y, theta of O) */
    pose2_t o;                  /* own O pose (odometry, team frame) */
    double weight[BEH_COUNT];
    double slot_err_m;          /* own estimate */
    int    team_size;           /* including self */
} rover_ctl_out_t;

typedef struct {
    int32_t id;
    rover_ctl_params_t p;
    odometry_t odo;
    int     have_enc, have_sonar;
    pose2_t start_c;
    double  enc_t_s, sonar_t_s, prev_enc_t_s;
    double  v_est_mps, w_est_radps;
    double  range_m[BEH_SONAR_N];
    double  goal_m[2];          /* team goal, team frame */
    team_t  team;
    formation_fsm_t fsm;
    behaviour_exception_t exc;
    int     esc_phase;          /* ROVER_ESC_* */
    int     esc_side;           /* -1: wall kept on the right, +1 left */
    double  esc_hit_dist_m, esc_s;
    int     escapes;            /* dead-zone entries */
    int     ann_code;           /* own latest announcement */
    int32_t ann_seq;
    double  team_tx_t_s;
    double  passage_m, passage_t_s;   /* last sensed passage width */
    int     formation_changes;  /* adopted changes of type (own view) */
    behaviour_blend_t blend;
} rover_ctl_t;

void rover_ctl_params_default(rover_ctl_params_t *p);
int  rover_ctl_params_check(const rover_ctl_params_t *p);

/* start_c: pose of C in the team frame; goal in the team frame. */
int  rover_ctl_init(rover_ctl_t *c, const rover_ctl_params_t *p, int32_t id,
                    const pose2_t *start_c, const double goal_m[2]);
/* Accumulated wheel angles at time t_s. The first reading anchors the
 * odometry at start_c. -1 on non-finite input. */
int  rover_ctl_encoders(rover_ctl_t *c, double left_rad, double right_rad, double t_s);
/* The latest range of each transducer (table order). -1 on bad input. */
int  rover_ctl_sonar(rover_ctl_t *c, const double range_m[BEH_SONAR_N], double t_s);
/* A team-mate's message heard at t_s. Returns team_update's result
 * (1 new member, 0 refreshed), -1 invalid. */
int  rover_ctl_team_msg(rover_ctl_t *c, const rover_team_msg_t *msg, double t_s);
/* Camera: beacon of `target` at range / bearing. -1 unknown or bad. */
int  rover_ctl_beacon(rover_ctl_t *c, int32_t target, double range_m, double bearing_rad);
/* One control period ending at t_s. -1 on bad input (out->u = 0). */
int  rover_ctl_step(rover_ctl_t *c, double t_s, double dt_s, rover_ctl_out_t *out);

/* Escape wall following (exposed for tests): command that keeps the
 * obstacle on `side` (-1 right, +1 left) at follow_dist_m. */
void rover_ctl_follow(unicycle_cmd_t *u, const sonar_groups_t *g, int side,
                      const rover_ctl_params_t *p);

#endif
