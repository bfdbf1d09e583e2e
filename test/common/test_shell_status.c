/* The daemon shell's status texts: every code of every module has its own
 * text, an unknown value the module's stated fallback
 * (test/unit/status_check.h), walked over the module's code list
 * (shell_status.h); worldgen's, a hand-written switch, over its codes as
 * its header defines them. */
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
#include "worldgen.h"
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
    STATUS_CHECK(wire_strerror, WIRE_CODES);
    STATUS_CHECK(world_file_strerror, WORLD_FILE_CODES);
}

/* auth_bus passes what is not its own to auth_strerror; worldgen's is
 * still a switch of its own */
static void test_other_modules(void **st)
{
    static const int bus[] = { AUTH_BUS_CODES(STATUS_CODE) };
    static const int gen[] = { WORLDGEN_OK, WORLDGEN_ERR_ARG, WORLDGEN_ERR_NO_WAY,
                               WORLDGEN_ERR_MEMORY };
    (void)st;
    status_check(auth_bus_strerror, bus, N(bus), auth_strerror(-1000));
    assert_string_equal(auth_bus_strerror(AUTH_ERR_REPLAY), auth_strerror(AUTH_ERR_REPLAY));
    status_check(worldgen_strerror, gen, N(gen), "unknown worldgen code");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_listed_modules),
        cmocka_unit_test(test_other_modules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
