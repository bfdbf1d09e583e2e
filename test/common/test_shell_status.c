/* The daemon shell's status texts: every code of every module has its own
 * text, an unknown value the module's stated fallback
 * (test/unit/status_check.h), walked over the module's code list
 * (shell_status.h). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <cmocka.h>

#include "shell_status.h"
#include "auth.h"
#include "auth_bus.h"
#include "auth_child.h"
#include "journal.h"
#include "world_file.h"
#include "../unit/status_check.h"

#define N(a) (sizeof(a) / sizeof((a)[0]))

static void test_listed_modules(void **st)
{
    (void)st;
    STATUS_CHECK(auth_strerror, AUTH_CODES);
    STATUS_CHECK(auth_acl_strerror, AUTH_ACL_CODES);
    STATUS_CHECK(auth_child_strerror, AUTH_CHILD_CODES);
    STATUS_CHECK(daemon_strerror, DAEMON_CODES);
    STATUS_CHECK(guard_strerror, GUARD_CODES);
    STATUS_CHECK(journal_strerror, JOURNAL_CODES);
    STATUS_CHECK(msg_strerror, MSG_CODES);
    STATUS_CHECK(netc_strerror, NETC_CODES);
    STATUS_CHECK(options_strerror, OPTIONS_CODES);
    STATUS_CHECK(proc_strerror, PROC_CODES);
    STATUS_CHECK(renew_strerror, RENEW_CODES);
    STATUS_CHECK(wire_strerror, WIRE_CODES);
    STATUS_CHECK(world_file_strerror, WORLD_FILE_CODES);
    STATUS_CHECK(worldgen_strerror, WORLDGEN_CODES);
}

/* auth_bus passes what is not its own to auth_strerror */
static void test_auth_bus(void **st)
{
    static const int bus[] = { AUTH_BUS_CODES(STATUS_CODE) };
    (void)st;
    status_check(auth_bus_strerror, bus, N(bus), auth_strerror(-1000));
    assert_string_equal(auth_bus_strerror(AUTH_ERR_REPLAY), auth_strerror(AUTH_ERR_REPLAY));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_listed_modules),
        cmocka_unit_test(test_auth_bus),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
