/* tandem-netc: compiles a task drawn as a Petri net (PNML) and its lookup
 * rows into the supervisor's const tables, after checking the net
 * (docs/tasks.md). Exit 0: checked and written; 1: refused (the reason and
 * a counterexample on stderr); 2: usage or files.
 */
#include <stdlib.h>
#include <string.h>
#include "netc.h"

static void usage(FILE *f)
{
    fprintf(
        f,
        "usage: tandem-netc TASK.pnml ROWS.csv|ROWS.yaml [--out DIR] [--name NAME] [--bound K] [--sim-args]\n"
        "  Reads a place/transition net (PNML; PIPE's inhibitor arcs) and its\n"
        "  lookup rows, checks it (validators, reachability within %d states:\n"
        "  bounded, safe for K = 1, deadlock-free, every transition fires, the\n"
        "  rows marked live stay live; P-invariants) and writes DIR/NAME_task.h\n"
        "  and DIR/NAME_task.c (petri_net and carry_row const tables).\n"
        "  --out DIR    where the C goes (must exist); without it, check only\n"
        "  --name NAME  C prefix (default: the PNML net's id)\n"
        "  --bound K    token bound per place (default 1: the net must be safe; 0: the\n"
        "               largest its P-invariants allow, as tandem-supervisor --task takes it)\n"
        "  --sim-args   last line: the tandem-sim options the cell needs for the task\n"
        "               (--handover-stand when a row sets a workpiece down at the hand-over,\n"
        "               --magazine when a row goes to arm 2's magazine)\n"
        "  exit 0 ok, 1 refused (with a counterexample), 2 usage or files\n"
        "  docs/tasks.md\n",
        PETRI_MAX_STATES);
}

static int name_ok(const char *s)
{
    const char *p;
    if (!*s || (*s >= '0' && *s <= '9'))
        return 0;
    for (p = s; *p; p++)
        if (!((*p >= 'a' && *p <= 'z') || (*p >= 'A' && *p <= 'Z') || (*p >= '0' && *p <= '9') ||
              *p == '_'))
            return 0;
    return 1;
}

/* --sim-args: what the simulated cell must have for the task, as
 * tandem-sim options on one line (tools/tandem-run reads it). */
static void print_sim_args(const netc_task *t)
{
    int j, stand = 0, magazine = 0;
    for (j = 0; j < t->n_transitions; j++) {
        stand |= carry_row_sets_down(&t->rows[j], 0) || carry_row_sets_down(&t->rows[j], 1);
        magazine |= carry_row_uses_magazine(&t->rows[j]);
    }
    printf("%s%s%s\n", stand ? "--handover-stand" : "", stand && magazine ? " " : "",
           magazine ? "--magazine" : "");
}

int main(int argc, char **argv)
{
    const char *pnml = NULL, *rows = NULL, *out = NULL;
    netc_task *t = calloc(1, sizeof *t);
    int bound = 1, sim_args = 0, i, rc;
    if (!t)
        return 2;
    for (i = 1; i < argc; i++) {
        if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) {
            usage(stdout);
            free(t);
            return 0;
        } else if (strcmp(argv[i], "--out") == 0 && i + 1 < argc)
            out = argv[++i];
        else if (strcmp(argv[i], "--name") == 0 && i + 1 < argc)
            snprintf(t->task, sizeof t->task, "%s", argv[++i]);
        else if (strcmp(argv[i], "--bound") == 0 && i + 1 < argc)
            bound = atoi(argv[++i]);
        else if (strcmp(argv[i], "--sim-args") == 0)
            sim_args = 1;
        else if (argv[i][0] != '-' && !pnml)
            pnml = argv[i];
        else if (argv[i][0] != '-' && !rows)
            rows = argv[i];
        else {
            usage(stderr);
            free(t);
            return 2;
        }
    }
    if (!pnml || !rows || bound < NETC_BOUND_FROM_INVARIANTS || bound >= PETRI_TOKEN_MAX) {
        usage(stderr);
        free(t);
        return 2;
    }
    rc = netc_pnml_read(t, pnml, stderr);
    if (rc == 0 && !name_ok(t->task)) {
        fprintf(stderr, "tandem-netc: task name \"%s\" is not a C identifier (--name)\n", t->task);
        rc = NETC_ERR_PNML;
    }
    if (rc == 0)
        rc = netc_rows_read(t, rows, stderr);
    if (rc == 0) {
        printf("%s: %d places, %d transitions%s\n", t->task, t->n_places, t->n_transitions,
               t->has_inhibit ? ", inhibitor arcs" : "");
        rc = netc_check(t, bound, stdout, stderr);
    }
    if (rc == 0 && out)
        rc = netc_emit(t, out, pnml, rows, stderr);
    if (rc == 0 && out)
        printf("wrote %s/%s_task.h and %s/%s_task.c\n", out, t->task, out, t->task);
    if (rc == 0 && sim_args)
        print_sim_args(t);
    if (rc != 0)
        fprintf(stderr, "tandem-netc: %s\n", netc_strerror(rc));
    free(t);
    return rc == 0 ? 0 : (rc == NETC_ERR_IO || rc == NETC_ERR_PNML || rc == NETC_ERR_ROWS) ? 2 : 1;
}
