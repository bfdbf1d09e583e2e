/* sim_rovers_free: robots far from everything stepped by their wheels
 * (tandem-sim --rover-far kinematic; docs/method/formation.md §1, "Far
 * robots").
 *
 * A robot whose footprint is clear of every obstacle and every other robot
 * touches nothing but the floor. There its wheels roll without sliding
 * sideways, forward at the motor's speed less the slip (the floor
 * contact's surface velocity, sim_rovers.c floor_contact), and all ODE does
 * is integrate that rolling, at the price of an exact solve of 3 bodies,
 * 2 hinges and 3 contacts every 4 ms: most of a large fleet's CPU.
 *
 * Here such a robot's bodies are disabled (the solver skips them) and moved
 * as the rolling says, the unicycle of formation.md §1 with the wheel
 * speeds v = (g_l + g_r) / 2, w = (g_l - g_r) / track, g = rim (1 - slip):
 * the axle centre C along the exact arc, every body by the same planar
 * rigid motion about C, each wheel turned about its axle, the velocities
 * set to match and the encoders counting the motor's speed. Its commands,
 * ramps and slip noise are drawn as for any robot, so the noise streams do
 * not change. The clearance is checked every RV_FREE_CHECK_PHYS rover steps with a
 * margin that two robots closing at the speed limit cannot use up before
 * the next check; below it (or on any contact ODE reports) the bodies
 * rejoin the solver with the velocities they move at.
 *
 * Left out: the chassis' bounce on its soft contacts and the motors' lag
 * behind the acceleration ramps (bench_fleet measures the difference from
 * the full model).
 */
#include "sim_rovers.h"
#include <math.h>

/* the clearance check's period, in rover steps (12 of 4 ms by default) */
#define RV_FREE_CHECK_PHYS 12
/* not before the robots stand settled on their wheels */
#define RV_FREE_SETTLE_STEPS 1000
/* the margin beyond two robots closing at the speed limit for a check
 * period: ODE gets them back with room to spare */
#define RV_FREE_SPARE_M 0.15

double sim_rovers_free_margin_m(const sim_rovers *team)
{
    return RV_FREE_SPARE_M + 2.0 * team->v_max * RV_FREE_CHECK_PHYS * team->phys_steps * SIM_DT_S;
}

static void set_free(sim_rover *r, int on)
{
    int s;
    if (r->free == on)
        return;
    r->free = on;
    if (on) {
        dBodyDisable(r->chassis);
        for (s = 0; s < 2; s++)
            dBodyDisable(r->wheel[s]);
    } else {
        dBodyEnable(r->chassis);
        for (s = 0; s < 2; s++)
            dBodyEnable(r->wheel[s]);
    }
}

void sim_rovers_free_check(sim_rovers *team, const sim_world *w)
{
    const double margin_m = sim_rovers_free_margin_m(team);
    int i;
    if (!team->far_kinematic || w->step % ((int64_t)RV_FREE_CHECK_PHYS * team->phys_steps) != 0)
        return;
    sim_rovers_clearance(team);
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        if (r->alive)
            set_free(r,
                     w->step >= RV_FREE_SETTLE_STEPS && team->s.cl[i] > margin_m && !r->bump_now);
    }
}

/* The step's planar rigid motion: about C0, turning by dth, to C1. */
typedef struct free_motion {
    pose2 c0, c1;
    double cos_dth, sin_dth, cos_th1, sin_th1;
    dQuaternion qz; /* the turn */
} free_motion;

/* Moves body b by the motion m, after turning it by q_extra (world frame). */
static void move_body(dBodyID b, const free_motion *m, const dQuaternion q_extra)
{
    const dReal *p = dBodyGetPosition(b);
    const double rx = p[0] - m->c0.x_m, ry = p[1] - m->c0.y_m;
    dQuaternion q1, q2;
    dBodySetPosition(b, m->c1.x_m + m->cos_dth * rx - m->sin_dth * ry,
                     m->c1.y_m + m->sin_dth * rx + m->cos_dth * ry, p[2]);
    dQMultiply0(q1, q_extra, dBodyGetQuaternion(b));
    dQMultiply0(q2, m->qz, q1);
    dBodySetQuaternion(b, q2);
}

/* The velocity of a point of the rolling robot: C's v along the heading,
 * turning at w about C. */
static void set_rolling_velocity(dBodyID b, const free_motion *m, double v, double w)
{
    const dReal *p = dBodyGetPosition(b);
    dBodySetLinearVel(b, v * m->cos_th1 - w * (p[1] - m->c1.y_m),
                      v * m->sin_th1 + w * (p[0] - m->c1.x_m), 0.0);
}

/* C0 -> C1 along the unicycle's exact arc for (v, w) over dt. */
static void arc_motion(free_motion *m, const pose2 *c0, double v, double w, double dt)
{
    const double dth = w * dt, s0 = sin(c0->theta_rad), k0 = cos(c0->theta_rad);
    m->c0 = *c0;
    m->c1 = *c0;
    m->c1.theta_rad = c0->theta_rad + dth;
    m->cos_dth = cos(dth);
    m->sin_dth = sin(dth);
    m->cos_th1 = k0 * m->cos_dth - s0 * m->sin_dth;
    m->sin_th1 = s0 * m->cos_dth + k0 * m->sin_dth;
    if (fabs(dth) < 1e-9) {
        m->c1.x_m += v * dt * k0;
        m->c1.y_m += v * dt * s0;
    } else {
        m->c1.x_m += v / w * (m->sin_th1 - s0);
        m->c1.y_m -= v / w * (m->cos_th1 - k0);
    }
    dQFromAxisAndAngle(m->qz, 0, 0, 1, dth);
}

void sim_rovers_free_move(sim_rover *r, double dt)
{
    static const dQuaternion q_none = { 1, 0, 0, 0 };
    double rate[2], g[2], v, w;
    pose2 c0;
    free_motion m;
    dVector3 axis;
    int s;
    for (s = 0; s < 2; s++) {
        rate[s] = dJointGetHingeParam(r->hinge[s], dParamVel); /* the motor's, rad/s */
        g[s] = rate[s] * RV_WHEEL_R * (1.0 - r->slip[s]);
        r->enc[s] += rate[s] * dt;
    }
    v = 0.5 * (g[0] + g[1]);
    w = (g[1] - g[0]) / RV_TRACK; /* wheel 0 is the left one */
    sim_rover_pose_c(r, &c0);
    arc_motion(&m, &c0, v, w, dt);
    for (s = 0; s < 2; s++) {
        dQuaternion spin;
        /* ODE's hinge rate is the chassis' against the wheel about the
         * axis: the wheel turns by -rate about it */
        dJointGetHingeAxis(r->hinge[s], axis);
        dQFromAxisAndAngle(spin, axis[0], axis[1], axis[2], -rate[s] * dt);
        move_body(r->wheel[s], &m, spin);
    }
    move_body(r->chassis, &m, q_none);
    set_rolling_velocity(r->chassis, &m, v, w);
    dBodySetAngularVel(r->chassis, 0.0, 0.0, w);
    for (s = 0; s < 2; s++) {
        dJointGetHingeAxis(r->hinge[s], axis);
        set_rolling_velocity(r->wheel[s], &m, v, w);
        dBodySetAngularVel(r->wheel[s], -axis[0] * rate[s], -axis[1] * rate[s],
                           w - axis[2] * rate[s]);
    }
}
