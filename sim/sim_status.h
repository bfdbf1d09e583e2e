/* The status codes of tandem-sim and its models and the text of each
 * (include/tandem/base/status.h): <module>_strerror(rc) returns it,
 * STATUS_UNKNOWN_TEXT for a value that is no code of the module; never
 * NULL. */
#ifndef TANDEM_SIM_STATUS_H
#define TANDEM_SIM_STATUS_H

#include "status.h"
#include "sim.h"
#include "sim_rovers.h"

#define SIM_CODES(X)                                                           \
    X(SIM_OK, "ok")                                                            \
    X(SIM_ERR_CREATE, "the world or a model cannot be built (said on stderr)") \
    X(SIM_ERR_CONTROL, "a control message for this model, but invalid (refused)")
#define SIM_ROVERS_CODES(X) \
    X(0, "ok")              \
    X(SIM_ROVERS_ERR_ARG, "no such robot, or a speed not finite")

const char *sim_strerror(int rc);
const char *sim_rovers_strerror(int rc);

#endif
