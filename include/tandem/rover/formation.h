/* formation: slot geometry (line / triangle / column), formation width,
 * slot assignment by sorted robot id, and the narrow-passage protocol
 * (docs/method/formation.md: shrink first, then line -> triangle -> column, restore
 * when clear), agreed across the team by sequenced announcements.
 *
 * Slots are given relative to the team reference point O_0 in R0's frame
 * (x forward along theta0, y to the left). Because R0 is the team AVERAGE,
 * the slot pattern is centred: the mean of all n slot positions is 0.
 *   line (abreast): y = s ((n-1)/2 - k), slot 0 leftmost
 *   triangle (wedge): slot 0 apex, then rows r = 1, 2, ... of two robots
 *       (odd k left, even k right) at x = -r s sqrt(3)/2, y = +-r s/2, so
 *       neighbours along each leg are s apart
 *   column: x = -k s, slot 0 in front
 * all multiplied by the scale factor (1 nominal, < 1 shrunk).
 */
#ifndef TANDEM_FORMATION_H
#define TANDEM_FORMATION_H

#include <stdint.h>

#define FORMATION_ERR_ARG \
    (-1)                          /* bad type, n, k, spacing, scale or
                                      announcement content               */
#define FORMATION_ERR_ABSENT (-2) /* formation_slot_of: id not in the team */

#define FORMATION_MAX_ROBOTS 128

/* Values match team_msg_t FORMATION_* and ANNOUNCE_*. */
enum { FORMATION_LINE = 0, FORMATION_TRIANGLE = 1, FORMATION_COLUMN = 2 };
enum {
    FORMATION_ANN_NONE = 0,
    FORMATION_ANN_LEAVE = 1,
    FORMATION_ANN_REJOIN = 2,
    FORMATION_ANN_SHRINK = 3,
    FORMATION_ANN_CHANGE = 4,
    FORMATION_ANN_RESTORE = 5,
    FORMATION_ANN_GIVE_WAY = 6 /* out of the formation making room for a LEAVE, not trapped */
};
enum {
    FORMATION_PHASE_NORMAL = 0,
    FORMATION_PHASE_SHRINK = 1,
    FORMATION_PHASE_CHANGE = 2,
    FORMATION_PHASE_RESTORE = 3
};

/* Slot k of n (0 <= k < n <= FORMATION_MAX_ROBOTS) as (x, y) and as
 * (l_d, phi_d). FORMATION_ERR_ARG on bad type, n, k, or non-positive spacing/scale. */
int formation_slot_xy(double xy_m[2], int type, int n, int k, double spacing_m, double scale);
/* Every slot at once, xy_m[k] = formation_slot_xy(.., k, ..) bit for bit,
 * in O(n) rather than n calls of O(n) each. 0 or FORMATION_ERR_ARG. */
int formation_slots_xy(double xy_m[][2], int type, int n, double spacing_m, double scale);
int formation_slot(double *l_d_m, double *phi_d_rad, int type, int n, int k, double spacing_m,
                   double scale);
/* Width D across the heading: lateral extent of the slots + robot width.
 * Returns a negative value on bad input. */
double formation_width(int type, int n, double spacing_m, double scale, double robot_width_m);
/* 1 for a known announcement code (FORMATION_ANN_*). */
int formation_ann_valid(int code);
/* 1 for a robot that announced it is out of the formation (LEAVE: trapped
 * and escaping; GIVE_WAY: making room for one that is): it is left out of
 * the team reference and of the passage protocol's rearmost test. */
int formation_ann_out(int code);
/* The next narrower type: line -> triangle -> column -> column. */
int formation_next_type(int type);
/* Slot of robot `id` in a team of n unique ids (any order): its rank among
 * the sorted ids, so every robot computes the same assignment and a member
 * leaving or joining re-slots everyone deterministically. FORMATION_ERR_ABSENT if absent. */
int formation_slot_of(const int32_t ids[], int n, int32_t id);

/* The formation is held: every one of the n slots has its own robot
 * within tol_m (a perfect matching of robots to slots, any robot in any
 * slot; Kuhn's augmenting paths, at most n^3 steps). 1 held, 0 not,
 * FORMATION_ERR_ARG on bad input. */
int formation_slots_held(const double xy_m[][2], const double slot_m[][2], int n, double tol_m);

/* ---- narrow-passage protocol ------------------------------------------- */
typedef struct {
    int code;       /* FORMATION_ANN_* */
    int32_t seq;    /* team_msg_t announce_seq */
    int32_t origin; /* robot that made the announcement */
    int type;       /* formation after the announcement */
    double scale;
} formation_announce;

typedef struct {
    double spacing_m; /* nominal neighbour spacing (scale 1) */
    double robot_width_m;
    double safety_m;     /* narrow: passage < D + safety */
    double shrink_scale; /* scale used by SHRINK, in (0, 1] */
    double dwell_s;      /* minimum time between two protocol steps */
    double clear_hold_s; /* passage clear for the nominal formation this
                            * long before RESTORE; set it >= the time the
                            * whole column needs to leave the passage */
    double confirm_s;    /* a passage must read narrow this long (sensed
                            * narrow, unknown readings in between hold the
                            * count, a wider one resets it) before SHRINK
                            * or CHANGE */
} formation_fsm_params;

/* spacing 1.0 m, width 0.38 m, safety 0.3 m, shrink 0.6, dwell 1 s,
 * clear hold 4 s, confirm 1 s. */
void formation_fsm_params_default(formation_fsm_params *p);

typedef struct {
    int type_nominal;
    double scale_nominal;
    int type; /* current formation */
    double scale;
    int phase;   /* FORMATION_PHASE_* */
    int32_t seq; /* adopted announcement (seq, origin) */
    int32_t origin;
    int code;             /* its code */
    int32_t seq_max_seen; /* highest announce_seq heard (any code) */
    double phase_s;       /* time since the last protocol step */
    double clear_s;       /* time the passage has been clear */
    double narrow_s;      /* time it has read narrow for the current formation */
    int witnessed;        /* this robot sensed the narrow passage this episode */
} formation_fsm;

int formation_fsm_init(formation_fsm *f, int type, double scale);

/* One control period. passage_width_m = sensed left + right + robot width
 * (INFINITY when nothing is sensed, NAN when this robot cannot tell: a
 * side or the front hidden by a mate; unknown is neither narrow nor
 * clear, the clear timer holds); n = team size; rearmost = 1 if this robot
 * is the last of the team along the direction of travel. When this robot
 * makes a new announcement, fills *out and returns 1 (send it); 0
 * otherwise; FORMATION_ERR_ARG on bad input (state unchanged).
 *   NORMAL: narrow for the current formation -> SHRINK (scale = shrink)
 *   SHRINK/CHANGE: after dwell, still narrow and not a column -> CHANGE to
 *       the next type; clear for the nominal formation for clear_hold_s,
 *       this robot saw the passage, and it is the rearmost -> RESTORE
 *       nominal type and scale (only the last robot through knows that the
 *       whole team is out: a leader that restored on its own clear reading
 *       pulled the others back to the line inside the passage, they shrank
 *       again, and the team flip-flopped)
 *   RESTORE: narrow again -> SHRINK; after dwell -> NORMAL (silently). */
int formation_fsm_step(formation_fsm *f, const formation_fsm_params *p, double passage_width_m,
                       int n, double dt_s, int32_t self_id, int rearmost, formation_announce *out);

/* A team-mate's announcement. Adopted (returns 1) if it is newer than the
 * adopted one: higher seq, or equal seq from a lower robot id (so two
 * simultaneous announcers resolve the same way everywhere). Repeats and
 * older ones are ignored (0). LEAVE / REJOIN only advance seq_max_seen (0).
 * FORMATION_ERR_ARG on invalid content. */
int formation_fsm_on_announce(formation_fsm *f, const formation_announce *a);

/* Next free announce_seq (for announcements made outside the protocol,
 * e.g. LEAVE by the dead-zone exception); advances seq_max_seen. */
int32_t formation_fsm_next_seq(formation_fsm *f);

#endif
