/* arm_status: every code of the arm modules has its own text, an
 * unknown value the stated fallback (test/unit/status_check.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "arm_status.h"
#include "status_check.h"

static void test_every_code_has_its_text(void **st)
{
    (void)st;
    STATUS_CHECK(arm_model_strerror, ARM_MODEL_CODES);
    STATUS_CHECK(arm_kin_strerror, ARM_KIN_CODES);
    STATUS_CHECK(arm_dyn_strerror, ARM_DYN_CODES);
    STATUS_CHECK(jointctl_strerror, JOINTCTL_CODES);
    STATUS_CHECK(jtraj_strerror, JTRAJ_CODES);
    STATUS_CHECK(cartctl_strerror, CARTCTL_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_code_has_its_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
