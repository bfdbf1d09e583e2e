/* msg_check: range checks of the messages that can move an arm, shared by
 * tandem-arm and the fuzz targets (docs/method/lockstep.md §6: bad data never moves an
 * arm). Each returns MSG_OK or a named reason. */
#ifndef TANDEM_MSG_CHECK_H
#define TANDEM_MSG_CHECK_H

#include "arm_model.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_joint_ref_t.h"

enum {
    MSG_OK = 0,
    MSG_ERR_ARM = -1,      /* not for this arm */
    MSG_ERR_ENUM = -2,     /* controller / flag outside its values */
    MSG_ERR_GAINS = -3,    /* not finite or outside the lookup table's bounds */
    MSG_ERR_SEGMENTS = -4, /* segment count out of range */
    MSG_ERR_NUMBER = -5,   /* a value not finite */
    MSG_ERR_RANGE = -6,    /* outside the joint ranges or speed limits */
    MSG_ERR_FAR = -7,      /* a reference too far from the measured pose */
    MSG_ERR_STEP = -8      /* a step outside the receiver's window */
};

/* The row's header: arm, controller, flags, ids, gains, segment count. */
int action_row_check(const tandem_action_row_t *r, int arm, int max_segments);

/* A joint reference may move the arm only where it already is: every q
 * within track_rad of the measured q_meas (a resolver tracking the arm
 * stays within its servo lag), inside the joint ranges, speeds within the
 * motor limits, accelerations within qdd_max, and its step within
 * [state_step - stale_steps, state_step + 1]. */
#define JOINT_REF_TRACK_RAD 0.2
#define JOINT_REF_QDD_MAX 200.0  /* rad/s^2 */
#define JOINT_REF_QD_MARGIN 1.05 /* rounding of a resolver at the speed limit */
int joint_ref_check(const tandem_arm_joint_ref_t *r, int arm, const arm_model *m,
                    const double q_meas[ARM_NJ], int64_t state_step, int64_t stale_steps);

#endif
