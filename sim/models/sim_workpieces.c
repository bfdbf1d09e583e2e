/* sim_workpieces: the table, the workpiece stream, the vision camera and
 * the grippers of the carry task (docs/method/carry.md §5, lockstep.md §3).
 *
 * Workpieces are bars (cell_default.workpiece_size_m) drawn from a fixed
 * pool of ODE bodies: a parked body is disabled and its geom off, so the
 * world's body list (and the state hash) never sees a freed body. A new
 * bar appears in the pick zone (seeded uniform spread in x, y and a small
 * yaw) whenever the zone has been clear for WP_SPAWN_DELAY_S, until
 * --workpieces are spawned (0 = endless).
 *
 * Gripper: an arm whose command closed the gripper grasps a bar when its
 * tool point is within cell_default.grasp_tolerance_m of that arm's grasp
 * point on it (arm 1 the -x end, arm 2 the +x end): a fixed joint to the
 * flange. A bar picked from the table is first re-centred in the fingers
 * (self-centring jaws: bar axis along the flange x axis, grasp point on
 * the tool point); a bar already held by the other arm (hand-over) is
 * attached where it is. Opening the gripper removes the joint.
 *
 * A bar released and at rest inside the delivery zone is counted
 * delivered and parked; one at rest anywhere else after it left the pick
 * zone (or on the floor) is counted dropped and parked, except on the
 * hand-over stand (--handover-stand): a task's buffer, where it waits for
 * an arm to take it (docs/tasks.md §6). The stand has two places, the
 * hand-over and cell_default.stand_b_center_m behind it, each its own box,
 * so two bars rest on it apart.
 *
 * Arm 2's magazine (--magazine, docs/tasks.md §8): a feeder that presents
 * one bar at cell_default.magazine_center_m, along x, when arm 2's tool
 * comes within WP_MAGAZINE_CALL_M of the point above it (ABOVE_MAGAZINE)
 * with nothing in its gripper and the magazine empty, while fewer than
 * --workpieces are spawned: a bar comes out only for an arm about to take
 * it, so none is left there at the end. A bar in the magazine is not seen
 * by the camera (arm 2 takes it at a fixed pose) and is not counted
 * dropped; taken and released at the delivery pose, it is delivered.
 *
 * Camera: VISION_DETECTIONS at 20 Hz with the free bars lying at rest,
 * positions with Gaussian noise (VISION_SIGMA_M) and yaw noise.
 * Bars collide with the table and the ground only.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "sim_workpieces.h"
#include "cell.h"
#include "vec3.h"
#include "tandem_workpiece_detections_t.h"

#define WP_SPAWN_DELAY_S 0.5
#define WP_REST_SPEED_MPS 0.01
#define WP_REST_TIME_S 0.2
#define WP_PICK_RADIUS_M 0.15
#define WP_DELIVER_RADIUS_M 0.10
/* The stand: narrower than the grasp points are apart (2 x 0.10 m) so the
 * fingers close beside it, its top this far below a bar held at the
 * hand-over so a bar released there drops onto it instead of being
 * pressed into it by an arm's tracking error. */
#define WP_STAND_SIZE_X_M 0.08
#define WP_STAND_SIZE_Y_M 0.04
#define WP_STAND_DROP_M 0.002
#define WP_STAND_RADIUS_M 0.05 /* a bar this near the stand's axis rests on it */
#define WP_YAW_SPREAD_RAD 0.05
#define WP_MAGAZINE_CALL_M 0.03 /* arm 2's tool this near above the magazine calls a bar */
#define VISION_PERIOD_STEPS 50
#define VISION_SIGMA_M 0.001
#define VISION_SIGMA_YAW_RAD 0.005

static double table_top_z(void)
{
    return cell_default.table_center_m[2] + 0.5 * cell_default.table_size_m[2];
}

static void park(sim_workpieces *m, int i)
{
    sim_workpiece *p = &m->pool[i];
    int k;
    for (k = 0; k < SIM_ARMS; k++) {
        if (p->hold[k]) {
            dJointDestroy(p->hold[k]);
            p->hold[k] = 0;
            sim_arms_arm(m->arms, k)->holding = -1;
        }
    }
    p->state = WP_PARKED;
    p->id = -1;
    dBodySetPosition(p->body, 0.0, 0.0, -10.0 - (double)i);
    dBodySetLinearVel(p->body, 0, 0, 0);
    dBodySetAngularVel(p->body, 0, 0, 0);
    dBodyDisable(p->body);
    dGeomDisable(p->geom);
}

/* The stand's places: the hand-over, and its second place behind it. */
static const double *stand_place(int k)
{
    return k == 0 ? cell_default.handover_center_m : cell_default.stand_b_center_m;
}

/* One place of the hand-over stand: a box on the table top up to just below
 * a bar held at the place; a table to the bars, nothing to the arms. */
static dGeomID stand_create(sim_world *w, const double *h)
{
    const double top = h[2] - 0.5 * cell_default.workpiece_size_m[2] - WP_STAND_DROP_M;
    const double height = top - table_top_z();
    dGeomID g = dCreateBox(w->space, WP_STAND_SIZE_X_M, WP_STAND_SIZE_Y_M, height);
    dGeomSetPosition(g, h[0], h[1], table_top_z() + 0.5 * height);
    dGeomSetCategoryBits(g, SIM_CAT_TABLE);
    dGeomSetCollideBits(g, SIM_CAT_WORKPIECE);
    return g;
}

static int wp_create(void *model, sim_world *w, const sim_config *cfg)
{
    sim_workpieces *m = model;
    const double *sz = cell_default.workpiece_size_m;
    dMass mass;
    int i;
    m->cfg = cfg;
    memset(m->pool, 0, sizeof m->pool);
    prng_seed(&m->rng, w->seed * 7919u + 17u);
    m->spawned = m->delivered = m->dropped = 0;
    m->last_after_step = -1;
    m->last_n_det = 0;
    m->next_id = 1;
    m->clear_s = 0.0;
    m->spawn_requests = 0;
    m->table_geom = dCreateBox(w->space, cell_default.table_size_m[0], cell_default.table_size_m[1],
                               cell_default.table_size_m[2]);
    dGeomSetPosition(m->table_geom, cell_default.table_center_m[0], cell_default.table_center_m[1],
                     cell_default.table_center_m[2]);
    dGeomSetCategoryBits(m->table_geom, SIM_CAT_TABLE);
    dGeomSetCollideBits(m->table_geom, SIM_CAT_WORKPIECE);
    for (i = 0; i < SIM_STAND_PLACES; i++)
        m->stand_geom[i] = cfg->handover_stand ? stand_create(w, stand_place(i)) : NULL;
    for (i = 0; i < WP_POOL; i++) {
        m->pool[i].body = sim_body_create(w);
        dMassSetBoxTotal(&mass, cell_default.workpiece_mass_kg, sz[0], sz[1], sz[2]);
        dBodySetMass(m->pool[i].body, &mass);
        m->pool[i].geom = dCreateBox(w->space, sz[0], sz[1], sz[2]);
        dGeomSetBody(m->pool[i].geom, m->pool[i].body);
        dGeomSetCategoryBits(m->pool[i].geom, SIM_CAT_WORKPIECE);
        dGeomSetCollideBits(m->pool[i].geom, SIM_CAT_TABLE | SIM_CAT_GROUND);
        park(m, i);
    }
    return 0;
}

static void wp_destroy(void *model, sim_world *w)
{
    sim_workpieces *m = model;
    (void)w; /* bodies, geoms and joints go with the ODE world */
    memset(m->pool, 0, sizeof m->pool);
    m->table_geom = NULL;
    memset(m->stand_geom, 0, sizeof m->stand_geom);
}

/* ---- geometry helpers ----------------------------------------------------- */

static void body_R(dBodyID b, double R[9])
{
    sim_from_ode_rotation(R, dBodyGetRotation(b));
}

static void set_body_R(dBodyID b, const double R[9])
{
    dMatrix3 r;
    sim_ode_rotation(r, R);
    dBodySetRotation(b, r);
}

/* Grasp point of arm k (0-based) on bar i: -x end for arm 1, +x for arm 2,
 * along the bar's own axis. */
static void grasp_point(const sim_workpiece *p, int k, double g[3])
{
    const dReal *c = dBodyGetPosition(p->body);
    double R[9], off[3];
    body_R(p->body, R);
    vec3_set(off, (k == 0 ? -1.0 : 1.0) * cell_default.grasp_offset_m, 0.0, 0.0);
    rot_apply(g, R, off);
    g[0] += c[0];
    g[1] += c[1];
    g[2] += c[2];
}

static double xy_dist(const dReal *p, const double c[3])
{
    return hypot(p[0] - c[0], p[1] - c[1]);
}

static double body_speed(dBodyID b)
{
    const dReal *v = dBodyGetLinearVel(b), *om = dBodyGetAngularVel(b);
    return sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) +
           0.1 * sqrt(om[0] * om[0] + om[1] * om[1] + om[2] * om[2]);
}

static int held_by_other(const sim_workpiece *p, int k)
{
    int j;
    for (j = 0; j < SIM_ARMS; j++)
        if (j != k && p->hold[j])
            return 1;
    return 0;
}

/* ---- spawning ------------------------------------------------------------- */

static int pick_zone_clear(const sim_workpieces *m)
{
    int i;
    for (i = 0; i < WP_POOL; i++) {
        if (m->pool[i].state == WP_PARKED || m->pool[i].state == WP_HELD)
            continue;
        if (xy_dist(dBodyGetPosition(m->pool[i].body), cell_default.pick_center_m) <
            WP_PICK_RADIUS_M)
            return 0;
    }
    return 1;
}

/* spawn: every workpiece of the pool is in use */
#define POOL_EMPTY (-1)

static int spawn(sim_workpieces *m)
{
    const double *pc = cell_default.pick_center_m, *sp = cell_default.pick_spread_m;
    double R[9], yaw;
    const double z[3] = { 0.0, 0.0, 1.0 };
    int i;
    for (i = 0; i < WP_POOL && m->pool[i].state != WP_PARKED; i++)
        ;
    if (i == WP_POOL)
        return POOL_EMPTY;
    yaw = WP_YAW_SPREAD_RAD * (2.0 * prng_uniform(&m->rng) - 1.0);
    rot_from_axis_angle(R, z, yaw);
    dBodyEnable(m->pool[i].body);
    dGeomEnable(m->pool[i].geom);
    set_body_R(m->pool[i].body, R);
    dBodySetPosition(m->pool[i].body, pc[0] + sp[0] * (2.0 * prng_uniform(&m->rng) - 1.0),
                     pc[1] + sp[1] * (2.0 * prng_uniform(&m->rng) - 1.0),
                     table_top_z() + 0.5 * cell_default.workpiece_size_m[2] + 0.001);
    dBodySetLinearVel(m->pool[i].body, 0, 0, 0);
    dBodySetAngularVel(m->pool[i].body, 0, 0, 0);
    m->pool[i].state = WP_ON_PICK;
    m->pool[i].id = m->next_id++;
    m->pool[i].rest_s = 0.0;
    m->spawned++;
    return i;
}

/* --magazine: a bar at the magazine when arm 2, empty-handed, comes above
 * it, the magazine is empty and bars remain to be fed. */
static void maybe_feed_magazine(sim_workpieces *m)
{
    const sim_arm *a = sim_arms_arm(m->arms, 1);
    const double *mc = cell_default.magazine_center_m;
    const double R[9] = { 1, 0, 0, 0, 1, 0, 0, 0, 1 };
    double tool[3], call[3], d[3];
    int i;
    if (!m->cfg->magazine || a->holding >= 0 ||
        (m->cfg->workpieces != 0 && m->spawned >= m->cfg->workpieces))
        return;
    for (i = 0; i < WP_POOL; i++)
        if (m->pool[i].state == WP_IN_MAGAZINE)
            return;
    sim_arm_tool(a, tool, NULL);
    cell_grasp_point(&cell_default, 1, mc, call);
    call[2] += cell_default.approach_height_m;
    vec3_sub(d, tool, call);
    if (vec3_norm(d) > WP_MAGAZINE_CALL_M)
        return;
    for (i = 0; i < WP_POOL && m->pool[i].state != WP_PARKED; i++)
        ;
    if (i == WP_POOL)
        return; /* every bar in use: called again next step */
    dBodyEnable(m->pool[i].body);
    dGeomEnable(m->pool[i].geom);
    set_body_R(m->pool[i].body, R);
    dBodySetPosition(m->pool[i].body, mc[0], mc[1], mc[2] + 0.001);
    dBodySetLinearVel(m->pool[i].body, 0, 0, 0);
    dBodySetAngularVel(m->pool[i].body, 0, 0, 0);
    m->pool[i].state = WP_IN_MAGAZINE;
    m->pool[i].id = m->next_id++;
    m->pool[i].rest_s = 0.0;
    m->spawned++;
    fprintf(stderr, "tandem-sim: workpiece %d in arm 2's magazine\n", (int)m->pool[i].id);
}

static void maybe_spawn(sim_workpieces *m)
{
    const int more = m->cfg->workpieces == 0 || m->spawned < m->cfg->workpieces;
    if (!pick_zone_clear(m)) {
        m->clear_s = 0.0;
        return;
    }
    m->clear_s += SIM_DT_S;
    if ((more && m->clear_s >= WP_SPAWN_DELAY_S) || m->spawn_requests > 0) {
        if (spawn(m) >= 0) {
            m->clear_s = 0.0;
            if (m->spawn_requests > 0)
                m->spawn_requests--;
        }
    }
}

/* ---- gripper -------------------------------------------------------------- */

static void attach(sim_workpieces *m, sim_world *w, int k, sim_workpiece *p)
{
    sim_arm *a = sim_arms_arm(m->arms, k);
    dBodyID flange = a->link[ARM_NJ - 1];
    if (!held_by_other(p, k)) {
        /* self-centring jaws: bar along the flange x axis, grasp point on
         * the tool point, bar z opposite the tool z (upright for tool-down) */
        double tool[3], Rf[9], Rb[9], c[3], off[3];
        const double flip[9] = { 1, 0, 0, 0, -1, 0, 0, 0, -1 };
        const dReal *v;
        sim_arm_tool(a, tool, Rf);
        rot_mul(Rb, Rf, flip);
        vec3_set(off, (k == 0 ? 1.0 : -1.0) * cell_default.grasp_offset_m, 0.0, 0.0);
        rot_apply(c, Rb, off);
        vec3_add(c, c, tool);
        set_body_R(p->body, Rb);
        dBodySetPosition(p->body, c[0], c[1], c[2]);
        v = dBodyGetLinearVel(flange);
        dBodySetLinearVel(p->body, v[0], v[1], v[2]);
        v = dBodyGetAngularVel(flange);
        dBodySetAngularVel(p->body, v[0], v[1], v[2]);
    }
    p->hold[k] = dJointCreateFixed(w->world, 0);
    dJointAttach(p->hold[k], p->body, flange);
    dJointSetFixed(p->hold[k]);
    p->state = WP_HELD;
    a->holding = p->id;
}

static void detach(sim_workpieces *m, int k, sim_workpiece *p)
{
    dJointDestroy(p->hold[k]);
    p->hold[k] = 0;
    sim_arms_arm(m->arms, k)->holding = -1;
    if (!held_by_other(p, k)) {
        p->state = WP_FREE;
        p->rest_s = 0.0;
    }
}

static void gripper_step(sim_workpieces *m, sim_world *w, int k)
{
    sim_arm *a = sim_arms_arm(m->arms, k);
    int i;
    if (a->gripper_closed && a->holding < 0) {
        double tool[3];
        sim_arm_tool(a, tool, NULL);
        for (i = 0; i < WP_POOL; i++) {
            double g[3], d[3];
            if (m->pool[i].state == WP_PARKED)
                continue;
            grasp_point(&m->pool[i], k, g);
            vec3_sub(d, g, tool);
            if (vec3_norm(d) <= cell_default.grasp_tolerance_m) {
                attach(m, w, k, &m->pool[i]);
                break;
            }
        }
    } else if (!a->gripper_closed && a->holding >= 0) {
        for (i = 0; i < WP_POOL; i++)
            if (m->pool[i].hold[k])
                detach(m, k, &m->pool[i]);
        a->holding = -1;
    }
}

static void wp_before_step(void *model, sim_world *w)
{
    sim_workpieces *m = model;
    int k;
    for (k = 0; k < SIM_ARMS; k++)
        gripper_step(m, w, k);
    maybe_spawn(m);
    maybe_feed_magazine(m);
}

/* ---- bookkeeping and camera ----------------------------------------------- */

/* A free bar at rest on one of the stand's places. */
static int on_stand(const sim_workpieces *m, const sim_workpiece *p, const dReal *c)
{
    int k;
    if (p->state != WP_FREE || !(c[2] > table_top_z() + 0.05))
        return 0;
    for (k = 0; k < SIM_STAND_PLACES; k++)
        if (m->stand_geom[k] && xy_dist(c, stand_place(k)) < WP_STAND_RADIUS_M)
            return 1;
    return 0;
}

static void settle(sim_workpieces *m, int i)
{
    sim_workpiece *p = &m->pool[i];
    const dReal *c = dBodyGetPosition(p->body);
    const int on_floor = c[2] < table_top_z() - 0.05;
    if (p->state == WP_HELD || p->state == WP_PARKED || on_stand(m, p, c) ||
        (p->state == WP_IN_MAGAZINE && !on_floor))
        return;
    if (body_speed(p->body) > WP_REST_SPEED_MPS) {
        p->rest_s = 0.0;
        return;
    }
    p->rest_s += SIM_DT_S;
    if (p->rest_s < WP_REST_TIME_S)
        return;
    if (p->state == WP_FREE && !on_floor &&
        xy_dist(c, cell_default.deliver_center_m) < WP_DELIVER_RADIUS_M) {
        m->delivered++;
        fprintf(stderr, "tandem-sim: workpiece %d delivered\n", (int)p->id);
        park(m, i);
    } else if (on_floor ||
               (p->state == WP_FREE &&
                xy_dist(c, cell_default.pick_center_m) >= WP_PICK_RADIUS_M) ||
               (p->state == WP_ON_PICK &&
                xy_dist(c, cell_default.pick_center_m) >= WP_PICK_RADIUS_M)) {
        m->dropped++;
        fprintf(stderr, "tandem-sim: workpiece %d dropped at (%.3f %.3f %.3f)\n", (int)p->id, c[0],
                c[1], c[2]);
        park(m, i);
    } else if (p->state == WP_FREE) {
        p->state = WP_ON_PICK; /* put back down in the pick zone: pick it again */
    }
}

/* fresh = 0: the same frame again (a re-announced step), no new noise */
static void publish_vision(sim_workpieces *m, sim_world *w, int fresh)
{
    tandem_workpiece_detections_t msg;
    tandem_workpiece_t *det = m->last_det;
    int i, n = 0;
    for (i = 0; i < WP_POOL && fresh; i++) {
        const sim_workpiece *p = &m->pool[i];
        double R[9], axis[3], yaw;
        const dReal *c;
        if (p->state != WP_ON_PICK || p->rest_s < WP_REST_TIME_S)
            continue;
        c = dBodyGetPosition(p->body);
        body_R(p->body, R);
        (void)axis;
        yaw = atan2(R[3], R[0]);
        det[n].id = p->id;
        det[n].position_m[0] = c[0] + VISION_SIGMA_M * prng_gauss(&m->rng);
        det[n].position_m[1] = c[1] + VISION_SIGMA_M * prng_gauss(&m->rng);
        det[n].position_m[2] = c[2] + VISION_SIGMA_M * prng_gauss(&m->rng);
        det[n].yaw_rad = yaw + VISION_SIGMA_YAW_RAD * prng_gauss(&m->rng);
        n++;
    }
    if (fresh)
        m->last_n_det = n;
    n = m->last_n_det;
    memset(&msg, 0, sizeof msg);
    msg.seq = m->vision_seq++;
    msg.utime = daemon_utime_now();
    msg.step = w->step;
    msg.n = (int16_t)n;
    msg.workpieces = det;
    AUTH_PUBLISH(tandem_workpiece_detections_t, &w->d.bus, w->d.lcm, "VISION_DETECTIONS", &msg);
}

static void wp_after_step(void *model, sim_world *w)
{
    sim_workpieces *m = model;
    /* the simulator re-announces a step while it waits for controllers:
     * publish the same frame again, without settling or drawing camera
     * noise a second time (how often that happens depends on the machine's
     * timing, and must not change the run) */
    const int repeat = w->step == m->last_after_step;
    int i;
    m->last_after_step = w->step;
    for (i = 0; i < WP_POOL && !repeat; i++)
        settle(m, i);
    if (w->step % VISION_PERIOD_STEPS == 0)
        publish_vision(m, w, !repeat);
}

static int wp_control(void *model, sim_world *w, const tandem_sim_control_t *c)
{
    sim_workpieces *m = model;
    (void)w;
    if (c->command != TANDEM_SIM_CONTROL_T_SPAWN_WORKPIECE)
        return 0;
    m->spawn_requests++;
    return 1;
}

static void wp_status(const void *model, const sim_world *w, tandem_sim_status_t *s)
{
    const sim_workpieces *m = model;
    (void)w;
    s->workpieces_spawned = m->spawned;
    s->workpieces_delivered = m->delivered;
    s->workpieces_dropped = m->dropped;
}

const sim_model_ops sim_workpieces_ops = { "workpieces",   wp_create,     wp_destroy,
                                           wp_before_step, wp_after_step, wp_control,
                                           wp_status,      NULL,          NULL };
