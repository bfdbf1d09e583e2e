/* The texts of the tdsd domain's status codes (tdsd_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "tdsd_status.h"

STATUS_STRERROR(tdsd_strerror, TDSD_CODES)
STATUS_STRERROR(tdsd_seg_strerror, TDSD_SEG_CODES)
