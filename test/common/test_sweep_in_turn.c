/* Unit tests for sweep_in_turn (tandem-scenario sweep's lists in turn):
 * with --robots 3,4,6,8 and --formation line,triangle,column, twelve runs
 * in a row give every (size, formation) pair exactly once, in both the
 * "--opt list" and "--opt=list" spellings; a single value and an option
 * that is not a list pass through as they are. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>

#include "sweep_worlds.h"

static const char *const SIZES[] = { "3", "4", "6", "8" };
static const char *const SHAPES[] = { "line", "triangle", "column" };

/* index of s in list[n], -1 if absent */
static int index_of(const char *const *list, int n, const char *s)
{
    int i;
    for (i = 0; i < n; i++)
        if (!strcmp(list[i], s))
            return i;
    return -1;
}

static void every_pair_once_in_twelve(const char *const *pass, int k_size, int k_shape,
                                      const char *prefix_size, const char *prefix_shape)
{
    int seen[4][3], run, a, b;
    memset(seen, 0, sizeof seen);
    for (run = 0; run < 12; run++) {
        char s1[64], s2[64];
        const char *size = sweep_in_turn(pass, k_size, run, s1, sizeof s1);
        const char *shape = sweep_in_turn(pass, k_shape, run, s2, sizeof s2);
        assert_int_equal(strncmp(size, prefix_size, strlen(prefix_size)), 0);
        assert_int_equal(strncmp(shape, prefix_shape, strlen(prefix_shape)), 0);
        a = index_of(SIZES, 4, size + strlen(prefix_size));
        b = index_of(SHAPES, 3, shape + strlen(prefix_shape));
        assert_true(a >= 0 && b >= 0);
        /* run i takes item i mod n */
        assert_int_equal(a, run % 4);
        assert_int_equal(b, run % 3);
        seen[a][b]++;
    }
    for (a = 0; a < 4; a++)
        for (b = 0; b < 3; b++)
            assert_int_equal(seen[a][b], 1);
}

static void test_lists_as_separate_words(void **state)
{
    const char *const pass[] = { "--world", "random",      "--robots",
                                 "3,4,6,8", "--formation", "line,triangle,column" };
    (void)state;
    every_pair_once_in_twelve(pass, 3, 5, "", "");
}

static void test_lists_after_equals(void **state)
{
    const char *const pass[] = { "--robots=3,4,6,8", "--formation=line,triangle,column" };
    (void)state;
    every_pair_once_in_twelve(pass, 0, 1, "--robots=", "--formation=");
}

static void test_other_words_pass_through(void **state)
{
    const char *const pass[] = { "--robots", "5", "--keys", "a,b", "--world-kind", "traps" };
    char buf[64];
    int k;
    (void)state;
    for (k = 0; k < 6; k++)
        assert_ptr_equal(sweep_in_turn(pass, k, 7, buf, sizeof buf), pass[k]);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lists_as_separate_words),
        cmocka_unit_test(test_lists_after_equals),
        cmocka_unit_test(test_other_words_pass_through),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
