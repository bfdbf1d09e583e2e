/* The texts of tandem-sim's status codes (sim_status.h): each module's
 * strerror is a switch over its code list, the one place a code's text is
 * written. */
#include "sim_status.h"

STATUS_STRERROR(sim_strerror, SIM_CODES)
STATUS_STRERROR(sim_rovers_strerror, SIM_ROVERS_CODES)
