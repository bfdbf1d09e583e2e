/* supervisor_journal: tandem-supervisor's --journal: every change of the
 * discrete state (marking, running rows, the workpieces bound to tokens,
 * action ids, the counters summary.json reports) appended as one
 * authenticated, fsynced record (journal.h); the last one taken back at
 * start after every field is checked. A journal that does not check out
 * stops the start (exit 1, naming the record and why): resuming from a
 * wrong state would send the arms rows for a cell that is not there.
 * A journal that cannot be written holds the cell (no new rows) until it
 * can be written again: state that is not on the disk would be lost by a
 * restart. Every record names the task it was written for (its
 * taskdef_digest and its name): a supervisor started on it with another
 * task (--task) refuses it, naming both, unless --journal-reset. Format
 * and policy: docs/carry.md "Recovery".
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "supervisor_daemon.h"
#include "vec3.h"

#define SNAP_HEAD 32
/* values in a snapshot of the task's net: the head, the marking, and
 * per transition and arm the slot's state, row id and step sent */
#define SNAP_LEN(pn) (SNAP_HEAD + (pn)->n_places + 6 * (pn)->n_transitions)
/* the largest task's snapshot fits a journal record */
typedef char snap_fits_a_record
    [SNAP_HEAD + PETRI_MAX_PLACES + 6 * PETRI_MAX_TRANSITIONS <= JOURNAL_MAX_VALUES ? 1 : -1];
#define RUNNING_MAX \
    4294967295.0 /* a uint32_t running set; petri_set_state
                                      refuses bits of transitions the task lacks */
#define SNAP_VERSION 3
#define ID_MAX 2147483647.0             /* int32 ids and counters */
#define COUNT_MAX 9007199254740992.0    /* 2^53: exact in a double */
#define POS_MAX_M 10.0                  /* a workpiece pose outside this is not the cell's */
#define YAW_MAX_RAD 0.5                 /* what on_vision accepts */
#define HALF_MAX 4294967295.0           /* a 32-bit half of the task's digest */
#define NAME_PART_MAX 281474976710655.0 /* 6 bytes of the task's name */
#define SNAP_TASK 27                    /* the task: digest (2 halves), name (3 parts) */
#define NAME_PARTS 3
#define NAME_BYTES 6

/* The head of a snapshot: name and range of each value (integers unless
 * real), checked before anything is restored. */
typedef struct snap_field {
    const char *name;
    double lo, hi;
    int real;
} snap_field;

static const snap_field head_fields[SNAP_HEAD] = {
    { "version", SNAP_VERSION, SNAP_VERSION, 0 },
    { "step", 0, COUNT_MAX, 0 },
    { "running", 0, RUNNING_MAX, 0 },
    { "fired_count", 0, COUNT_MAX, 0 },
    { "next_action_id (next row)", 1, ID_MAX, 0 },
    { "wp_id", 0, ID_MAX, 0 },
    { "wp_pos_x", -POS_MAX_M, POS_MAX_M, 1 },
    { "wp_pos_y", -POS_MAX_M, POS_MAX_M, 1 },
    { "wp_pos_z", -POS_MAX_M, POS_MAX_M, 1 },
    { "wp_yaw", -YAW_MAX_RAD, YAW_MAX_RAD, 1 },
    { "pick_id", 0, ID_MAX, 0 },
    { "pick_pos_x", -POS_MAX_M, POS_MAX_M, 1 },
    { "pick_pos_y", -POS_MAX_M, POS_MAX_M, 1 },
    { "pick_pos_z", -POS_MAX_M, POS_MAX_M, 1 },
    { "pick_yaw", -YAW_MAX_RAD, YAW_MAX_RAD, 1 },
    { "last_taken_id", 0, ID_MAX, 0 },
    { "p1_bound", 0, 1, 0 },
    { "detections", 0, ID_MAX, 0 },
    { "last_fired", 0, PETRI_MAX_TRANSITIONS, 0 },
    { "blockages", 0, ID_MAX, 0 },
    { "rows_reissued", 0, ID_MAX, 0 },
    { "dones_recovered", 0, ID_MAX, 0 },
    { "replans", 0, ID_MAX, 0 },
    { "deadlocks", 0, ID_MAX, 0 },
    { "faults", 0, ID_MAX, 0 },
    { "stalls", 0, ID_MAX, 0 },
    { "invariant_violations", 0, COUNT_MAX, 0 },
    { "task_digest_hi", 0, HALF_MAX, 0 },
    { "task_digest_lo", 0, HALF_MAX, 0 },
    { "task_name_0", 0, NAME_PART_MAX, 0 },
    { "task_name_1", 0, NAME_PART_MAX, 0 },
    { "task_name_2", 0, NAME_PART_MAX, 0 },
};

/* The name of the running task: its net's (--task), or the shipped carry's. */
static const char *task_name(const supervisor_daemon *sv)
{
    return sv->task ? sv->task->task : "carry";
}

/* The task into v[SNAP_TASK..]: the digest in two exact halves, the first
 * NAME_PARTS * NAME_BYTES bytes of the name, NAME_BYTES to a value. */
static void task_values(const supervisor_daemon *sv, double *v)
{
    const char *name = task_name(sv);
    int p, b, end = 0;
    v[SNAP_TASK] = (double)(sv->task_digest >> 32);
    v[SNAP_TASK + 1] = (double)(sv->task_digest & 0xffffffffu);
    for (p = 0; p < NAME_PARTS; p++) {
        uint64_t part = 0;
        for (b = 0; b < NAME_BYTES; b++) {
            const unsigned char c = end ? 0 : (unsigned char)name[p * NAME_BYTES + b];
            end = end || c == 0;
            part |= (uint64_t)c << (8 * b);
        }
        v[SNAP_TASK + 2 + p] = (double)part;
    }
}

/* A record's task name (checked values), printable, into out. */
static void task_name_of(const double *v, char *out, size_t cap)
{
    size_t n = 0;
    int p, b;
    for (p = 0; p < NAME_PARTS; p++) {
        const uint64_t part = (uint64_t)v[SNAP_TASK + 2 + p];
        for (b = 0; b < NAME_BYTES && n + 1 < cap; b++) {
            const unsigned char c = (unsigned char)(part >> (8 * b));
            if (c == 0) {
                out[n] = 0;
                return;
            }
            out[n++] = (char)(c >= 0x20 && c < 0x7f ? c : '?');
        }
    }
    out[n] = 0;
}

static int snapshot(supervisor_daemon *sv, double *v)
{
    int n = 0, i, a;
    v[n++] = SNAP_VERSION;
    v[n++] = (double)sv->d.step;
    v[n++] = sv->net.st.running;
    v[n++] = (double)sv->net.fired_count;
    v[n++] = sv->next_action_id;
    v[n++] = sv->wp_id;
    v[n++] = sv->wp_pos_m[0];
    v[n++] = sv->wp_pos_m[1];
    v[n++] = sv->wp_pos_m[2];
    v[n++] = sv->wp_yaw_rad;
    v[n++] = sv->pick_id;
    v[n++] = sv->pick_pos_m[0];
    v[n++] = sv->pick_pos_m[1];
    v[n++] = sv->pick_pos_m[2];
    v[n++] = sv->pick_yaw_rad;
    v[n++] = sv->last_taken_id;
    v[n++] = sv->p1_bound;
    v[n++] = sv->detections;
    v[n++] = sv->last_fired;
    v[n++] = sv->blockages;
    v[n++] = sv->rows_reissued;
    v[n++] = sv->dones_recovered;
    v[n++] = sv->replans;
    v[n++] = sv->deadlocks;
    v[n++] = sv->faults;
    v[n++] = sv->stall.stalls;
    v[n++] = (double)sv->net.invariant_violations;
    task_values(sv, v);
    n += 2 + NAME_PARTS;
    for (i = 0; i < sv->pn->n_places; i++)
        v[n++] = sv->net.st.m[i];
    for (i = 0; i < sv->pn->n_transitions; i++)
        for (a = 0; a < 2; a++) {
            v[n++] = sv->slot[i].state[a];
            v[n++] = sv->slot[i].action_id[a];
            v[n++] = (double)sv->slot[i].sent_step[a];
        }
    return n;
}

static int in_range(double x, double lo, double hi, int real)
{
    return isfinite(x) && x >= lo && x <= hi && (real || x == floor(x));
}

/* Every value of a snapshot in its range for the task's net, or why not
 * (into why). */
static int check_values(const supervisor_daemon *sv, const double *v, char *why, size_t cap)
{
    const int np = sv->pn->n_places, nt = sv->pn->n_transitions;
    int i, t, a;
    for (i = 0; i < SNAP_HEAD; i++) {
        const snap_field *f = &head_fields[i];
        if (!in_range(v[i], f->lo, f->hi, f->real)) {
            snprintf(why, cap, "%s = %.17g is outside [%g, %g]%s", f->name, v[i], f->lo, f->hi,
                     f->real ? "" : " or not a whole number");
            return SUPERVISOR_ERR_SNAPSHOT;
        }
    }
    if (v[18] > nt) {
        snprintf(why, cap, "last_fired = t%.0f: the task has %d transitions", v[18], nt);
        return SUPERVISOR_ERR_SNAPSHOT;
    }
    for (i = 0; i < np; i++)
        if (!in_range(v[SNAP_HEAD + i], 0, PETRI_TOKEN_MAX, 0)) {
            snprintf(why, cap, "tokens of place p%d = %.17g are not a token count", i + 1,
                     v[SNAP_HEAD + i]);
            return SUPERVISOR_ERR_SNAPSHOT;
        }
    for (t = 0; t < nt; t++)
        for (a = 0; a < 2; a++) {
            const double *s = &v[SNAP_HEAD + np + 6 * t + 3 * a];
            if (!in_range(s[0], ARM_SLOT_NONE, ARM_SLOT_DONE, 0) ||
                !in_range(s[1], 0, v[4] - 1, 0) || !in_range(s[2], 0, v[1], 0)) {
                snprintf(
                    why, cap,
                    "row of t%d for arm %d (state %.17g, row %.17g, sent at step %.17g) is not one "
                    "this supervisor could have sent",
                    t + 1, a + 1, s[0], s[1], s[2]);
                return SUPERVISOR_ERR_SNAPSHOT;
            }
        }
    return 0;
}

/* A checked snapshot into sv; the marking must be one of the net's (every
 * P-invariant holds, running bits of existing transitions). */
static int restore(supervisor_daemon *sv, const double *v, char *why, size_t cap)
{
    int n = SNAP_HEAD, i, a;
    petri_state st;
    if (check_values(sv, v, why, cap) != 0)
        return SUPERVISOR_ERR_SNAPSHOT;
    memset(&st, 0, sizeof st);
    st.running = (uint32_t)v[2];
    for (i = 0; i < sv->pn->n_places; i++)
        st.m[i] = (uint8_t)v[n++];
    if (petri_set_state(&sv->net, &st) != 0) {
        snprintf(why, cap, "the marking is not one of the task net's (a P-invariant fails)");
        return SUPERVISOR_ERR_SNAPSHOT;
    }
    sv->net.fired_count = (long)v[3];
    sv->next_action_id = (int32_t)v[4];
    sv->wp_id = (int32_t)v[5];
    vec3_set(sv->wp_pos_m, v[6], v[7], v[8]);
    sv->wp_yaw_rad = v[9];
    sv->pick_id = (int32_t)v[10];
    vec3_set(sv->pick_pos_m, v[11], v[12], v[13]);
    sv->pick_yaw_rad = v[14];
    sv->last_taken_id = (int32_t)v[15];
    sv->p1_bound = v[16] != 0;
    sv->detections = (int32_t)v[17];
    sv->last_fired = (int)v[18];
    sv->blockages = (int32_t)v[19];
    sv->rows_reissued = (int32_t)v[20];
    sv->dones_recovered = (int32_t)v[21];
    sv->replans = (int32_t)v[22];
    sv->deadlocks = (int32_t)v[23];
    sv->faults = (int32_t)v[24];
    sv->stall.stalls = (int)v[25];
    sv->net.invariant_violations = (long)v[26];
    for (i = 0; i < sv->pn->n_transitions; i++)
        for (a = 0; a < 2; a++) {
            sv->slot[i].state[a] = (int)v[n++];
            sv->slot[i].action_id[a] = (int32_t)v[n++];
            sv->slot[i].sent_step[a] = (int64_t)v[n++];
        }
    return 0;
}

/* The refusal: file, record, why, and what to do. */
static int refuse(const supervisor_daemon *sv, const journal_report *rep, const char *code,
                  const char *why)
{
    fprintf(stderr,
            "tandem-supervisor: journal %s: record %ld (line %ld): %s (%s); refusing to start "
            "(move the file away, or --journal-reset to start fresh on purpose)\n",
            sv->journal_path, rep->line, rep->line, why, code);
    return SUPERVISOR_ERR_JOURNAL;
}

/* The record's version and task before anything else: a journal of
 * another task (or of an older supervisor) is refused naming both. 0, or
 * SUPERVISOR_ERR_JOURNAL after saying why. */
static int same_task(const supervisor_daemon *sv, const journal_report *rep, const double *v, int n)
{
    char why[400], theirs[NAME_PARTS * NAME_BYTES + 1];
    int i;
    uint64_t digest;
    if (n < 1 || v[0] != SNAP_VERSION) {
        snprintf(why, sizeof why,
                 "version %.17g: this supervisor reads version %d (a journal of an older "
                 "tandem-supervisor)",
                 n < 1 ? 0.0 : v[0], SNAP_VERSION);
        return refuse(sv, rep, supervisor_strerror(SUPERVISOR_ERR_SNAPSHOT), why);
    }
    if (n < SNAP_HEAD) {
        snprintf(why, sizeof why, "%d values, fewer than a snapshot's head (%d)", n, SNAP_HEAD);
        return refuse(sv, rep, supervisor_strerror(SUPERVISOR_ERR_SNAPSHOT), why);
    }
    for (i = SNAP_TASK; i < SNAP_TASK + 2 + NAME_PARTS; i++)
        if (!in_range(v[i], head_fields[i].lo, head_fields[i].hi, 0)) {
            snprintf(why, sizeof why, "%s = %.17g is outside [%g, %g] or not a whole number",
                     head_fields[i].name, v[i], head_fields[i].lo, head_fields[i].hi);
            return refuse(sv, rep, supervisor_strerror(SUPERVISOR_ERR_SNAPSHOT), why);
        }
    digest = ((uint64_t)v[SNAP_TASK] << 32) | (uint64_t)v[SNAP_TASK + 1];
    if (digest == sv->task_digest)
        return 0;
    task_name_of(v, theirs, sizeof theirs);
    snprintf(why, sizeof why,
             "written for task '%s' (digest %016llx), but this supervisor runs task '%s' from %s "
             "(digest %016llx)",
             theirs, (unsigned long long)digest, task_name(sv),
             sv->task_dir ? sv->task_dir : "the shipped carry",
             (unsigned long long)sv->task_digest);
    return refuse(sv, rep, supervisor_strerror(SUPERVISOR_ERR_OTHER_TASK), why);
}

/* The last record of the journal, checked and restored: 0 (restored, or
 * no journal yet), or SUPERVISOR_ERR_JOURNAL after saying why. */
static int resume(supervisor_daemon *sv)
{
    double *v = sv->journal_values;
    journal_report rep;
    char why[200];
    const int n = journal_load_last(sv->journal_path, &sv->jr.key, v, JOURNAL_MAX_VALUES, &rep);
    if (n == JOURNAL_ERR_NONE)
        return 0;
    if (n == JOURNAL_ERR_READ) {
        fprintf(stderr, "tandem-supervisor: journal %s cannot be read: %s (JOURNAL_ERR_READ)\n",
                sv->journal_path, strerror(rep.err_no));
        return SUPERVISOR_ERR_JOURNAL;
    }
    if (n < 0)
        return refuse(sv, &rep, journal_strerror(n), rep.why);
    if (same_task(sv, &rep, v, n) != 0)
        return SUPERVISOR_ERR_JOURNAL;
    if (n != SNAP_LEN(sv->pn)) {
        snprintf(why, sizeof why, "%d values where a snapshot of this supervisor's task has %d", n,
                 SNAP_LEN(sv->pn));
        return refuse(sv, &rep, supervisor_strerror(SUPERVISOR_ERR_SNAPSHOT), why);
    }
    if (restore(sv, v, why, sizeof why) != 0)
        return refuse(sv, &rep, supervisor_strerror(SUPERVISOR_ERR_SNAPSHOT), why);
    sv->journal_seq_resumed = rep.last_seq;
    sv->resumed = (int)v[1] + 1; /* the snapshot's step + 1, checked in the first cycle */
    printf(
        "tandem-supervisor: resumed from %s record %ld (step %lld, fired %ld, next row %d, blockages %d)\n",
        sv->journal_path, rep.records, (long long)v[1], sv->net.fired_count,
        (int)sv->next_action_id, (int)sv->blockages);
    return 0;
}

int sup_journal_start(supervisor_daemon *sv)
{
    journal_key key;
    int rc;
    if (!sv->journal_path)
        return 0;
    journal_key_from_bus(&sv->d.bus, &key, "tandem-supervisor");
    sv->jr.key = key;
    if (sv->journal_reset)
        printf("tandem-supervisor: --journal-reset: starting fresh; %s emptied\n",
               sv->journal_path);
    else if (resume(sv) != 0)
        return SUPERVISOR_ERR_JOURNAL;
    rc = journal_open(&sv->jr, sv->journal_path, &key,
                      sv->journal_reset ? JOURNAL_TRUNCATE : JOURNAL_APPEND);
    if (rc != JOURNAL_OK) {
        fprintf(stderr, "tandem-supervisor: cannot open the journal %s: %s (%s)\n",
                sv->journal_path, strerror(sv->jr.err_no), journal_strerror(rc));
        return SUPERVISOR_ERR_JOURNAL;
    }
    sv->jr.seq = sv->journal_seq_resumed; /* appending goes on from the last record */
    return 0;
}

/* A failed write: the cell holds (sup_holding) and it is said once; a
 * write after failures: said once, and rows go out again. */
static void note_write(supervisor_daemon *sv, int rc)
{
    if (rc != JOURNAL_OK && sv->journal_rc == JOURNAL_OK) {
        fprintf(
            stderr,
            "[%9.3f] tandem-supervisor: cannot write the journal %s: %s (%s): HOLDING, no new rows "
            "until it can be written\n",
            sv->d.sim_time_s, sv->journal_path, strerror(sv->jr.err_no), journal_strerror(rc));
        printf("[%9.3f] HOLD: journal %s not written (%s); no new rows\n", sv->d.sim_time_s,
               sv->journal_path, strerror(sv->jr.err_no));
        fflush(stdout);
        sv->journal_errno = sv->jr.err_no;
        sv->changed = 1;
    } else if (rc == JOURNAL_OK && sv->journal_rc != JOURNAL_OK) {
        printf("[%9.3f] journal %s written again after %ld failed attempts: rows go out again\n",
               sv->d.sim_time_s, sv->journal_path, sv->journal_failures);
        fflush(stdout);
        sv->journal_failures = 0;
        sv->changed = 1;
    }
    if (rc != JOURNAL_OK)
        sv->journal_failures++;
    sv->journal_rc = rc;
    sv->d.safe_hold = rc != JOURNAL_OK;
}

int sup_holding(const supervisor_daemon *sv)
{
    return sv->journal_rc != JOURNAL_OK;
}

void sup_journal_cycle(supervisor_daemon *sv)
{
    double *v = sv->journal_values;
    if (!sv->journal_path)
        return;
    if (!sv->journal_checked && sv->d.step >= 0) {
        sv->journal_checked = 1;
        if (sv->resumed && sv->d.step + 1 < sv->resumed) {
            printf(
                "tandem-supervisor: the journal is from a later step than the simulator's: another run; starting fresh\n");
            memset(sv->slot, 0, sizeof sv->slot);
            petri_init(&sv->net, sv->pn);
            sv->resumed = 0;
        }
        sv->resumed = sv->resumed != 0;
        sv->dirty = 1;
    }
    /* while it fails, every cycle tries again (the state is still dirty) */
    if (sv->dirty) {
        const int rc = journal_append(&sv->jr, v, snapshot(sv, v));
        note_write(sv, rc);
        sv->dirty = rc != JOURNAL_OK;
    }
}
