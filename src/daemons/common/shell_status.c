/* The texts of the daemon shell's status codes (shell_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "shell_status.h"

STATUS_STRERROR(auth_acl_strerror, AUTH_ACL_CODES)
STATUS_STRERROR(daemon_strerror, DAEMON_CODES)
STATUS_STRERROR(guard_strerror, GUARD_CODES)
STATUS_STRERROR(msg_strerror, MSG_CODES)
STATUS_STRERROR(options_strerror, OPTIONS_CODES)
STATUS_STRERROR(proc_strerror, PROC_CODES)
STATUS_STRERROR(wire_strerror, WIRE_CODES)
