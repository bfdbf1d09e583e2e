/* The C tandem-netc writes for the shipped carry (build/gen/tasks, made by
 * test/netc/module.mk) compiles, passes its validator, and its tables are
 * the shipped carry_net and carry_table field by field (docs/tasks.md §5). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "carry_task.h"
#include "equal_carry.h"

static void test_generated_equals_shipped(void **st)
{
    (void)st;
    assert_int_equal(carry_task_validate(), 0);
    assert_int_equal(carry_TASK_N_TRANSITIONS, CARRY_N_TRANSITIONS);
    assert_carry_equal(&carry_task_net, carry_task_table);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_generated_equals_shipped),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
