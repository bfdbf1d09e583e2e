/* taskdef: a task the supervisor runs, held in fixed-capacity tables
 * (docs/tasks.md §7): the Petri net of docs/method/carry.md §5 and its
 * lookup rows (§6), with the names of its places and transitions, filled
 * at start-up from a task drawn as PNML (src/daemons/common/netc_*.c) or
 * pointing at the shipped carry_net / carry_table. Capacities are fixed
 * at compile time (PETRI_MAX_PLACES, PETRI_MAX_TRANSITIONS,
 * PETRI_MAX_INVARIANTS, TASKDEF_MAX_NAME): a bigger task is refused by
 * its reader, naming the limit, never truncated.
 *
 * The supervisor knows a task by the roles its net's structure gives
 * (taskdef_roles), not by the carry's indices:
 *   source  the one transition without input places: the vision system
 *           adding a workpiece token;
 *   place   the one place it fills; an inhibitor arc from it to the
 *           source lets the source start only while it is empty, so one
 *           detection at a time is bound to its token;
 *   pick    the one transition taking that token: its rows' vision poses
 *           (ABOVE_WORKPIECE, AT_WORKPIECE) are the detected workpiece's.
 */
#ifndef TANDEM_TASKDEF_H
#define TANDEM_TASKDEF_H

#include <stdint.h>

#include "carry_net.h"
#include "petri.h"

#define TASKDEF_MAX_NAME 64     /* a task, place or transition name, with its NUL */
#define TASKDEF_MAX_ROW_NAME 96 /* a row's name in the logs, with its NUL */

#define TASKDEF_OK 0
#define TASKDEF_ERR_ARG (-1) /* NULL net or roles                   */
#define TASKDEF_ERR_SOURCE \
    (-2) /* not exactly one source transition
                                            (no input place)                    */
#define TASKDEF_ERR_SOURCE_PLACE \
    (-3) /* the source fills not exactly one
                                            place, or that place does not
                                            inhibit it                          */
#define TASKDEF_ERR_PICK \
    (-4)                       /* not exactly one transition takes the
                                            source's token                      */
#define TASKDEF_ERR_NET (-5)   /* petri_net_validate refuses the net  */
#define TASKDEF_ERR_TABLE (-6) /* carry_table_validate refuses the rows */
#define TASKDEF_ERR_HEALTH \
    (-7) /* an arm's health places (armK_up,
                                            armK_down) not as taskdef_health
                                            says                                */

typedef struct {
    int source;       /* transition index */
    int source_place; /* place index      */
    int pick;         /* transition index */
} taskdef_roles;

/* A task in fixed tables; net and rows point into the arrays (taskdef_bind). */
typedef struct {
    char task[TASKDEF_MAX_NAME];
    int n_places, n_transitions;
    char place_id[PETRI_MAX_PLACES][TASKDEF_MAX_NAME];
    char place_name[PETRI_MAX_PLACES][TASKDEF_MAX_NAME];
    char trans_id[PETRI_MAX_TRANSITIONS][TASKDEF_MAX_NAME];
    char trans_name[PETRI_MAX_TRANSITIONS][TASKDEF_MAX_NAME];
    int8_t n_minus[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int8_t n_plus[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int8_t n_inhibit[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int has_inhibit;
    uint8_t m0[PETRI_MAX_PLACES];
    int n_invariants;
    int8_t invariants[PETRI_MAX_INVARIANTS * PETRI_MAX_PLACES];
    petri_net net;
    /* rows, one per transition (row t is transition t) */
    carry_row rows[PETRI_MAX_TRANSITIONS];
    char row_name[PETRI_MAX_TRANSITIONS][TASKDEF_MAX_ROW_NAME];
    int has_row[PETRI_MAX_TRANSITIONS];
    int live[PETRI_MAX_TRANSITIONS]; /* the rows file asks for liveness */
} taskdef;

/* The arms' health in a task's net (docs/tasks.md §8), found by name: a
 * place named (or with the id) "arm1_up" and one "arm1_down" (arm2_up,
 * arm2_down for arm 2), one token between them in the initial marking.
 * The supervisor moves that token from what the arms report (a FAULT, or
 * silence, puts arm K down; FAULT_CLEARED and its voice back put it up),
 * by firing the one transition whose only arcs are up -> down (the
 * fault) or down -> up (the recovery); those move no arm. Every other
 * transition may only test them, by inhibitor arcs ("needs arm K up" is
 * an inhibitor arc from armK_down), never take or give their token: the
 * task cannot lie about an arm's health. An arm whose places the net does
 * not name has no health transitions (-1): the shipped carry has none. */
typedef struct {
    int up[2], down[2];       /* place indices, or -1              */
    int fault[2], recover[2]; /* transition indices, or -1         */
    uint32_t mask;            /* bit t: t is a fault or a recovery */
} taskdef_health;

/* t->net points into t's arrays, with t's sizes and invariants. */
void taskdef_bind(taskdef *t);

/* The roles of the net's structure (above). TASKDEF_OK and *r set, or
 * the first TASKDEF_ERR_* found and *r all -1. */
int taskdef_roles_find(const petri_net *net, taskdef_roles *r);

/* What the supervisor takes into use: the net sound (petri_net_validate),
 * the rows sound against it (carry_table_validate), the roles found.
 * TASKDEF_OK (and *r set when r is not NULL) or the first
 * TASKDEF_ERR_*. For start-up checks. */
int taskdef_validate(const petri_net *net, const carry_row *rows, taskdef_roles *r);

/* The health places and transitions of t (taskdef_health above): TASKDEF_OK
 * and *h set (all -1 and mask 0 for a net without them), or
 * TASKDEF_ERR_HEALTH (*h all -1) when one of an arm's two places is
 * missing, they do not hold one token between them, not exactly one
 * transition does the fault or the recovery, or another transition takes
 * or gives their token; TASKDEF_ERR_ARG for NULL. */
int taskdef_health_find(const taskdef *t, taskdef_health *h);

/* taskdef_validate with the rows of the transitions in health_mask allowed
 * to move no arm (carry_table_validate_health); taskdef_validate is this
 * with 0. */
int taskdef_validate_health(const petri_net *net, const carry_row *rows, uint32_t health_mask,
                            taskdef_roles *r);

/* What a task does, in 64 bits (FNV-1a): the net's sizes, N-, N+, its
 * inhibitor arcs and initial marking, and every transition's row (arms,
 * target poses, grippers, gains bit for bit, sync group, segments) --
 * not the names of anything. The shipped carry and tasks/carry compiled
 * back give the same digest; a task with another net or other rows, a
 * different one. A journal records it (tandem-supervisor --journal), so
 * that a restart with another task does not resume from it. */
uint64_t taskdef_digest(const petri_net *net, const carry_row *rows);

/* 1 if arm a (0, 1) sets a workpiece down in row r where no delivery is
 * (a RELEASE not at the release pose and not handed to the partner, which
 * grasps in the same row): the task needs a stand at the hand-over. */
int carry_row_sets_down(const carry_row *r, int a);

/* 1 if an arm of row r moves to arm 2's magazine (ABOVE_MAGAZINE,
 * AT_MAGAZINE): the task needs the magazine (tandem-sim --magazine). */
int carry_row_uses_magazine(const carry_row *r);

#endif
