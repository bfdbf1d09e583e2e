/* cycles: one period of each daemon's core work (see cycles.h). */
#include "cycles.h"

#include <string.h>

int budget_arm_joint_cycle(budget_arm *a)
{
    double q_d[ARM_NJ], qd_d[ARM_NJ], qdd_d[ARM_NJ];
    jtraj_at(&a->traj, a->t_s, q_d, qd_d, qdd_d);
    a->t_s += BUDGET_ARM_DT_S;
    return jointctl_torque(a->model, &a->bar, &a->gains, a->q, a->qd, q_d, qd_d, qdd_d, a->tau_Nm,
                           NULL);
}

int budget_arm_cart_cycle(budget_arm *a)
{
    double x[3], v[3], l[2], s[2], s_star, s_ref[2];
    sync_ref r;
    cartseg_out o;
    cartctl_state kin;
    if (cartctl_state_at(a->model, &a->tool, a->q, a->qd, &kin) != 0 ||
        cartseg_tool_world_at(&kin, a->T_world_base, x, v) != 0)
        return -1;
    s[0] = erlaw_line_s(&a->cart.line, x);
    s[1] = a->partner_s_m;
    l[0] = a->s_f_m;
    l[1] = a->partner_s_f_m;
    if (sync_ref_init(&r, 2, l) != 0 || sync_ref_update(&r, s, &s_star, s_ref) != 0)
        return -1;
    if (cartseg_step_at(&a->cart, a->model, &a->bar, &kin, a->q, a->qd, s_ref[0], BUDGET_ARM_DT_S,
                        &o) != 0)
        return -1;
    memcpy(a->tau_Nm, o.tau_Nm, sizeof a->tau_Nm);
    return o.done;
}

int budget_arm_tdsd_cycle(budget_arm *a)
{
    tdsd_seg_out o;
    if (tdsd_seg_step(&a->tdsd, a->model, BUDGET_ARM_DT_S, &o) < 0)
        return -1;
    if (tdsd_servo_vlimit(&a->gains, a->model->qd_max_radps, a->q, o.q_d, o.qd_d, o.qdd_d) < 0)
        return -1;
    if (jointctl_torque(a->model, &a->bar, &a->gains, a->q, a->qd, o.q_d, o.qd_d, o.qdd_d,
                        a->tau_Nm, NULL) != 0)
        return -1;
    return tdsd_seg_done(&a->tdsd, a->q, a->qd);
}

/* The completion event of the lowest running transition (the arms report
 * one per action), then the daemon's scan: start every enabled transition
 * but the vision one. */
int budget_supervisor_step(budget_supervisor *s)
{
    int t;
    s->completed = -1;
    for (t = 0; t < carry_net.n_transitions && s->completed < 0; t++)
        if (petri_running(&s->net, t) && petri_complete(&s->net, t) == 0)
            s->completed = t;
    for (t = 0; t < CARRY_T_VISION; t++)
        if (petri_enabled(&s->net, t))
            (void)petri_start(&s->net, t);
    if (petri_enabled(&s->net, CARRY_T_VISION))
        (void)petri_fire(&s->net, CARRY_T_VISION); /* a workpiece is always in view */
    if (!petri_invariants_hold(&s->net))
        return -1;
    return petri_dead(&s->net);
}

int budget_rover_step(budget_rover *r)
{
    int i;
    r->t_s += BUDGET_ROVER_DT_S;
    if (rover_ctl_encoders(&r->ctl, r->enc_rad[0], r->enc_rad[1], r->t_s) != 0 ||
        rover_ctl_sonar(&r->ctl, r->range_m, r->t_s) != 0)
        return -1;
    for (i = 0; i < BUDGET_MATES; i++)
        if (rover_ctl_team_msg(&r->ctl, &r->mate[i], r->t_s) < 0)
            return -1;
    return rover_ctl_step(&r->ctl, r->t_s, BUDGET_ROVER_DT_S, &r->out);
}
