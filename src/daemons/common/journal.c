/* journal: append-only snapshots, each record authenticated (journal.h). */
#include "journal.h"
#include "auth_bus.h"
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <sodium.h>

#define JOURNAL_VERSION_TAG "J2"
/* "J2 K seq n" + n values of at most 24 characters + " " + the mac */
#define JOURNAL_LINE_MAX (JOURNAL_MAX_VALUES * 26 + 96)
#define MAC_HEX (2 * JOURNAL_MAC_BYTES)

/* The mac of a record's text (everything before " <mac>") as hex. */
static void record_mac(const journal_key *k, const char *text, size_t n, char hex[MAC_HEX + 1])
{
    uint8_t mac[JOURNAL_MAC_BYTES];
    crypto_generichash(mac, sizeof mac, (const unsigned char *)text, n, k->keyed ? k->bytes : NULL,
                       k->keyed ? JOURNAL_KEY_BYTES : 0);
    sodium_bin2hex(hex, MAC_HEX + 1, mac, sizeof mac);
}

int journal_open(journal *j, const char *path, const journal_key *key, int how)
{
    off_t end;
    memset(j, 0, sizeof *j);
    j->fd = -1;
    if (!path || !key || sodium_init() < 0)
        return JOURNAL_ERR_ARG;
    j->key = *key;
    j->fd = open(path, O_WRONLY | O_APPEND | O_CREAT | (how == JOURNAL_TRUNCATE ? O_TRUNC : 0),
                 0644);
    if (j->fd < 0) {
        j->err_no = errno;
        return JOURNAL_ERR_OPEN;
    }
    end = lseek(j->fd, 0, SEEK_END);
    j->size = end > 0 ? (long)end : 0;
    return JOURNAL_OK;
}

/* The record's text into line (capacity cap): its length, or 0 when it
 * does not fit. */
static size_t format_record(const journal *j, const double *v, int n, char *line, size_t cap)
{
    char hex[MAC_HEX + 1];
    size_t used = (size_t)snprintf(line, cap, "%s %c %ld %d", JOURNAL_VERSION_TAG,
                                   j->key.keyed ? 'K' : 'U', j->seq + 1, n);
    int i;
    for (i = 0; i < n && used < cap; i++)
        used += (size_t)snprintf(line + used, cap - used, " %.17g", v[i]);
    if (used + MAC_HEX + 3 >= cap)
        return 0;
    record_mac(&j->key, line, used, hex);
    used += (size_t)snprintf(line + used, cap - used, " %s\n", hex);
    return used;
}

/* Failure: nothing of the record may stay (a later read would call the
 * journal torn); on a device that cannot be truncated this does nothing. */
static int write_failed(journal *j, int rc)
{
    j->err_no = errno;
    if (ftruncate(j->fd, (off_t)j->size) != 0) { /* nothing more to do: said by rc */
    }
    return rc;
}

int journal_append(journal *j, const double *v, int n)
{
    char line[JOURNAL_LINE_MAX];
    size_t len, done = 0;
    if (j->fd < 0 || !v || n < 1 || n > JOURNAL_MAX_VALUES)
        return JOURNAL_ERR_ARG;
    len = format_record(j, v, n, line, sizeof line);
    if (len == 0)
        return JOURNAL_ERR_ARG;
    while (done < len) {
        const ssize_t w = write(j->fd, line + done, len - done);
        if (w < 0 && errno == EINTR)
            continue;
        if (w <= 0)
            return write_failed(j, JOURNAL_ERR_WRITE);
        done += (size_t)w;
    }
    if (fsync(j->fd) != 0)
        return write_failed(j, JOURNAL_ERR_SYNC);
    j->seq++;
    j->size += (long)len;
    j->appended++;
    j->err_no = 0;
    return JOURNAL_OK;
}

void journal_close(journal *j)
{
    if (j->fd >= 0)
        close(j->fd);
    j->fd = -1;
}

/* ---- reading ------------------------------------------------------------------ */

static int refuse(journal_report *rep, int rc, const char *why)
{
    snprintf(rep->why, sizeof rep->why, "%s", why);
    return rc;
}

/* The n values after the header, up to the mac at *mac_at. */
static int parse_values(const char *p, const char *mac_at, double *v, int n, journal_report *rep)
{
    int i;
    for (i = 0; i < n; i++) {
        char *end;
        v[i] = strtod(p, &end);
        if (end == p || end > mac_at || (*end != ' '))
            return refuse(rep, JOURNAL_ERR_FORMAT,
                          "a value is not a number, or fewer values than it says");
        p = end;
    }
    if (p != mac_at)
        return refuse(rep, JOURNAL_ERR_FORMAT, "more values than it says");
    return n;
}

/* One whole line (with its '\n' removed) into v: its length, or a refusal. */
static int parse_record(const char *line, const journal_key *key, long want_seq, double *v, int cap,
                        journal_report *rep)
{
    const size_t len = strlen(line);
    char mode = 0, hex[MAC_HEX + 1];
    long seq = 0;
    int n = 0, head = 0;
    if (len < MAC_HEX + 2 || strncmp(line, JOURNAL_VERSION_TAG " ", 3) != 0 ||
        sscanf(line, "J2 %c %ld %d%n", &mode, &seq, &n, &head) != 3 ||
        line[len - MAC_HEX - 1] != ' ')
        return refuse(rep, JOURNAL_ERR_FORMAT, "not a journal record (garbage, or another format)");
    if (mode != 'K' && mode != 'U')
        return refuse(rep, JOURNAL_ERR_FORMAT, "unknown mode (neither K nor U)");
    if ((mode == 'K') != (key->keyed != 0))
        return refuse(rep, JOURNAL_ERR_MODE,
                      mode == 'K' ? "written with a journal key, and this process has none "
                                    "(--insecure)"
                                  : "written unkeyed (--insecure), and this process has a key");
    record_mac(key, line, len - MAC_HEX - 1, hex);
    if (sodium_memcmp(hex, line + len - MAC_HEX, MAC_HEX) != 0)
        return refuse(rep, JOURNAL_ERR_MAC,
                      key->keyed ? "mac does not match: edited, corrupt, or another key"
                                 : "checksum does not match: corrupt or edited");
    if (seq != want_seq) {
        snprintf(rep->why, sizeof rep->why,
                 "sequence %ld where %ld was due: records missing or out of order", seq, want_seq);
        return JOURNAL_ERR_SEQUENCE;
    }
    if (n < 1 || n > cap)
        return refuse(rep, JOURNAL_ERR_FORMAT, "more values than a snapshot of this program has");
    return parse_values(line + head, line + len - MAC_HEX - 1, v, n, rep);
}

int journal_load_last(const char *path, const journal_key *key, double *v, int cap,
                      journal_report *rep)
{
    char line[JOURNAL_LINE_MAX + 2];
    double tmp[JOURNAL_MAX_VALUES];
    FILE *f;
    int best = JOURNAL_ERR_NONE;
    memset(rep, 0, sizeof *rep);
    if (!path || !key || !v || cap < 1)
        return JOURNAL_ERR_ARG;
    if (sodium_init() < 0)
        return JOURNAL_ERR_ARG;
    f = fopen(path, "r");
    if (!f) {
        rep->err_no = errno;
        return errno == ENOENT ? JOURNAL_ERR_NONE : JOURNAL_ERR_READ;
    }
    if (cap > JOURNAL_MAX_VALUES)
        cap = JOURNAL_MAX_VALUES;
    while (fgets(line, sizeof line, f)) {
        const size_t len = strlen(line);
        int n;
        rep->line++;
        if (len == 0 || line[len - 1] != '\n') {
            /* a record's beginning with no end is torn; anything else is garbage */
            best = feof(f) && strncmp(line, JOURNAL_VERSION_TAG " ", 3) == 0
                       ? refuse(rep, JOURNAL_ERR_TORN, "no end of line: the record was cut off")
                       : refuse(rep, JOURNAL_ERR_FORMAT,
                                "not a journal record (garbage, or longer than any record)");
            break;
        }
        line[len - 1] = '\0';
        n = parse_record(line, key, rep->records + 1, tmp, cap, rep);
        if (n < 0) {
            best = n;
            break;
        }
        memcpy(v, tmp, (size_t)n * sizeof *v);
        best = n;
        rep->records++;
        rep->last_seq = rep->records;
    }
    if (best >= 0 || best == JOURNAL_ERR_NONE) {
        if (ferror(f)) {
            rep->err_no = errno;
            best = refuse(rep, JOURNAL_ERR_READ, "read error");
        }
    }
    fclose(f);
    return best;
}

void journal_key_from_bus(const auth_bus *bus, journal_key *key, const char *prog)
{
    memset(key, 0, sizeof *key);
    key->keyed = auth_bus_journal_key(bus, key->bytes);
    if (!key->keyed)
        fprintf(stderr,
                "%s: --insecure: journal records are checksummed, not authenticated "
                "(an edited journal cannot be told from a good one)\n",
                prog);
}
