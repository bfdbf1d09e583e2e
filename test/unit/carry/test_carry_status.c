/* carry_status: every code of the carry modules has its own text, an
 * unknown value the stated fallback (test/unit/status_check.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "carry_status.h"
#include "status_check.h"

static void test_every_code_has_its_text(void **st)
{
    (void)st;
    STATUS_CHECK(petri_strerror, PETRI_CODES);
    STATUS_CHECK(carry_net_strerror, CARRY_NET_CODES);
    STATUS_CHECK(erlaw_strerror, ERLAW_CODES);
    STATUS_CHECK(cartseg_strerror, CARTSEG_CODES);
    STATUS_CHECK(sync_ref_strerror, SYNC_REF_CODES);
    STATUS_CHECK(stallwatch_strerror, STALLWATCH_CODES);
    STATUS_CHECK(cell_strerror, CELL_CODES);
    STATUS_CHECK(taskdef_strerror, TASKDEF_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_code_has_its_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
