/* msg_check: range checks of arm-moving messages (see msg_check.h). */
#include "msg_check.h"
#include <math.h>
#include "carry_net.h"
#include "daemon.h"
#include "linalg.h"

static int row_has_cartesian(const tandem_action_row_t *r)
{
    int i;
    for (i = 0; i < r->n_segments; i++)
        if (r->segments[i].kind == TANDEM_ACTION_SEGMENT_T_MOVE_CARTESIAN)
            return 1;
    return 0;
}

int action_row_check(const tandem_action_row_t *r, int arm, int max_segments)
{
    const erlaw_gains g = { r->v_m, r->a_m, r->u_m, r->k_p, r->k_v, r->k0, r->k1, r->k2 };
    if (r->arm != arm)
        return MSG_ERR_ARM;
    if ((r->controller != TANDEM_ACTION_ROW_T_CONTROLLER_EVENT &&
         r->controller != TANDEM_ACTION_ROW_T_CONTROLLER_TIME) ||
        (r->use_tdsd != 0 && r->use_tdsd != 1) || r->sync_group < 0 || r->transition < 0)
        return MSG_ERR_ENUM;
    if (r->n_segments < 1 || r->n_segments > max_segments)
        return MSG_ERR_SEGMENTS;
    /* a row without Cartesian moves uses no gains: zeros are fine there */
    if (!carry_gains_within_table(&g, !row_has_cartesian(r)))
        return MSG_ERR_GAINS;
    return MSG_OK;
}

int joint_ref_check(const tandem_arm_joint_ref_t *r, int arm, const arm_model *m,
                    const double q_meas[ARM_NJ], int64_t state_step, int64_t stale_steps)
{
    int i;
    if (r->arm != arm)
        return MSG_ERR_ARM;
    if (r->step < 0 || r->step > state_step + 1 || r->step < state_step - stale_steps)
        return MSG_ERR_STEP;
    if (arm_q_finite(r->q_rad) != 0 || !linalg_all_finite(r->qd_radps, ARM_NJ) ||
        !linalg_all_finite(r->qdd_radps2, ARM_NJ))
        return MSG_ERR_NUMBER;
    if (arm_q_outside_limits(m, r->q_rad) != 0)
        return MSG_ERR_RANGE;
    for (i = 0; i < ARM_NJ; i++) {
        if (fabs(r->qd_radps[i]) > JOINT_REF_QD_MARGIN * m->qd_max_radps[i] ||
            fabs(r->qdd_radps2[i]) > JOINT_REF_QDD_MAX)
            return MSG_ERR_RANGE;
        if (fabs(r->q_rad[i] - q_meas[i]) > JOINT_REF_TRACK_RAD)
            return MSG_ERR_FAR;
    }
    return MSG_OK;
}
