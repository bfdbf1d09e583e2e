/* journal: append-only snapshots with a checksum per line (journal.h). */
#include "journal.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define JOURNAL_LINE_MAX (JOURNAL_MAX_VALUES * 26 + 64)

/* FNV-1a over the line's text up to the checksum field. */
static uint32_t line_sum(const char *s, size_t n)
{
    uint32_t h = 2166136261u;
    size_t i;
    for (i = 0; i < n; i++) {
        h ^= (unsigned char)s[i];
        h *= 16777619u;
    }
    return h;
}

int journal_open(journal *j, const char *path)
{
    memset(j, 0, sizeof *j);
    j->f = fopen(path, "a");
    return j->f ? JOURNAL_OK : JOURNAL_ERR_OPEN;
}

int journal_append(journal *j, const double *v, int n)
{
    static char line[JOURNAL_LINE_MAX];
    size_t used;
    int i;
    if (!j->f || n < 1 || n > JOURNAL_MAX_VALUES) return JOURNAL_ERR_ARG;
    used = (size_t)snprintf(line, sizeof line, "J %d", n);
    for (i = 0; i < n && used < sizeof line; i++)
        used += (size_t)snprintf(line + used, sizeof line - used, " %.17g", v[i]);
    if (used + 16 >= sizeof line) return JOURNAL_ERR_ARG;
    snprintf(line + used, sizeof line - used, " #%08lx\n", (unsigned long)line_sum(line, used));
    if (fputs(line, j->f) < 0 || fflush(j->f) != 0) return JOURNAL_ERR_WRITE;
    j->appended++;
    return JOURNAL_OK;
}

void journal_close(journal *j)
{
    if (j->f) fclose(j->f);
    j->f = NULL;
}

/* parse_line: a line torn by a crash, or not a snapshot line */
#define LINE_BAD (-1)

/* One line into v: its length, or LINE_BAD. */
static int parse_line(const char *line, double *v, int cap)
{
    const char *hash = strrchr(line, '#');
    char *end;
    long n;
    int i;
    if (strncmp(line, "J ", 2) != 0 || !hash || hash == line) return LINE_BAD;
    if (strtoul(hash + 1, &end, 16) != line_sum(line, (size_t)(hash - 1 - line)) || end == hash + 1)
        return LINE_BAD;
    n = strtol(line + 2, &end, 10);
    if (n < 1 || n > cap) return LINE_BAD;
    for (i = 0; i < n; i++) {
        const char *p = end;
        v[i] = strtod(p, &end);
        if (end == p) return LINE_BAD;
    }
    return (int)n;
}

int journal_load_last(const char *path, double *v, int cap)
{
    static char line[JOURNAL_LINE_MAX];
    static double tmp[JOURNAL_MAX_VALUES];
    FILE *f = fopen(path, "r");
    int best = JOURNAL_ERR_NONE;
    if (!f) return JOURNAL_ERR_NONE;
    if (cap > JOURNAL_MAX_VALUES) cap = JOURNAL_MAX_VALUES;
    while (fgets(line, sizeof line, f)) {
        const int n = parse_line(line, tmp, cap);
        if (n > 0) {
            memcpy(v, tmp, (size_t)n * sizeof *v);
            best = n;
        }
    }
    fclose(f);
    return best;
}
