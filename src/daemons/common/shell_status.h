/* The status codes of the daemon shell's modules and the text of each
 * (include/tandem/base/status.h): <module>_strerror(rc) returns it,
 * STATUS_UNKNOWN_TEXT for a value that is no code of the module (auth_bus:
 * auth_strerror's text, as it passes auth's results on); never NULL. */
#ifndef TANDEM_SHELL_STATUS_H
#define TANDEM_SHELL_STATUS_H

#include "status.h"
#include "auth.h"
#include "auth_acl.h"
#include "auth_bus.h"
#include "auth_child.h"
#include "daemon.h"
#include "guard.h"
#include "journal.h"
#include "msg_check.h"
#include "netc.h"
#include "options.h"
#include "proc.h"
#include "renew.h"
#include "wire.h"
#include "world_file.h"
#include "worldgen.h"

#define AUTH_CODES(X)                                                  \
    X(AUTH_OK, "accepted")                                             \
    X(AUTH_ERR_UNSIGNED, "unsigned or not this trailer version")       \
    X(AUTH_ERR_MAC, "no tag for this receiver, or it does not verify") \
    X(AUTH_ERR_SENDER, "unknown sender, or no key with it (revoked)")  \
    X(AUTH_ERR_REPLAY, "replayed or outside the time window")          \
    X(AUTH_ERR_ACL, "sender not allowed on this channel")              \
    X(AUTH_ERR_ARG, "bad argument")                                    \
    X(AUTH_ERR_KEY, "key file error")                                  \
    X(AUTH_ERR_INIT, "libsodium does not start")                       \
    X(AUTH_ERR_CELL, "message of another cell")                        \
    X(AUTH_ERR_TYPE, "not a tandem type, or over its size")            \
    X(AUTH_ERR_CHANNEL, "channel not in the table")
/* auth_bus's own; the rest of its results are auth's (AUTH_CODES) */
#define AUTH_BUS_CODES(X)                                                     \
    X(AUTH_BUS_OK, "ok")                                                      \
    X(AUTH_BUS_ERR_OPTION, "bad --key-file / --insecure option")              \
    X(AUTH_BUS_ERR_NO_HOME, "no HOME or XDG_CONFIG_HOME for the default key") \
    X(AUTH_BUS_ERR_START, "the secure bus does not start")                    \
    X(AUTH_BUS_ERR_KEY, "no usable key file")                                 \
    X(AUTH_BUS_ERR_ARG, "bad argument (failed encode?)")                      \
    X(AUTH_BUS_ERR_MEMORY, "out of memory for the transmit buffer")           \
    X(AUTH_BUS_ERR_NOT_STARTED, "publishing before auth_bus_start")           \
    X(AUTH_BUS_ERR_SIGN, "the message cannot be signed")                      \
    X(AUTH_BUS_ERR_SEND, "lcm_publish failed")
#define AUTH_CHILD_CODES(X)                                                            \
    X(AUTH_CHILD_INHERIT, "the child inherits the key environment")                    \
    X(AUTH_CHILD_OK, "ok")                                                             \
    X(AUTH_CHILD_ERR_DIR, "no directory for the children's role files")                \
    X(AUTH_CHILD_ERR_KEY, "the master does not load or a role file cannot be written") \
    X(AUTH_CHILD_ERR_PRINCIPAL, "the child's principal is not in the cell's roster")   \
    X(AUTH_CHILD_ERR_ARG, "bad argument")
/* journal's texts are the codes' names (what the daemons print) */
#define JOURNAL_CODES(X)                            \
    X(JOURNAL_OK, "JOURNAL_OK")                     \
    X(JOURNAL_ERR_OPEN, "JOURNAL_ERR_OPEN")         \
    X(JOURNAL_ERR_WRITE, "JOURNAL_ERR_WRITE")       \
    X(JOURNAL_ERR_NONE, "JOURNAL_ERR_NONE")         \
    X(JOURNAL_ERR_ARG, "JOURNAL_ERR_ARG")           \
    X(JOURNAL_ERR_SYNC, "JOURNAL_ERR_SYNC")         \
    X(JOURNAL_ERR_READ, "JOURNAL_ERR_READ")         \
    X(JOURNAL_ERR_FORMAT, "JOURNAL_ERR_FORMAT")     \
    X(JOURNAL_ERR_TORN, "JOURNAL_ERR_TORN")         \
    X(JOURNAL_ERR_MAC, "JOURNAL_ERR_MAC")           \
    X(JOURNAL_ERR_SEQUENCE, "JOURNAL_ERR_SEQUENCE") \
    X(JOURNAL_ERR_MODE, "JOURNAL_ERR_MODE")
#define NETC_CODES(X)                                                    \
    X(NETC_OK, "ok")                                                     \
    X(NETC_ERR_IO, "a file cannot be read or written")                   \
    X(NETC_ERR_PNML, "not a PNML place/transition net this tool reads")  \
    X(NETC_ERR_ROWS, "the rows file is malformed")                       \
    X(NETC_ERR_CAPACITY, "beyond a fixed capacity of the supervisor")    \
    X(NETC_ERR_TABLE, "the tables are refused by their validators")      \
    X(NETC_ERR_UNBOUNDED, "a place exceeds its token bound")             \
    X(NETC_ERR_DEADLOCK, "a dead marking is reachable")                  \
    X(NETC_ERR_DEAD_TRANSITION, "a transition never fires")              \
    X(NETC_ERR_NOT_LIVE, "a transition that must stay live can be lost") \
    X(NETC_ERR_STATES, "the reachable set exceeds PETRI_MAX_STATES")     \
    X(NETC_ERR_INVARIANT, "P-invariants beyond their capacity")          \
    X(NETC_ERR_ROLES, "the net lacks a role the supervisor needs (source, its place, the pick)")
#define WORLD_FILE_CODES(X)                                                         \
    X(WORLD_FILE_OK, "ok")                                                          \
    X(WORLD_FILE_ERR_OPEN, "cannot read the YAML file")                             \
    X(WORLD_FILE_ERR_YAML, "not a YAML mapping")                                    \
    X(WORLD_FILE_ERR_FIELD, "a key missing or wrong")                               \
    X(WORLD_FILE_ERR_IMAGE, "the image is missing or not a PGM of the stated size") \
    X(WORLD_FILE_ERR_MAP, "the map is refused")                                     \
    X(WORLD_FILE_ERR_OPTION, "bad --start or --goal")                               \
    X(WORLD_FILE_ERR_MEMORY, "out of memory")                                       \
    X(WORLD_FILE_ERR_WRITE, "cannot write the world")
#define WORLDGEN_CODES(X)                                                          \
    X(WORLDGEN_OK, "ok")                                                           \
    X(WORLDGEN_ERR_ARG,                                                            \
      "kind, size or team out of range (the map must hold the team's start area)") \
    X(WORLDGEN_ERR_NO_WAY, "no passable world in 64 attempts (WORLDGEN_ATTEMPTS)") \
    X(WORLDGEN_ERR_MEMORY, "out of memory")

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
#define RENEW_CODES(X) \
    X(RENEW_OK, "ok")  \
    X(RENEW_ERR_THREAD, "the renewal worker thread does not start")
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
const char *renew_strerror(int rc);
const char *wire_strerror(int rc);

#endif
