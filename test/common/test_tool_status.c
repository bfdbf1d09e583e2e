/* The status texts of tandem-sim and tandem-scenario: every code of every
 * module has its own text, an unknown value STATUS_UNKNOWN_TEXT
 * (test/unit/status_check.h), walked over the code lists of
 * sim/sim_status.h and tools/scenario/scen_status.h. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "sim_status.h"
#include "scen_status.h"
#include "../unit/status_check.h"

static void test_sim_modules(void **st)
{
    (void)st;
    STATUS_CHECK(sim_strerror, SIM_CODES);
    STATUS_CHECK(sim_rovers_strerror, SIM_ROVERS_CODES);
}

static void test_scenario_modules(void **st)
{
    (void)st;
    STATUS_CHECK(scenario_strerror, SCENARIO_CODES);
    STATUS_CHECK(carry_scen_strerror, CARRY_SCEN_CODES);
    STATUS_CHECK(fm_strerror, FM_CODES);
    STATUS_CHECK(hang_watch_strerror, HANG_WATCH_CODES);
    STATUS_CHECK(run_key_strerror, RUN_KEY_CODES);
    STATUS_CHECK(sweep_strerror, SWEEP_CODES);
    STATUS_CHECK(tdsd_ode_strerror, TDSD_ODE_CODES);
    STATUS_CHECK(tdsd_scen_strerror, TDSD_SCEN_CODES);
    STATUS_CHECK(tdsd_setup_strerror, TDSD_SETUP_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_sim_modules),
        cmocka_unit_test(test_scenario_modules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
