/* The texts of the carry domain's status codes (carry_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "carry_status.h"

STATUS_STRERROR(petri_strerror, PETRI_CODES)
STATUS_STRERROR(carry_net_strerror, CARRY_NET_CODES)
STATUS_STRERROR(erlaw_strerror, ERLAW_CODES)
STATUS_STRERROR(cartseg_strerror, CARTSEG_CODES)
STATUS_STRERROR(sync_ref_strerror, SYNC_REF_CODES)
STATUS_STRERROR(stallwatch_strerror, STALLWATCH_CODES)
STATUS_STRERROR(cell_strerror, CELL_CODES)
STATUS_STRERROR(taskdef_strerror, TASKDEF_CODES)
