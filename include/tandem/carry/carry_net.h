/* carry_net: the two-arm carry task of docs/method/carry.md §5 as const Petri-net tables
 * and the per-transition lookup table of docs/method/carry.md §6.
 *
 * Indices are 0-based: CARRY_P1 = 0 is the seed's p1, CARRY_T1 = 0 its t1.
 * CARRY_T_VISION is the vision system as a source transition: it puts a
 * workpiece token in p1, guarded by an inhibitor arc so it may start only
 * while p1 is empty (the seed's dashed feedback loop).
 *
 * Poses are symbolic; their coordinates come from the supervisor / sim
 * configuration. "From vision" poses are the detected workpiece pose plus
 * a fixed offset (above it, or at grasp height).
 *
 * Segment sequence of each transition (per arm, run in order):
 *   t1 arm 1: move ABOVE_WORKPIECE (vision)
 *   t2 arm 1: descend AT_WORKPIECE (vision), grasp, lift ABOVE_WORKPIECE
 *   t3 both, sync group 1: arm 1 move HANDOVER_1, arm 2 move HANDOVER_2
 *   t4 arm 2: grasp; then arm 1 (after_partner): release
 *   t5 arm 2: move ABOVE_RELEASE, descend RELEASE_POSE
 *   t6 arm 1: back off CLEAR_1, move HOME_1
 *   t7 arm 2: release, lift ABOVE_RELEASE, move HOME_2
 */
#ifndef TANDEM_CARRY_NET_H
#define TANDEM_CARRY_NET_H

#include <stdint.h>

#include "erlaw.h"
#include "petri.h"

#define CARRY_NET_ERR_NO_GAINS \
    (-1) /* carry_gains_bounds: no row moves an
                                           arm, so there are no bounds    */
/* carry_table_validate only: */
#define CARRY_NET_ERR_ARG (-2) /* NULL rows or net                */
#define CARRY_NET_ERR_SIZE \
    (-3) /* not one row per transition, or a
                                           plan longer than
                                           CARRY_MAX_SEGMENTS or negative */
#define CARRY_NET_ERR_RANGE \
    (-4) /* a field outside its set: no name,
                                           arms, pose, gripper, segment
                                           kind, after_partner not 0/1,
                                           sync_group < 0                 */
#define CARRY_NET_ERR_GAINS \
    (-5) /* a row that moves an arm has gains
                                           erlaw_gains_validate refuses   */
#define CARRY_NET_ERR_INCONSISTENT \
    (-6) /* a row contradicts itself: an arm
                                           in arms without segments or the
                                           reverse, a move without pose or
                                           a grasp with one, target pose or
                                           gripper not what the plan ends
                                           with, after_partner without a
                                           partner that goes first, a sync
                                           group of one arm               */
#define CARRY_NET_ERR_NET \
    (-7) /* the net is not sound
                                           (petri_net_validate), or a row
                                           contradicts its transition: a
                                           source (no input place) that
                                           moves an arm, or a transition
                                           with inputs that moves none    */

enum {
    CARRY_P1 = 0, /* vision has located a workpiece   */
    CARRY_P2,     /* arm 2 idle at home               */
    CARRY_P3,     /* arm 1 idle at home               */
    CARRY_P4,     /* arm 1 above the workpiece        */
    CARRY_P5,     /* arm 1 holds it                   */
    CARRY_P6,     /* both arms at the hand-over pose  */
    CARRY_P7,     /* arm 1 has released it            */
    CARRY_P8,     /* arm 2 holds it                   */
    CARRY_P9,     /* arm 2 at the release pose        */
    CARRY_N_PLACES
};

enum {
    CARRY_T1 = 0,   /* arm 1 home -> above workpiece    */
    CARRY_T2,       /* arm 1 grasps                     */
    CARRY_T3,       /* both to the hand-over, synced    */
    CARRY_T4,       /* hand-over                        */
    CARRY_T5,       /* arm 2 to the release pose        */
    CARRY_T6,       /* arm 1 back home                  */
    CARRY_T7,       /* arm 2 releases and goes home     */
    CARRY_T_VISION, /* source: a workpiece located    */
    CARRY_N_TRANSITIONS
};

#define CARRY_N_INVARIANTS 2

typedef enum {
    CARRY_POSE_NONE = 0,
    CARRY_POSE_HOME_1,
    CARRY_POSE_ABOVE_WORKPIECE, /* from vision */
    CARRY_POSE_AT_WORKPIECE,    /* from vision */
    CARRY_POSE_HANDOVER_1,
    CARRY_POSE_CLEAR_1, /* arm 1 backed off the hand-over */
    CARRY_POSE_HOME_2,
    CARRY_POSE_HANDOVER_2,
    CARRY_POSE_ABOVE_RELEASE,
    CARRY_POSE_RELEASE_POSE,
    /* above the hand-over by CELL_STAND_CLEARANCE_M: a task that sets the bar
     * down on a stand there (docs/tasks.md §6) comes and goes vertically,
     * as at the pick and the delivery, so the bar clears the stand */
    CARRY_POSE_ABOVE_HANDOVER_1,
    CARRY_POSE_ABOVE_HANDOVER_2,
    /* arm 2's own source (cell_default.magazine_center_m, tandem-sim
     * --magazine): a bar it takes alone while arm 1 is down
     * (docs/tasks.md §8), at grasp height and approach_height_m above */
    CARRY_POSE_ABOVE_MAGAZINE,
    CARRY_POSE_AT_MAGAZINE,
    /* the stand's second place (cell_default.stand_b_center_m, docs/tasks.md
     * §6), as HANDOVER_k, ABOVE_HANDOVER_k and CLEAR_1 are at its first */
    CARRY_POSE_STAND_B_1,
    CARRY_POSE_ABOVE_STAND_B_1,
    CARRY_POSE_CLEAR_B_1,
    CARRY_POSE_STAND_B_2,
    CARRY_POSE_ABOVE_STAND_B_2,
    CARRY_N_POSES
} carry_pose;

typedef enum { CARRY_GRIP_NONE = 0, CARRY_GRIP_CLOSE = 1, CARRY_GRIP_OPEN = 2 } carry_grip;

/* Numbered like tandem action_segment_t (MOVE_CARTESIAN 0, GRASP 2,
 * RELEASE 3). */
typedef enum { CARRY_SEG_MOVE = 0, CARRY_SEG_GRASP = 2, CARRY_SEG_RELEASE = 3 } carry_seg_kind;

#define CARRY_ARM1 1u
#define CARRY_ARM2 2u
#define CARRY_MAX_SEGMENTS 4

typedef struct {
    int8_t kind; /* carry_seg_kind */
    int8_t pose; /* carry_pose, for CARRY_SEG_MOVE */
} carry_segment;

typedef struct {
    int8_t n_segments;
    int8_t after_partner; /* 1: start once the partner arm has finished
                               its segments of this transition            */
    carry_segment seg[CARRY_MAX_SEGMENTS];
} carry_arm_plan;

typedef struct {
    const char *name;
    uint8_t arms;           /* CARRY_ARM1 | CARRY_ARM2, 0 for vision    */
    int8_t target_pose[2];  /* final pose of arm 1 / arm 2 (NONE: stays) */
    int8_t gripper[2];      /* net gripper action of arm 1 / arm 2      */
    erlaw_gains lin;        /* v_m a_m u_m k_p k_v k0 k1 k2 (m, s)      */
    int32_t sync_group;     /* 0 alone, > 0 arms sharing s*             */
    carry_arm_plan plan[2]; /* arm 1, arm 2                             */
} carry_row;

/* The net: N-, N+, inhibitor, gamma0 = [1 1 1 0 0 0 0 0 0], invariants
 * p3+p4+p5+p6+p7 = 1 (arm 1) and p2+p6+p8+p9 = 1 (arm 2). */
extern const petri_net carry_net;
extern const carry_row carry_table[CARRY_N_TRANSITIONS];
/* Orientation channel gains (rad units) used with every row. */
extern const erlaw_gains carry_rot_gains;

/* The lookup table is sound against its net: n_rows rows, one per
 * transition of net (row t is transition t), each as the
 * CARRY_NET_ERR_* above describe. 0 or the first CARRY_NET_ERR_* found.
 * For start-up checks: carry_table_validate(carry_table,
 * CARRY_N_TRANSITIONS, &carry_net). */
int carry_table_validate(const carry_row *rows, int n_rows, const petri_net *net);

/* carry_table_validate, except that a transition t with bit t set in
 * health (an arm's fault or recovery, fired by the supervisor from the
 * arms' health: taskdef_health_find) has inputs and moves no arm; any
 * such transition that moves an arm is refused (CARRY_NET_ERR_NET).
 * carry_table_validate is this with health 0. */
int carry_table_validate_health(const carry_row *rows, int n_rows, const petri_net *net,
                                uint32_t health);

/* Bounds of the lookup table's gains: lo[i], hi[i] = min, max over every
 * row that moves an arm, field i in erlaw_gains order (v_m a_m u_m k_p k_v
 * k0 k1 k2). A row received from the bus must stay inside them (docs/method/lockstep.md §6).
 * 0 or CARRY_NET_ERR_NO_GAINS. */
#define CARRY_N_GAINS 8
int carry_gains_bounds(double lo[CARRY_N_GAINS], double hi[CARRY_N_GAINS]);
/* 1 if every field of g is finite and inside the table's bounds; with
 * allow_zero a field may also be exactly 0 (rows without Cartesian
 * segments carry no gains). */
int carry_gains_within_table(const erlaw_gains *g, int allow_zero);

/* Row of transition t, NULL for a bad index. */
const carry_row *carry_row_of(int t);
const char *carry_pose_name(int pose);
/* The arm (0, 1) whose tool the pose is for; -1 for NONE or a bad pose. */
int carry_pose_arm(int pose);
/* 1 if the pose's coordinates come from the vision system. */
int carry_pose_from_vision(int pose);

#endif
