/* journal: an append-only file of state snapshots, one line each, for a
 * daemon that must come back where it was after a crash or a kill
 * (tandem-supervisor --journal). A snapshot is a vector of numbers
 * (integers up to 2^53 and doubles, written exactly with %.17g); a line
 * ends with a checksum of its text, so a line torn by a crash mid-write
 * is skipped on reading. Every append is flushed to the kernel: a killed
 * process loses nothing; a power cut may lose what the disk had not
 * written yet.
 */
#ifndef TANDEM_JOURNAL_H
#define TANDEM_JOURNAL_H

#include <stdio.h>

#define JOURNAL_MAX_VALUES 256

enum { JOURNAL_OK = 0, JOURNAL_ERR_OPEN = -1, JOURNAL_ERR_WRITE = -2, JOURNAL_ERR_NONE = -3,
       JOURNAL_ERR_ARG = -4 };

typedef struct journal {
    FILE *f;
    long  appended;
} journal;

/* Opens path for appending (created 0644 if missing). */
int  journal_open(journal *j, const char *path);
int  journal_append(journal *j, const double *v, int n);
void journal_close(journal *j);
/* The last intact snapshot of path into v (capacity cap): its length, or
 * JOURNAL_ERR_NONE when the file is missing or holds none. */
int  journal_load_last(const char *path, double *v, int cap);

#endif
