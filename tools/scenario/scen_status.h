/* The status codes of tandem-scenario's files and the text of each
 * (include/tandem/base/status.h): <module>_strerror(rc) returns it,
 * STATUS_UNKNOWN_TEXT for a value that is no code of the module; never
 * NULL. The codes stay defined beside the functions that return them. */
#ifndef TANDEM_SCEN_STATUS_H
#define TANDEM_SCEN_STATUS_H

#include "status.h"
#include "scenario.h"
#include "carry_scen.h"
#include "formation_scen.h"
#include "hang_watch.h"
#include "run_key.h"
#include "tdsd_ode.h"
#include "tdsd_scen.h"
#include "tdsd_setup.h"

/* scenario_sweep.c's failures (its run ends with exit status 1 or 2) */
#define SWEEP_ERR_USAGE (-1) /* no NAME, a bad option, or too many keys (said) */
#define SWEEP_ERR_FULL (-2)  /* more --keys than SWEEP_MAX_KEYS */
#define SWEEP_ERR_RUN (-3)   /* a seed's directory not made, fork or waitpid failed */

#define SCENARIO_CODES(X)                                                 \
    X(SCENARIO_OK, "ok")                                                  \
    X(SCENARIO_ERR_ARG, "a bad option value (--drop-rate, --fault, ...)") \
    X(SCENARIO_ERR_IO, "a directory or file not made, or gnuplot failed")
#define CARRY_SCEN_CODES(X)                                                 \
    X(0, "ok")                                                              \
    X(CARRY_SCEN_ERR_BLOCK, "--block not A:L:S:D[:t3] inside its ranges")   \
    X(CARRY_SCEN_ERR_RUN, "no LCM, a daemon did not start or exited early") \
    X(CARRY_SCEN_ERR_FAULT, "--fault or a hung daemon: not restarted, or not back within 60 s")
/* the formation run's texts name their codes (formation_scen.h) */
#define FM_CODES(X)                                                                 \
    X(0, "ok")                                                                      \
    X(FM_ERR_START, "FM_ERR_START: the simulator or a rover process did not start") \
    X(FM_ERR_FAULT, "FM_ERR_FAULT: a rover not restarted, or not back within 60 s") \
    X(FM_ERR_HUNG, "FM_ERR_HUNG: the simulator or the one process of all rovers hung")
#define HANG_WATCH_CODES(X)                                                  \
    X(0, "ok")                                                               \
    X(HANG_WATCH_ERR_FULL, "HANG_WATCH_ERR_FULL: too many children watched") \
    X(HANG_WATCH_ERR_NAME, "HANG_WATCH_ERR_NAME: empty or too long a daemon name")
#define RUN_KEY_CODES(X)                                               \
    X(0, "ok")                                                         \
    X(RUN_KEY_ERR_OPTION, "a --key-file or --insecure option refused") \
    X(RUN_KEY_ERR_KEY, "no key made for this run")
#define SWEEP_CODES(X)                                                     \
    X(0, "ok")                                                             \
    X(SWEEP_ERR_USAGE, "no scenario name, a bad option, or too many keys") \
    X(SWEEP_ERR_FULL, "more --keys than the sweep keeps (SWEEP_MAX_KEYS)") \
    X(SWEEP_ERR_RUN, "a seed's directory not made, or fork or waitpid failed")
#define TDSD_ODE_CODES(X) \
    X(0, "ok")            \
    X(TDSD_ODE_ERR_RUN, "no LCM, the children did not start or died, or the wall-time limit")
#define TDSD_SCEN_CODES(X)                              \
    X(0, "ok")                                          \
    X(TDSD_SCEN_ERR_ARG, "bad usage")                   \
    X(TDSD_SCEN_ERR_IO, "DIR or a file in it not made") \
    X(TDSD_SCEN_ERR_RUN, "the plant did not run (--plant ode: the children)")
#define TDSD_SETUP_CODES(X) \
    X(0, "ok")              \
    X(TDSD_SETUP_ERR_START, "the start pose is not reachable inside the ranges")

const char *scenario_strerror(int rc);
const char *carry_scen_strerror(int rc);
const char *run_key_strerror(int rc);
const char *sweep_strerror(int rc);
const char *tdsd_ode_strerror(int rc);
const char *tdsd_scen_strerror(int rc);
const char *tdsd_setup_strerror(int rc);
/* fm_strerror is declared in formation_scen.h, hang_watch_strerror in hang_watch.h */

#endif
