/* sim_rovers: Pioneer 2 DX robots (docs/method/formation.md §1, sonar.md).
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
 * Sensors (sim_rovers_sense.c): sonar, encoders, bumper, camera and
 * ground truth on LCM. Commands are taken on ROVERk_COMMAND and
 * ROVERS_COMMAND alike. KILL_ROBOT removes a robot from the world.
 */
#include "sim_rovers.h"
#include "world_file.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "formation.h"
#include "tandem_rover_command_t.h"
#include "tandem_rovers_command_t.h"

#define RV_CHASSIS_H 0.20
#define RV_CHASSIS_Z 0.15
#define RV_CASTER_R 0.04
#define RV_SLIP_SD 0.005
#define RV_SLIP_TAU_S 0.5
#define RV_ACCEL_V 1.0 /* m/s^2 */
#define RV_ACCEL_W 3.0 /* rad/s^2 */

/* tunables from the environment (the sim's command line belongs to sim_main) */
static double env_num(const char *name, double def, double lo, double hi)
{
    const char *s = getenv(name);
    char *end;
    double v;
    if (!s || !*s)
        return def;
    v = strtod(s, &end);
    if (*end || !isfinite(v) || v < lo || v > hi) {
        fprintf(stderr, "tandem-sim: %s='%s' ignored (expected %g..%g)\n", name, s, lo, hi);
        return def;
    }
    return v;
}

static void on_command(const lcm_recv_buf_t *rb, const char *ch, void *u);
static void on_commands(const lcm_recv_buf_t *rb, const char *ch, void *u);

static int rover_index(const sim_rovers *team, int32_t id)
{
    return (id >= 1 && id <= team->n) ? id - 1 : -1;
}

void sim_rover_pose_c(const sim_rover *r, pose2 *c)
{
    if (r->free) { /* out of ODE: its bodies stand where it left the solver */
        *c = r->free_c;
        return;
    }
    const dReal *p = dBodyGetPosition(r->chassis);
    const dReal *m = dBodyGetRotation(r->chassis);
    c->theta_rad = atan2(m[4], m[0]);
    c->x_m = p[0] - ROVER_BODY_OFFSET_M * cos(c->theta_rad);
    c->y_m = p[1] - ROVER_BODY_OFFSET_M * sin(c->theta_rad);
}

void sim_rovers_sonar_model(sonar_model *m)
{
    sonar_model_default(m);
}

static void build_robot(sim_rovers *team, sim_rover *r, const pose2 *c, sim_world *w)
{
    const double ct = cos(c->theta_rad), st = sin(c->theta_rad);
    dMass m;
    dMatrix3 rot;
    int s;
    dRFromAxisAndAngle(rot, 0, 0, 1, c->theta_rad);
    r->chassis = dBodyCreate(team->world);
    dMassSetBoxTotal(&m, 8.0, ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, RV_CHASSIS_H);
    dBodySetMass(r->chassis, &m);
    dBodySetPosition(r->chassis, c->x_m + ROVER_BODY_OFFSET_M * ct,
                     c->y_m + ROVER_BODY_OFFSET_M * st, RV_CHASSIS_Z);
    dBodySetRotation(r->chassis, rot);
    dBodySetData(r->chassis, r);
    r->box = dCreateBox(team->space, ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M, RV_CHASSIS_H);
    dGeomSetBody(r->box, r->chassis);
    dGeomSetCategoryBits(r->box, SIM_CAT_ROVER);
    dGeomSetCollideBits(r->box, SIM_CAT_ROVER | SIM_CAT_OBSTACLE);
    for (s = 0; s < 2; s++) {
        const double side = s == 0 ? 0.5 * RV_TRACK : -0.5 * RV_TRACK; /* 0 left, 1 right */
        r->wheel[s] = dBodyCreate(team->world);
        dMassSetSphereTotal(&m, 0.5, RV_WHEEL_R);
        dBodySetMass(r->wheel[s], &m);
        dBodySetPosition(r->wheel[s], c->x_m - side * st, c->y_m + side * ct, RV_WHEEL_R);
        dBodySetRotation(r->wheel[s], rot);
        dBodySetData(r->wheel[s], r);
        r->hinge[s] = dJointCreateHinge(team->world, 0);
        dJointAttach(r->hinge[s], r->chassis, r->wheel[s]);
        dJointSetHingeAnchor(r->hinge[s], c->x_m - side * st, c->y_m + side * ct, RV_WHEEL_R);
        dJointSetHingeAxis(r->hinge[s], st, -ct,
                           0.0); /* ODE measures body1 vs body2: +rate rolls forward */
        dJointSetHingeParam(r->hinge[s], dParamFMax, 1.5);
        dJointSetHingeParam(r->hinge[s], dParamVel, 0.0);
    }
    /* the sim's state hash covers the rover bodies too */
    r->hash_slot = -1;
    if (w->n_bodies + 3 <= SIM_MAX_BODIES) {
        r->hash_slot = w->n_bodies;
        w->bodies[w->n_bodies++] = r->chassis;
        w->bodies[w->n_bodies++] = r->wheel[0];
        w->bodies[w->n_bodies++] = r->wheel[1];
    }
}

/* The team's layout and tunables; SIM_ERR_CREATE (said) for a team the world
 * cannot hold. */
static int team_layout(sim_rovers *team, const sim_config *cfg)
{
    const world_opts wo = { rover_world_id(cfg->rover_world), cfg->rover_world_file,
                            cfg->rover_start, cfg->rover_goal };
    int i;
    team->formation = cfg->rover_formation; /* the rovers get the same --formation */
    if (cfg->rovers < 1 || cfg->rovers > RV_MAX || (wo.world < 0 && !wo.file)) {
        fprintf(stderr,
                "tandem-sim: --rovers %d --world %s: not a valid fleet (1..%d robots: "
                "ROVER_WORLD_MAX_ROBOTS, set at build time)\n",
                cfg->rovers, cfg->rover_world, RV_MAX);
        return SIM_ERR_CREATE;
    }
    if (world_opts_fleet_layout(&team->layout, &team->fleet, &wo, cfg->rovers, cfg->rover_teams,
                                cfg->rover_per_team, cfg->rover_team_goals, team->formation,
                                "tandem-sim") != 0)
        return SIM_ERR_CREATE;
    team->n = cfg->rovers;
    team->batch = cfg->rover_batch;
    team->last_after_step = -1;
    team->v_max = env_num("TANDEM_ROVER_VMAX", 0.75, 0.05, 2.0);
    team->w_max = env_num("TANDEM_ROVER_WMAX_DEG", 100.0, 5.0, 360.0) * VEC2_PI / 180.0;
    team->stale_s = env_num("TANDEM_ROVER_STALE_S", 0.5, 0.01, 10.0);
    team->phys_steps = (int)env_num("TANDEM_ROVER_PHYS_STEPS", 4, 1, 10);
    team->far_kinematic = cfg->rover_far_kinematic;
    {
        const char *nb = getenv("TANDEM_SIM_NEIGHBOURS");
        team->brute = nb && strcmp(nb, "scan") == 0;
    }
    sim_rovers_sonar_model(&team->sm);
    for (i = 0; i < SONAR_N; i++)
        team->sonar_angle_rad[i] = sonar_p2dx_front[i].angle_rad;
    return 0;
}

/* The rovers' own ODE world with the layout's obstacles. */
static void team_world_create(sim_rovers *team)
{
    int i;
    team->world = dWorldCreate();
    team->park = dWorldCreate();
    dWorldSetGravity(team->world, 0, 0, -9.81);
    dWorldSetERP(team->world, 0.2);
    dWorldSetCFM(team->world, 1e-5);
    dWorldSetQuickStepNumIterations(team->world, 10);
    team->space = dHashSpaceCreate(0);
    dHashSpaceSetLevels(team->space, -3, 4);
    team->contacts = dJointGroupCreate(0);
    for (i = 0; i < team->layout.n_obst; i++) {
        const rover_obstacle *o = &team->layout.obst[i];
        dGeomID g;
        if (o->kind == ROVER_OBST_CIRCLE) {
            g = dCreateCylinder(team->space, o->r_m, o->height_m);
        } else {
            dMatrix3 rot;
            g = dCreateBox(team->space, 2.0 * o->hx_m, 2.0 * o->hy_m, o->height_m);
            dRFromAxisAndAngle(rot, 0, 0, 1, o->angle_rad);
            dGeomSetRotation(g, rot);
        }
        dGeomSetPosition(g, o->cx_m, o->cy_m, 0.5 * o->height_m);
        dGeomSetCategoryBits(g, SIM_CAT_OBSTACLE);
        dGeomSetCollideBits(g, SIM_CAT_ROVER);
        team->obst[i] = g;
    }
}

static void team_robots_create(sim_rovers *team, sim_world *w)
{
    int i, k;
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        r->id = i + 1;
        r->alive = 1;
        r->cmd_step = -1;
        r->min_clear = INFINITY;
        prng_seed(&r->rng, w->seed * 1000003ULL + (uint64_t)r->id);
        build_robot(team, r, &team->layout.start_c[i], w);
        for (k = 0; k < SONAR_N; k++)
            r->range[k] = team->sm.range_max_m;
    }
}

/* Every per-robot array, once, for n robots: nothing is allocated after. */
static void team_free(sim_rovers *team)
{
    sim_rovers_scratch *s = &team->s;
    sim_rovers_frames *f = &team->frames;
    void *p[] = { team->r,     f->obs,   f->target,    f->range_m,  f->bearing_rad, s->sens,
                  s->scan,     s->pose,  s->cam,       s->x,        s->y,           s->th,
                  s->cl,       s->id,    s->col,       s->near,     s->al,          s->alive,
                  s->cam_grid, s->clear, s->post_grid, s->post_near };
    size_t i;
    for (i = 0; i < sizeof p / sizeof p[0]; i++)
        free(p[i]);
    team->r = NULL;
    memset(f, 0, sizeof *f);
    memset(s, 0, sizeof *s);
}

static int team_alloc(sim_rovers *team, int n)
{
    sim_rovers_scratch *s = &team->s;
    sim_rovers_frames *f = &team->frames;
    const size_t k = (size_t)n;
    team->r = calloc(k, sizeof *team->r);
    f->obs = calloc(k, sizeof *f->obs);
    f->target = calloc(k, sizeof *f->target);
    f->range_m = calloc(k, sizeof *f->range_m);
    f->bearing_rad = calloc(k, sizeof *f->bearing_rad);
    s->sens = calloc(k, sizeof *s->sens);
    s->scan = calloc(k, sizeof *s->scan);
    s->pose = calloc(k, sizeof *s->pose);
    s->cam = calloc(k, sizeof *s->cam);
    s->x = calloc(k, sizeof *s->x);
    s->y = calloc(k, sizeof *s->y);
    s->th = calloc(k, sizeof *s->th);
    s->cl = calloc(k, sizeof *s->cl);
    s->id = calloc(k, sizeof *s->id);
    s->col = calloc(k, sizeof *s->col);
    s->near = calloc(k, sizeof *s->near);
    s->al = calloc(k, sizeof *s->al);
    s->alive = calloc(k, sizeof *s->alive);
    s->cam_grid = calloc(1, sizeof *s->cam_grid);
    s->clear = calloc(1, sizeof *s->clear);
    s->post_grid = calloc(1, sizeof *s->post_grid);
    s->post_near = calloc(ROVER_WORLD_MAX_POSTS, sizeof *s->post_near);
    if (!team->r || !f->obs || !f->target || !f->range_m || !f->bearing_rad || !s->sens ||
        !s->scan || !s->pose || !s->cam || !s->x || !s->y || !s->th || !s->cl || !s->id ||
        !s->col || !s->near || !s->al || !s->alive || !s->cam_grid || !s->clear || !s->post_grid ||
        !s->post_near) {
        fprintf(stderr, "tandem-sim: no memory for %d robots\n", n);
        team_free(team);
        return SIM_ERR_CREATE;
    }
    return 0;
}

static int rovers_create(void *model, sim_world *w, const sim_config *cfg)
{
    sim_rovers *team = model;
    memset(team, 0, sizeof *team);
    team->w = w;
    if (team_layout(team, cfg) != 0 || team_alloc(team, team->n) != 0 ||
        sim_rovers_index_posts(team) != 0)
        return SIM_ERR_CREATE;
    team_world_create(team);
    team_robots_create(team, w);
    if (w->d.lcm) {
        /* a whole team answers in one burst: the deep queue of
         * daemon_subscribe keeps large teams' commands. Subscribed once
         * for the daemon's life: after a reset the same subscriptions
         * (rx_subscribe), and a renewed handle takes them over. */
        lcm_subscription_t *sub[DAEMON_EXPLICIT_MAX];
        daemon_subscribe_numbered(&w->d, "ROVER", 1, team->n, "_COMMAND", on_command, team, sub,
                                  DAEMON_EXPLICIT_MAX);
        daemon_subscribe(&w->d, "ROVERS_COMMAND", on_commands, team);
    }
    fprintf(stderr, "tandem-sim: %d Pioneer robots in world '%s' (goal %.1f, %.1f)\n", team->n,
            cfg->rover_world_file ? cfg->rover_world_file : cfg->rover_world,
            team->layout.goal_m[0], team->layout.goal_m[1]);
    return 0;
}

static void rovers_destroy(void *model, sim_world *w)
{
    sim_rovers *team = model;
    if (team->world)
        fprintf(stderr,
                "tandem-sim: rovers: %lld of %lld physics steps had chassis contacts "
                "(QuickStep); free robots found touching: %lld\n",
                (long long)team->quick_steps, (long long)(w->step / team->phys_steps),
                (long long)team->free_overlaps);
    if (team->world) {
        dJointGroupDestroy(team->contacts);
        dSpaceDestroy(team->space);
        dWorldDestroy(team->world);
        dWorldDestroy(team->park);
        team->world = NULL;
        team->park = NULL;
    }
    team_free(team);
}

/* ---- commands ------------------------------------------------------------- */

/* docs/method/lockstep.md §6: the right robot (on its own channel, when it has one), finite,
 * physically sane; anything else is counted and changes nothing. */
static void take_command(sim_rovers *team, const tandem_rover_command_t *m, int chan_id)
{
    const int idx = rover_index(team, m->robot);
    sim_rover *r;
    if (idx < 0 || (chan_id >= 0 && chan_id != m->robot) || !isfinite(m->v_mps) ||
        !isfinite(m->w_radps) || fabs(m->v_mps) > 5.0 || fabs(m->w_radps) > 20.0 || m->step < 0 ||
        m->step > team->w->step) { /* an answer to a step not taken yet */
        team->w->d.msgs.rejected++;
        team->rejected++;
        return;
    }
    r = &team->r[idx];
    /* an older command than the one held is stale; in lockstep one for the
     * same step is a copy (republished after a loss) and changes nothing */
    if (m->step < r->cmd_step || (team->w->lockstep && m->step == r->cmd_step)) {
        team->w->d.msgs.duplicate++;
        return;
    }
    r->cmd_step = m->step;
    r->cmd_v = fmax(-team->v_max, fmin(team->v_max, m->v_mps));
    r->cmd_w = fmax(-team->w_max, fmin(team->w_max, m->w_radps));
    r->cmd_rx_step = team->w->step;
    r->have_cmd = 1;
}

static void on_command(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    sim_rovers *team = u;
    tandem_rover_command_t m;
    int chan_id = 0;
    if (!DAEMON_DECODE(&team->w->d.msgs, tandem_rover_command_t, rb, &m))
        return;
    sscanf(ch, "ROVER%d_COMMAND", &chan_id);
    take_command(team, &m, chan_id);
}

static void on_commands(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    sim_rovers *team = u;
    tandem_rovers_command_t m;
    int i;
    (void)ch;
    if (!DAEMON_DECODE(&team->w->d.msgs, tandem_rovers_command_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++) {
        /* a rover host commands its own robots alone */
        if (!auth_bus_sender_covers(&team->w->d.bus, m.cmd[i].robot)) {
            team->w->d.msgs.rejected++;
            team->rejected++;
            continue;
        }
        take_command(team, &m.cmd[i], -1);
    }
    tandem_rovers_command_t_decode_cleanup(&m);
}

static double ramp(double cur, double target, double max_step)
{
    if (target > cur + max_step)
        return cur + max_step;
    if (target < cur - max_step)
        return cur - max_step;
    return target;
}

/* ---- physics ---------------------------------------------------------------- */

static sim_rover *rover_of_body(dBodyID b)
{
    return b ? (sim_rover *)dBodyGetData(b) : NULL;
}

static void near_cb(void *data, dGeomID g1, dGeomID g2)
{
    dContact c[4];
    sim_rovers *team = data;
    dBodyID b1 = dGeomGetBody(g1), b2 = dGeomGetBody(g2);
    int n, i;
    if (b1 && b2 && dAreConnected(b1, b2))
        return;
    n = dCollide(g1, g2, 4, &c[0].geom, sizeof(dContact));
    if (n <= 0)
        return;
    /* chassis against an obstacle or another chassis: a collision */
    {
        sim_rover *r1 = rover_of_body(b1), *r2 = rover_of_body(b2);
        if (r1)
            r1->bump_now = 1;
        if (r2)
            r2->bump_now = 1;
        team->chassis_contacts += n;
    }
    for (i = 0; i < n; i++) {
        dJointID j;
        memset(&c[i].surface, 0, sizeof c[i].surface);
        c[i].surface.mode = dContactSoftERP | dContactSoftCFM | dContactApprox1;
        c[i].surface.mu = 0.3;
        c[i].surface.soft_erp = 0.3;
        c[i].surface.soft_cfm = 1e-4;
        j = dJointCreateContact(team->world, team->contacts, &c[i]);
        dJointAttach(j, b1, b2);
    }
}

/* Floor contacts without a broad phase: the wheels and the caster are
 * spheres on the plane z = 0, so each is one contact when it touches.
 * Wheels grip along their rolling direction, with the slip noise as a
 * surface velocity; the caster is frictionless. */
static void floor_contact(sim_rovers *team, sim_rover *r, dBodyID b, const dVector3 p,
                          double radius, int wheel)
{
    dContact c;
    dJointID j;
    const double depth = radius - p[2];
    if (depth < -0.001)
        return;
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
        c.fdir1[0] = m[0];
        c.fdir1[1] = m[4];
        c.fdir1[2] = 0.0;
        /* slip: the floor under the wheel gives way a little */
        c.surface.motion1 = -r->slip[wheel] * rim;
    } else {
        c.surface.mu = 0.0;
    }
    j = dJointCreateContact(team->world, team->contacts, &c);
    dJointAttach(j, b, 0);
}

static void floor_contacts(sim_rovers *team)
{
    int i, s;
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        dVector3 p;
        if (!r->alive || r->free)
            continue;
        for (s = 0; s < 2; s++) {
            const dReal *q = dBodyGetPosition(r->wheel[s]);
            p[0] = q[0];
            p[1] = q[1];
            p[2] = q[2];
            floor_contact(team, r, r->wheel[s], p, RV_WHEEL_R, s);
        }
        dBodyGetRelPointPos(r->chassis, -0.18 - ROVER_BODY_OFFSET_M, 0.0,
                            RV_CASTER_R - RV_CHASSIS_Z, p);
        floor_contact(team, r, r->chassis, p, RV_CASTER_R, -1);
    }
}

/* Robot r's wheel motors for the next dt: the held command (nothing once
 * stale) through the acceleration ramps, and its wheels' slip drawn on. */
static void drive(sim_rovers *team, sim_rover *r, sim_world *w, double dt)
{
    const int was = r->stale;
    double v, wr;
    int s;
    r->stale = !r->have_cmd || (double)(w->step - r->cmd_rx_step) * SIM_DT_S > team->stale_s;
    if (r->stale && !was && r->have_cmd)
        w->stale_commands++;
    v = r->stale ? 0.0 : r->cmd_v;
    wr = r->stale ? 0.0 : r->cmd_w;
    r->v_ref = ramp(r->v_ref, v, RV_ACCEL_V * dt);
    r->w_ref = ramp(r->w_ref, wr, RV_ACCEL_W * dt);
    for (s = 0; s < 2; s++) {
        const double side = s == 0 ? 0.5 * RV_TRACK : -0.5 * RV_TRACK;
        const double rim = r->v_ref - side * r->w_ref;
        r->motor_radps[s] = rim / RV_WHEEL_R;
        if (!r->free) /* a free robot's hinges wait in the parking world */
            dJointSetHingeParam(r->hinge[s], dParamVel, r->motor_radps[s]);
        r->slip[s] += -r->slip[s] / RV_SLIP_TAU_S * dt +
                      RV_SLIP_SD * sqrt(2.0 * dt / RV_SLIP_TAU_S) * prng_gauss(&r->rng);
    }
    r->bump_prev = r->bump_now;
    r->bump_now = 0;
}

/* One step of the rovers' world: contacts, then the solver. */
static void team_world_step(sim_rovers *team, double dt)
{
    dJointGroupEmpty(team->contacts);
    floor_contacts(team);
    team->chassis_contacts = 0;
    dSpaceCollide(team->space, team, near_cb);
    /* A robot touching nothing but the floor is an island of 3 bodies,
     * which ODE's exact solver handles as fast as QuickStep; QuickStep's
     * 10 iterations leave a residual that lets a parked robot creep
     * (5 mm/s at 4 ms, 0.02 mm in 4 s exact). Chassis contacts (with
     * friction) make the exact solver's cost grow steeply, and robots
     * pushing each other join islands (cost ~ island size cubed): in a
     * step with any chassis contact, QuickStep bounds the cost. */
    if (team->chassis_contacts == 0)
        dWorldStep(team->world, dt);
    else {
        dWorldQuickStep(team->world, dt);
        team->quick_steps++;
    }
}

static void rovers_before_step(void *model, sim_world *w)
{
    sim_rovers *team = model;
    const double dt = SIM_DT_S * team->phys_steps;
    int i, s;
    /* the rover world advances every phys_steps simulator steps (4 ms by
     * default: a wheeled robot at 0.75 m/s moves 3 mm per step; after a
     * 12 s, 9 m drive the encoder totals agree with 1 ms stepping to
     * 0.02 % and the pose differs by less than the wheel slip scatters it
     * between seeds (1-2 cm along the path); it quarters the cost of
     * large teams) */
    if (w->step % team->phys_steps != 0)
        return;
    for (i = 0; i < team->n; i++)
        if (team->r[i].alive)
            drive(team, &team->r[i], w, dt);
    sim_rovers_free_check(team, w);
    team_world_step(team, dt);
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        if (!r->alive)
            continue;
        if (r->free)
            sim_rovers_free_move(r, dt);
        else
            for (s = 0; s < 2; s++)
                r->enc[s] += dJointGetHingeAngleRate(r->hinge[s]) * dt;
        if (r->bump_now && !r->bump_prev)
            r->collisions++;
    }
}

/* Lockstep: at a control tick every live robot still commanded (it
 * answered one of the last two ticks, or this is the first tick) must have
 * its command for this step before the world moves on -- unless the
 * process hosting it has left the lockstep (killed: its body stands on
 * the held command until that goes stale). */
static int rovers_ready(const void *model, const sim_world *w, int64_t k)
{
    const sim_rovers *team = model;
    const int64_t p = RV_SENSORS_STEPS;
    int i;
    if (k % p != 0 || k < p)
        return 1;
    for (i = 0; i < team->n; i++) {
        const sim_rover *r = &team->r[i];
        const int commanded = k == p || r->cmd_step >= k - 2 * p;
        if (r->alive && commanded && r->cmd_step < k && sim_lockstep_robot_hosted(w, r->id))
            return 0;
    }
    return 1;
}

static int rovers_control(void *model, sim_world *w, const tandem_sim_control_t *c)
{
    sim_rovers *team = model;
    const int idx = rover_index(team, c->target);
    sim_rover *r;
    if (c->command != TANDEM_SIM_CONTROL_T_KILL_ROBOT)
        return 0;
    if (idx < 0)
        return SIM_ERR_CONTROL;
    r = &team->r[idx];
    if (!r->alive)
        return 1;
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
int64_t sim_rovers_rays_cast(const sim_rovers *team)
{
    return team->rays;
}

int sim_rovers_set_command(sim_rovers *team, int32_t id, double v_mps, double w_radps, int64_t step)
{
    const int idx = rover_index(team, id);
    if (idx < 0 || !isfinite(v_mps) || !isfinite(w_radps))
        return SIM_ROVERS_ERR_ARG;
    team->r[idx].cmd_v = fmax(-team->v_max, fmin(team->v_max, v_mps));
    team->r[idx].cmd_w = fmax(-team->w_max, fmin(team->w_max, w_radps));
    team->r[idx].cmd_rx_step = step;
    team->r[idx].have_cmd = 1;
    return 0;
}

const sim_model_ops sim_rovers_ops = {
    "rovers",       rovers_create, rovers_destroy, rovers_before_step,  sim_rovers_after_step,
    rovers_control, NULL,          rovers_ready,   sim_rovers_free_hash
};
