/* tdsd_status: every code of the tdsd modules has its own text, an
 * unknown value the stated fallback (test/unit/status_check.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "tdsd_status.h"
#include "status_check.h"

static void test_every_code_has_its_text(void **st)
{
    (void)st;
    STATUS_CHECK(tdsd_strerror, TDSD_CODES);
    STATUS_CHECK(tdsd_seg_strerror, TDSD_SEG_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_code_has_its_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
