/* sim_arms: the PUMA 560 pair as torque-driven ODE bodies (docs/method/lockstep.md §3).
 *
 * Each link is one ODE body whose mass, centre of mass and inertia are
 * exactly arm_model_puma560's (the body origin sits at the COM because ODE
 * requires it; geometry is offset accordingly). Joints are hinges on the
 * DH z axes. Commands are held between messages (zero-order hold); a
 * command older than ARM_STALE_STEPS puts the joints on their brakes
 * (velocity motors at zero speed, limited to the motor torque) until fresh
 * commands arrive.
 *
 * The drives and the mechanics hold the arm's limits, as a real PUMA's do:
 * - every joint's range is a hard stop: a one-axis ODE angular motor in
 *   user mode beside each hinge carries the stops, fed with the joint's
 *   continuous angle, so ranges wider than the hinge's (-pi, pi) angle
 *   window, q4 and q6, are held too (joint_stops);
 * - a drive gives at most its peak torque and never drives its joint past
 *   its speed limit: the commanded torque acts through a velocity motor
 *   (ODE's velocity-limited torque), and a joint pushed faster than the
 *   limit by outside forces is braked back with the peak torque
 *   (drive_motor);
 * - a drive's rotor has its inertia reflected through the gear (the
 *   model's armature_kgm2, Jm G^2), carried by the same motor: the wrist's
 *   is 100-1000 times its link's, and without it a stick hitting link 6 at
 *   cruise spun joint 6 past its limit within a step;
 * - the stick is a compliant contact (a hand-held rod with a force sensor,
 *   sim_world.c) and goes in clear of every link (sim_stick.c).
 * Contact forces go out raw (this 1 ms step) and as a 10 ms moving average.
 */
#include "sim_arms.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "arm_kin.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

#define ARM_STALE_STEPS 20        /* 20 ms: docs/method/lockstep.md §6 bounded safe hold */
#define ARM_TAU_REJECT_FACTOR 2.0 /* |tau| beyond 2x the motor limit = bad data */
/* A range end gets a stop once it lies within this of the joint (ODE's
 * rotational stops act inside (-pi, pi) of the motor's angle); a joint
 * cannot cover the rest in one 1 ms step. */
#define STOP_WINDOW_RAD 3.0
/* A joint above this share of its speed limit (driven there by outside
 * forces) is braked back to it: the joint watchdogs' limit (1.0) is not
 * reached by the drive's own overshoot of one step. */
#define DRIVE_SPEED_GUARD 0.98

static const char *const state_channel[SIM_ARMS] = { "ARM1_STATE", "ARM2_STATE" };
static const char *const command_channel[SIM_ARMS] = { "ARM1_COMMAND", "ARM2_COMMAND" };
const double sim_arm_link_radius_m[ARM_NJ] = { 0.09, 0.07, 0.06, 0.045, 0.04, 0.035 };

const arm_model *sim_arms_model(const sim_config *cfg, int k)
{
    return (k == 0 && cfg->arm1_model) ? cfg->arm1_model : &arm_model_puma560;
}

sim_arm *sim_arms_arm(sim_arms *arms, int k)
{
    return &arms->pair[k];
}

/* ---- building ------------------------------------------------------------- */

static void world_from_link(const sim_arm *a, const double T_mount_link[16], double T[16])
{
    tf_mul(T, a->T_world_mount, T_mount_link);
}

static void set_body_pose(dBodyID b, const double R[9], const double p[3])
{
    dMatrix3 Rm;
    sim_ode_rotation(Rm, R);
    dBodySetRotation(b, Rm);
    dBodySetPosition(b, p[0], p[1], p[2]);
}

/* A capsule from point p0 to p1, both in link-frame coordinates, attached to
 * the link body whose origin is the COM. */
static dGeomID link_capsule(sim_world *w, dBodyID body, const double com[3], const double p0[3],
                            const double p1[3], double radius)
{
    double axis[3], mid[3], R[9];
    dMatrix3 Rm;
    double len;
    dGeomID g;
    vec3_sub(axis, p1, p0);
    len = vec3_normalize(axis, axis);
    if (len < 1e-3)
        return NULL;
    vec3_add(mid, p0, p1);
    vec3_scale(mid, mid, 0.5);
    vec3_sub(mid, mid, com);
    sim_rot_z_to(R, axis);
    g = dCreateCapsule(w->space, radius, len);
    dGeomSetBody(g, body);
    dGeomSetOffsetPosition(g, mid[0], mid[1], mid[2]);
    sim_ode_rotation(Rm, R);
    dGeomSetOffsetRotation(g, Rm);
    dGeomSetCategoryBits(g, SIM_CAT_ARM);
    dGeomSetCollideBits(g, SIM_CAT_STICK);
    return g;
}

static void build_link(sim_world *w, sim_arm *a, int i, double Tl[ARM_NJ + 1][16])
{
    const arm_model *m = a->model;
    const double *I = m->inertia_kgm2[i];
    double T[16], R[9], p[3], com_w[3], origin_prev[3], p0[3], p1[3], Tinv[16];
    dMass mass;
    world_from_link(a, Tl[i + 1], T);
    tf_rot(R, T);
    tf_pos(p, T);
    rot_apply(com_w, R, m->com_m[i]);
    vec3_add(com_w, com_w, p);
    a->link[i] = sim_body_create(w);
    set_body_pose(a->link[i], R, com_w);
    dMassSetParameters(&mass, m->mass_kg[i], 0, 0, 0, I[0], I[4], I[8], I[1], I[2], I[5]);
    dBodySetMass(a->link[i], &mass);

    /* Collision shape: joint i's origin (frame i-1) to frame i's origin, and
     * on along z_i by d_{i+1} (the part of the next offset fixed in link i). */
    tf_inverse(Tinv, Tl[i + 1]);
    tf_pos(origin_prev, Tl[i]);
    rot_apply(p0,
              (double[9]){ Tinv[0], Tinv[1], Tinv[2], Tinv[4], Tinv[5], Tinv[6], Tinv[8], Tinv[9],
                           Tinv[10] },
              origin_prev);
    p0[0] += Tinv[3];
    p0[1] += Tinv[7];
    p0[2] += Tinv[11];
    vec3_set(p1, 0.0, 0.0, 0.0);
    a->geom[i][0] = link_capsule(w, a->link[i], m->com_m[i], p0, p1, sim_arm_link_radius_m[i]);
    vec3_set(p0, 0.0, 0.0, i + 1 < ARM_NJ ? m->d_m[i + 1] : CELL_TOOL_LENGTH_M);
    a->geom[i][1] = link_capsule(w, a->link[i], m->com_m[i], p1, p0, sim_arm_link_radius_m[i]);
}

static void build_joint(sim_world *w, sim_arm *a, int i, double Tl[ARM_NJ + 1][16])
{
    double T[16], anchor[3], axis[3];
    dJointID j = dJointCreateHinge(w->world, 0);
    world_from_link(a, Tl[i], T);
    tf_pos(anchor, T);
    vec3_set(axis, T[2], T[6], T[10]); /* z_{i-1} */
    /* body1 = the link, body2 = its parent: the hinge angle then grows with
     * the link turning positively about z_{i-1}, as q_i does. */
    dJointAttach(j, a->link[i], i > 0 ? a->link[i - 1] : 0);
    dJointSetHingeAnchor(j, anchor[0], anchor[1], anchor[2]);
    dJointSetHingeAxis(j, axis[0], axis[1], axis[2]);
    a->joint[i] = j;
    /* the stops: same bodies, the hinge axis fixed in the link (rel 1) */
    a->stop[i] = dJointCreateAMotor(w->world, 0);
    dJointAttach(a->stop[i], a->link[i], i > 0 ? a->link[i - 1] : 0);
    dJointSetAMotorMode(a->stop[i], dAMotorUser);
    dJointSetAMotorNumAxes(a->stop[i], 1);
    dJointSetAMotorAxis(a->stop[i], 0, 1, axis[0], axis[1], axis[2]);
}

/* home_q: the home pose has no IK solution inside the ranges */
#define HOME_UNREACHABLE (-1)

static int home_q(const sim_arm *a, int idx, double q[ARM_NJ])
{
    double T[16], R[9], p_arm[3], Tw[16], Tinv[16], pw[4];
    arm_tool tool;
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    arm_ik_result r;
    const double q_ref[ARM_NJ] = { 0.0, 0.6, 2.9, 0.0, -0.4, 0.0 };
    int b;
    arm_tool_offset(&tool, off);
    cell_world_from_arm(&cell_default, idx, Tw);
    tf_inverse(Tinv, Tw);
    vec3_copy(pw, cell_default.home_tool_m[idx]);
    rot_apply(p_arm,
              (double[9]){ Tinv[0], Tinv[1], Tinv[2], Tinv[4], Tinv[5], Tinv[6], Tinv[8], Tinv[9],
                           Tinv[10] },
              pw);
    p_arm[0] += Tinv[3];
    p_arm[1] += Tinv[7];
    p_arm[2] += Tinv[11];
    cell_tool_down_R(&cell_default, idx, R);
    tf_from_rot_pos(T, R, p_arm);
    if (arm_ik(a->model, &tool, T, &r) != 0 || r.unreachable)
        return HOME_UNREACHABLE;
    b = arm_ik_nearest(&r, q_ref);
    if (b < 0)
        return HOME_UNREACHABLE;
    memcpy(q, r.branch[b].q_rad, sizeof(double) * ARM_NJ);
    return 0;
}

static void on_command(const lcm_recv_buf_t *rb, const char *ch, void *user);

/* Arm k (0-based) at its start pose: bodies, hinges and range stops. */
static int build_arm(sim_world *w, const sim_config *cfg, sim_arm *a, int k)
{
    double Tl[ARM_NJ + 1][16];
    int i;
    memset(a, 0, sizeof *a);
    a->model = sim_arms_model(cfg, k);
    a->holding = -1;
    a->mode = TANDEM_ARM_COMMAND_T_MODE_BRAKE;
    cell_world_from_arm(&cell_default, k, a->T_world_mount);
    if (k == 0 && cfg->arm1_q0_set)
        memcpy(a->q_init, cfg->arm1_q0_rad, sizeof a->q_init);
    else if (home_q(a, k, a->q_init) != 0) {
        fprintf(stderr, "tandem-sim: arm %d home pose has no IK solution\n", k + 1);
        return SIM_ERR_CREATE;
    }
    arm_link_frames(a->model, a->q_init, Tl);
    for (i = 0; i < ARM_NJ; i++)
        build_link(w, a, i, Tl);
    for (i = 0; i < ARM_NJ; i++)
        build_joint(w, a, i, Tl);
    memcpy(a->q, a->q_init, sizeof a->q);
    return 0;
}

static int arms_create(void *model, sim_world *w, const sim_config *cfg)
{
    sim_arms *arms = model;
    int k;
    arms->cfg = cfg;
    arms->w = w;
    for (k = 0; k < SIM_ARMS; k++) {
        sim_arms_channel *ch = &arms->chan[k];
        if (build_arm(w, cfg, &arms->pair[k], k) != 0)
            return SIM_ERR_CREATE;
        ch->arms = arms;
        ch->k = k;
        /* after a reset the same subscription (rx_subscribe); a renewed
         * handle takes it over */
        daemon_subscribe(&w->d, command_channel[k], on_command, ch);
    }
    return 0;
}

static void arms_destroy(void *model, sim_world *w)
{
    sim_arms *arms = model;
    (void)w;
    /* bodies, joints and the stick's geom go with the ODE world: the
     * stick must not outlive it (a seed reset builds a new world) */
    arms->stick = NULL;
}

/* ---- commands in ---------------------------------------------------------- */

static int command_valid(const sim_arm *a, int idx, const tandem_arm_command_t *c)
{
    int i;
    if (c->arm != idx + 1 || c->step < 0)
        return 0;
    if (c->mode != TANDEM_ARM_COMMAND_T_MODE_TORQUE && c->mode != TANDEM_ARM_COMMAND_T_MODE_BRAKE)
        return 0;
    if (c->gripper < TANDEM_ARM_COMMAND_T_GRIP_KEEP || c->gripper > TANDEM_ARM_COMMAND_T_GRIP_OPEN)
        return 0;
    for (i = 0; i < ARM_NJ; i++)
        if (!isfinite(c->tau_Nm[i]) ||
            fabs(c->tau_Nm[i]) > ARM_TAU_REJECT_FACTOR * a->model->tau_max_Nm[i])
            return 0;
    return 1;
}

/* A command answers a state the simulator published: its step is at most
 * the simulator's own and no older than the watchdog's limit (an older one
 * would be stale on arrival). Checked against the simulator's step, not
 * only the last command's, so one command from the future cannot latch. */
static int command_step_plausible(const sim_arm *a, int64_t now, int64_t step)
{
    return step <= now && step >= now - ARM_STALE_STEPS && step >= a->cmd_step;
}

static void on_command(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    const sim_arms_channel *ch = user;
    sim_world *w = ch->arms->w;
    sim_arm *a = &ch->arms->pair[ch->k];
    tandem_arm_command_t c;
    (void)channel;
    if (!DAEMON_DECODE(&w->d.msgs, tandem_arm_command_t, rb, &c))
        return;
    if (!command_valid(a, ch->k, &c)) {
        w->d.msgs.rejected++;
        return;
    }
    if (!command_step_plausible(a, w->step, c.step)) {
        w->d.msgs.rejected++;
        return;
    }
    memcpy(a->tau_cmd, c.tau_Nm, sizeof a->tau_cmd);
    a->mode = c.mode;
    a->cmd_step = c.step;
    a->have_cmd = 1;
    if (c.gripper == TANDEM_ARM_COMMAND_T_GRIP_CLOSE)
        a->gripper_closed = 1;
    else if (c.gripper == TANDEM_ARM_COMMAND_T_GRIP_OPEN)
        a->gripper_closed = 0;
}

/* ---- the step ------------------------------------------------------------- */

static void read_joints(sim_arm *a)
{
    int i;
    for (i = 0; i < ARM_NJ; i++) {
        /* ODE hinge angles wrap at +-pi; q1, q4, q6 may travel further
         * (e.g. q1 through the shoulder singularity): keep q continuous */
        const double raw = a->q_init[i] + dJointGetHingeAngle(a->joint[i]);
        a->q[i] = raw + 6.283185307179586 * floor((a->q[i] - raw) / 6.283185307179586 + 0.5);
        a->qd[i] = dJointGetHingeAngleRate(a->joint[i]);
    }
}

/* ---- limits held by the mechanics and the drives --------------------------- */

/* Range stops of joint i for this step: the stop motor's angle is 0 and
 * the range ends are given relative to the joint's angle q, so they stay
 * inside ODE's window whatever q is; an end further than STOP_WINDOW_RAD
 * gets none this step. ODE keeps lo <= hi: open hi first. */
static void joint_stops(sim_arm *a, int i)
{
    const double lo = a->model->q_min_rad[i] - a->q[i];
    const double hi = a->model->q_max_rad[i] - a->q[i];
    dJointSetAMotorAngle(a->stop[i], 0, 0.0);
    dJointSetAMotorParam(a->stop[i], dParamHiStop, dInfinity);
    dJointSetAMotorParam(a->stop[i], dParamLoStop, lo > -STOP_WINDOW_RAD ? lo : -dInfinity);
    dJointSetAMotorParam(a->stop[i], dParamHiStop, hi < STOP_WINDOW_RAD ? hi : dInfinity);
}

/* Joint i's drive for one step. Braking (or a joint above the guard speed,
 * driven there by outside forces): a velocity motor towards 0 (or back to
 * the guard speed) with the peak torque, a hard constraint (cfm0, the
 * world's). Otherwise the commanded torque tau with the rotor's reflected
 * inertia J, implicitly: a velocity motor whose target is qd + h tau / J,
 * softened into a damper of J / h (CFM = h / J, no force bound), pulls
 * with (qd + h tau / J - qd') J / h = tau - J qdd', so the joint moves as
 * (M + J) qdd = tau + ..., the controllers' model (arm_rne); a target
 * past the speed limit is the limit, held with at most |tau|. Without an
 * armature (J = 0): the torque through a motor whose target is the speed
 * limit, as before. Returns the torque the drive was asked for. */
static double drive_motor(sim_arm *a, int i, int brake, double cfm0)
{
    const double lim = a->model->tau_max_Nm[i], vmax = a->model->qd_max_radps[i];
    const double J = a->model->armature_kgm2[i];
    const double qd = a->qd[i];
    double tau = brake ? 0.0 : a->tau_cmd[i], vel, fmax, cfm = cfm0;
    tau = tau > lim ? lim : (tau < -lim ? -lim : tau);
    if (brake) {
        vel = 0.0;
        fmax = lim;
    } else if (fabs(qd) > DRIVE_SPEED_GUARD * vmax) {
        vel = (qd > 0.0 ? 1.0 : -1.0) * DRIVE_SPEED_GUARD * vmax;
        fmax = lim;
        tau = 0.0;
        a->speed_brakes++;
    } else if (J > 0.0) {
        vel = qd + SIM_DT_S * tau / J;
        fmax = dInfinity;
        cfm = SIM_DT_S / J;
        if (fabs(vel) > vmax) {
            vel = vel > 0.0 ? vmax : -vmax;
            fmax = fabs(tau);
        }
    } else {
        vel = tau >= 0.0 ? vmax : -vmax;
        fmax = fabs(tau);
    }
    dJointSetHingeParam(a->joint[i], dParamVel, vel);
    dJointSetHingeParam(a->joint[i], dParamFMax, fmax);
    dJointSetHingeParam(a->joint[i], dParamCFM, cfm);
    return tau;
}

static double friction_Nm(const sim_config *cfg, double qd)
{
    /* tanh smooths the Coulomb sign so the integrator does not chatter. */
    return -cfg->arm_friction_viscous * qd - cfg->arm_friction_coulomb * tanh(qd / 0.01);
}

static void arms_before_step(void *model, sim_world *w)
{
    sim_arms *arms = model;
    int k, i;
    for (k = 0; k < SIM_ARMS; k++) {
        sim_arm *a = &arms->pair[k];
        const int stale = !a->have_cmd || w->step - a->cmd_step > ARM_STALE_STEPS;
        const int brake = stale || a->mode == TANDEM_ARM_COMMAND_T_MODE_BRAKE;
        if (stale && !a->stale && a->have_cmd)
            w->stale_commands++;
        a->stale = stale;
        read_joints(a);
        for (i = 0; i < ARM_NJ; i++) {
            joint_stops(a, i);
            if (a->q[i] <= a->model->q_min_rad[i] || a->q[i] >= a->model->q_max_rad[i])
                a->limit_stops++;
            a->tau_applied[i] = drive_motor(a, i, brake, dWorldGetCFM(w->world));
            dJointAddHingeTorque(a->joint[i], friction_Nm(arms->cfg, a->qd[i]));
        }
    }
}

void sim_arm_tool(const sim_arm *a, double p_world[3], double R_world[9])
{
    double T[16], Tw[16];
    arm_tool tool;
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    arm_tool_offset(&tool, off);
    arm_fk(a->model, &tool, a->q, T);
    tf_mul(Tw, a->T_world_mount, T);
    tf_pos(p_world, Tw);
    if (R_world)
        tf_rot(R_world, Tw);
}

/* Per link: the contact force of this step, and its moving average over
 * the last SIM_FORCE_AVG_STEPS steps (a force sensor's 10 ms filter). */
static void contact_sense(const sim_world *w, sim_arm *a)
{
    const int slot = (int)(w->step % SIM_FORCE_AVG_STEPS);
    int i, j;
    a->max_contact_N = a->max_contact_avg_N = 0.0;
    for (i = 0; i < ARM_NJ; i++) {
        double sum = 0.0;
        a->contact_N[i] = sim_contact_force_on(w, a->link[i]);
        a->contact_hist_N[i][slot] = a->contact_N[i];
        for (j = 0; j < SIM_FORCE_AVG_STEPS; j++)
            sum += a->contact_hist_N[i][j];
        a->contact_avg_N[i] = sum / SIM_FORCE_AVG_STEPS;
        a->max_contact_N = fmax(a->max_contact_N, a->contact_N[i]);
        a->max_contact_avg_N = fmax(a->max_contact_avg_N, a->contact_avg_N[i]);
    }
}

static void publish_state(sim_arms *arms, sim_world *w, int k)
{
    sim_arm *a = &arms->pair[k];
    tandem_arm_state_t s;
    int i;
    read_joints(a);
    memset(&s, 0, sizeof s);
    s.seq = a->seq++;
    s.utime = daemon_utime_now();
    s.step = w->step;
    s.sim_time_s = w->time_s;
    s.arm = (int8_t)(k + 1);
    contact_sense(w, a);
    for (i = 0; i < ARM_NJ; i++) {
        s.q_rad[i] = a->q[i];
        s.qd_radps[i] = a->qd[i];
        s.tau_applied_Nm[i] = a->tau_applied[i];
        s.contact_force_N[i] = a->contact_N[i];
        s.contact_force_10ms_N[i] = a->contact_avg_N[i];
    }
    s.max_contact_force_N = a->max_contact_N;
    s.max_contact_force_10ms_N = a->max_contact_avg_N;
    sim_arm_tool(a, s.tool_position_m, NULL);
    s.gripper_closed = (int8_t)a->gripper_closed;
    s.holding_workpiece = a->holding;
    AUTH_PUBLISH(tandem_arm_state_t, &w->d.bus, w->d.lcm, state_channel[k], &s);
}

static void arms_after_step(void *model, sim_world *w)
{
    int k;
    for (k = 0; k < SIM_ARMS; k++)
        publish_state(model, w, k);
}

static int arms_control(void *model, sim_world *w, const tandem_sim_control_t *c)
{
    return sim_stick_control(model, w, c);
}

static void arms_status(const void *model, const sim_world *w, tandem_sim_status_t *s)
{
    (void)w;
    sim_stick_status(model, s);
}

/* Lockstep: the step moves on only with each arm's command answering it
 * (the state step it was computed from), when the arm's controller
 * (tandem-arm-N) takes part and owes one: a command lost on the way is
 * asked for again by announcing the step again (the controller sends it
 * again, its repeat), never replaced by the one before, which would make
 * the run depend on what the network lost. */
static int arms_ready(const void *model, const sim_world *w, int64_t k)
{
    const sim_arms *arms = model;
    char name[DAEMON_NAME_MAX];
    int i;
    for (i = 0; i < SIM_ARMS; i++) {
        int64_t owed;
        snprintf(name, sizeof name, "tandem-arm-%d", i + 1);
        owed = sim_lockstep_owed_step(w, name, k);
        if (owed >= 0 && (!arms->pair[i].have_cmd || arms->pair[i].cmd_step < owed))
            return 0;
    }
    return 1;
}

const sim_model_ops sim_arms_ops = { "arms",           arms_create,     arms_destroy,
                                     arms_before_step, arms_after_step, arms_control,
                                     arms_status,      arms_ready,      NULL };
