/* netc_task: a task directory read and checked into the fixed tables the
 * supervisor runs (docs/tasks.md §7): DIR holds one PNML net (*.pnml) and
 * its rows (rows.csv or rows.yaml, not both); both go through the same reader and checker as
 * tandem-netc, so what the supervisor takes at start-up is what the
 * offline compiler would have written as const tables.
 */
#include <dirent.h>
#include <stdarg.h>
#include <string.h>
#include "netc.h"

#define PATH_CHARS 1024

static const char *program = "tandem-netc";

void netc_set_program(const char *name)
{
    program = name ? name : "tandem-netc";
}

void netc_say(FILE *f, const char *fmt, ...)
{
    va_list ap;
    if (!f)
        return;
    fprintf(f, "%s: ", program);
    va_start(ap, fmt);
    vfprintf(f, fmt, ap);
    va_end(ap);
}

static int ends_with(const char *s, const char *suffix)
{
    const size_t n = strlen(s), k = strlen(suffix);
    return n > k && strcmp(s + n - k, suffix) == 0;
}

/* DIR's one *.pnml into path: 0, or NETC_ERR_IO after saying why (none,
 * several: which one is the task would be a guess). */
static int find_pnml(const char *dir, char *path, size_t cap, FILE *err)
{
    DIR *d = opendir(dir);
    const struct dirent *e;
    int n = 0;
    if (!d) {
        netc_say(err, "task %s: not a readable directory\n", dir);
        return NETC_ERR_IO;
    }
    while ((e = readdir(d)) != NULL)
        if (ends_with(e->d_name, ".pnml") && n++ == 0)
            snprintf(path, cap, "%s/%s", dir, e->d_name);
    closedir(d);
    if (n != 1) {
        netc_say(err, "task %s: %s PNML file (*.pnml) where the task needs exactly one\n", dir,
                 n == 0 ? "no" : "more than one");
        return NETC_ERR_IO;
    }
    return NETC_OK;
}

static int readable(const char *path)
{
    FILE *f = fopen(path, "r");
    if (f)
        fclose(f);
    return f != NULL;
}

/* DIR's rows: rows.csv or rows.yaml into path (rows.csv when neither
 * is there, for the reader to say it cannot be read); both: NETC_ERR_IO,
 * which one holds the task would be a guess. */
static int find_rows(const char *dir, char *path, size_t cap, FILE *err)
{
    char yaml[1024];
    snprintf(yaml, sizeof yaml, "%s/rows.yaml", dir);
    snprintf(path, cap, "%s/rows.csv", dir);
    if (!readable(yaml))
        return NETC_OK;
    if (readable(path)) {
        netc_say(err, "task %s: both rows.csv and rows.yaml where the task needs one\n", dir);
        return NETC_ERR_IO;
    }
    snprintf(path, cap, "%s", yaml);
    return NETC_OK;
}

int netc_task_load(netc_task *t, const char *dir, int bound, int *bound_out, FILE *out, FILE *err)
{
    char pnml[PATH_CHARS], rows[PATH_CHARS];
    int rc;
    memset(t, 0, sizeof *t);
    if (!dir || bound < 0 || bound >= PETRI_TOKEN_MAX)
        return NETC_ERR_CAPACITY;
    if ((rc = find_pnml(dir, pnml, sizeof pnml, err)) != NETC_OK)
        return rc;
    if ((rc = find_rows(dir, rows, sizeof rows, err)) != NETC_OK)
        return rc;
    if ((rc = netc_pnml_read(t, pnml, err)) != NETC_OK ||
        (rc = netc_rows_read(t, rows, err)) != NETC_OK)
        return rc;
    return netc_check_bound(t, bound, bound_out, out, err);
}
