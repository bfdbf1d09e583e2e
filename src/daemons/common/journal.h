/* journal: an append-only file of state snapshots, one record a line, for
 * a daemon that must come back where it was after a crash or a kill
 * (tandem-supervisor and tandem-rover --journal). The format and the
 * policy are in docs/carry.md "Recovery" (journal format):
 *
 *   J2 <mode> <seq> <n> <v1> ... <vn> <mac>\n
 *
 * mode K: mac is keyed BLAKE2b-128 (libsodium crypto_generichash) of the
 * text before it under the journal key (auth_bus_journal_key: derived
 * from the bus key), so an edited record cannot be given a valid mac
 * without the key; mode U (--insecure): the same hash unkeyed, which
 * finds corruption only. seq counts records from 1 with no gap; values
 * are integers up to 2^53 or doubles written exactly (%.17g).
 *
 * Every append is one write(2) followed by fsync(2): a killed process
 * cannot tear a record, a power cut loses at most the record being
 * written. A write that fails is cut off again (ftruncate) so the file
 * keeps only whole records.
 *
 * Reading refuses the whole journal at the first record that is not
 * right -- garbage, torn (no end of line), a mac that does not match, a
 * gap in seq, a mode other than this process's -- and says which record
 * and why (journal_report): a journal that lies is never resumed from,
 * and never silently replaced by an older record.
 */
#ifndef TANDEM_JOURNAL_H
#define TANDEM_JOURNAL_H

#include <stdint.h>

#define JOURNAL_MAX_VALUES 256
#define JOURNAL_KEY_BYTES 32
#define JOURNAL_MAC_BYTES 16

/* Distinct codes; journal_strerror names them. */
enum {
    JOURNAL_OK = 0,
    JOURNAL_ERR_OPEN = -1,      /* the file does not open for appending */
    JOURNAL_ERR_WRITE = -2,     /* write(2) failed (disk full, EIO): record not kept */
    JOURNAL_ERR_NONE = -3,      /* no journal: the file is missing or empty */
    JOURNAL_ERR_ARG = -4,       /* bad arguments, or a record longer than a line may be */
    JOURNAL_ERR_SYNC = -5,      /* fsync(2) failed: the record may not be on the disk */
    JOURNAL_ERR_READ = -6,      /* the file exists but cannot be read */
    JOURNAL_ERR_FORMAT = -7,    /* a line that is not a record (garbage) */
    JOURNAL_ERR_TORN = -8,      /* the last record has no end of line (cut off) */
    JOURNAL_ERR_MAC = -9,       /* a record's mac does not match: edited or corrupt */
    JOURNAL_ERR_SEQUENCE = -10, /* records missing, repeated or out of order */
    JOURNAL_ERR_MODE = -11      /* keyed journal read without the key, or unkeyed with one */
};

/* The key records are authenticated with; keyed = 0: unkeyed (--insecure). */
typedef struct journal_key {
    uint8_t bytes[JOURNAL_KEY_BYTES];
    int keyed;
} journal_key;

typedef struct journal {
    int fd;    /* -1 when closed */
    long seq;  /* last record's seq: the next is seq + 1 */
    long size; /* bytes of whole records: a failed write is cut back to it */
    long appended;
    int err_no; /* errno of the last failure, 0 none */
    journal_key key;
} journal;

/* Where and why reading stopped. */
typedef struct journal_report {
    long line;     /* line of the offending record (1-based), or of the last one */
    long records;  /* whole records read */
    long last_seq; /* seq of the last record */
    int err_no;    /* JOURNAL_ERR_READ: errno */
    char why[160]; /* what is wrong with that record */
} journal_report;

enum { JOURNAL_APPEND = 0, JOURNAL_TRUNCATE = 1 };

const char *journal_strerror(int rc);

/* Opens path for appending (created 0644 if missing; JOURNAL_TRUNCATE
 * empties it: --journal-reset), records authenticated with key.
 * j->seq must then be set to the last seq read (journal_report.last_seq)
 * when appending to an existing journal. JOURNAL_OK or JOURNAL_ERR_OPEN
 * (j->err_no). */
struct auth_bus;
/* The journal key of this process's bus (auth_bus_journal_key); without one
 * (--insecure) says on stderr, as prog, that records are only
 * checksummed. */
void journal_key_from_bus(const struct auth_bus *bus, journal_key *key, const char *prog);
int journal_open(journal *j, const char *path, const journal_key *key, int how);
/* One record of n values, written and fsynced: JOURNAL_OK, or
 * JOURNAL_ERR_WRITE / JOURNAL_ERR_SYNC (j->err_no; nothing of the record
 * left in the file, retry later) or JOURNAL_ERR_ARG. */
int journal_append(journal *j, const double *v, int n);
void journal_close(journal *j);
/* Reads every record of path, checking each: the last one's values into
 * v (capacity cap) and its length; JOURNAL_ERR_NONE when the file is
 * missing or empty; any other JOURNAL_ERR_* refuses the journal, with the
 * record and why in *rep. */
int journal_load_last(const char *path, const journal_key *key, double *v, int cap,
                      journal_report *rep);

#endif
