/* The texts of tandem-scenario's status codes (scen_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "scen_status.h"

STATUS_STRERROR(scenario_strerror, SCENARIO_CODES)
STATUS_STRERROR(carry_scen_strerror, CARRY_SCEN_CODES)
STATUS_STRERROR(fm_strerror, FM_CODES)
STATUS_STRERROR(hang_watch_strerror, HANG_WATCH_CODES)
STATUS_STRERROR(run_key_strerror, RUN_KEY_CODES)
STATUS_STRERROR(sweep_strerror, SWEEP_CODES)
STATUS_STRERROR(tdsd_ode_strerror, TDSD_ODE_CODES)
STATUS_STRERROR(tdsd_scen_strerror, TDSD_SCEN_CODES)
STATUS_STRERROR(tdsd_setup_strerror, TDSD_SETUP_CODES)
