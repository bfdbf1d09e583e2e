/* Tests of netc_task_load, the loader behind tandem-supervisor --task
 * (docs/tasks.md §7): a task directory read into the fixed tables and
 * checked. The shipped carry loads to the shipped tables with bound 1 and
 * the carry's roles; the buffer task with bound 1 from its P-invariants;
 * and each broken directory is refused for its own reason, the message
 * naming the file, the limit, or the place or transition. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

#include "netc.h"
#include "equal_carry.h"

#define TMP "build/test_task_load"

static netc_task TASK;
static char MSG[16384];

/* Loads dir with the bound from the invariants; err into MSG. */
static int load(const char *dir, int *bound)
{
    FILE *out = tmpfile(), *err = tmpfile();
    int rc;
    size_t got;
    assert_non_null(out);
    assert_non_null(err);
    rc = netc_task_load(&TASK, dir, NETC_BOUND_FROM_INVARIANTS, bound, out, err);
    rewind(err);
    got = fread(MSG, 1, sizeof MSG - 1, err);
    MSG[got] = '\0';
    fclose(out);
    fclose(err);
    return rc;
}

static void slurp(const char *path, char *text, size_t cap)
{
    FILE *f = fopen(path, "r");
    size_t n;
    assert_non_null(f);
    n = fread(text, 1, cap - 1, f);
    text[n] = '\0';
    fclose(f);
}

static void spit(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static int copy_file(const char *from, const char *to)
{
    static char text[65536];
    slurp(from, text, sizeof text);
    spit(to, text);
    return 0;
}

/* TMP/name/ holding the carry's rows and the net `pnml` with `find`
 * replaced by `repl` (find NULL: unchanged); returns the directory. */
static const char *task_dir(const char *pnml, const char *name, const char *find, const char *repl)
{
    static char dir[256];
    static char text[65536], edited[70000];
    char path[512];
    snprintf(dir, sizeof dir, "%s/%s", TMP, name);
    mkdir("build", 0755);
    mkdir(TMP, 0755);
    mkdir(dir, 0755);
    slurp(pnml, text, sizeof text);
    if (find) {
        char *at = strstr(text, find);
        assert_non_null(at);
        snprintf(edited, sizeof edited, "%.*s%s%s", (int)(at - text), text, repl,
                 at + strlen(find));
    } else {
        snprintf(edited, sizeof edited, "%s", text);
    }
    snprintf(path, sizeof path, "%s/task.pnml", dir);
    spit(path, edited);
    slurp("tasks/carry/rows.csv", text, sizeof text);
    snprintf(path, sizeof path, "%s/rows.csv", dir);
    spit(path, text);
    return dir;
}

static const char *carry_variant(const char *name, const char *find, const char *repl)
{
    return task_dir("tasks/carry/carry.pnml", name, find, repl);
}

static void test_carry_loads_to_the_shipped_tables(void **st)
{
    taskdef_roles r;
    int bound = 0;
    (void)st;
    assert_int_equal(load("tasks/carry", &bound), NETC_OK);
    assert_int_equal(bound, 1);
    assert_carry_equal(&TASK.net, TASK.rows);
    assert_int_equal(taskdef_validate(&TASK.net, TASK.rows, &r), TASKDEF_OK);
    assert_int_equal(r.source, CARRY_T_VISION);
    assert_int_equal(r.source_place, CARRY_P1);
    assert_int_equal(r.pick, CARRY_T1);
}

static void test_buffer_loads_safe(void **st)
{
    taskdef_roles r;
    int bound = 0;
    (void)st;
    assert_int_equal(load("tasks/carry_buffer", &bound), NETC_OK);
    assert_int_equal(bound,
                     1); /* p6X + pbX + pfX + p7X + p8X = 1: each stand place, one arm at a time */
    assert_int_equal(TASK.n_invariants, 4);
    assert_int_equal(taskdef_validate(&TASK.net, TASK.rows, &r), TASKDEF_OK);
    assert_string_equal(TASK.trans_name[r.source], "tv");
    assert_string_equal(TASK.place_name[r.source_place], "p1");
    assert_string_equal(TASK.trans_name[r.pick], "t1");
}

static void test_files_refused(void **st)
{
    char path[512];
    (void)st;
    assert_int_equal(load(TMP "/no-such-task", NULL), NETC_ERR_IO);
    assert_non_null(strstr(MSG, "not a readable directory"));
    /* no net */
    assert_int_equal(load("test/unit", NULL), NETC_ERR_IO);
    assert_non_null(strstr(MSG, "no PNML file"));
    /* two nets: which is the task would be a guess */
    snprintf(path, sizeof path, "%s/other.pnml", carry_variant("two", NULL, NULL));
    spit(path, "<pnml/>\n");
    assert_int_equal(load(TMP "/two", NULL), NETC_ERR_IO);
    assert_non_null(strstr(MSG, "more than one"));
    /* no rows */
    snprintf(path, sizeof path, "%s/rows.csv", carry_variant("norows", NULL, NULL));
    remove(path);
    assert_int_equal(load(TMP "/norows", NULL), NETC_ERR_IO);
    assert_non_null(strstr(MSG, "rows.csv: cannot read"));
    /* rows as YAML instead of CSV; both: which holds the task would be a guess */
    snprintf(path, sizeof path, "%s/rows.csv", carry_variant("yaml", NULL, NULL));
    assert_int_equal(copy_file("test/netc/carry_rows.yaml", TMP "/yaml/rows.yaml"), 0);
    assert_int_equal(load(TMP "/yaml", NULL), NETC_ERR_IO);
    assert_non_null(strstr(MSG, "both rows.csv and rows.yaml"));
    remove(path);
    assert_int_equal(load(TMP "/yaml", NULL), NETC_OK);
    assert_carry_equal(&TASK.net, TASK.rows);
    /* bad arguments */
    assert_int_equal(netc_task_load(&TASK, NULL, 0, NULL, stdout, stderr), NETC_ERR_CAPACITY);
    assert_int_equal(netc_task_load(&TASK, "tasks/carry", PETRI_TOKEN_MAX, NULL, stdout, stderr),
                     NETC_ERR_CAPACITY);
}

/* One place more than the supervisor's tables hold: refused naming the
 * limit, not truncated. */
static void test_capacity_refused(void **st)
{
    static char places[PETRI_MAX_PLACES * 80 + 64];
    size_t n = 0;
    int i;
    (void)st;
    for (i = 0; i < PETRI_MAX_PLACES; i++)
        n += (size_t)snprintf(places + n, sizeof places - n, "<place id=\"x%d\"/>\n", i);
    assert_int_equal(load(carry_variant("big", "</page>", strcat(places, "</page>")), NULL),
                     NETC_ERR_CAPACITY);
    assert_non_null(strstr(MSG, "PETRI_MAX_PLACES"));
    assert_non_null(strstr(MSG, "task.pnml"));
    /* a name longer than the tables hold: refused, not cut */
    assert_int_equal(
        load(
            carry_variant(
                "longname", "<text>p5</text>",
                "<text>p5 arm 1 holds the workpiece it took from the pick zone, on its way</text>"),
            NULL),
        NETC_ERR_CAPACITY);
    assert_non_null(strstr(MSG, "the name of p5 longer than 63 characters (TASKDEF_MAX_NAME)"));
}

/* A second transition taking the workpiece token (t2 from p1 too): the
 * net runs, but the supervisor could not tell which one binds the
 * detected pose. */
static void test_roles_refused(void **st)
{
    (void)st;
    assert_int_equal(load(carry_variant("twopicks", "</page>",
                                        "<arc id=\"x\" source=\"p1\" target=\"t2\"/>\n</page>"),
                          NULL),
                     NETC_ERR_ROLES);
    assert_non_null(strstr(MSG, "source transition tv"));
    assert_non_null(strstr(MSG, "TASKDEF_ERR_PICK"));
}

/* The checks of tandem-netc refuse as they do there, with the
 * counterexample: the carry without the arc t7 -> p2 (arm 2 never comes
 * home) deadlocks. */
static void test_deadlock_refused(void **st)
{
    (void)st;
    assert_int_equal(load(task_dir("test/netc/carry_deadlock.pnml", "dead", NULL, NULL), NULL),
                     NETC_ERR_DEADLOCK);
    assert_non_null(strstr(MSG, "firing sequence from the initial marking"));
    assert_non_null(strstr(MSG, "22. complete tv"));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_carry_loads_to_the_shipped_tables),
        cmocka_unit_test(test_buffer_loads_safe),
        cmocka_unit_test(test_files_refused),
        cmocka_unit_test(test_capacity_refused),
        cmocka_unit_test(test_roles_refused),
        cmocka_unit_test(test_deadlock_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
