/* The status codes of the daemon shell's modules that had no text, and
 * the text of each (include/tandem/base/status.h): <module>_strerror(rc)
 * returns it, STATUS_UNKNOWN_TEXT for a value that is no code of the
 * module; never NULL. auth, auth_bus, auth_child, journal, world_file and
 * worldgen name theirs in their own headers. */
#ifndef TANDEM_SHELL_STATUS_H
#define TANDEM_SHELL_STATUS_H

#include "status.h"
#include "auth_acl.h"
#include "daemon.h"
#include "guard.h"
#include "msg_check.h"
#include "options.h"
#include "proc.h"
#include "wire.h"

#define AUTH_ACL_CODES(X)                                                       \
    X(AUTH_ACL_OK, "ok")                                                        \
    X(AUTH_ACL_ERR_EMPTY, "the channel table has no rules")                     \
    X(AUTH_ACL_ERR_NAME, "a rule's prefix or suffix missing or not [A-Z0-9_]")  \
    X(AUTH_ACL_ERR_MATCH, "unknown match kind, or an exact rule with a suffix") \
    X(AUTH_ACL_ERR_ROLES, "a rule with no role, or an unknown role bit")        \
    X(AUTH_ACL_ERR_OWN, "own on a channel without a number")                    \
    X(AUTH_ACL_ERR_OVERLAP, "a channel two rules match")                        \
    X(AUTH_ACL_ERR_READERS, "a rule with no reader, or an unknown reader role bit")
#define DAEMON_CODES(X)                                               \
    X(DAEMON_OK, "ok")                                                \
    X(DAEMON_ERR_NUMBER, "not a finite number or not an integer")     \
    X(DAEMON_ERR_RANGE, "a value or the period out of range")         \
    X(DAEMON_ERR_TABLE, "the validator refused the table")            \
    X(DAEMON_ERR_AUTH, "the secure bus does not start (no key, ...)") \
    X(DAEMON_ERR_LCM, "LCM does not open at the URL")
#define GUARD_CODES(X)                                             \
    X(GUARD_OK, "ok")                                              \
    X(GUARD_ERR_NEGATIVE, "a negative step")                       \
    X(GUARD_ERR_BEHIND, "a step older than the last accepted one") \
    X(GUARD_ERR_JUMP, "a step further ahead than the window")
#define MSG_CODES(X)                                                          \
    X(MSG_OK, "ok")                                                           \
    X(MSG_ERR_ARM, "not for this arm")                                        \
    X(MSG_ERR_ENUM, "a controller or flag outside its values")                \
    X(MSG_ERR_GAINS, "gains not finite or outside the lookup table's bounds") \
    X(MSG_ERR_SEGMENTS, "segment count out of range")                         \
    X(MSG_ERR_NUMBER, "a value not finite")                                   \
    X(MSG_ERR_RANGE, "outside the joint ranges or speed limits")              \
    X(MSG_ERR_FAR, "a reference too far from the measured pose")              \
    X(MSG_ERR_STEP, "a step outside the receiver's window")
/* OPTIONS_EXIT (-1, --help or --version printed) shares its value with
 * OPTIONS_ERR_VALUE: the two are results of different calls, and the
 * text is the error's */
#define OPTIONS_CODES(X)                                            \
    X(0, "ok")                                                      \
    X(OPTIONS_ERR_VALUE, "a bad option value")                      \
    X(OPTIONS_ERR_ARG, "a bad option (said on stderr)")             \
    X(OPTIONS_ERR_SAID, "a bad option value (said by its handler)") \
    X(OPTIONS_ERR_TABLE, "the options table is unsound (the entry said on stderr)")
#define PROC_CODES(X)                                            \
    X(0, "ok")                                                   \
    X(PROC_ERR_SYS, "pipe or fork failed (errno says why)")      \
    X(PROC_ERR_KEY, "the child's role file cannot be made")      \
    X(PROC_ERR_FULL, "PROC_MAX children already, or no argv[0]") \
    X(PROC_ERR_UNKNOWN, "not a child of this set")
#define WIRE_CODES(X)                                                                         \
    X(WIRE_OK, "ok")                                                                          \
    X(WIRE_ERR_SHORT, "the buffer ends inside a field")                                       \
    X(WIRE_ERR_FINGERPRINT, "not this type, or an unknown type")                              \
    X(WIRE_ERR_LENGTH, "an array length negative, over its capacity, or an empty byte array") \
    X(WIRE_ERR_STRING, "a string length out of range, or its NUL not only at the end")        \
    X(WIRE_ERR_TRAILING, "bytes left over after the message")                                 \
    X(WIRE_ERR_DEPTH, "nesting deeper than any tandem type")

const char *auth_acl_strerror(int rc);
const char *daemon_strerror(int rc);
const char *guard_strerror(int rc);
const char *msg_strerror(int rc);
const char *options_strerror(int rc);
const char *proc_strerror(int rc);
const char *wire_strerror(int rc);

#endif
