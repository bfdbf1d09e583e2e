/* The status codes of the base domain's modules and the text of each
 * (status.h): <module>_strerror(rc) returns it, STATUS_UNKNOWN_TEXT for a
 * value that is no code of the module. Never NULL. */
#ifndef TANDEM_BASE_STATUS_H
#define TANDEM_BASE_STATUS_H

#include "status.h"
#include "linalg.h"
#include "loopstats.h"
#include "pgrid.h"
#include "rtloop.h"
#include "sprofile.h"

#define LINALG_CODES(X)                                                   \
    X(LINALG_OK, "ok")                                                    \
    X(LINALG_ERR_SIZE, "a dimension outside 1..LINALG_MAX")               \
    X(LINALG_ERR_NONFINITE, "NaN or Inf in an input")                     \
    X(LINALG_ERR_ARG, "bad scalar argument (a negative tolerance, ...)")  \
    X(LINALG_ERR_NOT_PD, "Cholesky: the matrix is not positive definite") \
    X(LINALG_ERR_NOCONV, "SVD: sweep cap reached (the result is still usable)")
#define LOOPSTATS_CODES(X) \
    X(0, "ok")             \
    X(LOOPSTATS_ERR_ARG, "a sample negative or not finite (ignored)")
#define PGRID_CODES(X)                                                             \
    X(PGRID_OK, "ok")                                                              \
    X(PGRID_ERR_ARG, "NULL, a count outside 0..PGRID_MAX_ITEMS, a cell or radius " \
                     "not > 0, or a position not finite")                          \
    X(PGRID_ERR_FULL, "more items in range than the caller's buffer holds")
#define RTLOOP_CODES(X) \
    X(0, "ok")          \
    X(RTLOOP_ERR_RANGE, "period outside [RTLOOP_MIN_PERIOD_NS, RTLOOP_MAX_PERIOD_NS]")
#define SPROFILE_CODES(X) \
    X(0, "ok")            \
    X(SPROFILE_ERR_ARG, "NULL, not finite, s_f < 0 or a limit <= 0")

const char *linalg_strerror(int rc);
const char *loopstats_strerror(int rc);
const char *pgrid_strerror(int rc);
const char *rtloop_strerror(int rc);
const char *sprofile_strerror(int rc);

#endif
