/* Tests of tandem-netc's modules (docs/tasks.md): the shipped carry drawn
 * as PNML compiles to carry_net and carry_table field by field; the buffer
 * task passes with its bound and is refused as unsafe without it; a
 * deadlocking variant, a dead transition, a lost transition, a bad row,
 * an unreadable net and a weighted arc are refused, each for its reason;
 * the task where arm 2 works alone while arm 1 is down is safe, never
 * lets arm 2 leave a bar it holds with arm 1, and its health places are
 * refused when a row takes their token. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>
#include <string.h>

#include "netc.h"
#include "status.h"
#include "equal_carry.h"

#define CARRY_PNML "tasks/carry/carry.pnml"
#define CARRY_ROWS "tasks/carry/rows.csv"
#define BUFFER_PNML "tasks/carry_buffer/carry_buffer.pnml"
#define BUFFER_ROWS "tasks/carry_buffer/rows.csv"
/* the buffer task's first net: two slots on one stand (pf = 2), which let
 * arm 1 above the stand while arm 2 lifted a bar off it */
#define SOLO_PNML "tasks/carry_solo/carry_solo.pnml"
#define SOLO_ROWS "tasks/carry_solo/rows.csv"
#define UNSAFE_PNML "test/netc/buffer_unsafe.pnml"
#define UNSAFE_ROWS "test/netc/buffer_unsafe_rows.csv"

/* Reads and checks a task; what the checker said to err goes to msg. */
static int compile(netc_task *t, const char *pnml, const char *rows, int bound, char *msg, size_t n)
{
    FILE *out = tmpfile(), *err = tmpfile();
    int rc;
    size_t got;
    assert_non_null(out);
    assert_non_null(err);
    memset(t, 0, sizeof *t);
    rc = netc_pnml_read(t, pnml, err);
    if (rc == 0)
        rc = netc_rows_read(t, rows, err);
    if (rc == 0)
        rc = netc_check(t, bound, out, err);
    rewind(err);
    got = fread(msg, 1, n - 1, err);
    msg[got] = '\0';
    fclose(out);
    fclose(err);
    return rc;
}

/* A copy of a text file with one substring replaced, in a temporary file. */
static void edit_copy(const char *from, const char *to, const char *find, const char *repl)
{
    static char text[65536];
    FILE *f = fopen(from, "r");
    size_t n;
    char *at;
    assert_non_null(f);
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    at = strstr(text, find);
    assert_non_null(at);
    f = fopen(to, "w");
    assert_non_null(f);
    fwrite(text, 1, (size_t)(at - text), f);
    fputs(repl, f);
    fputs(at + strlen(find), f);
    fclose(f);
}

static netc_task TASK;
static char MSG[16384];

static void test_carry_compiles_to_the_shipped_tables(void **st)
{
    (void)st;
    assert_int_equal(compile(&TASK, CARRY_PNML, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_OK);
    assert_string_equal(TASK.task, "carry");
    assert_carry_equal(&TASK.net, TASK.rows);
}

/* The rows as YAML: the same tables as the CSV; a broken row refused
 * with its line and the field. */
static const struct {
    const char *find, *repl, *said;
} BAD_YAML[] = {
    { "gains: FINE", "gains: [0.1, 0.3, 4]", "rows.yaml:9: gains" },
    { "    name: \"t6 arm 1 back home\"", "", "name: missing" },
    { "gains: SYNC", "gains: {a: 1}", "gains: not a value or a list of values" },
    { "rows:", "rows: [", "not YAML" },
    { "name: \"t6 arm 1 back home\"",
      "name: \"t6 arm 1 back home, the long way round: past the hand-over, "
      "behind the table, along the wall and past the camera\"",
      "name: longer than the tables hold" },
};

static void test_yaml_rows(void **st)
{
    const char *path = "build/test_netc_rows.yaml";
    size_t k;
    (void)st;
    assert_int_equal(compile(&TASK, CARRY_PNML, "test/netc/carry_rows.yaml", 1, MSG, sizeof MSG),
                     NETC_OK);
    assert_carry_equal(&TASK.net, TASK.rows);
    for (k = 0; k < sizeof BAD_YAML / sizeof BAD_YAML[0]; k++) {
        edit_copy("test/netc/carry_rows.yaml", path, BAD_YAML[k].find, BAD_YAML[k].repl);
        assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_ROWS);
        assert_non_null(strstr(MSG, BAD_YAML[k].said));
    }
    remove(path);
}

static void test_buffer_task_is_bounded_not_safe(void **st)
{
    (void)st;
    assert_int_equal(compile(&TASK, UNSAFE_PNML, UNSAFE_ROWS, 2, MSG, sizeof MSG), NETC_OK);
    assert_int_equal(TASK.n_invariants, 3);
    assert_int_equal(carry_table_validate(TASK.rows, TASK.n_transitions, &TASK.net), 0);
    /* the two buffer slots are two tokens in pf at the start */
    assert_int_equal(compile(&TASK, UNSAFE_PNML, UNSAFE_ROWS, 1, MSG, sizeof MSG),
                     NETC_ERR_UNBOUNDED);
    assert_non_null(strstr(MSG, "the net must be safe"));
}

/* The index of the place or transition named s, -1 if none. */
static int place_index(const netc_task *t, const char *s)
{
    int i;
    for (i = 0; i < t->n_places; i++)
        if (strcmp(t->place_name[i], s) == 0)
            return i;
    return -1;
}

static int trans_index(const netc_task *t, const char *s)
{
    int j;
    for (j = 0; j < t->n_transitions; j++)
        if (strcmp(t->trans_name[j], s) == 0)
            return j;
    return -1;
}

/* The invariant whose support is exactly the places in want (" a b c"),
 * all with weight 1: found once. */
static int has_invariant(const netc_task *t, const char *want)
{
    int k, i, found = 0;
    for (k = 0; k < t->n_invariants; k++) {
        char support[256] = "";
        for (i = 0; i < t->n_places; i++)
            if (t->invariants[k * t->n_places + i] == 1) {
                strcat(support, " ");
                strcat(support, t->place_name[i]);
            } else if (t->invariants[k * t->n_places + i] != 0) {
                strcat(support, " ?");
            }
        found += strcmp(support, want) == 0;
    }
    return found;
}

/* The shipped buffer: a stand with two places, A (the hand-over) and B,
 * each held by one arm at a time, so safe, and p6X + pbX + pfX + p7X +
 * p8X = 1 for each place X says no two of "arm 1 above the place or
 * setting a bar down there", "a bar on it", "arm 2 coming for it or
 * lifting it off" at once: never both arms, nor two bars, at one place.
 * Each arm is in one state at a time. */
static void test_buffer_task_is_safe(void **st)
{
    (void)st;
    assert_int_equal(compile(&TASK, BUFFER_PNML, BUFFER_ROWS, 1, MSG, sizeof MSG), NETC_OK);
    assert_int_equal(TASK.n_invariants, 4);
    assert_int_equal(carry_table_validate(TASK.rows, TASK.n_transitions, &TASK.net), 0);
    assert_int_equal(has_invariant(&TASK, " p6A pbA pfA p7A p8A"), 1);
    assert_int_equal(has_invariant(&TASK, " p6B pbB pfB p7B p8B"), 1);
    assert_int_equal(has_invariant(&TASK, " p3 p4 p5 p6A p6B"), 1);
    assert_int_equal(has_invariant(&TASK, " p2 p7A p7B p8A p8B p10 p9"), 1);
}

/* The task where arm 2 carries alone while arm 1 is down (docs/tasks.md
 * §8): safe and live with faults and recoveries at any moment (f1, r1 are
 * in the graph); pz + p6 + q1..q4 = 1 says arm 2 is never working from its
 * magazine while the arms hold a bar together (p6, t3 and t4 running,
 * which hold pz); every row of arm 1 waits for arm 1
 * up, arm 2 starts alone only with arm 1 down; f1 and r1 are the health
 * transitions and move no arm, which the plain validator refuses. */
static void test_solo_task_is_safe(void **st)
{
    taskdef_health h;
    int j, up, down;
    (void)st;
    assert_int_equal(compile(&TASK, SOLO_PNML, SOLO_ROWS, 1, MSG, sizeof MSG), NETC_OK);
    assert_int_equal(TASK.n_invariants, 4);
    assert_int_equal(has_invariant(&TASK, " arm1_up arm1_down"), 1);
    assert_int_equal(has_invariant(&TASK, " p6 pz q1 q2 q3 q4"), 1);
    assert_int_equal(has_invariant(&TASK, " p3 p4 p5 p6 p7"), 1);
    assert_int_equal(has_invariant(&TASK, " p2 p6 p8 p9 q1 q2 q3 q4"), 1);
    assert_int_equal(taskdef_health_find(&TASK, &h), TASKDEF_OK);
    up = place_index(&TASK, "arm1_up");
    down = place_index(&TASK, "arm1_down");
    assert_int_equal(h.up[0], up);
    assert_int_equal(h.down[0], down);
    assert_int_equal(h.fault[0], trans_index(&TASK, "f1"));
    assert_int_equal(h.recover[0], trans_index(&TASK, "r1"));
    assert_int_equal(h.up[1], -1);
    assert_int_equal(h.fault[1], -1);
    assert_int_equal(h.mask, 1u << h.fault[0] | 1u << h.recover[0]);
    assert_int_equal(carry_table_validate(TASK.rows, TASK.n_transitions, &TASK.net),
                     CARRY_NET_ERR_NET);
    assert_int_equal(carry_table_validate_health(TASK.rows, TASK.n_transitions, &TASK.net, h.mask),
                     0);
    for (j = 0; j < TASK.n_transitions; j++) {
        const int inhibited_down = TASK.n_inhibit[down * TASK.n_transitions + j] != 0;
        if (TASK.rows[j].arms & CARRY_ARM1)
            assert_true(inhibited_down); /* no row goes to arm 1 while it is down */
    }
    /* arm 2 goes to its magazine (s1 from home, s5 after a delivery)
     * only with arm 1 down, and back to the carry (s6) only with it up */
    assert_true(TASK.n_inhibit[up * TASK.n_transitions + trans_index(&TASK, "s1")] != 0);
    assert_true(TASK.n_inhibit[up * TASK.n_transitions + trans_index(&TASK, "s5")] != 0);
    assert_true(TASK.n_inhibit[down * TASK.n_transitions + trans_index(&TASK, "s6")] != 0);
}

/* Health places whose token a row takes, or a fault transition with another
 * arc, are refused (TASKDEF_ERR_HEALTH): only the supervisor moves it. */
static void test_solo_health_refused(void **st)
{
    const char *path = "build/test_netc_solo.pnml";
    (void)st;
    edit_copy(SOLO_PNML, path, "    </page>",
              "      <arc id=\"x1\" source=\"arm1_down\" target=\"s2\"/>\n    </page>");
    assert_int_equal(compile(&TASK, path, SOLO_ROWS, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    assert_non_null(strstr(MSG, "TASKDEF_ERR_HEALTH"));
    edit_copy(SOLO_PNML, path, "    </page>",
              "      <arc id=\"x1\" source=\"pz\" target=\"f1\"/>\n    </page>");
    assert_int_equal(compile(&TASK, path, SOLO_ROWS, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    assert_non_null(strstr(MSG, "TASKDEF_ERR_HEALTH"));
    remove(path);
}

static void test_deadlock_refused_with_counterexample(void **st)
{
    (void)st;
    assert_int_equal(
        compile(&TASK, "test/netc/carry_deadlock.pnml", CARRY_ROWS, 1, MSG, sizeof MSG),
        NETC_ERR_DEADLOCK);
    assert_non_null(strstr(MSG, "deadlock"));
    /* arm 2 delivered one workpiece and never came home: the path goes
     * through t7's completion and ends with arm 1 holding the next one */
    assert_non_null(strstr(MSG, "complete t7"));
    assert_non_null(strstr(MSG, "22. complete tv"));
    assert_non_null(
        strstr(MSG, "    1     0     0     0     1     0     0     0     0   running:\n"));
}

static void test_dead_transition_refused(void **st)
{
    const char *path = "build/test_netc_dead.pnml";
    (void)st;
    /* vision inhibited by arm 1's home place, which is marked until t1:
     * t1 needs p1, so tv and t1 never fire */
    edit_copy(CARRY_PNML, path, "<arc id=\"i1\" source=\"p1\"", "<arc id=\"i1\" source=\"p3\"");
    edit_copy(path, path, "<initialMarking><text>1</text></initialMarking>",
              "<initialMarking><text>0</text></initialMarking>");
    assert_int_equal(compile(&TASK, path, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_ERR_DEADLOCK);
    remove(path);
}

static void test_lost_transition_refused(void **st)
{
    const char *path = "build/test_netc_live.pnml";
    (void)st;
    /* t6 returns arm 1 to p4 instead of home: the net runs on (arm 1
     * re-grasps from p4 forever, vision keeps p1 full) but t1 is lost */
    edit_copy(CARRY_PNML, path, "source=\"t6\" target=\"p3\"", "source=\"t6\" target=\"p4\"");
    assert_int_equal(compile(&TASK, path, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_ERR_NOT_LIVE);
    assert_non_null(strstr(MSG, "transition t1 is not live"));
    remove(path);
}

static void test_bad_rows_refused(void **st)
{
    const char *path = "build/test_netc_rows.csv";
    (void)st;
    edit_copy(CARRY_ROWS, path, "MOVE HANDOVER_1", "MOVE HANDOVER_3");
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_ROWS);
    assert_non_null(strstr(MSG, "arm1/arm2"));
    /* gains beyond what the arms accept */
    edit_copy(CARRY_ROWS, path, "t1,yes,FREE", "t1,yes,0.5 0.5 4 100 20 0.2 5 50");
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    /* a row contradicting its transition: the vision source moves an arm */
    edit_copy(CARRY_ROWS, path, "tv,yes,FREE,0,-,-", "tv,yes,FREE,0,MOVE HOME_1,-");
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    /* arm 2 sent to a pose of arm 1's side of the cell */
    edit_copy(CARRY_ROWS, path, "-,MOVE ABOVE_RELEASE; MOVE RELEASE_POSE",
              "-,MOVE ABOVE_RELEASE; MOVE HOME_1");
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    assert_non_null(strstr(MSG, "arm 2 cannot go to HOME_1"));
    /* arm 2 sent above the stand's second place on arm 1's side of the bar */
    edit_copy(BUFFER_ROWS, path, "-,MOVE ABOVE_STAND_B_2,", "-,MOVE ABOVE_STAND_B_1,");
    assert_int_equal(compile(&TASK, BUFFER_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_TABLE);
    assert_non_null(strstr(MSG, "arm 2 cannot go to ABOVE_STAND_B_1"));
    /* a transition without its row */
    edit_copy(CARRY_ROWS, path, "t5,yes", "t6,yes");
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_ROWS);
    /* a line longer than the reader's buffer: refused, not read as two */
    {
        static char longer[700];
        memset(longer, 'x', sizeof longer - 1);
        /* NOLINTNEXTLINE(bugprone-not-null-terminated-result): overwrites the start of a string terminated above */
        memcpy(longer, "vision locates a workpiece ", 27);
        edit_copy(CARRY_ROWS, path, "vision locates a workpiece", longer);
    }
    assert_int_equal(compile(&TASK, CARRY_PNML, path, 1, MSG, sizeof MSG), NETC_ERR_ROWS);
    assert_non_null(strstr(MSG, "longer than 510 characters"));
    remove(path);
}

static void test_bad_pnml_refused(void **st)
{
    const char *path = "build/test_netc_bad.pnml";
    (void)st;
    assert_int_equal(compile(&TASK, "build/no-such.pnml", CARRY_ROWS, 1, MSG, sizeof MSG),
                     NETC_ERR_IO);
    edit_copy(CARRY_PNML, path, "<inscription><text>1</text></inscription>",
              "<inscription><text>2</text></inscription>");
    assert_int_equal(compile(&TASK, path, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_ERR_CAPACITY);
    assert_non_null(strstr(MSG, "weight 2"));
    edit_copy(CARRY_PNML, path, "source=\"t1\" target=\"p4\"", "source=\"t1\" target=\"t2\"");
    assert_int_equal(compile(&TASK, path, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_ERR_PNML);
    edit_copy(CARRY_PNML, path, "  <type value=\"inhibitor\"/>", "  <type value=\"reset\"/>");
    assert_int_equal(compile(&TASK, path, CARRY_ROWS, 1, MSG, sizeof MSG), NETC_ERR_PNML);
    remove(path);
}

static void test_strerror_distinct(void **st)
{
    int a, b;
    (void)st;
    for (a = NETC_ERR_ROLES; a <= NETC_OK; a++)
        for (b = a + 1; b <= NETC_OK; b++)
            assert_string_not_equal(netc_strerror(a), netc_strerror(b));
    assert_string_equal(netc_strerror(NETC_ERR_ROLES - 1), STATUS_UNKNOWN_TEXT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_carry_compiles_to_the_shipped_tables),
        cmocka_unit_test(test_yaml_rows),
        cmocka_unit_test(test_buffer_task_is_bounded_not_safe),
        cmocka_unit_test(test_buffer_task_is_safe),
        cmocka_unit_test(test_solo_task_is_safe),
        cmocka_unit_test(test_solo_health_refused),
        cmocka_unit_test(test_deadlock_refused_with_counterexample),
        cmocka_unit_test(test_dead_transition_refused),
        cmocka_unit_test(test_lost_transition_refused),
        cmocka_unit_test(test_bad_rows_refused),
        cmocka_unit_test(test_bad_pnml_refused),
        cmocka_unit_test(test_strerror_distinct),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
