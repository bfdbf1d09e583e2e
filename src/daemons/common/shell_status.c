/* The texts of the daemon shell's status codes (shell_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "shell_status.h"
#include <string.h>

STATUS_STRERROR(auth_strerror, AUTH_CODES)
STATUS_STRERROR(auth_child_strerror, AUTH_CHILD_CODES)
STATUS_STRERROR(journal_strerror, JOURNAL_CODES)
STATUS_STRERROR(netc_strerror, NETC_CODES)
STATUS_STRERROR(world_file_strerror, WORLD_FILE_CODES)
STATUS_STRERROR(worldgen_strerror, WORLDGEN_CODES)

static STATUS_STRERROR(auth_bus_own_strerror, AUTH_BUS_CODES)

    const char *auth_bus_strerror(int rc)
{
    const char *own = auth_bus_own_strerror(rc);
    return strcmp(own, STATUS_UNKNOWN_TEXT) == 0 ? auth_strerror(rc) : own;
}

STATUS_STRERROR(auth_acl_strerror, AUTH_ACL_CODES)
STATUS_STRERROR(daemon_strerror, DAEMON_CODES)
STATUS_STRERROR(guard_strerror, GUARD_CODES)
STATUS_STRERROR(msg_strerror, MSG_CODES)
STATUS_STRERROR(options_strerror, OPTIONS_CODES)
STATUS_STRERROR(proc_strerror, PROC_CODES)
STATUS_STRERROR(renew_strerror, RENEW_CODES)
STATUS_STRERROR(wire_strerror, WIRE_CODES)
