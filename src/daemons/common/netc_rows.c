/* netc_rows: reads a task's lookup table (docs/method/carry.md §6) from
 * its rows file, a CSV with one line per transition (docs/tasks.md §3):
 * the arms' segments (move to a named pose of the cell, grasp, release),
 * the gains by name (FREE, FINE, SYNC: the shipped table's) or as eight
 * numbers, the sync group and whether the transition must stay live.
 * Which arms act, their target poses and gripper actions follow from the
 * segments, so a row cannot contradict them.
 */
#include <ctype.h>
#include <stdlib.h>
#include <string.h>
#include "netc.h"

#define LINE_MAX_CHARS 512
#define N_FIELDS NETC_ROW_FIELDS /* transition,live,gains,sync_group,arm1,arm2,name */

static const char *const HEADER = "transition,live,gains,sync_group,arm1,arm2,name";

typedef struct {
    const char *name;
    int transition; /* the shipped row whose gains these are */
} named_gains;

/* The shipped table's gain sets, by the names carry_net.c gives them. */
static const named_gains GAINS[] = {
    { "FREE", CARRY_T1 },
    { "FINE", CARRY_T2 },
    { "SYNC", CARRY_T3 },
};

int netc_pose_from_name(const char *s)
{
    int p;
    for (p = 1; p < CARRY_N_POSES; p++)
        if (strcmp(s, carry_pose_name(p)) == 0)
            return p;
    return -1;
}

static char *trim(char *s)
{
    char *e;
    while (isspace((unsigned char)*s))
        s++;
    e = s + strlen(s);
    while (e > s && isspace((unsigned char)e[-1]))
        *--e = '\0';
    return s;
}

/* Splits line into N_FIELDS fields; the last (the name) takes the rest. */
static int split(char *line, char *f[N_FIELDS])
{
    int i;
    for (i = 0; i < N_FIELDS - 1; i++) {
        char *c = strchr(line, ',');
        if (!c)
            return 0;
        *c = '\0';
        f[i] = trim(line);
        line = c + 1;
    }
    f[N_FIELDS - 1] = trim(line);
    return 1;
}

static int parse_gains(const char *s, erlaw_gains *g)
{
    double v[CARRY_N_GAINS];
    size_t i;
    char *end;
    const char *p = s;
    for (i = 0; i < sizeof GAINS / sizeof GAINS[0]; i++)
        if (strcmp(s, GAINS[i].name) == 0) {
            *g = carry_table[GAINS[i].transition].lin;
            return 0;
        }
    for (i = 0; i < CARRY_N_GAINS; i++) {
        v[i] = strtod(p, &end);
        if (end == p)
            return -1;
        p = end;
    }
    if (*trim((char *)p))
        return -1;
    g->v_m = v[0];
    g->a_m = v[1];
    g->u_m = v[2];
    g->k_p = v[3];
    g->k_v = v[4];
    g->k0 = v[5];
    g->k1 = v[6];
    g->k2 = v[7];
    return 0;
}

/* One segment: "MOVE POSE", "GRASP" or "RELEASE". */
static int parse_segment(char *s, carry_segment *seg)
{
    s = trim(s);
    seg->pose = CARRY_POSE_NONE;
    if (strcmp(s, "GRASP") == 0)
        seg->kind = CARRY_SEG_GRASP;
    else if (strcmp(s, "RELEASE") == 0)
        seg->kind = CARRY_SEG_RELEASE;
    else if (strncmp(s, "MOVE ", 5) == 0) {
        const int p = netc_pose_from_name(trim(s + 5));
        if (p < 0)
            return -1;
        seg->kind = CARRY_SEG_MOVE;
        seg->pose = (int8_t)p;
    } else
        return -1;
    return 0;
}

/* An arm's plan: "-" (none) or ["AFTER "]SEG[; SEG]...; its target pose
 * and gripper action are where the plan ends. */
static int parse_plan(char *s, carry_row *r, int a)
{
    carry_arm_plan *pl = &r->plan[a];
    char *tok;
    int k;
    memset(pl, 0, sizeof *pl);
    r->target_pose[a] = CARRY_POSE_NONE;
    r->gripper[a] = CARRY_GRIP_NONE;
    if (strcmp(s, "-") == 0)
        return 0;
    if (strncmp(s, "AFTER ", 6) == 0) {
        pl->after_partner = 1;
        s += 6;
    }
    for (tok = strtok(s, ";"); tok; tok = strtok(NULL, ";")) {
        if (pl->n_segments >= CARRY_MAX_SEGMENTS ||
            parse_segment(tok, &pl->seg[pl->n_segments]) != 0)
            return -1;
        pl->n_segments++;
    }
    for (k = 0; k < pl->n_segments; k++) {
        if (pl->seg[k].kind == CARRY_SEG_MOVE)
            r->target_pose[a] = pl->seg[k].pose;
        else
            r->gripper[a] = pl->seg[k].kind == CARRY_SEG_GRASP ? CARRY_GRIP_CLOSE : CARRY_GRIP_OPEN;
    }
    r->arms |= (uint8_t)(pl->n_segments > 0 ? (a == 0 ? CARRY_ARM1 : CARRY_ARM2) : 0);
    return pl->n_segments > 0 ? 0 : -1;
}

static int find_transition(const netc_task *t, const char *s)
{
    int j;
    for (j = 0; j < t->n_transitions; j++)
        if (strcmp(s, t->trans_name[j]) == 0 || strcmp(s, t->trans_id[j]) == 0)
            return j;
    return -1;
}

/* One line's fields; *what names the field that is wrong. */
int netc_row_fields(netc_task *t, char *f[NETC_ROW_FIELDS], const char **what)
{
    carry_row *r;
    char *end;
    long sync;
    int j;
    if ((j = find_transition(t, f[0])) < 0 || t->has_row[j])
        return *what = "transition (a transition of the net, once)", -1;
    r = &t->rows[j];
    memset(r, 0, sizeof *r);
    if (strcmp(f[1], "yes") != 0 && strcmp(f[1], "no") != 0)
        return *what = "live (yes, no)", -1;
    t->live[j] = strcmp(f[1], "yes") == 0;
    if (parse_gains(f[2], &r->lin) != 0)
        return *what = "gains (FREE, FINE, SYNC or v_m a_m u_m k_p k_v k0 k1 k2)", -1;
    sync = strtol(f[3], &end, 10);
    if (end == f[3] || *end || sync < 0 || sync > 127)
        return *what = "sync_group (0..127)", -1;
    r->sync_group = (int32_t)sync;
    if (parse_plan(f[4], r, 0) != 0 || parse_plan(f[5], r, 1) != 0)
        return *what = "arm1/arm2 (-, or [AFTER ]MOVE POSE; GRASP; RELEASE, at most "
                       "CARRY_MAX_SEGMENTS, poses of the cell)",
               -1;
    if (!f[6][0])
        return *what = "name", -1;
    if (strlen(f[6]) >= sizeof t->row_name[j]) /* refused, not cut */
        return *what = "name: longer than the tables hold (TASKDEF_MAX_ROW_NAME - 1 characters)",
               -1;
    snprintf(t->row_name[j], sizeof t->row_name[j], "%s", f[6]);
    r->name = t->row_name[j];
    t->has_row[j] = 1;
    return 0;
}

/* One data line; *what names the field that is wrong. */
static int parse_line(netc_task *t, char *line, const char **what)
{
    char *f[N_FIELDS];
    if (!split(line, f))
        return *what = "fields (7, comma separated)", -1;
    return netc_row_fields(t, f, what);
}

int netc_rows_complete(const netc_task *t, const char *path, FILE *err)
{
    int j;
    for (j = 0; j < t->n_transitions; j++)
        if (!t->has_row[j]) {
            netc_say(err, "%s: no row for transition %s\n", path, t->trans_name[j]);
            return NETC_ERR_ROWS;
        }
    return NETC_OK;
}

int netc_rows_read(netc_task *t, const char *path, FILE *err)
{
    if (netc_is_yaml(path))
        return netc_rows_read_yaml(t, path, err);
    return netc_rows_read_csv(t, path, err);
}

int netc_rows_read_csv(netc_task *t, const char *path, FILE *err)
{
    char line[LINE_MAX_CHARS];
    FILE *f = fopen(path, "r");
    int n = 0, header = 0;
    if (!f) {
        netc_say(err, "%s: cannot read\n", path);
        return NETC_ERR_IO;
    }
    while (fgets(line, sizeof line, f)) {
        const char *what = NULL;
        char *s;
        n++;
        if (!strchr(line, '\n') && !feof(f)) {
            /* the rest would be read as a line of its own */
            netc_say(err, "%s:%d: longer than %d characters\n", path, n, LINE_MAX_CHARS - 2);
            fclose(f);
            return NETC_ERR_ROWS;
        }
        s = trim(line);
        if (!*s || *s == '#')
            continue;
        if (!header) {
            if (strcmp(s, HEADER) != 0) {
                netc_say(err, "%s:%d: the header must be %s\n", path, n, HEADER);
                fclose(f);
                return NETC_ERR_ROWS;
            }
            header = 1;
        } else if (parse_line(t, s, &what) != 0) {
            netc_say(err, "%s:%d: %s\n", path, n, what);
            fclose(f);
            return NETC_ERR_ROWS;
        }
    }
    fclose(f);
    return netc_rows_complete(t, path, err);
}
