/* netc: the task compiler (docs/tasks.md), shared by tandem-netc and
 * tandem-supervisor --task. A Petri net drawn in a PNML editor and its
 * lookup rows become the supervisor's fixed tables (taskdef: petri_net,
 * carry_row of docs/method/carry.md §5, §6) once the net has passed the
 * checks of docs/tasks.md §4. It lives in the daemon shell, above the
 * core: libxml2 reads the PNML, and the checker's graph is allocated
 * once at start-up, never in a control cycle.
 */
#ifndef TANDEM_NETC_H
#define TANDEM_NETC_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "carry_net.h"
#include "taskdef.h"
#include "petri.h"

#define NETC_OK 0
#define NETC_ERR_IO (-1)       /* a file cannot be read or written     */
#define NETC_ERR_PNML (-2)     /* the PNML is not a net this tool reads */
#define NETC_ERR_ROWS (-3)     /* the rows file is malformed            */
#define NETC_ERR_CAPACITY (-4) /* more than a PETRI_* or NETC_* maximum */
#define NETC_ERR_TABLE \
    (-5)                              /* petri_net_validate / carry_table_validate
                                     or the cell refuse the tables        */
#define NETC_ERR_UNBOUNDED (-6)       /* a place exceeds the bound            */
#define NETC_ERR_DEADLOCK (-7)        /* a dead marking is reachable          */
#define NETC_ERR_DEAD_TRANSITION (-8) /* a transition never fires         */
#define NETC_ERR_NOT_LIVE (-9)        /* a live transition can be lost for good */
#define NETC_ERR_STATES (-10)         /* the reachable set exceeds PETRI_MAX_STATES */
#define NETC_ERR_INVARIANT \
    (-11) /* more P-invariants than
                                     PETRI_MAX_INVARIANTS, or Farkas rows
                                     beyond NETC_MAX_FARKAS_ROWS         */
#define NETC_ERR_ROLES \
    (-12) /* the net lacks a role the supervisor
                                     needs (taskdef_roles_find)        */

#define NETC_MAX_NAME TASKDEF_MAX_NAME
#define NETC_MAX_ROW_NAME TASKDEF_MAX_ROW_NAME
#define NETC_MAX_FARKAS_ROWS 512
/* netc_check's bound: the largest a P-invariant allows any place it
 * covers (y^T m0 / y_i), at least 1; places no invariant covers are held
 * to it by the reachability graph. A buffer of two slots (pb + pf = 2)
 * gives 2, a net whose every invariant is an arm's cycle 1 (safe). */
#define NETC_BOUND_FROM_INVARIANTS 0

/* The task in its fixed tables (the core's taskdef). */
typedef taskdef netc_task;

/* Messages start with the program's name ("tandem-netc" unless set). */
void netc_set_program(const char *name);
void netc_say(FILE *f, const char *fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

const char *netc_strerror(int rc);

/* PNML (docs/tasks.md §2) into t: places, transitions, N-, N+, inhibitor,
 * m0; t->net set (no invariants yet). Writes what is wrong to err. */
int netc_pnml_read(netc_task *t, const char *path, FILE *err);
/* The same from len bytes in memory (the fuzz target, fuzz/fuzz_pnml.c);
 * name stands for the file in what is said; err may be NULL (silent). */
int netc_pnml_read_memory(netc_task *t, const char *buf, int len, const char *name, FILE *err);
/* The rows file (docs/tasks.md §3): one row per transition of t, from a
 * CSV, or from YAML when path ends in .yaml or .yml (§3.1). */
int netc_rows_read(netc_task *t, const char *path, FILE *err);
int netc_rows_read_csv(netc_task *t, const char *path, FILE *err);
int netc_rows_read_yaml(netc_task *t, const char *path, FILE *err);
int netc_is_yaml(const char *path);

/* Shared by the two rows readers: one row from its fields (transition,
 * live, gains, sync_group, arm1, arm2, name as the CSV writes them; *what
 * names the one that is wrong, -1), and every transition has its row. */
#define NETC_ROW_FIELDS 7
int netc_row_fields(netc_task *t, char *f[NETC_ROW_FIELDS], const char **what);
int netc_rows_complete(const netc_task *t, const char *path, FILE *err);
/* The checks of docs/tasks.md §4 with token bound `bound` (or
 * NETC_BOUND_FROM_INVARIANTS); fills t->invariants. Reports on out, a
 * refusal with its counterexample on err. */
int netc_check(netc_task *t, int bound, FILE *out, FILE *err);
/* The same, the bound used into *bound_out (if not NULL). */
int netc_check_bound(netc_task *t, int bound, int *bound_out, FILE *out, FILE *err);
/* DIR/<task>_task.h and DIR/<task>_task.c. */
int netc_emit(const netc_task *t, const char *dir, const char *pnml, const char *rows, FILE *err);

/* A task directory (docs/tasks.md §7): its one *.pnml and rows.csv read
 * into t and checked (netc_check); 0 or the first NETC_ERR_*, after
 * naming the file and why on err. *bound_out (if not NULL): the bound the
 * check used. */
int netc_task_load(netc_task *t, const char *dir, int bound, int *bound_out, FILE *out, FILE *err);

/* Helpers shared by the modules. */
#define netc_task_bind taskdef_bind /* t->net points into t's arrays */
int netc_pose_from_name(const char *s);

#endif
