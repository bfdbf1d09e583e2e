/* sim_rovers_sense: the Pioneer team's sensors (docs/method/formation.md §12, sonar.md; the robots
 * and their world are in sim_rovers.c).
 *
 * ROVERk_SENSORS (encoders, bumper, 20 Hz) and ROVERk_SONAR (the latest
 * echo of each transducer, 20 Hz, sent with the encoders as the Pioneer's
 * own packet does; the transducers fire one per 40 ms in the Pioneer
 * order, sonar_cast on a primitive list of the obstacles and the other
 * robots' boxes rebuilt every firing), ROVERk_BEACONS (camera at O on a pan
 * unit stepping ahead/left/ahead/right: LED beacons of mates and the
 * world's LED landmarks within 6 m and +-60 deg of where it looks, line of
 * sight, noise; 10 Hz), ROVER_TRUTH (ground truth, 20 Hz, for metrics
 * only; a fleet of more than RV_TRUTH_CHUNK robots in several messages). With --rover-batch the same frames of all robots go out as one
 * message per tick (ROVERS_SENSORS, ROVERS_BEACONS), a fleet of more than
 * BATCH_MAX robots in several (daemon.h).
 *
 * Cost per robot independent of the fleet: the sonar world is one grid of
 * obstacles and robot boxes rebuilt each firing (O(robots + obstacles),
 * sonar.c: its cells stay fine however the fleet is spread); a camera
 * frame takes the mates within its range from a grid of the beacons
 * (pgrid.h), and the truth's clearance its neighbours from a grid of the
 * bodies (rover_world_clearance_indexed). Both return exactly the robots
 * the scan over all of them found, in the same ascending order, so the
 * noise is drawn in the same order and every reading is bit for bit what
 * it was (TANDEM_SIM_NEIGHBOURS=scan runs the scan, for comparison).
 */
#include "sim_rovers.h"
#include "rover_batch.h"
#include <math.h>
#include <stdio.h>
#include "unicycle.h"
#include "tandem_rover_sensors_t.h"
#include "tandem_rover_truth_t.h"
#include "tandem_rovers_beacons_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_sonar_scan_t.h"

#define RV_BEACON_STEPS ROVER_CAMERA_PERIOD_STEPS
#define RV_TRUTH_STEPS 50
#define RV_TRUTH_CHUNK 1024 /* = rover_truth_t.n in lcmtypes/capacities */
#define RV_CAM_RANGE_M 6.0
#define RV_CAM_HALF_FOV (60.0 * VEC2_PI / 180.0)
#define RV_BEACON_Z_M 0.30
#define RV_CAM_CELL_M 3.0 /* the beacons' grid: half the camera's range */

static void rebuild_sonar_world(sim_rovers *team)
{
    int i;
    sonar_world_init(&team->sw);
    for (i = 0; i < team->layout.n_obst; i++) {
        const rover_obstacle *o = &team->layout.obst[i];
        if (o->kind == ROVER_OBST_CIRCLE)
            sonar_world_add_circle(&team->sw, o->cx_m, o->cy_m, o->r_m, 0.0, o->height_m);
        else
            sonar_world_add_box(&team->sw, o->cx_m, o->cy_m, o->hx_m, o->hy_m, o->angle_rad, 0.0,
                                o->height_m);
    }
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        pose2 c;
        r->prim = -1;
        if (!r->alive)
            continue;
        sim_rover_pose_c(r, &c);
        r->prim = sonar_world_add_box(&team->sw, c.x_m + ROVER_BODY_OFFSET_M * cos(c.theta_rad),
                                      c.y_m + ROVER_BODY_OFFSET_M * sin(c.theta_rad),
                                      0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M,
                                      c.theta_rad, 0.05, 0.25);
    }
    sonar_world_build(&team->sw);
}

/* Fire the transducer due now on every robot (the Pioneer sequence). */
static void fire_sonars(sim_rovers *team, const sim_world *w)
{
    const int k = sonar_fired_index(w->time_s, &team->sm);
    int i;
    rebuild_sonar_world(team);
    for (i = 0; i < team->n; i++) {
        sim_rover *r = &team->r[i];
        pose2 c;
        if (!r->alive)
            continue;
        sim_rover_pose_c(r, &c);
        /* a transducer does not hear its own chassis: lift the robot's own
         * box out of the ray plane for its firing */
        if (r->prim >= 0) {
            team->sw.p[r->prim].z_min = -2.0;
            team->sw.p[r->prim].z_max = -1.0;
        }
        sonar_fire(&r->range[k], &team->sw, &team->sm, &c, k, &r->rng);
        team->rays += team->sm.rays_per_cone;
        r->fired = k;
        if (r->prim >= 0) {
            team->sw.p[r->prim].z_min = 0.05;
            team->sw.p[r->prim].z_max = 0.25;
        }
    }
}

/* One robot's hardware frame: encoders + bumper, and the latest echo of
 * every transducer (the Pioneer's own packet carries the readings that
 * came in since the last one, once per control tick). */
static void fill_sensors(sim_rovers *team, sim_rover *r, int64_t step, int64_t utime,
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
    m->angle_rad = team->sonar_angle_rad;
    m->range_m = r->range;
    m->fired = (int8_t)r->fired;
}

static void publish_sensors(sim_rovers *team, sim_world *w)
{
    tandem_rover_sensors_t *s = team->s.sens;
    tandem_sonar_scan_t *m = team->s.scan;
    const int64_t utime = daemon_utime_now();
    int i, c, n = 0;
    for (i = 0; i < team->n; i++)
        if (team->r[i].alive)
            fill_sensors(team, &team->r[i], w->step, utime, &s[n], &m[n]), n++;
    for (c = 0; team->batch && c < BATCH_CHUNKS(n); c++) {
        tandem_rovers_sensors_t b;
        BATCH_HEADER(b, team->batch_seq[0]++, utime, w->step, BATCH_CHUNK_N(n, c));
        b.sensors = s + c * BATCH_MAX;
        b.sonar = m + c * BATCH_MAX;
        AUTH_PUBLISH(tandem_rovers_sensors_t, &w->d.bus, w->d.lcm, "ROVERS_SENSORS", &b);
    }
    if (team->batch)
        return;
    for (i = 0; i < n; i++) {
        char ch[32];
        snprintf(ch, sizeof ch, "ROVER%d_SENSORS", s[i].robot);
        AUTH_PUBLISH(tandem_rover_sensors_t, &w->d.bus, w->d.lcm, ch, &s[i]);
        snprintf(ch, sizeof ch, "ROVER%d_SONAR", s[i].robot);
        AUTH_PUBLISH(tandem_sonar_scan_t, &w->d.bus, w->d.lcm, ch, &m[i]);
    }
}

/* One LED at (x, y) seen from camera pose o: appended as target `id`
 * with noisy range and bearing if in view (6 m, the pan's field of view)
 * and not hidden by an obstacle taller than the LED (robots, 0.25 m, do
 * not hide it). */
static int see_led(sim_rovers *team, sim_rover *r, const pose2 *o, double pan, double x, double y,
                   int32_t id, int32_t *tgt, double *rng, double *brg, int n)
{
    const double dx = x - o->x_m, dy = y - o->y_m, d = hypot(dx, dy);
    const double b = vec2_angle_diff_rad(atan2(dy, dx), o->theta_rad);
    sonar_hit hit;
    if (d > RV_CAM_RANGE_M || d < 0.05 || fabs(vec2_angle_diff_rad(b, pan)) > RV_CAM_HALF_FOV)
        return n;
    if (n >= RV_SEEN_MAX) { /* a frame holds what its message may carry */
        team->seen_dropped++;
        return n;
    }
    if (sonar_cast(&hit, &team->sw, o->x_m, o->y_m, RV_BEACON_Z_M, atan2(dy, dx), d) == 1)
        return n;
    tgt[n] = id;
    rng[n] = d + (0.01 + 0.02 * d) * prng_gauss(&r->rng);
    brg[n] = b + 0.01 * prng_gauss(&r->rng);
    return n + 1;
}

/* Robot i's camera frame: mates' LED beacons and the world's LED landmarks
 * (target ROVER_LANDMARK_ID_BASE + k) in view (range, bearing). */
static void observe_beacons(sim_rovers *team, int i, const pose2 o[], double pan, int64_t step,
                            int64_t utime, int32_t *tgt, double *rng, double *brg,
                            tandem_beacon_obs_t *m)
{
    sim_rover *r = &team->r[i];
    int32_t *near = team->s.near;
    const int k = team->brute ? pgrid_query_brute(team->s.cam_grid, o[i].x_m, o[i].y_m,
                                                  RV_CAM_RANGE_M + 1e-6, near, team->n)
                              : pgrid_query(team->s.cam_grid, o[i].x_m, o[i].y_m,
                                            RV_CAM_RANGE_M + 1e-6, near, team->n);
    int j, q, n = 0, k_posts;
    /* every mate within range, ascending (those farther were refused by
     * see_led before drawing anything) */
    for (q = 0; q < k; q++) {
        j = near[q];
        if (j != i)
            n = see_led(team, r, &o[i], pan, o[j].x_m, o[j].y_m, team->r[j].id, tgt, rng, brg, n);
    }
    /* the posts within reach, ascending as the scan over all of them went
     * (a fleet's world holds hundreds) */
    k_posts = pgrid_query(team->s.post_grid, o[i].x_m, o[i].y_m, RV_CAM_RANGE_M + 1e-6,
                          team->s.post_near, ROVER_WORLD_MAX_POSTS);
    for (q = 0; q < k_posts; q++) {
        j = team->s.post_near[q];
        n = see_led(team, r, &o[i], pan, team->layout.landmark_m[j][0],
                    team->layout.landmark_m[j][1], ROVER_LANDMARK_ID_BASE + j, tgt, rng, brg, n);
    }
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
static void publish_beacons(sim_rovers *team, sim_world *w, int fresh)
{
    /* the camera sits on a pan unit that looks ahead, left, ahead, right in
     * turn, one frame each (abreast mates are seen every 0.4 s) */
    static const double pans[4] = { 0.0, 0.5 * VEC2_PI, 0.0, -0.5 * VEC2_PI };
    sim_rovers_frames *f = &team->frames;
    tandem_beacon_obs_t *m = f->obs;
    int *n = &f->n;
    const double pan = pans[(w->step / RV_BEACON_STEPS) % 4];
    const int64_t utime = daemon_utime_now();
    pose2 *o = team->s.cam, c;
    int i, k;
    for (i = 0; fresh && i < team->n; i++) {
        team->s.alive[i] = team->r[i].alive;
        team->s.x[i] = team->s.y[i] = 0.0;
        if (!team->r[i].alive)
            continue;
        sim_rover_pose_c(&team->r[i], &c);
        unicycle_o_from_c(&o[i], &c, ROVER_BEACON_D_M);
        team->s.x[i] = o[i].x_m;
        team->s.y[i] = o[i].y_m;
    }
    if (fresh)
        (void)pgrid_build(team->s.cam_grid, team->s.x, team->s.y, team->s.alive, team->n,
                          RV_CAM_CELL_M); /* n <= RV_MAX <= PGRID_MAX_ITEMS, finite poses */
    if (fresh)
        *n = 0;
    for (i = 0; fresh && i < team->n; i++)
        if (team->r[i].alive)
            observe_beacons(team, i, o, pan, w->step, utime, f->target[*n], f->range_m[*n],
                            f->bearing_rad[*n], &m[*n]),
                (*n)++;
    for (k = 0; team->batch && k < BATCH_CHUNKS(*n); k++) {
        tandem_rovers_beacons_t b;
        BATCH_HEADER(b, team->batch_seq[1]++, utime, w->step, BATCH_CHUNK_N(*n, k));
        b.obs = m + k * BATCH_MAX;
        AUTH_PUBLISH(tandem_rovers_beacons_t, &w->d.bus, w->d.lcm, "ROVERS_BEACONS", &b);
    }
    if (team->batch)
        return;
    for (i = 0; i < *n; i++) {
        char ch[32];
        snprintf(ch, sizeof ch, "ROVER%d_BEACONS", m[i].observer);
        AUTH_PUBLISH(tandem_beacon_obs_t, &w->d.bus, w->d.lcm, ch, &m[i]);
    }
}

void sim_rovers_clearance(sim_rovers *team)
{
    sim_rovers_scratch *s = &team->s;
    int i;
    for (i = 0; i < team->n; i++) {
        sim_rover_pose_c(&team->r[i], &s->pose[i]);
        s->alive[i] = team->r[i].alive;
    }
    if (team->brute)
        rover_world_clearance(&team->layout, s->pose, s->alive, team->n, s->cl);
    else
        rover_world_clearance_indexed(&team->layout, s->pose, s->alive, team->n, s->clear, s->cl);
}

static void publish_truth(sim_rovers *team, sim_world *w)
{
    sim_rovers_scratch *s = &team->s;
    int32_t *id = s->id, *col = s->col;
    double *x = s->x, *y = s->y, *th = s->th, *cl = s->cl;
    int8_t *al = s->al;
    pose2 *c = s->pose, o;
    int i;
    tandem_rover_truth_t m;
    sim_rovers_clearance(team);
    for (i = 0; i < team->n; i++) {
        unicycle_o_from_c(&o, &c[i], ROVER_BEACON_D_M);
        id[i] = team->r[i].id;
        x[i] = o.x_m;
        y[i] = o.y_m;
        th[i] = o.theta_rad;
        col[i] = team->r[i].collisions;
        al[i] = (int8_t)team->r[i].alive;
        if (!isfinite(cl[i]))
            cl[i] = 1e3;
    }
    /* RV_TRUTH_CHUNK robots a message (a datagram holds about 1,500):
     * a team's truth is one message, a larger fleet's several */
    for (i = 0; i < team->n; i += RV_TRUTH_CHUNK) {
        const int k = team->n - i < RV_TRUTH_CHUNK ? team->n - i : RV_TRUTH_CHUNK;
        m.seq = team->truth_seq++;
        m.utime = daemon_utime_now();
        m.step = w->step;
        m.sim_time_s = w->time_s;
        m.n = (int16_t)k;
        m.robot = id + i;
        m.x_m = x + i;
        m.y_m = y + i;
        m.theta_rad = th + i;
        m.min_clearance_m = cl + i;
        m.collisions = col + i;
        m.alive = al + i;
        AUTH_PUBLISH(tandem_rover_truth_t, &w->d.bus, w->d.lcm, "ROVER_TRUTH", &m);
    }
}

void sim_rovers_after_step(void *model, sim_world *w)
{
    sim_rovers *team = model;
    /* the simulator re-announces a step while it waits for controllers to
     * start: publish the same readings again, without firing or drawing
     * noise a second time (that would change the run) */
    const int repeat = w->step == team->last_after_step;
    team->last_after_step = w->step;
    const int64_t fire_steps = (int64_t)llround(team->sm.fire_period_s / SIM_DT_S);
    if (w->step % fire_steps == 0 && !repeat)
        fire_sonars(team, w);
    if (!w->d.lcm)
        return;
    if (w->step % RV_SENSORS_STEPS == 0)
        publish_sensors(team, w);
    if (w->step % RV_BEACON_STEPS == 0)
        publish_beacons(team, w, !repeat);
    if (w->step % RV_TRUTH_STEPS == 0)
        publish_truth(team, w);
}

int sim_rovers_index_posts(sim_rovers *team)
{
    double x[ROVER_WORLD_MAX_POSTS], y[ROVER_WORLD_MAX_POSTS];
    int k;
    for (k = 0; k < team->layout.n_landmarks; k++) {
        x[k] = team->layout.landmark_m[k][0];
        y[k] = team->layout.landmark_m[k][1];
    }
    if (pgrid_build(team->s.post_grid, x, y, NULL, team->layout.n_landmarks, RV_CAM_RANGE_M) !=
        PGRID_OK) {
        fprintf(stderr, "tandem-sim: the world's %d LED posts could not be indexed\n",
                team->layout.n_landmarks);
        return SIM_ERR_CREATE;
    }
    return 0;
}
