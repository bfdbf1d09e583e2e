/* The texts of the base domain's status codes (base_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "base_status.h"

STATUS_STRERROR(linalg_strerror, LINALG_CODES)
STATUS_STRERROR(loopstats_strerror, LOOPSTATS_CODES)
STATUS_STRERROR(pgrid_strerror, PGRID_CODES)
STATUS_STRERROR(rtloop_strerror, RTLOOP_CODES)
STATUS_STRERROR(sprofile_strerror, SPROFILE_CODES)
