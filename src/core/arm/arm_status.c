/* The texts of the arm domain's status codes (arm_status.h): each
 * module's strerror is a switch over its code list, the one place a
 * code's text is written. */
#include "arm_status.h"

STATUS_STRERROR(arm_model_strerror, ARM_MODEL_CODES)
STATUS_STRERROR(arm_kin_strerror, ARM_KIN_CODES)
STATUS_STRERROR(arm_dyn_strerror, ARM_DYN_CODES)
STATUS_STRERROR(jointctl_strerror, JOINTCTL_CODES)
STATUS_STRERROR(jtraj_strerror, JTRAJ_CODES)
STATUS_STRERROR(cartctl_strerror, CARTCTL_CODES)
