/* Integration: tandem-supervisor's journal cannot lie (docs/carry.md
 * "Recovery").
 *
 * 1. A journal written with the run's key resumes; the same journal torn,
 *    garbage, edited without the key, or edited with it into values no
 *    supervisor could have written (NaN pose, next row -5) is refused:
 *    exit 1, the file, the record and why on stderr. --journal-reset
 *    starts fresh on purpose.
 * 1b. A journal of another task -- the same net with other rows, whose
 *    snapshots would fit, or the buffer task, whose would not -- is
 *    refused naming the record and both tasks; tasks/carry (the shipped
 *    carry as files) is the same task.
 * 2. A journal on a full disk (/dev/full): the supervisor holds -- one
 *    HOLD line, no row sent -- while the simulator offers workpieces.
 * 3. A rover whose journal is on a full disk stops: every command it
 *    sends is zero, its health says safe_hold and why, while its mate
 *    without a journal drives on.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "harness.h"
#include "auth_bus.h"
#include "carry_net.h"
#include "journal.h"
#include "taskdef.h"
#include "tandem_health_t.h"
#include "tandem_rover_command_t.h"

#define SNAP_HEAD 32
#define SNAP_TASK 27 /* digest (2 halves), name (3 parts of 6 bytes) */
#define SNAP_LEN (SNAP_HEAD + CARRY_N_PLACES + 6 * CARRY_N_TRANSITIONS)

/* What the tests share (cmocka's state). */
typedef struct ctx {
    harness h;
    char dir[256];
} ctx;

/* The snapshot of a fresh supervisor at step 100 (supervisor_journal.c's layout). */
static int fresh_snapshot(double *v)
{
    int i;
    const uint64_t digest = taskdef_digest(&carry_net, carry_table);
    const char *name = "carry";
    memset(v, 0, SNAP_LEN * sizeof *v);
    v[0] = 3;   /* version */
    v[1] = 100; /* step */
    v[4] = 1;   /* next row */
    v[SNAP_TASK] = (double)(digest >> 32);
    v[SNAP_TASK + 1] = (double)(digest & 0xffffffffu);
    for (i = 0; name[i]; i++)
        v[SNAP_TASK + 2 + i / 6] += (double)((uint64_t)(unsigned char)name[i] << (8 * (i % 6)));
    for (i = 0; i < CARRY_N_PLACES; i++)
        v[SNAP_HEAD + i] = carry_net.m0[i];
    return SNAP_LEN;
}

/* path holds one record of v under key. */
static void write_journal(const char *path, const journal_key *key, const double *v)
{
    journal j;
    assert_int_equal(journal_open(&j, path, key, JOURNAL_TRUNCATE), JOURNAL_OK);
    assert_int_equal(journal_append(&j, v, SNAP_LEN), JOURNAL_OK);
    assert_int_equal(journal_append(&j, v, SNAP_LEN), JOURNAL_OK);
    journal_close(&j);
}

static journal_key run_key(const harness *h)
{
    journal_key k;
    memset(&k, 0, sizeof k);
    k.keyed = auth_bus_journal_key(&h->bus, k.bytes);
    assert_int_equal(k.keyed, 1);
    return k;
}

/* tandem-supervisor on journal path (plus extra option, or NULL) for at
 * most 3 s: its exit status (-1: still running, then stopped), stderr in err. */
static int supervisor(ctx *c, const char *path, const char *extra, char *err, int cap)
{
    const char *dir = c->dir;
    char errf[400], outf[400];
    const char *bin = getenv("TANDEM_BIN") ? getenv("TANDEM_BIN") : "build/bin";
    int rc;
    snprintf(errf, sizeof errf, "%s/sup.err", dir);
    snprintf(outf, sizeof outf, "%s/sup.out", dir);
    rc = harness_sh(
        "timeout -s TERM 3 %s/tandem-supervisor --lcm-url '%s' --journal '%s' %s >'%s' 2>'%s'", bin,
        c->h.url, path, extra ? extra : "", outf, errf);
    harness_slurp(errf, err, cap);
    if (WIFEXITED(rc) && WEXITSTATUS(rc) == 124)
        return -1;
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -2;
}

static void expect_refused(ctx *c, const char *path, const char *record, const char *code)
{
    static char err[8192];
    assert_int_equal(supervisor(c, path, NULL, err, sizeof err), 1);
    if (!strstr(err, record) || !strstr(err, code) || !strstr(err, path))
        fail_msg("refusal does not name %s / %s / the file:\n%s", record, code, err);
}

static void test_journal_refused_or_resumed(void **state)
{
    static char err[8192], text[1 << 16];
    char path[400];
    double v[SNAP_LEN];
    ctx *c = *state;
    journal_key key = run_key(&c->h), other = key;
    FILE *f;
    long n;
    snprintf(path, sizeof path, "%s/sup.journal", c->dir);
    fresh_snapshot(v);
    /* good: resumes (still running when stopped after 3 s) */
    write_journal(path, &key, v);
    assert_int_equal(supervisor(c, path, NULL, err, sizeof err), -1);
    n = harness_slurp(path, text, sizeof text);
    assert_true(n > 0);
    /* torn: the last record cut */
    write_journal(path, &key, v);
    n = harness_slurp(path, text, sizeof text);
    assert_non_null(f = fopen(path, "w"));
    fwrite(text, 1, (size_t)n - 5, f);
    fclose(f);
    expect_refused(c, path, "record 2 (line 2)", "JOURNAL_ERR_TORN");
    /* garbage */
    assert_non_null(f = fopen(path, "w"));
    fputs("\x7f"
          "ELF garbage\n",
          f);
    fclose(f);
    expect_refused(c, path, "record 1 (line 1)", "JOURNAL_ERR_FORMAT");
    /* edited, its checksum recomputed without the key */
    other.bytes[3] ^= 0x40;
    v[4] = -5;
    write_journal(path, &other, v);
    expect_refused(c, path, "record 1 (line 1)", "JOURNAL_ERR_MAC");
    /* edited by a key holder into values no supervisor writes */
    write_journal(path, &key, v);
    expect_refused(c, path, "record 2 (line 2)", "next_action_id (next row) = -5");
    v[4] = 1;
    v[6] = NAN;
    write_journal(path, &key, v);
    expect_refused(c, path, "record 2 (line 2)", "wp_pos_x = nan");
    /* --journal-reset: starts fresh on purpose */
    assert_int_equal(supervisor(c, path, "--journal-reset", err, sizeof err), -1);
}

/* A journal of the shipped carry, and a supervisor started on it with
 * another task: refused, naming the record and both tasks, even when the
 * other task's snapshot has the carry's size (its net, other rows) and
 * would be taken without the check. */
static void test_journal_of_another_task_refused(void **state)
{
    static char err[8192];
    char path[400], task[400], extra[600];
    const char *need[4];
    double v[SNAP_LEN];
    ctx *c = *state;
    const journal_key key = run_key(&c->h);
    int i;
    snprintf(path, sizeof path, "%s/task.journal", c->dir);
    snprintf(task, sizeof task, "%s/carry_t1_fine", c->dir);
    assert_int_equal(
        harness_sh("mkdir -p %s && cp tasks/carry/carry.pnml %s/ && "
                   "sed 's/^t1,yes,FREE,/t1,yes,FINE,/' tasks/carry/rows.csv >%s/rows.csv",
                   task, task, task),
        0);
    fresh_snapshot(v);
    /* tasks/carry is the shipped carry as files: the same task, resumed */
    write_journal(path, &key, v);
    assert_int_equal(supervisor(c, path, "--task tasks/carry", err, sizeof err), -1);
    /* the same net with t1's gains changed: another task */
    write_journal(path, &key, v);
    snprintf(extra, sizeof extra, "--task %s", task);
    assert_int_equal(supervisor(c, path, extra, err, sizeof err), 1);
    need[0] = "record 2 (line 2)";
    need[1] = "written for task 'carry'";
    need[2] = task;
    need[3] = "SUPERVISOR_ERR_OTHER_TASK";
    for (i = 0; i < 4; i++)
        if (!strstr(err, need[i]))
            fail_msg("the refusal does not name %s:\n%s", need[i], err);
    if (!strstr(err, path))
        fail_msg("the refusal does not name the journal %s:\n%s", path, err);
    printf("%s", err);
    /* the buffer task, whose snapshot has another size: refused for its
     * task, not for the snapshot's size */
    write_journal(path, &key, v);
    assert_int_equal(supervisor(c, path, "--task tasks/carry_buffer", err, sizeof err), 1);
    if (!strstr(err, "SUPERVISOR_ERR_OTHER_TASK") || !strstr(err, "tasks/carry_buffer"))
        fail_msg("the buffer task is not refused as another task:\n%s", err);
    /* --journal-reset: the other task starts fresh on purpose */
    snprintf(extra, sizeof extra, "--task %s --journal-reset", task);
    assert_int_equal(supervisor(c, path, extra, err, sizeof err), -1);
}

/* The supervisor with its journal on a full disk and the simulator
 * offering workpieces: one HOLD line, no row out. */
static void test_disk_full_holds(void **state)
{
    static char out[1 << 16];
    const char *sim[] = { "tandem-sim", "--workpieces", "2", NULL };
    const char *sup[] = { "tandem-supervisor", "--journal", "/dev/full", "--journal-reset", NULL };
    pid_t ps, pv;
    const char *p;
    int holds = 0;
    ctx *c = *state;
    harness *h = &c->h;
    if (access("/dev/full", W_OK) != 0)
        skip();
    ps = harness_spawn(h, sim);
    pv = harness_spawn(h, sup);
    assert_true(ps > 0 && pv > 0);
    sleep(8);
    kill(pv, SIGTERM);
    harness_wait(h, pv, 5.0);
    harness_read_output(h, pv, out, sizeof out);
    for (p = out; (p = strstr(p, "HOLD: journal")) != NULL; p++)
        holds++;
    if (holds != 1 || strstr(out, "-> arm"))
        fail_msg("expected one HOLD line and no row:\n%s", out);
    harness_kill_all(h);
}

/* What the rovers sent: commands per robot, robot 1's last health. */
typedef struct rover_seen {
    int cmds[3];
    double max_speed[3]; /* |v| + |w| */
    int held, health;
    char status[128];
} rover_seen;

static void on_rover_cmd(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_command_t *m,
                         void *u)
{
    rover_seen *w = u;
    (void)rb;
    (void)ch;
    if (m->robot == 1 || m->robot == 2) {
        w->cmds[m->robot]++;
        w->max_speed[m->robot] = fmax(w->max_speed[m->robot], fabs(m->v_mps) + fabs(m->w_radps));
    }
}

static void on_rover_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m,
                            void *u)
{
    rover_seen *w = u;
    (void)rb;
    (void)ch;
    w->health++;
    w->held = m->safe_hold;
    snprintf(w->status, sizeof w->status, "%s", m->status);
}

AUTH_TYPED_HANDLER(tandem_rover_command_t, raw_on_rover_cmd, on_rover_cmd)
AUTH_TYPED_HANDLER(tandem_health_t, raw_on_rover_health, on_rover_health)

static void test_rover_disk_full_stops(void **state)
{
    const char *sim[] = { "tandem-sim", "--no-arms", "--rovers", "2", "--world", "open", NULL };
    const char *r1[] = { "tandem-rover",    "--id", "1", "--robots", "2", "--journal", "/dev/full",
                         "--journal-reset", NULL };
    const char *r2[] = { "tandem-rover", "--id", "2", "--robots", "2", NULL };
    rover_seen w;
    lcm_subscription_t *s1, *s2, *s3;
    ctx *c = *state;
    harness *h = &c->h;
    if (access("/dev/full", W_OK) != 0)
        skip();
    memset(&w, 0, sizeof w);
    s1 = auth_bus_subscribe(&h->bus, h->lcm, "ROVER1_COMMAND", raw_on_rover_cmd, &w);
    s2 = auth_bus_subscribe(&h->bus, h->lcm, "ROVER2_COMMAND", raw_on_rover_cmd, &w);
    s3 = auth_bus_subscribe(&h->bus, h->lcm, "HEALTH_TANDEM_ROVER_1", raw_on_rover_health, &w);
    assert_true(harness_spawn(h, sim) > 0);
    assert_true(harness_spawn(h, r1) > 0);
    assert_true(harness_spawn(h, r2) > 0);
    harness_pump(h, 6000);
    printf(
        "robot 1 (journal on /dev/full): %d commands, max |v|+|w| %.3f; robot 2: %d commands, max %.3f; "
        "robot 1's health: safe_hold %d, \"%s\"\n",
        w.cmds[1], w.max_speed[1], w.cmds[2], w.max_speed[2], w.held, w.status);
    assert_true(w.cmds[1] > 20 && w.cmds[2] > 20);
    assert_true(w.max_speed[1] == 0.0);
    assert_true(w.max_speed[2] > 0.05);
    assert_true(w.health > 0 && w.held == 1);
    assert_non_null(strstr(w.status, "journal not written"));
    lcm_unsubscribe(h->lcm, s1);
    lcm_unsubscribe(h->lcm, s2);
    lcm_unsubscribe(h->lcm, s3);
    harness_kill_all(h);
}

int main(void)
{
    static ctx c;
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_prestate(test_journal_refused_or_resumed, &c),
        cmocka_unit_test_prestate(test_journal_of_another_task_refused, &c),
        cmocka_unit_test_prestate(test_disk_full_holds, &c),
        cmocka_unit_test_prestate(test_rover_disk_full_stops, &c),
    };
    int rc;
    harness_private_net();
    snprintf(c.dir, sizeof c.dir, "build/it_journal.%d", (int)getpid());
    harness_sh("mkdir -p %s", c.dir);
    if (harness_open(&c.h, 37) != 0)
        return 1;
    rc = cmocka_run_group_tests(tests, NULL, NULL);
    harness_close(&c.h);
    harness_sh("rm -rf %s", c.dir);
    return rc;
}
