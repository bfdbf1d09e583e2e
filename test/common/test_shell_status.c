/* The daemon shell's status texts: every code of every module has its own
 * text, an unknown value the module's stated fallback
 * (test/unit/status_check.h). The modules with a code list
 * (shell_status.h) are walked over it; the older ones, whose strerror is
 * a hand-written switch, over their codes as the headers define them. */
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
    STATUS_CHECK(auth_acl_strerror, AUTH_ACL_CODES);
    STATUS_CHECK(daemon_strerror, DAEMON_CODES);
    STATUS_CHECK(guard_strerror, GUARD_CODES);
    STATUS_CHECK(msg_strerror, MSG_CODES);
    STATUS_CHECK(options_strerror, OPTIONS_CODES);
    STATUS_CHECK(proc_strerror, PROC_CODES);
    STATUS_CHECK(wire_strerror, WIRE_CODES);
}

static void test_switch_modules(void **st)
{
    static const int auth[] = {
        AUTH_OK,         AUTH_ERR_UNSIGNED, AUTH_ERR_MAC,  AUTH_ERR_SENDER,
        AUTH_ERR_REPLAY, AUTH_ERR_ACL,      AUTH_ERR_ARG,  AUTH_ERR_KEY,
        AUTH_ERR_INIT,   AUTH_ERR_CELL,     AUTH_ERR_TYPE, AUTH_ERR_CHANNEL
    };
    /* auth_bus passes what is not its own to auth_strerror */
    static const int bus[] = { AUTH_BUS_ERR_OPTION,      AUTH_BUS_ERR_NO_HOME, AUTH_BUS_ERR_START,
                               AUTH_BUS_ERR_KEY,         AUTH_BUS_ERR_ARG,     AUTH_BUS_ERR_MEMORY,
                               AUTH_BUS_ERR_NOT_STARTED, AUTH_BUS_ERR_SIGN,    AUTH_BUS_ERR_SEND };
    static const int child[] = { AUTH_CHILD_INHERIT,       AUTH_CHILD_OK,
                                 AUTH_CHILD_ERR_DIR,       AUTH_CHILD_ERR_KEY,
                                 AUTH_CHILD_ERR_PRINCIPAL, AUTH_CHILD_ERR_ARG };
    static const int journal[] = { JOURNAL_OK,       JOURNAL_ERR_OPEN,     JOURNAL_ERR_WRITE,
                                   JOURNAL_ERR_NONE, JOURNAL_ERR_ARG,      JOURNAL_ERR_SYNC,
                                   JOURNAL_ERR_READ, JOURNAL_ERR_FORMAT,   JOURNAL_ERR_TORN,
                                   JOURNAL_ERR_MAC,  JOURNAL_ERR_SEQUENCE, JOURNAL_ERR_MODE };
    static const int world[] = {
        WORLD_FILE_OK,         WORLD_FILE_ERR_OPEN,   WORLD_FILE_ERR_YAML,
        WORLD_FILE_ERR_FIELD,  WORLD_FILE_ERR_IMAGE,  WORLD_FILE_ERR_MAP,
        WORLD_FILE_ERR_OPTION, WORLD_FILE_ERR_MEMORY, WORLD_FILE_ERR_WRITE
    };
    static const int gen[] = { WORLDGEN_OK, WORLDGEN_ERR_ARG, WORLDGEN_ERR_NO_WAY,
                               WORLDGEN_ERR_MEMORY };
    (void)st;
    status_check(auth_strerror, auth, N(auth), "unknown auth result");
    status_check(auth_bus_strerror, bus, N(bus), "unknown auth result");
    status_check(auth_child_strerror, child, N(child), "unknown auth_child result");
    status_check(journal_strerror, journal, N(journal), "JOURNAL_ERR_?");
    status_check(world_file_strerror, world, N(world), "unknown world_file code");
    status_check(worldgen_strerror, gen, N(gen), "unknown worldgen code");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_listed_modules),
        cmocka_unit_test(test_switch_modules),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
