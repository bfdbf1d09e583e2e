/* netc: tandem-netc, the task compiler (docs/tasks.md). A Petri net drawn
 * in a PNML editor and its lookup rows become the supervisor's const
 * tables (petri_net, carry_row: docs/method/carry.md §5, §6) once the net
 * has passed the checks of docs/tasks.md §4.
 */
#ifndef TANDEM_NETC_H
#define TANDEM_NETC_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include "carry_net.h"
#include "petri.h"

#define NETC_OK 0
#define NETC_ERR_IO (-1)          /* a file cannot be read or written     */
#define NETC_ERR_PNML (-2)        /* the PNML is not a net this tool reads */
#define NETC_ERR_ROWS (-3)        /* the rows file is malformed            */
#define NETC_ERR_CAPACITY (-4)    /* more than a PETRI_* or NETC_* maximum */
#define NETC_ERR_TABLE (-5)       /* petri_net_validate / carry_table_validate
                                     or the cell refuse the tables        */
#define NETC_ERR_UNBOUNDED (-6)   /* a place exceeds the bound            */
#define NETC_ERR_DEADLOCK (-7)    /* a dead marking is reachable          */
#define NETC_ERR_DEAD_TRANSITION (-8) /* a transition never fires         */
#define NETC_ERR_NOT_LIVE (-9)    /* a live transition can be lost for good */
#define NETC_ERR_STATES (-10)     /* the reachable set exceeds PETRI_MAX_STATES */
#define NETC_ERR_INVARIANT (-11)  /* more P-invariants than
                                     PETRI_MAX_INVARIANTS, or Farkas rows
                                     beyond NETC_MAX_FARKAS_ROWS         */

#define NETC_MAX_NAME 64
#define NETC_MAX_ROW_NAME 96
#define NETC_MAX_FARKAS_ROWS 512

typedef struct {
    char task[NETC_MAX_NAME];
    int n_places, n_transitions;
    char place_id[PETRI_MAX_PLACES][NETC_MAX_NAME];
    char place_name[PETRI_MAX_PLACES][NETC_MAX_NAME];
    char trans_id[PETRI_MAX_TRANSITIONS][NETC_MAX_NAME];
    char trans_name[PETRI_MAX_TRANSITIONS][NETC_MAX_NAME];
    int8_t n_minus[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int8_t n_plus[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int8_t n_inhibit[PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS];
    int has_inhibit;
    uint8_t m0[PETRI_MAX_PLACES];
    int n_invariants;
    int8_t invariants[PETRI_MAX_INVARIANTS * PETRI_MAX_PLACES];
    petri_net net;                           /* points into the arrays above */
    /* rows, one per transition (row t is transition t) */
    carry_row rows[PETRI_MAX_TRANSITIONS];
    char row_name[PETRI_MAX_TRANSITIONS][NETC_MAX_ROW_NAME];
    int has_row[PETRI_MAX_TRANSITIONS];
    int live[PETRI_MAX_TRANSITIONS];         /* the rows file asks for liveness */
} netc_task;

const char *netc_strerror(int rc);

/* PNML (docs/tasks.md §2) into t: places, transitions, N-, N+, inhibitor,
 * m0; t->net set (no invariants yet). Writes what is wrong to err. */
int netc_pnml_read(netc_task *t, const char *path, FILE *err);
/* The rows file (CSV, docs/tasks.md §3): one row per transition of t. */
int netc_rows_read(netc_task *t, const char *path, FILE *err);
/* The checks of docs/tasks.md §4 with token bound `bound`; fills
 * t->invariants. Reports on out, a refusal with its counterexample on err. */
int netc_check(netc_task *t, int bound, FILE *out, FILE *err);
/* DIR/<task>_task.h and DIR/<task>_task.c. */
int netc_emit(const netc_task *t, const char *dir, const char *pnml, const char *rows, FILE *err);

/* Helpers shared by the modules. */
void netc_task_bind(netc_task *t);   /* t->net points into t's arrays */
int netc_pose_from_name(const char *s);

#endif
