/* The status codes of the tdsd domain's modules and the text of each
 * (status.h): <module>_strerror(rc) returns it, STATUS_UNKNOWN_TEXT for a
 * value that is no code of the module. Never NULL. */
#ifndef TANDEM_TDSD_STATUS_H
#define TANDEM_TDSD_STATUS_H

#include "status.h"
#include "tdsd.h"
#include "tdsd_seg.h"

#define TDSD_CODES(X)                                               \
    X(TDSD_OK, "ok")                                                \
    X(TDSD_ERR_ARG, "non-finite or out-of-range input (dq zeroed)") \
    X(TDSD_ERR_NUMERIC, "linear algebra failure (dq zeroed)")
#define TDSD_SEG_CODES(X) \
    X(0, "ok")            \
    X(TDSD_SEG_ERR_ARG,   \
      "NULL, non-finite input, invalid parameters or gains, or FK / the profile refused")

const char *tdsd_strerror(int rc);
const char *tdsd_seg_strerror(int rc);

#endif
