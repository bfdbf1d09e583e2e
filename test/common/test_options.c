/* Unit tests of the option table (src/daemons/common/options.c): every type
 * lands in its destination with its range and choices enforced, a
 * repeatable option sees every occurrence, unknown options, missing values
 * and missing required options are refused (exit status 2), and the
 * generated help names every option of every group. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "daemon.h"
#include "options.h"

typedef struct test_opts {
    int flag;
    int count_i;
    long count_l;
    int64_t count_64;
    double gain;
    double period_s;
    double xyz[3];
    int have_xyz;
    const char *path;
    int mode;
    int side;
    const char *tags[3];
    int n_tags;
    int calls;
    char last_call[16];
    const char *out;
    int out_given;
} test_opts;

static const char *const modes[] = { "slow", "fast", "off", NULL };
static const char *const sides[] = { "left", "right", NULL };
static const int side_values[] = { -1, 1 };

/* Accepts words of at most 15 characters that do not start with 'x'. */
static int record_call(const char *prog, void *dest, char *value)
{
    test_opts *o = dest;
    (void)prog;
    if (value[0] == 'x' || strlen(value) >= sizeof o->last_call)
        return OPTIONS_ERR_VALUE;
    o->calls++;
    snprintf(o->last_call, sizeof o->last_call, "%s", value);
    return 0;
}

static const option_entry table[] = {
    { .name = "flag",
      .letter = 'f',
      .type = OPTION_FLAG,
      OPTION_AT(test_opts, flag),
      .help = "a flag" },
    { .name = "count",
      .type = OPTION_INT,
      OPTION_AT(test_opts, count_i),
      .min = -5,
      .max = 10,
      .meta = "N",
      .help = "an int",
      .def = "0" },
    { .name = "count-long",
      .type = OPTION_INT,
      OPTION_AT(test_opts, count_l),
      .min = 0,
      .max = 2147483647.0,
      .meta = "N",
      .help = "a long" },
    { .name = "count-64",
      .type = OPTION_INT,
      OPTION_AT(test_opts, count_64),
      .min = 0,
      .max = 1e15,
      .meta = "N",
      .help = "an int64_t" },
    { .name = "gain",
      .type = OPTION_DOUBLE,
      OPTION_AT(test_opts, gain),
      .min = 0.5,
      .max = 2.0,
      .meta = "G",
      .help = "a double" },
    { .name = "interval-ms",
      .type = OPTION_DOUBLE,
      OPTION_AT(test_opts, period_s),
      .min = 1.0,
      .max = 100.0,
      .scale = 1e-3,
      .meta = "MS",
      .help = "a scaled double" },
    { .name = "xyz",
      .type = OPTION_DOUBLE,
      OPTION_AT(test_opts, xyz),
      .nargs = 3,
      .min = -1.0,
      .max = 1.0,
      OPTION_SEEN(test_opts, have_xyz),
      .meta = "X Y Z",
      .help = "three words" },
    { .name = "path",
      .type = OPTION_STRING,
      OPTION_AT(test_opts, path),
      .min = 1,
      .max = 8,
      .meta = "P",
      .help = "a string" },
    { .name = "mode",
      .type = OPTION_CHOICE,
      OPTION_AT(test_opts, mode),
      .choices = modes,
      .help = "a choice" },
    { .name = "side",
      .type = OPTION_CHOICE,
      OPTION_AT(test_opts, side),
      .choices = sides,
      .values = side_values,
      .meta = "S",
      .help = "a mapped choice" },
    { .name = "tag",
      .type = OPTION_LIST,
      OPTION_AT(test_opts, tags),
      .max = 3,
      .count = offsetof(test_opts, n_tags),
      .meta = "T",
      .help = "a list" },
    { .name = "call",
      .type = OPTION_CALL,
      OPTION_ALL(test_opts),
      .call = record_call,
      .repeatable = 1,
      .meta = "WORD",
      .help = "a handler" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(test_opts, out),
      OPTION_SEEN(test_opts, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "required" },
    { .name = "help", .letter = 'h', .type = OPTION_HELP, .help = "this text" },
    { .name = NULL }
};

static test_opts O;

static option_program program(void)
{
    option_program p;
    memset(&p, 0, sizeof p);
    p.name = "test-options";
    p.usage = "usage: test-options [options]\n";
    p.epilog = "Exit status: 2 on bad options.\n";
    p.groups[0].table = table;
    p.groups[0].base = &O;
    p.n_groups = 1;
    return p;
}

/* Parses the NULL-terminated words after a program name. */
static int parse_words(const option_program *p, char **words)
{
    static char prog[] = "test-options";
    char *argv[32];
    int argc = 1;
    argv[0] = prog;
    while (*words)
        argv[argc++] = *words++;
    argv[argc] = NULL;
    memset(&O, 0, sizeof O);
    return options_parse(p, argc, argv, 1);
}

#define PARSE(...) parse_words(&p, (char *[]){ __VA_ARGS__, NULL })

static void test_table_valid(void **state)
{
    (void)state;
    assert_int_equal(options_table_validate(table), 0);
    assert_int_equal(options_table_validate(options_daemon_common), 0);
    assert_int_equal(options_table_validate(options_bus_tool), 0);
}

static void test_validate_refuses_bad_tables(void **state)
{
    const option_entry twice[] = { { .name = "a", .type = OPTION_FLAG, OPTION_AT(test_opts, flag) },
                                   { .name = "a", .type = OPTION_FLAG, OPTION_AT(test_opts, flag) },
                                   { .name = NULL } };
    const option_entry wrong_size[] = {
        { .name = "g", .type = OPTION_DOUBLE, OPTION_AT(test_opts, count_i), .min = 0, .max = 1 },
        { .name = NULL }
    };
    const option_entry bad_range[] = {
        { .name = "n", .type = OPTION_INT, OPTION_AT(test_opts, count_i), .min = 2, .max = 1 },
        { .name = NULL }
    };
    const option_entry required_unseen[] = {
        { .name = "o", .type = OPTION_STRING, OPTION_AT(test_opts, out), .required = 1 },
        { .name = NULL }
    };
    (void)state;
    assert_int_equal(options_table_validate(twice), OPTIONS_ERR_TABLE);
    assert_int_equal(options_table_validate(wrong_size), OPTIONS_ERR_TABLE);
    assert_int_equal(options_table_validate(bad_range), OPTIONS_ERR_TABLE);
    assert_int_equal(options_table_validate(required_unseen), OPTIONS_ERR_TABLE);
}

static void test_types_land_in_their_fields(void **state)
{
    const option_program p = program();
    char big[] = "123456789012";
    (void)state;
    assert_int_equal(PARSE("--flag", "--count", "-5", "--count-long=2147483647", "--count-64", big,
                           "--gain", "2", "--interval-ms", "20", "--xyz", "-1", "0.5", "1",
                           "--path", "a/b", "--mode", "off", "--side", "left", "--out", "d"),
                     23);
    assert_int_equal(O.flag, 1);
    assert_int_equal(O.count_i, -5);
    assert_int_equal(O.count_l, 2147483647L);
    assert_true(O.count_64 == INT64_C(123456789012));
    assert_true(O.gain == 2.0);
    assert_true(O.period_s == 20.0 * 1e-3); /* the same product the programs computed */
    assert_true(O.xyz[0] == -1.0 && O.xyz[1] == 0.5 && O.xyz[2] == 1.0);
    assert_int_equal(O.have_xyz, 1);
    assert_string_equal(O.path, "a/b");
    assert_int_equal(O.mode, 2);
    assert_int_equal(O.side, -1);
    assert_string_equal(O.out, "d");
}

static void test_short_letter_prefix_and_last_wins(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(
        PARSE("-f", "--gai", "1", "--count", "3", "--count", "4", "--pa", "x", "--out", "d"), 12);
    assert_true(O.gain == 1.0);
    assert_int_equal(O.flag, 1);
    assert_int_equal(O.count_i, 4);
    assert_string_equal(O.path, "x");
    /* "--count" is exact although "--count-long" starts with it; "--cou" is ambiguous */
    assert_int_equal(PARSE("--cou", "1", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(options_exit_status(OPTIONS_ERR_ARG), OPTIONS_EXIT_BAD_ARGS);
}

static void test_ranges_enforced(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(PARSE("--count", "11", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--count", "-6", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--count", "10", "--out", "d"), 5);
    assert_int_equal(PARSE("--count", "1.5", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--count", "", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--count-long", "99999999999999999999", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--gain", "0.49", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--gain", "nan", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--gain", "inf", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--gain", "1x", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--xyz", "0", "2", "0", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--path", "", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--path", "123456789", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--path", "12345678", "--out", "d"), 5);
}

static void test_choices_enforced(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(PARSE("--mode", "medium", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--mode", "fas", "--out", "d"), OPTIONS_ERR_ARG); /* words are exact */
    assert_int_equal(PARSE("--side", "right", "--out", "d"), 5);
    assert_int_equal(O.side, 1);
}

static void test_repeatable(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(
        PARSE("--tag", "a", "--call", "one", "--tag", "b", "--call", "two", "--out", "d"), 11);
    assert_int_equal(O.n_tags, 2);
    assert_string_equal(O.tags[0], "a");
    assert_string_equal(O.tags[1], "b");
    assert_int_equal(O.calls, 2);
    assert_string_equal(O.last_call, "two");
    assert_int_equal(PARSE("--tag", "a", "--tag", "b", "--tag", "c", "--tag", "d", "--out", "d"),
                     OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--call", "xyz", "--out", "d"), OPTIONS_ERR_ARG);
}

static void test_unknown_missing_and_extra_refused(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(PARSE("--nope", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("-x", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--out", "d", "--count"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--out", "d", "--xyz", "1", "2"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--out", "d", "stray"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--flag=1", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--count", "1"), OPTIONS_ERR_ARG); /* --out is required */
}

static void test_values_may_start_with_a_dash(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(PARSE("--path", "-f", "--out", "--flag"), 5);
    assert_string_equal(O.path, "-f");
    assert_string_equal(O.out, "--flag");
    assert_int_equal(O.flag, 0);
}

static void test_stop_at_argument_and_double_dash(void **state)
{
    option_program p = program();
    (void)state;
    p.args = OPTIONS_ARGS_STOP;
    assert_int_equal(PARSE("--out", "d", "fk", "-1", "--flag"), 3);
    assert_int_equal(O.flag, 0);
    p.args = OPTIONS_ARGS_NONE;
    assert_int_equal(PARSE("--out", "d", "--", "--flag"), OPTIONS_ERR_ARG);
    p.args = OPTIONS_ARGS_STOP;
    assert_int_equal(PARSE("--out", "d", "--", "--flag"), 4);
}

static int collected_n;
static const char *collected[8];

static int collect(void *user, const char *word)
{
    (void)user;
    collected[collected_n++] = word;
    return 0;
}

static void test_unknown_words_passed_on(void **state)
{
    option_program p = program();
    (void)state;
    p.other = collect;
    collected_n = 0;
    assert_int_equal(PARSE("--method", "pinv", "--out", "d", "--cou", "2", "--", "x"), 9);
    assert_string_equal(O.out, "d");
    /* exact names only: "--cou" is the receiver's, not a prefix of --count */
    assert_int_equal(collected_n, 6);
    assert_string_equal(collected[0], "--method");
    assert_string_equal(collected[1], "pinv");
    assert_string_equal(collected[2], "--cou");
    assert_string_equal(collected[5], "x");
}

static void test_help_lists_every_option(void **state)
{
    const option_program p = program();
    const option_entry *e;
    char text[8192], want[64];
    FILE *f = tmpfile();
    size_t n;
    (void)state;
    assert_non_null(f);
    options_print_help(&p, f);
    rewind(f);
    n = fread(text, 1, sizeof text - 1, f);
    text[n] = '\0';
    fclose(f);
    assert_non_null(strstr(text, "usage: test-options"));
    assert_non_null(strstr(text, "Exit status: 2"));
    for (e = table; e->name; e++) {
        snprintf(want, sizeof want, "--%s ", e->name);
        if (!strstr(text, want)) {
            snprintf(want, sizeof want, "--%s\n", e->name);
            assert_non_null(strstr(text, want));
        }
    }
    assert_non_null(strstr(text, "-h, --help"));
    assert_non_null(strstr(text, "-5..10"));        /* range */
    assert_non_null(strstr(text, "default 0"));     /* default */
    assert_non_null(strstr(text, "slow|fast|off")); /* choices */
    assert_non_null(strstr(text, "left | right"));
    assert_non_null(strstr(text, "repeatable"));
    assert_non_null(strstr(text, "(required)"));
    assert_non_null(strstr(text, "1..8 characters"));
}

static void test_help_and_version_exit_zero(void **state)
{
    const option_program p = program();
    (void)state;
    assert_int_equal(PARSE("--help"), OPTIONS_EXIT);
    assert_int_equal(options_exit_status(OPTIONS_EXIT), 0);
}

static void test_daemon_common_group(void **state)
{
    static daemon d;
    option_program p = program();
    (void)state;
    daemon_defaults(&d, "test-options", 0.001);
    p.groups[1].table = options_daemon_common;
    p.groups[1].base = &d;
    p.n_groups = 2;
    assert_int_equal(PARSE("--lockstep", "--period-ms", "50", "--rt", "10", "--lcm-url", "udpm://x",
                           "--out", "d"),
                     10);
    assert_int_equal(d.lockstep, 1);
    assert_true(d.period_s == 50 * 1e-3);
    assert_int_equal(d.rt_prio, 10);
    assert_string_equal(d.lcm_url, "udpm://x");
    assert_int_equal(PARSE("--rt", "100", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--lcm-url", "", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--drop-rate", "0.95", "--out", "d"), OPTIONS_ERR_ARG);
    assert_int_equal(PARSE("--drop-seed", "-1", "--out", "d"), OPTIONS_ERR_ARG);
    assert_true(d.drop_rate == 0.0);
    assert_int_equal(d.drop_seed, 1); /* daemon_defaults */
    assert_int_equal(PARSE("--drop-rate", "0.25", "--drop-seed", "7", "--out", "d"), 7);
    assert_true(d.drop_rate == 0.25);
    assert_int_equal(d.drop_seed, 7);
    assert_int_equal(PARSE("--version"), OPTIONS_EXIT);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_valid),
        cmocka_unit_test(test_validate_refuses_bad_tables),
        cmocka_unit_test(test_types_land_in_their_fields),
        cmocka_unit_test(test_short_letter_prefix_and_last_wins),
        cmocka_unit_test(test_ranges_enforced),
        cmocka_unit_test(test_choices_enforced),
        cmocka_unit_test(test_repeatable),
        cmocka_unit_test(test_unknown_missing_and_extra_refused),
        cmocka_unit_test(test_values_may_start_with_a_dash),
        cmocka_unit_test(test_stop_at_argument_and_double_dash),
        cmocka_unit_test(test_unknown_words_passed_on),
        cmocka_unit_test(test_help_lists_every_option),
        cmocka_unit_test(test_help_and_version_exit_zero),
        cmocka_unit_test(test_daemon_common_group),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
