/* The status codes of the arm domain's modules and the text of each
 * (status.h): <module>_strerror(rc) returns it, STATUS_UNKNOWN_TEXT for a
 * value that is no code of the module. Never NULL. */
#ifndef TANDEM_ARM_STATUS_H
#define TANDEM_ARM_STATUS_H

#include "status.h"
#include "arm_model.h"
#include "arm_kin.h"
#include "arm_dyn.h"
#include "jointctl.h"
#include "jtraj.h"
#include "cartctl.h"

#define ARM_MODEL_CODES(X)                                                                      \
    X(0, "ok")                                                                                  \
    X(ARM_MODEL_ERR_ARG, "NULL model or name, or a non-finite joint or tool offset")            \
    X(ARM_MODEL_ERR_NONFINITE, "a model table entry is NaN or Inf")                             \
    X(ARM_MODEL_ERR_RANGE, "a length, joint range, speed or torque limit or mass out of range") \
    X(ARM_MODEL_ERR_INCONSISTENT, "cos/sin_alpha do not match alpha, or an inertia is not SPD") \
    X(ARM_MODEL_ERR_STRUCTURE,                                                                  \
      "claims the PUMA structure without its zeros and right angles, or an unknown structure")
#define ARM_KIN_CODES(X)                                                      \
    X(0, "ok")                                                                \
    X(ARM_KIN_ERR_ARG, "NULL, or a non-finite joint vector or pose")          \
    X(ARM_KIN_ERR_GEOMETRY, "inverse kinematics: the model is not PUMA-type") \
    X(ARM_KIN_ERR_NO_BRANCH, "no IK branch: unknown name, or none inside the joint limits")
#define ARM_DYN_CODES(X)                                               \
    X(0, "ok")                                                         \
    X(ARM_DYN_ERR_ARG, "NULL, non-finite input or a negative payload") \
    X(ARM_DYN_ERR_NOT_PD, "the mass matrix is not positive definite")
#define JOINTCTL_CODES(X) \
    X(0, "ok")            \
    X(JOINTCTL_ERR_ARG,   \
      "non-finite reference, negative gains, or inverse dynamics refused the state")
#define JTRAJ_CODES(X)                                                                  \
    X(0, "ok")                                                                          \
    X(JTRAJ_ERR_ARG, "non-finite q0/q1, speed fraction outside (0, 1] or qdd_max <= 0") \
    X(JTRAJ_ERR_STOP, "a stop from a non-finite q0/qd0, or a deceleration not finite and > 0")
#define CARTCTL_CODES(X)                                                             \
    X(0, "ok")                                                                       \
    X(CARTCTL_ERR_ARG,                                                               \
      "NULL, non-finite input, invalid gains, or the kinematics or dynamics failed") \
    X(CARTCTL_ERR_SINGULAR,                                                          \
      "a diagonal block of the wrist inverse is singular (elbow or wrist singularity)")

const char *arm_model_strerror(int rc);
const char *arm_kin_strerror(int rc);
const char *arm_dyn_strerror(int rc);
const char *jointctl_strerror(int rc);
const char *jtraj_strerror(int rc);
const char *cartctl_strerror(int rc);

#endif
