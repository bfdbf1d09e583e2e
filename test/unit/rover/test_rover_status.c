/* rover_status: every code of the rover modules has its own text, an
 * unknown value the stated fallback (test/unit/status_check.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "rover_status.h"
#include "status_check.h"

static void test_every_code_has_its_text(void **st)
{
    (void)st;
    STATUS_CHECK(unicycle_strerror, UNICYCLE_CODES);
    STATUS_CHECK(odometry_strerror, ODOMETRY_CODES);
    STATUS_CHECK(localize_strerror, LOCALIZE_CODES);
    STATUS_CHECK(sonar_strerror, SONAR_CODES);
    STATUS_CHECK(behaviour_strerror, BEHAVIOUR_CODES);
    STATUS_CHECK(formation_strerror, FORMATION_CODES);
    STATUS_CHECK(team_strerror, TEAM_CODES);
    STATUS_CHECK(rover_world_strerror, ROVER_WORLD_CODES);
    STATUS_CHECK(rover_ctl_strerror, ROVER_CTL_CODES);
    STATUS_CHECK(rover_map_strerror, ROVER_MAP_CODES);
    STATUS_CHECK(navfield_strerror, NAVFIELD_CODES);
    STATUS_CHECK(goal_place_strerror, GOAL_PLACE_CODES);
    STATUS_CHECK(slot_assign_strerror, SLOT_ASSIGN_CODES);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_code_has_its_text),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
