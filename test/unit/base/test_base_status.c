/* base_status: every code of the base modules has its own text, an
 * unknown value the stated fallback (test/unit/status_check.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "base_status.h"
#include "status_check.h"

static void test_linalg(void **st)
{
    (void)st;
    STATUS_CHECK(linalg_strerror, LINALG_CODES);
}

static void test_loop_and_profile(void **st)
{
    (void)st;
    STATUS_CHECK(loopstats_strerror, LOOPSTATS_CODES);
    STATUS_CHECK(pgrid_strerror, PGRID_CODES);
    STATUS_CHECK(rtloop_strerror, RTLOOP_CODES);
    STATUS_CHECK(sprofile_strerror, SPROFILE_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_linalg),
        cmocka_unit_test(test_loop_and_profile),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
