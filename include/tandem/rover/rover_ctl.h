/* rover_ctl: one Pioneer's distributed formation controller (docs/method/
 * formation.md), the whole per-robot algorithm behind tandem-rover:
 *   own pose from wheel encoders fused with the world's LED landmarks seen
 *   by the camera (localize.h, EKF), or with localization off odometry
 *   alone with a frame consensus among mates seen by the camera,
 *   team table from team messages (1 s heartbeat) and beacon fusion,
 *   team-average reference R0, slot by sorted id, the four behaviours and
 *   the blend (eq. 11 or a baseline), the narrow-passage protocol, the
 *   dead-zone escape and giving way to it, a collision guard, and a safe
 *   stop on stale sensors.
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
 * Mates in each other's way: one total priority order (trapped, giving
 * way, the rest; then the lower id), computed alike by every robot from
 * the team messages; a robot waits only for outranking mates it conflicts
 * with, so nobody waits on anybody that waits on it. A trapped robot's
 * only way out is back the way it came: a robot waiting for a trapped mate
 * that comes its way gives way (GIVE_WAY), turns away from it and follows
 * the boundary out with the same leave rule; it reports MODE_CHANGING, not
 * a dead-zone entry of its own. The escape's phases are the const table
 * rover_esc_table (docs/method/formation.md §10).
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
#include "localize.h"
#include "navfield.h"
#include "odometry.h"
#include "team.h"

/* Values match rover_state_t MODE_*. */
enum {
    ROVER_MODE_FORMATION = 0,
    ROVER_MODE_DEAD_ZONE = 1,
    ROVER_MODE_CHANGING = 2,
    ROVER_MODE_AT_GOAL = 3,
    ROVER_MODE_SAFE_STOP = 4
};
/* The formation behaviour flown: the seed's law (behaviour_formation_seed)
 * or Kanayama slot tracking (behaviour_slot_track), for comparison. */
enum { ROVER_LAW_SEED = 0, ROVER_LAW_KANAYAMA = 1 };
/* Escape phases, the rows of rover_esc_table (docs/method/formation.md §10):
 * TURN eq. 2's turn, FOLLOW the boundary (both trapped, LEAVE); YIELD
 * turning away from a trapped mate, CLEAR following the boundary out of
 * its way (both giving way, GIVE_WAY); FACE turning toward the way out of
 * a stall before FOLLOW (stalled, LEAVE). */
enum {
    ROVER_ESC_NONE = 0,
    ROVER_ESC_TURN = 1,
    ROVER_ESC_FOLLOW = 2,
    ROVER_ESC_YIELD = 3,
    ROVER_ESC_CLEAR = 4,
    ROVER_ESC_FACE = 5,
    ROVER_ESC_COUNT = 6
};
/* What bounds the time spent in a phase: nothing (the seed's turn ends
 * with the front free), yield_max_s, escape_max_s of boundary following. */
enum { ROVER_ESC_LIMIT_NONE = 0, ROVER_ESC_LIMIT_YIELD = 1, ROVER_ESC_LIMIT_FOLLOW = 2 };
/* What a phase flies: the blend (not escaping), eq. 2's turn, a turn on
 * the spot (away from the trapped mate, or toward the way), the boundary
 * follower. */
enum {
    ROVER_ESC_FLY_BLEND = 0,
    ROVER_ESC_FLY_EQ2 = 1,
    ROVER_ESC_FLY_SPIN = 2,
    ROVER_ESC_FLY_FOLLOW = 3
};

/* stale_s's default in ms (tandem-rover --stale-ms shows it as written). */
#define ROVER_CTL_STALE_MS 500

/* One row of the escape's state table. */
typedef struct {
    int phase;    /* ROVER_ESC_*: the row's own index */
    int announce; /* FORMATION_ANN_* broadcast while in it (NONE row: FORMATION_ANN_NONE,
                      * the passage protocol's own announcement goes out) */
    int mode;     /* ROVER_MODE_* reported */
    int fly;      /* ROVER_ESC_FLY_* */
    int limit;    /* ROVER_ESC_LIMIT_* */
    int next;     /* phase taken when its exit condition holds */
    int on_limit; /* phase taken when the limit runs out (itself: the other wall side) */
} rover_esc_row;

/* The table flown (rover_ctl_escape.c) and its validator:
 * ROVER_CTL_OK, or ROVER_CTL_ERR_ARG for a table of the wrong size, a row
 * out of order, a target phase out of range, an escaping row that does not
 * announce itself out of the formation, a mode that does not match its
 * announcement, or a phase from which the exit transitions never lead
 * back to NONE. */
extern const rover_esc_row rover_esc_table[ROVER_ESC_COUNT];
int rover_esc_table_validate(const rover_esc_row *t, int n);

/* Status of the rover_ctl_* functions (0 ok, negative an error). */
#define ROVER_CTL_OK 0
#define ROVER_CTL_ERR_ARG (-1)      /* bad argument, parameter set or reading */
#define ROVER_CTL_ERR_SNAPSHOT (-2) /* a snapshot of another robot or out of range */
#define ROVER_CTL_ERR_TEAM (-3)     /* a team message from a robot of another team: not taken */

/* Waiting for outranking mates (rover_ctl_state.holding). */
enum { ROVER_WAIT_NONE = 0, ROVER_WAIT_STAND = 1, ROVER_WAIT_BACK = 2 };

/* Robots of other teams (fleet.h) the camera saw lately, kept to give way
 * to those of outranking teams (rover_ctl_teams.c). */
#define ROVER_STRANGERS 16
typedef struct {
    int32_t id;     /* 0: free */
    double xy_m[2]; /* where its beacon was seen (own team frame) */
    double t_s;     /* when */
} rover_stranger;

/* Breadcrumbs of the axle's path for backing out of a wedge (there is no
 * rear sonar: the way the robot came is the only way known free of walls;
 * rover_ctl_escape.c). 8 x 0.1 m: twice back_max_m's default. */
#define ROVER_CRUMBS 8
#define ROVER_CRUMB_STEP_M 0.1

typedef struct {
    behaviour_params beh;
    formation_fsm_params fsm;
    int blend_mode;        /* BEH_BLEND_* */
    int formation_law;     /* ROVER_LAW_* */
    int formation;         /* nominal FORMATION_* */
    double team_timeout_s; /* heartbeat: 1 s */
    double beacon_alpha;   /* team_observe gain */
    double stale_s;        /* sensors older than this: safe stop (ROVER_CTL_STALE_MS) */
    double team_period_s;  /* team messages: 0.1 s (10 Hz) */
    double wheel_radius_m, axle_track_m;
    double follow_dist_m; /* escape: wall distance kept */
    double follow_v_mps;
    double follow_w_radps;
    double escape_max_s; /* boundary following: the other way round after this long */
    double give_way_m;   /* a trapped (LEAVE) mate this near conflicts; coming our way: give way */
    double yield_max_s;  /* giving way: turn away at most this long, then follow */
    double give_way_seen_s;  /* ... to a mate the camera saw this recently (no wall between) */
    double yield_near_m;     /* axles this near, walls near or one out of formation: a conflict */
    double arrival_m;        /* the team's mean within the formation's half extent plus this
                                   of the goal: slots by where the robots are (0: by id) */
    double arrival_swap_m2;  /* the goal's slots leave the order by id only when the least summed
                                   squared distance is shorter than by id by more than this */
    int column_by_place;     /* 1: on the way, a column's slots go by where the robots are
                                (as the goal's, with arrival_swap_m2); 0: by id */
    double arrive_face_rad;  /* arriving, a turn on the spot goes on until the target lies
                               within this of ahead */
    double cut_off_spacings; /* a formation slot out of sight (beyond a wall) and farther
                                than this many spacings: the formation behaviour drives
                                the way to it */
    double queue_m;          /* a mate in formation this near ahead ... */
    double queue_cone_rad;   /* ... within this of our heading ... */
    double queue_slow_mps;   /* ... slower than this, or than us by queue_closing_mps: a conflict */
    double queue_closing_mps;
    double hold_max_s; /* wait at most this long for outranking mates in formation */
    /* other teams (fleet.h): a robot of a team with lower ids, seen by the
     * camera within stranger_seen_s, nearer than stranger_give_m and within
     * stranger_cone_rad of the heading: stand, at most stranger_hold_max_s
     * at a time */
    double stranger_give_m, stranger_cone_rad, stranger_seen_s, stranger_hold_max_s;
    double back_max_m; /* clearing an outranking mate's way: back out at most this far ... */
    double back_v_mps; /* ... this fast */
    double
        wedge_max_s; /* wedged this long (may neither turn nor back): a turn clear of mates' boxes */
    double follow_lost_s;    /* boundary following: no wall in reach this long ends it */
    double walls_near_m;     /* a wall within follow_dist_m + this on a side: confined */
    double leave_gain_m;     /* Bug2's leave rule: this much nearer the goal than the hit point */
    int leave_by_way;        /* 1: "nearer" along the map's way where the robot holds one
                             (navfield_way_from); 0: straight, as Bug2 has it */
    int entry_by_way;        /* 1: a dead-zone entry turns first toward the map's way, then
                             alternates (§10); 0: eq. 2's alternation alone */
    int map_graze;           /* 1: with the map, no turn swings a chassis corner into a wall
                             (rover_ctl_turn_grazes, §10); 0: the sonar's guard alone */
    double follow_regress_m; /* with the map, a trapped robot following the boundary this far
                                farther along the way than its hit point turns back toward the
                                way (FACE; §10); 0: never */
    /* a stall (docs/method/formation.md §10): farther than stall_near_m
     * from its slot (arriving: its goal slot), the axle within stall_move_m
     * of one place for stall_s of not waiting: a trap eq. 2's test does not
     * see, escaped as one (stall_s 0: never) */
    double stall_s, stall_move_m, stall_near_m;
    double follow_mate_ahead_m;   /* a follower turns away from a mate this short of it */
    double follow_moving_mps;     /* slower than this a follower is not following (escape_max_s) */
    double passage_sense_max_m;   /* side readings beyond: no passage wall */
    double mate_keep_m;           /* a mate's echo nearer than this stays an obstacle */
    double passage_front_min_m;   /* a passage needs the front open this far */
    double passage_ahead_m;       /* with the map: passages looked for this far along the way */
    double passage_short_m;       /* ... those shorter than this along it (the sonar's too short) */
    int passage_long_by_map;      /* 1: a longer one too, where the sonar cannot tell; 0: never */
    double v_change_mps;          /* speed cap while shrinking / changing type */
    double guard_m, guard_stop_m; /* collision guard: slow below, stop at (echo in the way) */
    double guard_lane_m;          /* an echo this far outside the swept lane is not in the way */
    double side_guard_m;          /* an echo alongside this near: turn away ... */
    double side_turn_radps;       /* ... at least this fast */
    double goal_heading_gain;     /* R0 heading toward the goal bearing, 0..1 (see .c) */
    double arrive_m;              /* R0 drawn onto the goal frame within this of it (0: off) */
    double sonar_max_m;           /* range reported for a masked (mate) echo */
    double consensus_gain;        /* frame consensus rate, 1/s (0: own odometry only) */
    double consensus_age_s;       /* only mates seen this recently count */
    double consensus_max_mps;     /* at most this much correction per second */
    double consensus_range_m;     /* only mates seen this near count (own heading error) */
    int localize;                 /* 1: fuse landmarks (rover_ctl_set_landmarks); 0: odometry
                                 * and frame consensus */
    localize_params loc;          /* its d_m is taken from beh.d_m */
    double loc_sd0_xy_m, loc_sd0_theta_rad; /* start pose uncertainty */
} rover_ctl_params;

/* One received team message (fields of team_msg_t). */
typedef struct {
    team_member m; /* robot .. announce_seq; t_s = receive time */
    double goal_m[2];
} rover_team_msg;

typedef struct {
    unicycle_cmd u;   /* drive command */
    int mode;         /* ROVER_MODE_* */
    int send_team;    /* 1: publish `team` now */
    team_member team; /* own team message (x, y, theta of O) */
    pose2 o;          /* own O pose (odometry, team frame) */
    double weight[BEH_COUNT];
    double slot_err_m; /* own estimate */
    int team_size;     /* including self */
} rover_ctl_out;

/* The dead-zone escape and giving way (docs/method/formation.md §10), one
 * phase of rover_esc_table at a time. Written by rover_ctl_escape.c alone
 * (rover_ctl_escape_step); the rest of the controller reads it. */
typedef struct {
    int phase;         /* ROVER_ESC_* */
    int side;          /* -1: wall kept on the right, +1 left */
    int yield;         /* 1: giving way to a leaving mate, not trapped (YIELD, CLEAR) */
    int turn;          /* giving way, facing the way, eq. 2's turn: direction (+1 left) */
    double hit_dist_m; /* goal distance at the hit point: Bug2 leaves nearer than it */
    double s;          /* time in this phase (standing for a mate not counted) */
    double lost_s;     /* time without a wall in reach while following */
    double wait_s;     /* escaping: time stood for an outranking mate in the way */
    int backing;       /* 1: backing out of an outranking mate's way (V < 0 allowed) */
    double back_m;     /* backed so far in this escape */
    double wedge_s;    /* standing wedged between mates this long */
    int turned_back;   /* 1: this escape has turned back once (follow_regress_m) */
} rover_esc_state;

typedef struct {
    int32_t id;
    int32_t team_lo, team_hi; /* its team's ids (rover_ctl_set_team; init: every id) */
    rover_ctl_params p;
    odometer odo;
    double corr_m[2]; /* frame consensus: added to the odometry position */
    localizer loc;    /* own pose when p.localize (started with the odometry) */
    int n_lm;         /* landmarks known (team frame) */
    double lm_m[LOCALIZE_LANDMARKS_MAX][2];
    int have_enc, have_sonar;
    pose2 start_c;
    double enc_t_s, sonar_t_s, prev_enc_t_s;
    double v_est_mps, w_est_radps;
    double range_m[BEH_SONAR_N];
    double goal_m[2]; /* team goal, team frame */
    team_table team;
    formation_fsm fsm;
    behaviour_exception exc;
    rover_esc_state esc;
    int holding; /* in formation, waiting for outranking mates: ROVER_WAIT_* */
    /* arriving, turning to face the own slot: the way round held (+1 left,
     * -1 right), 0 the short way (rover_ctl.c arrival_turn_other_way) */
    int arrive_turn;
    double stall_xy_m[2]; /* where the stall clock last started (rover_ctl.c stall_watch) */
    double stall_t_s;     /* how long (not waiting) the axle has stayed within stall_move_m of it */
    double crumb_m[ROVER_CRUMBS][2]; /* the axle's path, a crumb every ROVER_CRUMB_STEP_M,
                                       * oldest first: the way back known free */
    int crumb_n;                     /* crumbs held (the newest is crumb_m[crumb_n - 1]) */
    double hold_s;             /* time waited (in formation) since the wait set was last empty */
    unicycle_cmd wait_u;       /* the command while holding (stand, or back along the crumbs) */
    int wait_n;                /* the wait set's size this period */
    int32_t wait_id[TEAM_MAX]; /* the mates waited for this period (rover_ctl_wait_set) */
    int escapes;               /* dead-zone entries */
    int ann_code;              /* own latest announcement */
    int32_t ann_seq;
    double team_tx_t_s;
    double tx_xy_m[2];     /* own position in the last team message (the goal's slot
                                   assignment ranks us by it, as every mate does) */
    int formation_changes; /* adopted changes of type (own view) */
    rover_stranger stranger[ROVER_STRANGERS]; /* other teams' robots seen (rover_ctl_teams.c) */
    double stranger_hold_s;                   /* stood this long for them since last free to go */
    double stranger_free_s; /* nobody to stand for this long (STRANGER_FREE_S: free to go) */
    int giving_way_team;    /* 1: standing for another team's robot this period */
    behaviour_blender blend;
    const navfield
        *nav; /* the world's navigation function, or NULL: the goal straight (the seed) */
} rover_ctl_state;

void rover_ctl_params_default(rover_ctl_params *p);
/* ROVER_CTL_OK or ROVER_CTL_ERR_ARG. */
int rover_ctl_params_validate(const rover_ctl_params *p);

/* How far the point xy (team frame) is from the goal as the escape's leave
 * rule measures it: along the map's way where the robot holds a
 * navigation field (and leave_by_way), else straight to goal. */
double rover_ctl_leave_measure_m(const rover_ctl_state *c, const double xy[2],
                                 const double goal[2]);

/* start_c: pose of C in the team frame; goal in the team frame.
 * ROVER_CTL_ERR_ARG on bad input or parameters. */
int rover_ctl_init(rover_ctl_state *c, const rover_ctl_params *p, int32_t id, const pose2 *start_c,
                   const double goal_m[2]);
/* The navigation function the goal behaviour and the reference heading
 * steer by (docs/method/formation.md §14), built on the world in the team
 * frame; NULL (as after init) steers for the goal straight, as the seed.
 * The field is read, never written, and must outlive the controller. */
void rover_ctl_set_navfield(rover_ctl_state *c, const navfield *f);
/* The world's LED landmarks in the team frame (landmark k is camera
 * target ROVER_LANDMARK_ID_BASE + k); call before the first encoder
 * reading. ROVER_CTL_ERR_ARG on bad input or too many. */
int rover_ctl_set_landmarks(rover_ctl_state *c, const double (*lm_m)[2], int n);
/* The robot's team in a fleet of many (fleet.h): the ids lo..hi, its own
 * among them. Team messages from any other robot are not its team's and
 * are not taken (rover_ctl_team_msg). ROVER_CTL_ERR_ARG when its own id
 * is outside lo..hi. */
int rover_ctl_set_team(rover_ctl_state *c, int32_t lo, int32_t hi);
/* Accumulated wheel angles at time t_s. The first reading anchors the
 * odometry at start_c. ROVER_CTL_ERR_ARG on non-finite input. */
int rover_ctl_encoders(rover_ctl_state *c, double left_rad, double right_rad, double t_s);
/* The latest range of each transducer (table order). ROVER_CTL_ERR_ARG on
 * bad input. */
int rover_ctl_sonar(rover_ctl_state *c, const double range_m[BEH_SONAR_N], double t_s);
/* A team-mate's message heard at t_s. Returns team_update's result
 * (1 new member, 0 refreshed), ROVER_CTL_ERR_ARG invalid,
 * ROVER_CTL_ERR_TEAM from a robot outside its team (nothing changed). */
int rover_ctl_team_msg(rover_ctl_state *c, const rover_team_msg *msg, double t_s);
/* Camera: beacon of `target` (a mate, or a landmark: ROVER_LANDMARK_ID_BASE
 * + k) at range / bearing. ROVER_CTL_ERR_ARG unknown or bad (team_observe's
 * and localize_landmark's -1 alike); for a landmark 1 fused, 0 gated out
 * or localization off. */
int rover_ctl_beacon(rover_ctl_state *c, int32_t target, double range_m, double bearing_rad);
/* ---- restart (tandem-rover --journal) ------------------------------------
 * What a controller restarted after a crash or a kill takes back from its
 * last snapshot: its own pose (odometry with the encoder readings it
 * belongs to, frame correction, the landmark filter's mean and
 * covariance), the formation protocol's state, the dead-zone escape and
 * the counters. Not its view of the team, its sonar ranges or its blend:
 * the mates' next messages and the next frames rebuild those. The first
 * encoder reading after rover_ctl_resume integrates the wheels' travel
 * while the process was down. A snapshot is ROVER_CTL_SNAPSHOT_VALUES
 * numbers, id first. */
#define ROVER_CTL_SNAPSHOT_VALUES 83
/* ROVER_CTL_ERR_ARG before the first encoder reading (nothing to keep). */
int rover_ctl_snapshot(const rover_ctl_state *c, double v[ROVER_CTL_SNAPSHOT_VALUES]);
/* c as made by rover_ctl_init (same id) and rover_ctl_set_landmarks;
 * ROVER_CTL_ERR_SNAPSHOT (c unchanged) for another robot's snapshot or
 * values out of range. */
int rover_ctl_resume(rover_ctl_state *c, const double v[ROVER_CTL_SNAPSHOT_VALUES]);
/* ROVER_CTL_OK if the snapshot's field table is sound (rover_snapshot.c). */
int rover_snapshot_validate(void);

/* One control period ending at t_s. ROVER_CTL_ERR_ARG on bad input
 * (out->u = 0). */
int rover_ctl_step(rover_ctl_state *c, double t_s, double dt_s, rover_ctl_out *out);

/* The ranges with every echo the team table explains as a mate (its
 * chassis where the table puts it) replaced by sonar_max_m, except echoes
 * nearer than keep_m; keep_m > 0 (avoidance) also keeps echoes far behind
 * the mate's near face. o is own O pose. (Used by the step; exposed for
 * tests.) */
void rover_ctl_mask_mates(const rover_ctl_state *c, const pose2 *o, double keep_m,
                          double masked[BEH_SONAR_N]);

/* Collision guard applied to the blended command u (exposed for tests):
 * range_m are the raw ranges (mates are obstacles here), o own O pose,
 * goal own goal (see rover_ctl.c). */
void rover_ctl_guard(unicycle_cmd *u, const double range_m[BEH_SONAR_N], const pose2 *o,
                     const double goal[2], const rover_ctl_params *p);

/* Escape wall following (exposed for tests): command that keeps the
 * obstacle on `side` (-1 right, +1 left) at follow_dist_m. */
void rover_ctl_follow(unicycle_cmd *u, const sonar_groups *g, int side, const rover_ctl_params *p);

#endif
