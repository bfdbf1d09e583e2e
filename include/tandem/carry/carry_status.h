/* The status codes of the carry domain's modules and the text of each
 * (status.h): <module>_strerror(rc) returns it, STATUS_UNKNOWN_TEXT for a
 * value that is no code of the module. Never NULL. */
#ifndef TANDEM_CARRY_STATUS_H
#define TANDEM_CARRY_STATUS_H

#include "status.h"
#include "petri.h"
#include "carry_net.h"
#include "erlaw.h"
#include "cartseg.h"
#include "sync_ref.h"
#include "stallwatch.h"
#include "cell.h"
#include "taskdef.h"

#define PETRI_CODES(X)                                                            \
    X(0, "ok")                                                                    \
    X(PETRI_ERR_ARG, "bad argument or index")                                     \
    X(PETRI_ERR_NOT_ENABLED, "start of a transition that is not enabled")         \
    X(PETRI_ERR_NOT_RUNNING, "completion of a transition that is not running")    \
    X(PETRI_ERR_OVERFLOW, "a place would exceed PETRI_TOKEN_MAX tokens")          \
    X(PETRI_ERR_SIZE, "places, transitions or invariants outside 1..PETRI_MAX_*") \
    X(PETRI_ERR_ENTRY, "an N-, N+ or inhibitor entry is not 0 or 1")              \
    X(PETRI_ERR_TRANSITION, "a transition that can never act")                    \
    X(PETRI_ERR_INVARIANT, "an invariant that is zero or not a P-invariant")      \
    X(PETRI_ERR_NONE_ENABLED, "no transition is enabled")
#define CARRY_NET_CODES(X)                                                                   \
    X(0, "ok")                                                                               \
    X(CARRY_NET_ERR_NO_GAINS, "no row moves an arm, so there are no gain bounds")            \
    X(CARRY_NET_ERR_ARG, "NULL rows or net")                                                 \
    X(CARRY_NET_ERR_SIZE, "not one row per transition, or a plan too long or negative")      \
    X(CARRY_NET_ERR_RANGE, "a row field outside its set")                                    \
    X(CARRY_NET_ERR_GAINS, "a row that moves an arm has gains erlaw_gains_validate refuses") \
    X(CARRY_NET_ERR_INCONSISTENT, "a row contradicts itself")                                \
    X(CARRY_NET_ERR_NET, "the net is not sound, or a row contradicts its transition")
#define ERLAW_CODES(X) \
    X(0, "ok")         \
    X(ERLAW_ERR_ARG, "NULL, non-finite input, invalid gains, bad reference mode, or dt < 0")
#define CARTSEG_CODES(X)                                                                 \
    X(0, "ok")                                                                           \
    X(CARTSEG_ERR_ARG, "NULL, non-finite input, bad reference mode, or a failure below") \
    X(CARTSEG_ERR_NO_GOAL,                                                               \
      "no IK solution keeps the margin (pose unreachable or configuration unknown)")
#define SYNC_REF_CODES(X) \
    X(0, "ok")            \
    X(SYNC_REF_ERR_ARG, "NULL, n outside 1..SYNC_MAX, a length < 0 or a non-finite number")
#define STALLWATCH_CODES(X) \
    X(STALLWATCH_OK, "ok")  \
    X(STALLWATCH_ERR_ARG, "bad argument")
#define CELL_CODES(X)                                                            \
    X(0, "ok")                                                                   \
    X(CELL_ERR_ARG, "NULL layout")                                               \
    X(CELL_ERR_NONFINITE, "a number of the cell is NaN or Inf")                  \
    X(CELL_ERR_RANGE, "a size, mass, offset or clearance <= 0, or a spread < 0") \
    X(CELL_ERR_INCONSISTENT, "parts of the cell that do not fit together")
#define TASKDEF_CODES(X)                                                           \
    X(TASKDEF_OK, "ok")                                                            \
    X(TASKDEF_ERR_ARG, "NULL net or roles")                                        \
    X(TASKDEF_ERR_SOURCE, "not exactly one source transition (no input place)")    \
    X(TASKDEF_ERR_SOURCE_PLACE,                                                    \
      "the source fills not exactly one place, or it does not inhibit the source") \
    X(TASKDEF_ERR_PICK, "not exactly one transition takes the source's token")     \
    X(TASKDEF_ERR_NET, "petri_net_validate refuses the net")                       \
    X(TASKDEF_ERR_TABLE, "carry_table_validate refuses the rows")                  \
    X(TASKDEF_ERR_HEALTH, "an arm's health places (armK_up, armK_down) are not as taskdef.h says")

const char *petri_strerror(int rc);
const char *carry_net_strerror(int rc);
const char *erlaw_strerror(int rc);
const char *cartseg_strerror(int rc);
const char *sync_ref_strerror(int rc);
const char *stallwatch_strerror(int rc);
const char *cell_strerror(int rc);
const char *taskdef_strerror(int rc);

#endif
