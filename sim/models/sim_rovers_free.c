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
 * Here such a robot leaves ODE. Its bodies and hinges move to a parking
 * world that is never stepped, its chassis box leaves the broad phase, and
 * a few numbers carry it: the axle centre C, moved along the unicycle's
 * exact arc (formation.md §1) for the wheel speeds v = (g_l + g_r) / 2,
 * w = (g_l - g_r) / track, g = rim (1 - slip), each wheel's turn and the
 * encoders at the motor's speed. Its commands, ramps and slip noise are
 * drawn as for any robot, so the noise streams do not change. When it
 * comes back, every body takes the planar rigid motion about C from where
 * it left to where it is, each wheel turned about its axle, with the
 * velocities of the rolling.
 *
 * Why not just disable the bodies (the first way): ODE walks every body
 * and joint of a world at each step, disabled ones too, and touching each
 * robot's ODE objects every step is a few kB per robot: at 10,000 robots
 * that no longer stays in the cache, and the CPU per robot-step was twice
 * the 1,000-robot figure (docs/benchmarks.md, "Many hosts").
 *
 * What keeps it safe: the clearance (the truth's, to walls and to every
 * other robot) is checked every RV_FREE_CHECK_PHYS rover steps, and a
 * robot is free only beyond a margin that two robots closing at the speed
 * limit cannot use up before the next check; below it, it rejoins the
 * solver. A free robot found overlapping anything at a check would mean
 * that bound failed: it is counted (free_overlaps, printed at exit) and
 * it_rover_far requires none.
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

/* ---- the planar motion -------------------------------------------------- */

/* The rigid motion about C0 turning by dth to C1. */
typedef struct free_motion {
    pose2 c0, c1;
    double cos_dth, sin_dth;
    dQuaternion qz; /* the turn */
} free_motion;

static void motion_between(free_motion *m, const pose2 *c0, const pose2 *c1)
{
    const double dth = c1->theta_rad - c0->theta_rad;
    m->c0 = *c0;
    m->c1 = *c1;
    m->cos_dth = cos(dth);
    m->sin_dth = sin(dth);
    dQFromAxisAndAngle(m->qz, 0, 0, 1, dth);
}

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
static void set_rolling_velocity(dBodyID b, const pose2 *c, double v, double w)
{
    const dReal *p = dBodyGetPosition(b);
    dBodySetLinearVel(b, v * cos(c->theta_rad) - w * (p[1] - c->y_m),
                      v * sin(c->theta_rad) + w * (p[0] - c->x_m), 0.0);
}

/* C along the unicycle's exact arc for (v, w) over dt. */
static void arc_step(pose2 *c, double v, double w, double dt)
{
    const double dth = w * dt, s0 = sin(c->theta_rad), k0 = cos(c->theta_rad);
    c->theta_rad += dth;
    if (fabs(dth) < 1e-9) {
        c->x_m += v * dt * k0;
        c->y_m += v * dt * s0;
    } else {
        c->x_m += v / w * (sin(c->theta_rad) - s0);
        c->y_m -= v / w * (cos(c->theta_rad) - k0);
    }
}

void sim_rovers_free_move(sim_rover *r, double dt)
{
    double g[2];
    int s;
    for (s = 0; s < 2; s++) {
        g[s] = r->motor_radps[s] * RV_WHEEL_R * (1.0 - r->slip[s]);
        r->enc[s] += r->motor_radps[s] * dt;
        /* ODE's hinge rate is the chassis' against the wheel about the
         * axis: the wheel turns by -rate about it */
        r->free_spin_rad[s] -= r->motor_radps[s] * dt;
    }
    r->free_v_mps = 0.5 * (g[0] + g[1]);
    r->free_w_radps = (g[1] - g[0]) / RV_TRACK; /* wheel 0 is the left one */
    arc_step(&r->free_c, r->free_v_mps, r->free_w_radps, dt);
}

/* The parked bodies (as they stood when the robot left the solver) to
 * where the rolling took C, with its velocities. */
static void bodies_catch_up(sim_rover *r)
{
    static const dQuaternion q_none = { 1, 0, 0, 0 };
    const double v = r->free_v_mps, w = r->free_w_radps;
    free_motion m;
    dVector3 axis;
    int s;
    motion_between(&m, &r->free_c0, &r->free_c);
    for (s = 0; s < 2; s++) {
        dQuaternion spin;
        dJointGetHingeAxis(r->hinge[s], axis); /* as it left: the chassis has not moved */
        dQFromAxisAndAngle(spin, axis[0], axis[1], axis[2], r->free_spin_rad[s]);
        move_body(r->wheel[s], &m, spin);
    }
    move_body(r->chassis, &m, q_none);
    set_rolling_velocity(r->chassis, &r->free_c, v, w);
    dBodySetAngularVel(r->chassis, 0.0, 0.0, w);
    for (s = 0; s < 2; s++) {
        dJointGetHingeAxis(r->hinge[s], axis);
        set_rolling_velocity(r->wheel[s], &r->free_c, v, w);
        dBodySetAngularVel(r->wheel[s], -axis[0] * r->motor_radps[s], -axis[1] * r->motor_radps[s],
                           w - axis[2] * r->motor_radps[s]);
    }
}

/* ---- in and out of the solver's world ------------------------------------ */

/* A copy of body b in world `to` (mass, state, owner, geoms); b stays. */
static dBodyID body_copy(dBodyID b, dWorldID to)
{
    const dReal *p = dBodyGetPosition(b), *v = dBodyGetLinearVel(b), *a = dBodyGetAngularVel(b);
    dBodyID c = dBodyCreate(to);
    dGeomID g = dBodyGetFirstGeom(b);
    dMass m;
    dBodyGetMass(b, &m);
    dBodySetMass(c, &m);
    dBodySetPosition(c, p[0], p[1], p[2]);
    dBodySetQuaternion(c, dBodyGetQuaternion(b));
    dBodySetLinearVel(c, v[0], v[1], v[2]);
    dBodySetAngularVel(c, a[0], a[1], a[2]);
    dBodySetData(c, dBodyGetData(b));
    while (g) {
        dGeomID next = dBodyGetNextGeom(g);
        dGeomSetBody(g, c);
        g = next;
    }
    return c;
}

/* Wheel hinge h again in world `to` between the copied bodies, with its
 * anchor, axis and motor; h destroyed. */
static dJointID hinge_move(dJointID h, dWorldID to, dBodyID chassis, dBodyID wheel,
                           double motor_radps)
{
    dJointID c = dJointCreateHinge(to, 0);
    dVector3 anchor, axis;
    dJointGetHingeAnchor(h, anchor);
    dJointGetHingeAxis(h, axis);
    dJointAttach(c, chassis, wheel);
    dJointSetHingeAnchor(c, anchor[0], anchor[1], anchor[2]);
    dJointSetHingeAxis(c, axis[0], axis[1], axis[2]);
    dJointSetHingeParam(c, dParamFMax, dJointGetHingeParam(h, dParamFMax));
    dJointSetHingeParam(c, dParamVel, motor_radps);
    dJointDestroy(h);
    return c;
}

/* Robot r's bodies and hinges into world `to`; the simulator's state hash
 * follows them (the same slots). */
static void robot_move(sim_rovers *team, sim_rover *r, dWorldID to)
{
    dBodyID b[3];
    int s;
    b[0] = body_copy(r->chassis, to);
    for (s = 0; s < 2; s++)
        b[1 + s] = body_copy(r->wheel[s], to);
    for (s = 0; s < 2; s++)
        r->hinge[s] = hinge_move(r->hinge[s], to, b[0], b[1 + s], r->motor_radps[s]);
    dBodyDestroy(r->chassis);
    r->chassis = b[0];
    for (s = 0; s < 2; s++) {
        dBodyDestroy(r->wheel[s]);
        r->wheel[s] = b[1 + s];
    }
    if (r->hash_slot >= 0)
        for (s = 0; s < 3; s++)
            team->w->bodies[r->hash_slot + s] = b[s];
}

static void set_free(sim_rovers *team, sim_rover *r, int on)
{
    if (r->free == on)
        return;
    if (on) {
        sim_rover_pose_c(r, &r->free_c0);
        r->free_c = r->free_c0;
        r->free_spin_rad[0] = r->free_spin_rad[1] = 0.0;
        r->free_v_mps = r->free_w_radps = 0.0;
        robot_move(team, r, team->park);
        dGeomDisable(r->box);
    } else {
        bodies_catch_up(r);
        robot_move(team, r, team->world);
        dGeomEnable(r->box);
    }
    r->free = on;
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
        if (!r->alive)
            continue;
        if (r->free && team->s.cl[i] <= 0.0)
            team->free_overlaps++;
        set_free(team, r,
                 w->step >= RV_FREE_SETTLE_STEPS && team->s.cl[i] > margin_m && !r->bump_now);
    }
}

uint64_t sim_rovers_free_hash(const void *model, uint64_t h)
{
    const sim_rovers *team = model;
    int i;
    for (i = 0; i < team->n; i++) {
        const sim_rover *r = &team->r[i];
        if (!r->free)
            continue;
        h = sim_hash_bytes(h, &r->free_c, sizeof r->free_c);
        h = sim_hash_bytes(h, r->free_spin_rad, sizeof r->free_spin_rad);
        h = sim_hash_bytes(h, r->enc, sizeof r->enc);
    }
    return h;
}
