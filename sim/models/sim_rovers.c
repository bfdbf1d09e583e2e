/* sim_rovers: Pioneer 2 DX robots (SPEC.md §4, §5).
 *
 * Each robot: a 0.44 x 0.38 m chassis box (8 kg) with a frictionless caster
 * ball, two 0.5 kg wheels (r 0.0825 m, track 0.33 m) on hinge motors; wheel
 * slip is a Gauss-Markov surface velocity on each wheel's ground contact
 * (so encoders and true motion disagree a little, as on the floor).
 * Speed limits (default 0.75 m/s, 100 deg/s) and acceleration ramps apply
 * to the held command; a command older than --rover-stale (0.5 s of sim
 * time) stops the robot.
 *
 * Cost: the rovers live in their own ODE world, stepped every 4 ms on the
 * simulator's clock (exact solver while no chassis touches anything,
 * QuickStep otherwise: see rovers_before_step), apart from the PUMA pair's
 * world. Contacts are only wheel/caster-floor (computed directly: spheres on
 * a plane) and chassis-obstacle/chassis-chassis, found by a hash-space
 * broad phase that holds nothing but chassis boxes and obstacles.
 * Their bodies still enter the simulator's state hash. They stand at
 * x > 4 m, away from the work cell, in the world layout of rover_world.
 *
 * Sensors (LCM): ROVERk_SENSORS (encoders, 20 Hz) and ROVERk_SONAR (the
 * latest echo of each transducer, 20 Hz, sent with the encoders as the
 * Pioneer's own packet does; the transducers fire one per 40 ms in the
 * Pioneer order, sonar_cast on a primitive list of the obstacles and the
 * other robots' boxes rebuilt every firing), ROVERk_BEACONS (camera at O on
 * a pan unit stepping ahead/left/ahead/right: LED beacons of mates and the
 * world's LED landmarks within 6 m and +-60 deg of where it looks, line of
 * sight, noise; 10 Hz),
 * ROVER_TRUTH (ground truth, 20 Hz, for metrics only). With --rover-batch
 * the same frames of all robots go out as one message per tick
 * (ROVERS_SENSORS, ROVERS_BEACONS); commands are taken on ROVERk_COMMAND
 * and ROVERS_COMMAND alike. KILL_ROBOT removes a robot from the world.
 */
#include "sim.h"
#include "sim_rovers.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "formation.h"
#include "prng.h"
#include "rover_world.h"
#include "sonar.h"
#include "unicycle.h"
#include "tandem_beacon_obs_t.h"
#include "tandem_rover_command_t.h"
#include "tandem_rover_sensors_t.h"
#include "tandem_rover_truth_t.h"
#include "tandem_rovers_beacons_t.h"
#include "tandem_rovers_command_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_sonar_scan_t.h"

#define RV_MAX            ROVER_WORLD_MAX_ROBOTS
#define RV_WHEEL_R        0.0825
#define RV_TRACK          0.33
#define RV_CHASSIS_H      0.20
#define RV_CHASSIS_Z      0.15
#define RV_CASTER_R       0.04
#define RV_SENSORS_STEPS  ROVER_SENSOR_PERIOD_STEPS
#define RV_BEACON_STEPS   ROVER_CAMERA_PERIOD_STEPS
#define RV_TRUTH_STEPS    50
#define RV_CAM_RANGE_M    6.0
#define RV_CAM_HALF_FOV   (60.0 * VEC2_PI / 180.0)
#define RV_BEACON_Z_M     0.30
#define RV_SLIP_SD        0.005
#define RV_SLIP_TAU_S     0.5
#define RV_ACCEL_V        1.0     /* m/s^2 */
#define RV_ACCEL_W        3.0     /* rad/s^2 */

typedef struct rover {
    int32_t id;
    int     alive;
    dBodyID chassis, wheel[2];
    dJointID hinge[2];
    dGeomID box;
    double  cmd_v, cmd_w;             /* held (clipped) command */
    double  v_ref, w_ref;             /* after the acceleration ramp */
    int64_t cmd_rx_step;
    int64_t cmd_step;         /* the step the held command answers (-1 none) */
    int     have_cmd, stale;
    double  slip[2];
    double  enc[2];                   /* accumulated wheel angles */
    double  range[SONAR_N];
    int     bump_now, bump_prev, collisions;
    double  min_clear;
    prng_state  rng;
    int     prim;                     /* its box in the sonar world */
    int     fired;                    /* transducer fired last */
    int64_t seq_sens, seq_sonar, seq_beacon;
} rover;

static struct {
    int      n;
    rover    r[RV_MAX];
    rover_world_config layout;
    sonar_world sw;
    sonar_model sm;
    dWorldID world;
    dSpaceID space;
    dJointGroupID contacts;
    dGeomID  obst[ROVER_WORLD_MAX_OBST];
    double   sonar_angle_rad[SONAR_N];
    lcm_subscription_t *sub, *sub_batch;
    sim_world *w;
    int      batch;                   /* 1: ROVERS_* messages, not ROVERk_* */
    int64_t  batch_seq[2];
    double   v_max, w_max, stale_s;
    int      phys_steps;
    int      chassis_contacts;        /* chassis contact joints this step */
    int64_t  quick_steps;             /* steps that fell back to QuickStep */
    int64_t  last_after_step;
    int      beacon_frames;       /* camera frames last drawn (published again on a repeat) */
    int64_t  truth_seq, rejected, rays;
    int      formation;
} R;

/* tunables from the environment (the sim's command line belongs to sim_main) */
static double env_num(const char *name, double def, double lo, double hi)
{
    const char *s = getenv(name);
    char *end;
    double v;
    if (!s || !*s) return def;
    v = strtod(s, &end);
    if (*end || !isfinite(v) || v < lo || v > hi) {
        fprintf(stderr, "tandem-sim: %s='%s' ignored (expected %g..%g)\n", name, s, lo, hi);
        return def;
    }
    return v;
}

static void on_command(const lcm_recv_buf_t *rb, const char *ch, void *u);
static void on_commands(const lcm_recv_buf_t *rb, const char *ch, void *u);

static int rover_index(int32_t id) { return (id >= 1 && id <= R.n) ? id - 1 : -1; }

static void pose_c(const rover *r, pose2 *c)
{
    const dReal *p = dBodyGetPosition(r->chassis);
    const dReal *m = dBodyGetRotation(r->chassis);
    c->theta_rad = atan2(m[4], m[0]);
    c->x_m = p[0] - ROVER_BODY_OFFSET_M * cos(c->theta_rad);
    c->y_m = p[1] - ROVER_BODY_OFFSET_M * sin(c->theta_rad);
}

static void build_robot(rover *r, const pose2 *c, sim_world *w)
{
    const double ct = cos(c->theta_rad), st = sin(c->theta_rad);
    dMass m;
    dMatrix3 rot;
    int s;
    dRFromAxisAndAngle(rot, 0, 0, 1, c->theta_rad);
    r->chassis = dBodyCreate(R.world);
    dMassSetBoxTotal(&m, 8.0, ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, RV_CHASSIS_H);
    dBodySetMass(r->chassis, &m);
    dBodySetPosition(r->chassis, c->x_m + ROVER_BODY_OFFSET_M * ct,
                     c->y_m + ROVER_BODY_OFFSET_M * st, RV_CHASSIS_Z);
    dBodySetRotation(r->chassis, rot);
    dBodySetData(r->chassis, r);
    r->box = dCreateBox(R.space, ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, RV_CHASSIS_H);
    dGeomSetBody(r->box, r->chassis);
    dGeomSetCategoryBits(r->box, SIM_CAT_ROVER);
    dGeomSetCollideBits(r->box, SIM_CAT_ROVER | SIM_CAT_OBSTACLE);
    for (s = 0; s < 2; s++) {
        const double side = s == 0 ? 0.5 * RV_TRACK : -0.5 * RV_TRACK;  /* 0 left, 1 right */
        r->wheel[s] = dBodyCreate(R.world);
        dMassSetSphereTotal(&m, 0.5, RV_WHEEL_R);
        dBodySetMass(r->wheel[s], &m);
        dBodySetPosition(r->wheel[s], c->x_m - side * st, c->y_m + side * ct, RV_WHEEL_R);
        dBodySetRotation(r->wheel[s], rot);
        dBodySetData(r->wheel[s], r);
        r->hinge[s] = dJointCreateHinge(R.world, 0);
        dJointAttach(r->hinge[s], r->chassis, r->wheel[s]);
        dJointSetHingeAnchor(r->hinge[s], c->x_m - side * st, c->y_m + side * ct, RV_WHEEL_R);
        dJointSetHingeAxis(r->hinge[s], st, -ct, 0.0);   /* ODE measures body1 vs body2: +rate rolls forward */
        dJointSetHingeParam(r->hinge[s], dParamFMax, 1.5);
        dJointSetHingeParam(r->hinge[s], dParamVel, 0.0);
    }
    /* the sim's state hash covers the rover bodies too */
    if (w->n_bodies + 3 <= SIM_MAX_BODIES) {
        w->bodies[w->n_bodies++] = r->chassis;
        w->bodies[w->n_bodies++] = r->wheel[0];
        w->bodies[w->n_bodies++] = r->wheel[1];
    }
}

static int rovers_create(sim_world *w, const sim_config *cfg)
{
    int i, world;
    char pattern[32];
    memset(&R, 0, sizeof R);
    R.w = w;
    world = rover_world_id(cfg->rover_world);
    R.formation = cfg->rover_formation;   /* the rovers get the same --formation */
    if (cfg->rovers < 1 || cfg->rovers > RV_MAX || world < 0 ||
        rover_world_layout(&R.layout, world, cfg->rovers, 1.0, R.formation) != 0) {
        fprintf(stderr, "tandem-sim: --rovers %d --world %s: not a valid team (1..%d robots)\n",
                cfg->rovers, cfg->rover_world, RV_MAX);
        return -1;
    }
    R.n = cfg->rovers;
    R.batch = cfg->rover_batch;
    R.last_after_step = -1;
    R.v_max = env_num("TANDEM_ROVER_VMAX", 0.75, 0.05, 2.0);
    R.w_max = env_num("TANDEM_ROVER_WMAX_DEG", 100.0, 5.0, 360.0) * VEC2_PI / 180.0;
    R.stale_s = env_num("TANDEM_ROVER_STALE_S", 0.5, 0.01, 10.0);
    R.phys_steps = (int)env_num("TANDEM_ROVER_PHYS_STEPS", 4, 1, 10);
    sonar_model_default(&R.sm);
    for (i = 0; i < SONAR_N; i++) R.sonar_angle_rad[i] = sonar_p2dx_front[i].angle_rad;
    R.world = dWorldCreate();
    dWorldSetGravity(R.world, 0, 0, -9.81);
    dWorldSetERP(R.world, 0.2);
    dWorldSetCFM(R.world, 1e-5);
    dWorldSetQuickStepNumIterations(R.world, 10);
    R.space = dHashSpaceCreate(0);
    dHashSpaceSetLevels(R.space, -3, 4);
    R.contacts = dJointGroupCreate(0);
    for (i = 0; i < R.layout.n_obst; i++) {
        const rover_obstacle *o = &R.layout.obst[i];
        dGeomID g;
        if (o->kind == ROVER_OBST_CIRCLE) {
            g = dCreateCylinder(R.space, o->r_m, o->height_m);
        } else {
            dMatrix3 rot;
            g = dCreateBox(R.space, 2.0 * o->hx_m, 2.0 * o->hy_m, o->height_m);
            dRFromAxisAndAngle(rot, 0, 0, 1, o->angle_rad);
            dGeomSetRotation(g, rot);
        }
        dGeomSetPosition(g, o->cx_m, o->cy_m, 0.5 * o->height_m);
        dGeomSetCategoryBits(g, SIM_CAT_OBSTACLE);
        dGeomSetCollideBits(g, SIM_CAT_ROVER);
        R.obst[i] = g;
    }
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        r->id = i + 1;
        r->alive = 1;
        r->cmd_step = -1;
        r->min_clear = INFINITY;
        prng_seed(&r->rng, w->seed * 1000003ULL + (uint64_t)r->id);
        build_robot(r, &R.layout.start_c[i], w);
        {
            int k;
            for (k = 0; k < SONAR_N; k++) r->range[k] = R.sm.range_max_m;
        }
    }
    snprintf(pattern, sizeof pattern, "ROVER[0-9]+_COMMAND");
    if (w->lcm) {
        /* a whole team answers in one burst: the deep queue of
         * daemon_subscribe keeps large teams' commands */
        R.sub = daemon_subscribe(&w->d, pattern, on_command, NULL);
        R.sub_batch = daemon_subscribe(&w->d, "ROVERS_COMMAND", on_commands, NULL);
    }
    fprintf(stderr, "tandem-sim: %d Pioneer robots in world '%s' (goal %.1f, %.1f)\n", R.n,
            cfg->rover_world, R.layout.goal_m[0], R.layout.goal_m[1]);
    return 0;
}

static void rovers_destroy(sim_world *w)
{
    if (R.world)
        fprintf(stderr, "tandem-sim: rovers: %lld of %lld physics steps had chassis contacts "
                "(QuickStep)\n", (long long)R.quick_steps, (long long)(w->step / R.phys_steps));
    if (R.sub && R.w && R.w->lcm) lcm_unsubscribe(R.w->lcm, R.sub);
    if (R.sub_batch && R.w && R.w->lcm) lcm_unsubscribe(R.w->lcm, R.sub_batch);
    R.sub = R.sub_batch = NULL;
    if (R.world) {
        dJointGroupDestroy(R.contacts);
        dSpaceDestroy(R.space);
        dWorldDestroy(R.world);
        R.world = NULL;
    }
}

/* ---- commands ------------------------------------------------------------- */

/* SPEC 7: the right robot (on its own channel, when it has one), finite,
 * physically sane; anything else is counted and changes nothing. */
static void take_command(const tandem_rover_command_t *m, int chan_id)
{
    const int idx = rover_index(m->robot);
    rover *r;
    if (idx < 0 || (chan_id >= 0 && chan_id != m->robot) || !isfinite(m->v_mps) ||
        !isfinite(m->w_radps) || fabs(m->v_mps) > 5.0 || fabs(m->w_radps) > 20.0 ||
        m->step < 0 || m->step > R.w->step) {   /* an answer to a step not taken yet */
        R.w->d.msgs.rejected++;
        R.rejected++;
        return;
    }
    r = &R.r[idx];
    /* an older command than the one held is stale; in lockstep one for the
     * same step is a copy (republished after a loss) and changes nothing */
    if (m->step < r->cmd_step || (R.w->lockstep && m->step == r->cmd_step)) {
        R.w->d.msgs.duplicate++;
        return;
    }
    r->cmd_step = m->step;
    r->cmd_v = fmax(-R.v_max, fmin(R.v_max, m->v_mps));
    r->cmd_w = fmax(-R.w_max, fmin(R.w_max, m->w_radps));
    r->cmd_rx_step = R.w->step;
    r->have_cmd = 1;
}

static void on_command(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_rover_command_t m;
    int chan_id = 0;
    (void)u;
    if (!DAEMON_DECODE(&R.w->d.msgs, tandem_rover_command_t, rb, &m))
        return;
    sscanf(ch, "ROVER%d_COMMAND", &chan_id);
    take_command(&m, chan_id);
}

static void on_commands(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_rovers_command_t m;
    int i;
    (void)ch; (void)u;
    if (!DAEMON_DECODE(&R.w->d.msgs, tandem_rovers_command_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++) take_command(&m.cmd[i], -1);
    tandem_rovers_command_t_decode_cleanup(&m);
}

static double ramp(double cur, double target, double max_step)
{
    if (target > cur + max_step) return cur + max_step;
    if (target < cur - max_step) return cur - max_step;
    return target;
}

/* ---- physics ---------------------------------------------------------------- */

static rover *rover_of_body(dBodyID b) { return b ? (rover *)dBodyGetData(b) : NULL; }

static void near_cb(void *data, dGeomID g1, dGeomID g2)
{
    dContact c[4];
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    int n, i;
    (void)data;
    if (b1 && b2 && dAreConnected(b1, b2)) return;
    n = dCollide(g1, g2, 4, &c[0].geom, sizeof(dContact));
    if (n <= 0) return;
    /* chassis against an obstacle or another chassis: a collision */
    {
        rover *r1 = rover_of_body(b1), *r2 = rover_of_body(b2);
        if (r1) r1->bump_now = 1;
        if (r2) r2->bump_now = 1;
        R.chassis_contacts += n;
    }
    for (i = 0; i < n; i++) {
        dJointID j;
        memset(&c[i].surface, 0, sizeof c[i].surface);
        c[i].surface.mode = dContactSoftERP | dContactSoftCFM | dContactApprox1;
        c[i].surface.mu = 0.3;
        c[i].surface.soft_erp = 0.3;
        c[i].surface.soft_cfm = 1e-4;
        j = dJointCreateContact(R.world, R.contacts, &c[i]);
        dJointAttach(j, b1, b2);
    }
}

/* Floor contacts without a broad phase: the wheels and the caster are
 * spheres on the plane z = 0, so each is one contact when it touches.
 * Wheels grip along their rolling direction, with the slip noise as a
 * surface velocity; the caster is frictionless. */
static void floor_contact(rover *r, dBodyID b, const dVector3 p, double radius, int wheel)
{
    dContact c;
    dJointID j;
    const double depth = radius - p[2];
    if (depth < -0.001) return;
    memset(&c, 0, sizeof c);
    c.geom.pos[0] = p[0];
    c.geom.pos[1] = p[1];
    c.geom.pos[2] = 0.0;
    c.geom.normal[2] = 1.0;
    c.geom.depth = depth > 0.0 ? depth : 0.0;
    c.surface.mode = dContactSoftERP | dContactSoftCFM | dContactApprox1;
    c.surface.soft_erp = 0.5;
    c.surface.soft_cfm = 1e-4;
    if (wheel >= 0) {
        const dReal *m = dBodyGetRotation(r->chassis);
        const double rim = dJointGetHingeAngleRate(r->hinge[wheel]) * RV_WHEEL_R;
        c.surface.mode |= dContactFDir1 | dContactMotion1;
        c.surface.mu = 1.0;
        c.fdir1[0] = m[0]; c.fdir1[1] = m[4]; c.fdir1[2] = 0.0;
        /* slip: the floor under the wheel gives way a little */
        c.surface.motion1 = -r->slip[wheel] * rim;
    } else {
        c.surface.mu = 0.0;
    }
    j = dJointCreateContact(R.world, R.contacts, &c);
    dJointAttach(j, b, 0);
}

static void floor_contacts(void)
{
    int i, s;
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        dVector3 p;
        if (!r->alive) continue;
        for (s = 0; s < 2; s++) {
            const dReal *q = dBodyGetPosition(r->wheel[s]);
            p[0] = q[0]; p[1] = q[1]; p[2] = q[2];
            floor_contact(r, r->wheel[s], p, RV_WHEEL_R, s);
        }
        dBodyGetRelPointPos(r->chassis, -0.18 - ROVER_BODY_OFFSET_M, 0.0,
                            RV_CASTER_R - RV_CHASSIS_Z, p);
        floor_contact(r, r->chassis, p, RV_CASTER_R, -1);
    }
}

static void rovers_before_step(sim_world *w)
{
    const double dt = SIM_DT_S * R.phys_steps;
    int i, s;
    /* the rover world advances every phys_steps simulator steps (4 ms by
     * default: a wheeled robot at 0.75 m/s moves 3 mm per step; after a
     * 12 s, 9 m drive the encoder totals agree with 1 ms stepping to
     * 0.02 % and the pose differs by less than the wheel slip scatters it
     * between seeds (1-2 cm along the path); it quarters the cost of
     * large teams) */
    if (w->step % R.phys_steps != 0) return;
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        double v, wr;
        if (!r->alive) continue;
        {
            const int was = r->stale;
            r->stale = !r->have_cmd || (double)(w->step - r->cmd_rx_step) * SIM_DT_S > R.stale_s;
            if (r->stale && !was && r->have_cmd) w->stale_commands++;
        }
        v = r->stale ? 0.0 : r->cmd_v;
        wr = r->stale ? 0.0 : r->cmd_w;
        r->v_ref = ramp(r->v_ref, v, RV_ACCEL_V * dt);
        r->w_ref = ramp(r->w_ref, wr, RV_ACCEL_W * dt);
        for (s = 0; s < 2; s++) {
            const double side = s == 0 ? 0.5 * RV_TRACK : -0.5 * RV_TRACK;
            const double rim = r->v_ref - side * r->w_ref;
            dJointSetHingeParam(r->hinge[s], dParamVel, rim / RV_WHEEL_R);
            r->slip[s] += -r->slip[s] / RV_SLIP_TAU_S * dt +
                          RV_SLIP_SD * sqrt(2.0 * dt / RV_SLIP_TAU_S) * prng_gauss(&r->rng);
        }
        r->bump_prev = r->bump_now;
        r->bump_now = 0;
    }
    dJointGroupEmpty(R.contacts);
    floor_contacts();
    R.chassis_contacts = 0;
    dSpaceCollide(R.space, NULL, near_cb);
    /* A robot touching nothing but the floor is an island of 3 bodies,
     * which ODE's exact solver handles as fast as QuickStep; QuickStep's
     * 10 iterations leave a residual that lets a parked robot creep
     * (5 mm/s at 4 ms, 0.02 mm in 4 s exact). Chassis contacts (with
     * friction) make the exact solver's cost grow steeply, and robots
     * pushing each other join islands (cost ~ island size cubed): in a
     * step with any chassis contact, QuickStep bounds the cost. */
    if (R.chassis_contacts == 0) dWorldStep(R.world, dt);
    else {
        dWorldQuickStep(R.world, dt);
        R.quick_steps++;
    }
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        if (!r->alive) continue;
        for (s = 0; s < 2; s++) r->enc[s] += dJointGetHingeAngleRate(r->hinge[s]) * dt;
        if (r->bump_now && !r->bump_prev) r->collisions++;
    }
}

/* ---- sensors ------------------------------------------------------------------ */

static void rebuild_sonar_world(void)
{
    int i;
    sonar_world_init(&R.sw);
    for (i = 0; i < R.layout.n_obst; i++) {
        const rover_obstacle *o = &R.layout.obst[i];
        if (o->kind == ROVER_OBST_CIRCLE)
            sonar_world_add_circle(&R.sw, o->cx_m, o->cy_m, o->r_m, 0.0, o->height_m);
        else
            sonar_world_add_box(&R.sw, o->cx_m, o->cy_m, o->hx_m, o->hy_m, o->angle_rad, 0.0,
                                o->height_m);
    }
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        pose2 c;
        r->prim = -1;
        if (!r->alive) continue;
        pose_c(r, &c);
        r->prim = sonar_world_add_box(&R.sw, c.x_m + ROVER_BODY_OFFSET_M * cos(c.theta_rad),
                                      c.y_m + ROVER_BODY_OFFSET_M * sin(c.theta_rad),
                                      0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M,
                                      c.theta_rad, 0.05, 0.25);
    }
    sonar_world_build(&R.sw);
}

/* Fire the transducer due now on every robot (the Pioneer sequence). */
static void fire_sonars(sim_world *w)
{
    const int k = sonar_fired_index(w->time_s, &R.sm);
    int i;
    rebuild_sonar_world();
    for (i = 0; i < R.n; i++) {
        rover *r = &R.r[i];
        pose2 c;
        if (!r->alive) continue;
        pose_c(r, &c);
        /* a transducer does not hear its own chassis: lift the robot's own
         * box out of the ray plane for its firing */
        if (r->prim >= 0) { R.sw.p[r->prim].z_min = -2.0; R.sw.p[r->prim].z_max = -1.0; }
        sonar_fire(&r->range[k], &R.sw, &R.sm, &c, k, &r->rng);
        R.rays += R.sm.rays_per_cone;
        r->fired = k;
        if (r->prim >= 0) { R.sw.p[r->prim].z_min = 0.05; R.sw.p[r->prim].z_max = 0.25; }
    }
}

/* One robot's hardware frame: encoders + bumper, and the latest echo of
 * every transducer (the Pioneer's own packet carries the readings that
 * came in since the last one, once per control tick). */
static void fill_sensors(rover *r, int64_t step, int64_t utime,
                         tandem_rover_sensors_t *s, tandem_sonar_scan_t *m)
{
    s->seq = r->seq_sens++;
    s->utime = utime;
    s->step = step;
    s->robot = r->id;
    s->wheel_left_rad = r->enc[0];
    s->wheel_right_rad = r->enc[1];
    s->bumper = (int8_t)r->bump_now;
    m->seq = r->seq_sonar++;
    m->utime = utime;
    m->step = step;
    m->robot = r->id;
    m->n = SONAR_N;
    m->angle_rad = R.sonar_angle_rad;
    m->range_m = r->range;
    m->fired = (int8_t)r->fired;
}

static void publish_sensors(sim_world *w)
{
    static tandem_rover_sensors_t s[RV_MAX];
    static tandem_sonar_scan_t m[RV_MAX];
    const int64_t utime = daemon_utime_now();
    int i, n = 0;
    for (i = 0; i < R.n; i++)
        if (R.r[i].alive) fill_sensors(&R.r[i], w->step, utime, &s[n], &m[n]), n++;
    if (R.batch) {
        tandem_rovers_sensors_t b;
        BATCH_HEADER(b, R.batch_seq[0]++, utime, w->step, n);
        b.sensors = s;
        b.sonar = m;
        AUTH_PUBLISH(tandem_rovers_sensors_t, w->lcm, "ROVERS_SENSORS", &b);
        return;
    }
    for (i = 0; i < n; i++) {
        char ch[32];
        snprintf(ch, sizeof ch, "ROVER%d_SENSORS", s[i].robot);
        AUTH_PUBLISH(tandem_rover_sensors_t, w->lcm, ch, &s[i]);
        snprintf(ch, sizeof ch, "ROVER%d_SONAR", s[i].robot);
        AUTH_PUBLISH(tandem_sonar_scan_t, w->lcm, ch, &m[i]);
    }
}

/* One LED at (x, y) seen from camera pose o: appended as target `id`
 * with noisy range and bearing if in view (6 m, the pan's field of view)
 * and not hidden by an obstacle taller than the LED (robots, 0.25 m, do
 * not hide it). */
static int see_led(rover *r, const pose2 *o, double pan, double x, double y, int32_t id,
                   int32_t *tgt, double *rng, double *brg, int n)
{
    const double dx = x - o->x_m, dy = y - o->y_m, d = hypot(dx, dy);
    const double b = vec2_angle_diff_rad(atan2(dy, dx), o->theta_rad);
    sonar_hit hit;
    if (d > RV_CAM_RANGE_M || d < 0.05 || fabs(vec2_angle_diff_rad(b, pan)) > RV_CAM_HALF_FOV)
        return n;
    if (sonar_cast(&hit, &R.sw, o->x_m, o->y_m, RV_BEACON_Z_M, atan2(dy, dx), d) == 1) return n;
    tgt[n] = id;
    rng[n] = d + (0.01 + 0.02 * d) * prng_gauss(&r->rng);
    brg[n] = b + 0.01 * prng_gauss(&r->rng);
    return n + 1;
}

/* Robot i's camera frame: mates' LED beacons and the world's LED landmarks
 * (target ROVER_LANDMARK_ID_BASE + k) in view (range, bearing). */
static void observe_beacons(int i, const pose2 o[], double pan, int64_t step, int64_t utime,
                            int32_t *tgt, double *rng, double *brg, tandem_beacon_obs_t *m)
{
    rover *r = &R.r[i];
    int j, n = 0;
    for (j = 0; j < R.n; j++)
        if (j != i && R.r[j].alive)
            n = see_led(r, &o[i], pan, o[j].x_m, o[j].y_m, R.r[j].id, tgt, rng, brg, n);
    for (j = 0; j < R.layout.n_landmarks; j++)
        n = see_led(r, &o[i], pan, R.layout.landmark_m[j][0], R.layout.landmark_m[j][1],
                    ROVER_LANDMARK_ID_BASE + j, tgt, rng, brg, n);
    m->seq = r->seq_beacon++;
    m->utime = utime;
    m->step = step;
    m->observer = r->id;
    m->n = (int16_t)n;
    m->target = tgt;
    m->range_m = rng;
    m->bearing_rad = brg;
}

/* fresh = 0 (the step announced again): the frames already drawn, again. */
static void publish_beacons(sim_world *w, int fresh)
{
    /* the camera sits on a pan unit that looks ahead, left, ahead, right in
     * turn, one frame each (abreast mates are seen every 0.4 s) */
    static const double pans[4] = { 0.0, 0.5 * VEC2_PI, 0.0, -0.5 * VEC2_PI };
    static int32_t tgt[RV_MAX][RV_MAX + ROVER_WORLD_MAX_LANDMARKS];
    static double rng[RV_MAX][RV_MAX + ROVER_WORLD_MAX_LANDMARKS];
    static double brg[RV_MAX][RV_MAX + ROVER_WORLD_MAX_LANDMARKS];
    static tandem_beacon_obs_t m[RV_MAX];
    int *n = &R.beacon_frames;
    const double pan = pans[(w->step / RV_BEACON_STEPS) % 4];
    const int64_t utime = daemon_utime_now();
    pose2 o[RV_MAX], c;
    int i;
    for (i = 0; fresh && i < R.n; i++) {
        if (!R.r[i].alive) continue;
        pose_c(&R.r[i], &c);
        unicycle_o_from_c(&o[i], &c, ROVER_BEACON_D_M);
    }
    if (fresh) *n = 0;
    for (i = 0; fresh && i < R.n; i++)
        if (R.r[i].alive) observe_beacons(i, o, pan, w->step, utime, tgt[*n], rng[*n], brg[*n], &m[*n]), (*n)++;
    if (R.batch) {
        tandem_rovers_beacons_t b;
        BATCH_HEADER(b, R.batch_seq[1]++, utime, w->step, *n);
        b.obs = m;
        AUTH_PUBLISH(tandem_rovers_beacons_t, w->lcm, "ROVERS_BEACONS", &b);
        return;
    }
    for (i = 0; i < *n; i++) {
        char ch[32];
        snprintf(ch, sizeof ch, "ROVER%d_BEACONS", m[i].observer);
        AUTH_PUBLISH(tandem_beacon_obs_t, w->lcm, ch, &m[i]);
    }
}

static void publish_truth(sim_world *w)
{
    static int32_t id[RV_MAX], col[RV_MAX];
    static double x[RV_MAX], y[RV_MAX], th[RV_MAX], cl[RV_MAX];
    static int8_t al[RV_MAX];
    pose2 c[RV_MAX], o;
    int alive[RV_MAX], i;
    tandem_rover_truth_t m;
    for (i = 0; i < R.n; i++) {
        pose_c(&R.r[i], &c[i]);
        alive[i] = R.r[i].alive;
    }
    rover_world_clearance(&R.layout, c, alive, R.n, cl);
    for (i = 0; i < R.n; i++) {
        unicycle_o_from_c(&o, &c[i], ROVER_BEACON_D_M);
        id[i] = R.r[i].id;
        x[i] = o.x_m;
        y[i] = o.y_m;
        th[i] = o.theta_rad;
        col[i] = R.r[i].collisions;
        al[i] = (int8_t)R.r[i].alive;
        if (!isfinite(cl[i])) cl[i] = 1e3;
    }
    m.seq = R.truth_seq++;
    m.utime = daemon_utime_now();
    m.step = w->step;
    m.sim_time_s = w->time_s;
    m.n = (int16_t)R.n;
    m.robot = id; m.x_m = x; m.y_m = y; m.theta_rad = th;
    m.min_clearance_m = cl; m.collisions = col; m.alive = al;
    AUTH_PUBLISH(tandem_rover_truth_t, w->lcm, "ROVER_TRUTH", &m);
}

static void rovers_after_step(sim_world *w)
{
    /* the simulator re-announces a step while it waits for controllers to
     * start: publish the same readings again, without firing or drawing
     * noise a second time (that would change the run) */
    const int repeat = w->step == R.last_after_step;
    R.last_after_step = w->step;
    const int64_t fire_steps = (int64_t)llround(R.sm.fire_period_s / SIM_DT_S);
    if (w->step % fire_steps == 0 && !repeat) fire_sonars(w);
    if (!w->lcm) return;
    if (w->step % RV_SENSORS_STEPS == 0) publish_sensors(w);
    if (w->step % RV_BEACON_STEPS == 0) publish_beacons(w, !repeat);
    if (w->step % RV_TRUTH_STEPS == 0) publish_truth(w);
}

/* Lockstep: at a control tick every live robot still commanded (it
 * answered one of the last two ticks, or this is the first tick) must have
 * its command for this step before the world moves on -- unless the
 * process hosting it has left the lockstep (killed: its body stands on
 * the held command until that goes stale). */
static int rovers_ready(const sim_world *w, int64_t k)
{
    const int64_t p = RV_SENSORS_STEPS;
    int i;
    if (k % p != 0 || k < p) return 1;
    for (i = 0; i < R.n; i++) {
        const rover *r = &R.r[i];
        const int commanded = k == p || r->cmd_step >= k - 2 * p;
        if (r->alive && commanded && r->cmd_step < k && sim_lockstep_robot_hosted(w, r->id)) return 0;
    }
    return 1;
}

static int rovers_control(sim_world *w, const tandem_sim_control_t *c)
{

    const int idx = rover_index(c->target);
    rover *r;
    (void)w;
    if (c->command != TANDEM_SIM_CONTROL_T_KILL_ROBOT) return 0;
    if (idx < 0) return -1;
    r = &R.r[idx];
    if (!r->alive) return 1;
    r->alive = 0;
    dBodyDisable(r->chassis);
    dBodyDisable(r->wheel[0]);
    dBodyDisable(r->wheel[1]);
    dGeomDisable(r->box);
    fprintf(stderr, "tandem-sim: robot %d killed at t = %.2f s\n", r->id, w->time_s);
    return 1;
}

/* Benchmarks read the ray count and drive the robots through these
 * (declared in sim_rovers.h). */
int64_t sim_rovers_rays_cast(void) { return R.rays; }

int sim_rovers_set_command(int32_t id, double v_mps, double w_radps, int64_t step)
{
    const int idx = rover_index(id);
    if (idx < 0 || !isfinite(v_mps) || !isfinite(w_radps)) return -1;
    R.r[idx].cmd_v = fmax(-R.v_max, fmin(R.v_max, v_mps));
    R.r[idx].cmd_w = fmax(-R.w_max, fmin(R.w_max, w_radps));
    R.r[idx].cmd_rx_step = step;
    R.r[idx].have_cmd = 1;
    return 0;
}

const sim_model_ops sim_rovers_ops = {
    "rovers", rovers_create, rovers_destroy, rovers_before_step, rovers_after_step,
    rovers_control, NULL, rovers_ready
};
