/* rover_inputs: what tandem-rover takes in: the hosted robots' frames
 * (encoders, sonar, camera; per robot or batched), the mates' team
 * messages, and in lockstep whether a step's inputs are all here (see
 * tandem_rover.c).
 */
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include "rover_daemon.h"
#include "formation.h"
#include "tandem_beacon_obs_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_rover_sensors_t.h"
#include "tandem_rovers_beacons_t.h"
#include "tandem_teams_msg_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_sonar_scan_t.h"

#define ROVER_INPUT_WAIT_NS 300000000LL /* a missing input: asked about after 0.3 s */
/* A mate's process running but silent this long (no ack at all: a waiting
 * participant says "still here" on every announcement) hangs: taken as
 * gone (peer_dead). */
#define ROVER_MATE_SILENT_NS 3000000000LL

/* ---- messages in ------------------------------------------------------------ */

static int64_t now_ns(void)
{
    return rtloop_now_ns();
}

/* Lockstep start-up: the simulator publishes step 0 once, possibly before
 * every host has subscribed; whether a host saw it must not change the
 * run, so lockstep hosts ignore step 0 and start at their first period. */
int rover_too_early(rover_daemon *rd, int64_t step)
{
    return rd->d.lockstep && step < rd->d.period_steps;
}

static int all_ranges(const double *r, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(r[i]) || r[i] < 0.0)
            return 0;
    return 1;
}

/* A frame at or before the last one taken of its kind is a copy (the
 * simulator announcing a step again, or a replay): counted, ignored. */
static int is_copy(rover_daemon *rd, int64_t step, const int64_t *last)
{
    if (step > *last)
        return 0;
    rd->d.msgs.duplicate++;
    return 1;
}

/* The hardware frames of one robot, from its own channels or from a
 * batch: only hosted robots count; bad values are dropped and counted. */
static void take_sensors(rover_daemon *rd, const tandem_rover_sensors_t *m)
{
    hosted *h = rover_find_hosted(rd, m->robot);
    if (!h || rover_too_early(rd, m->step))
        return; /* another host's robot / start-up */
    rd->d.msgs.received++;
    if (is_copy(rd, m->step, &h->sens_step))
        return;
    if (m->step < 0 || !isfinite(m->wheel_left_rad) || !isfinite(m->wheel_right_rad)) {
        rd->d.msgs.rejected++;
        return;
    }
    h->enc_rad[0] = m->wheel_left_rad;
    h->enc_rad[1] = m->wheel_right_rad;
    h->new_enc = 1;
    h->sens_step = m->step;
    h->silent = 0;
    h->last_rx_ns = now_ns();
}

static void take_sonar(rover_daemon *rd, const tandem_sonar_scan_t *m)
{
    hosted *h = rover_find_hosted(rd, m->robot);
    if (!h || rover_too_early(rd, m->step))
        return;
    rd->d.msgs.received++;
    if (is_copy(rd, m->step, &h->sonar_step))
        return;
    if (m->n != BEH_SONAR_N || m->step < 0 || !all_ranges(m->range_m, m->n)) {
        rd->d.msgs.rejected++;
        return;
    }
    memcpy(h->sonar_m, m->range_m, sizeof h->sonar_m);
    h->new_sonar = 1;
    h->sonar_step = m->step;
}

static void take_beacons(rover_daemon *rd, const tandem_beacon_obs_t *m)
{
    hosted *h = rover_find_hosted(rd, m->observer);
    int i;
    if (!h || rover_too_early(rd, m->step))
        return;
    rd->d.msgs.received++;
    if (is_copy(rd, m->step, &h->camera_step))
        return;
    if (m->n < 0 || m->n > ROVER_TEAM_MAX + ROVER_WORLD_MAX_LANDMARKS) {
        rd->d.msgs.rejected++;
        return;
    }
    h->camera_step = m->step;
    h->cam_n = 0;
    for (i = 0; i < m->n; i++)
        if (isfinite(m->range_m[i]) && isfinite(m->bearing_rad[i]) && m->range_m[i] >= 0.0) {
            h->cam_target[h->cam_n] = m->target[i];
            h->cam_range_m[h->cam_n] = m->range_m[i];
            h->cam_bearing_rad[h->cam_n] = m->bearing_rad[i];
            h->cam_n++;
        }
    h->new_cam = 1;
}

/* A camera target as the robot's controller knows it: a mate's id as it
 * is, a post of the world (ROVER_LANDMARK_ID_BASE + its world index) as
 * ROVER_LANDMARK_ID_BASE + its place in the robot's own list (h->post,
 * ascending: a binary search), or -1 for a post the robot does not hold. */
static int32_t localized_target(const hosted *h, int32_t target)
{
    int lo = 0, hi = h->n_posts - 1;
    if (target < ROVER_LANDMARK_ID_BASE)
        return target;
    while (lo <= hi) {
        const int mid = (lo + hi) / 2;
        if (h->post[mid] == target - ROVER_LANDMARK_ID_BASE)
            return ROVER_LANDMARK_ID_BASE + mid;
        if (h->post[mid] < target - ROVER_LANDMARK_ID_BASE)
            lo = mid + 1;
        else
            hi = mid - 1;
    }
    return -1;
}

/* The frames taken since the last cycle, into the controller. */
void rover_apply_frames(rover_daemon *rd, hosted *h)
{
    int i;
    if (h->new_enc && rover_ctl_encoders(&h->c, h->enc_rad[0], h->enc_rad[1],
                                         (double)h->sens_step * DAEMON_SIM_DT_S) != 0)
        rd->d.msgs.rejected++;
    if (h->new_sonar &&
        rover_ctl_sonar(&h->c, h->sonar_m, (double)h->sonar_step * DAEMON_SIM_DT_S) != 0)
        rd->d.msgs.rejected++;
    /* unknown targets (not heard yet) are fine: skipped */
    for (i = 0; h->new_cam && i < h->cam_n; i++) {
        const int32_t target = localized_target(h, h->cam_target[i]);
        if (target >= 0)
            rover_ctl_beacon(&h->c, target, h->cam_range_m[i], h->cam_bearing_rad[i]);
    }
    h->new_enc = h->new_sonar = h->new_cam = 0;
}

/* A message that does not decode is counted once, as received and rejected. */
#define ROVER_DECODE(rd, type, rb, m)                        \
    (type##_decode((rb)->data, 0, (rb)->data_size, (m)) >= 0 \
         ? 1                                                 \
         : ((rd)->d.msgs.received++, (rd)->d.msgs.rejected++, 0))

void rover_on_sensors(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_rover_sensors_t m;
    (void)ch;
    if (ROVER_DECODE(rd, tandem_rover_sensors_t, rb, &m))
        take_sensors(rd, &m);
}

void rover_on_sonar(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_sonar_scan_t m;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_sonar_scan_t, rb, &m))
        return;
    take_sonar(rd, &m);
    tandem_sonar_scan_t_decode_cleanup(&m);
}

void rover_on_beacons(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_beacon_obs_t m;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_beacon_obs_t, rb, &m))
        return;
    take_beacons(rd, &m);
    tandem_beacon_obs_t_decode_cleanup(&m);
}

/* tandem-sim --rover-batch: every robot's frames in one message */
void rover_on_sensors_batch(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_rovers_sensors_t m;
    int i;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_rovers_sensors_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++) {
        take_sensors(rd, &m.sensors[i]);
        take_sonar(rd, &m.sonar[i]);
    }
    tandem_rovers_sensors_t_decode_cleanup(&m);
}

void rover_on_beacons_batch(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_rovers_beacons_t m;
    int i;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_rovers_beacons_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++)
        take_beacons(rd, &m.obs[i]);
    tandem_rovers_beacons_t_decode_cleanup(&m);
}

static int team_msg_valid(const tandem_team_msg_t *m)
{
    return m->robot >= 1 && isfinite(m->x_m) && isfinite(m->y_m) && isfinite(m->theta_rad) &&
           isfinite(m->v_mps) && isfinite(m->w_radps) && isfinite(m->formation_scale) &&
           m->formation_scale > 0.0 && m->formation_scale <= 1.0 &&
           m->formation >= FORMATION_LINE && m->formation <= FORMATION_COLUMN &&
           formation_ann_valid(m->announce) && isfinite(m->goal_m[0]) && isfinite(m->goal_m[1]) &&
           m->step >= 0;
}

/* One mate's team message, from TEAM or a TEAMS batch: queued for the
 * first cycle after the step it was sent at (rover_deliver_team). */
static void take_team(rover_daemon *rd, const tandem_team_msg_t *m)
{
    teamq_item *q;
    rd->d.msgs.received++;
    /* a host speaks for its own robots alone (auth_bus_sender_covers):
     * one that signs a message for another host's robot is refused */
    if (!team_msg_valid(m) || m->robot > rd->robots ||
        !auth_bus_sender_covers(&rd->d.bus, m->robot)) {
        rd->d.msgs.rejected++;
        return;
    }
    if (m->robot < rd->listen_lo || m->robot > rd->listen_hi)
        return; /* another team's (fleet.h): not heard */
    if (is_copy(rd, m->step, &rd->mate_step[m->robot]))
        return;
    rd->mate_step[m->robot] = m->step;
    rd->mate_gone[m->robot] = 0;
    if (rd->nq >= TEAMQ_MAX) {
        rd->dropped_q++;
        rd->d.msgs.stale++;
        return;
    }
    q = &rd->q[rd->nq++];
    memset(q, 0, sizeof *q);
    q->step = m->step;
    q->m.m.robot = m->robot;
    q->m.m.x_m = m->x_m;
    q->m.m.y_m = m->y_m;
    q->m.m.theta_rad = m->theta_rad;
    q->m.m.v_mps = m->v_mps;
    q->m.m.w_radps = m->w_radps;
    q->m.m.formation = m->formation;
    q->m.m.scale = m->formation_scale;
    q->m.m.announce = m->announce;
    q->m.m.announce_seq = m->announce_seq;
    q->m.goal_m[0] = m->goal_m[0];
    q->m.goal_m[1] = m->goal_m[1];
}

void rover_on_team(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_team_msg_t m;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_team_msg_t, rb, &m))
        return;
    take_team(rd, &m);
}

/* tandem-rover --batch: a host's robots' team messages in one message */
void rover_on_teams(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_teams_msg_t m;
    int i;
    (void)ch;
    if (!ROVER_DECODE(rd, tandem_teams_msg_t, rb, &m))
        return;
    for (i = 0; i < m.n; i++)
        take_team(rd, &m.team[i]);
    tandem_teams_msg_t_decode_cleanup(&m);
}

/* This process started after the run had (a restart): its first cycle
 * was later than the first period. */
static int joined_late(const rover_daemon *rd)
{
    return rd->first_step > rd->d.period_steps;
}

/* The hosted robots of robot id's team: lo..hi (empty: lo > hi); with one
 * team every hosted robot, so a message costs its team's robots only. */
static void team_hosted(const rover_daemon *rd, int32_t id, int32_t *lo, int32_t *hi)
{
    *lo = rd->id_lo;
    *hi = rd->id_hi;
    if (rd->teams > 1 &&
        rover_fleet_members(&rd->fleet, rover_fleet_team_of(&rd->fleet, id), lo, hi) == 0) {
        if (*lo < rd->id_lo)
            *lo = rd->id_lo;
        if (*hi > rd->id_hi)
            *hi = rd->id_hi;
    }
}

/* Deliver queued team messages sent before `step` (all of them in real
 * time). Lockstep: only those sent after this process's first cycle; what
 * a mate sent up to that step may or may not have reached a process that
 * was just starting (republished on a repeated step, or not), so it must
 * not count. */
void rover_deliver_team(rover_daemon *rd, int64_t step, double t_s)
{
    int i, k = 0, j;
    int32_t lo, hi;
    for (i = 0; i < rd->nq; i++) {
        if (rd->d.lockstep && rd->q[i].step >= step) {
            rd->q[k++] = rd->q[i];
            continue;
        }
        if (rd->d.lockstep && joined_late(rd) && rd->q[i].step <= rd->first_step)
            continue;
        team_hosted(rd, rd->q[i].m.m.robot, &lo, &hi);
        for (j = lo; j <= hi; j++)
            if (j != rd->q[i].m.m.robot &&
                rover_ctl_team_msg(&rd->h[j - rd->id_lo].c, &rd->q[i].m, t_s) < 0)
                rd->d.msgs.rejected++;
    }
    rd->nq = k;
}

/* A lockstep participant's ack (any step): the process hosting the
 * robots its name says is alive, and which pid it has. Its CPU time is
 * read once (/proc) and copied to every robot it hosts: a host of the
 * whole fleet costs one read an ack, not one a robot. */
void rover_on_ack(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rover_daemon *rd = u;
    tandem_clock_ack_t m;
    long lo, hi, j;
    (void)ch;
    if (!DAEMON_DECODE(&rd->d.msgs, tandem_clock_ack_t, rb, &m))
        return;
    if (m.pid > 0 && m.name && !m.leaving && peer_rover_range(m.name, &lo, &hi) && lo >= 1 &&
        lo <= rd->robots) {
        peer_heard(&rd->mate_peer[lo], m.pid, now_ns());
        for (j = lo + 1; j <= hi && j <= rd->robots; j++)
            rd->mate_peer[j] = rd->mate_peer[lo];
    }
    tandem_clock_ack_t_decode_cleanup(&m);
}

/* ---- lockstep: a step's inputs complete ------------------------------------------ */

/* The frame a lockstep cycle at `step` needs: the last one of its period,
 * if that falls after start-up and not before this process's first cycle
 * (a process restarted at step k never saw what was sent before k: a
 * frame or team message it cannot have must not decide anything, or
 * whether it waited would depend on the machine's speed) (-1: none). */
static int64_t frame_due(rover_daemon *rd, int64_t step, int64_t period)
{
    const int64_t due = step - step % period;
    return due >= rd->d.period_steps && due >= rd->first_step ? due : -1;
}

/* Lockstep: are this step's inputs all here (see the top of the file)? A
 * hosted robot needs its encoder/sonar frame and camera frame of this
 * step's periods; every robot's last team tick (sent every team period)
 * must be in for the robots that listen to it. */
static int inputs_missing(rover_daemon *rd, int64_t step, int mark_gone)
{
    const int64_t sens = frame_due(rd, step, ROVER_SENSOR_PERIOD_STEPS);
    const int64_t cam = frame_due(rd, step, ROVER_CAMERA_PERIOD_STEPS);
    const int64_t team_w = (int64_t)llround(rd->params.team_period_s / DAEMON_SIM_DT_S);
    const int64_t team_from = joined_late(rd) ? rd->first_step + 1 : 0; /* see rover_deliver_team */
    int j, missing = 0;
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        if (h->silent)
            continue;
        if (h->sens_step < sens || h->sonar_step < sens || h->camera_step < cam) {
            missing++;
            if (mark_gone)
                h->silent = 1;
        }
    }
    for (j = rd->listen_lo; j <= rd->listen_hi; j++) {
        const int listened = rd->id_lo != rd->id_hi || rd->id_lo != j;
        if (!listened || rd->mate_gone[j] || step - team_w < team_from ||
            rd->mate_step[j] >= step - team_w)
            continue;
        missing++;
        /* a mate whose process is alive (slow, or stopped) is waited for:
         * what this cycle sees must not depend on the machine's load */
        if (mark_gone && peer_dead(&rd->mate_peer[j], now_ns(), ROVER_MATE_SILENT_NS))
            rd->mate_gone[j] = 1;
    }
    return missing;
}

int rover_inputs_complete(rover_daemon *rd, int64_t step)
{
    const int64_t now = now_ns();
    int n, left;
    if (inputs_missing(rd, step, 0) == 0)
        return 1;
    if (rd->wait_step != step) {
        rd->wait_step = step;
        rd->wait_since_ns = now;
    }
    if (now - rd->wait_since_ns < ROVER_INPUT_WAIT_NS)
        return 0;
    /* announced again and again for 0.3 s: not lost. A source whose process
     * is gone or hangs (a killed robot, a dead mate) is gone: go on without
     * it until it speaks again; one that is alive is waited for. */
    n = inputs_missing(rd, step, 1);
    left = inputs_missing(rd, step, 0);
    if (n > left) {
        rd->gone_count += n - left;
        fprintf(
            stderr,
            "%s: step %lld: %d input source(s) silent for %.1f s and not alive, taken as gone\n",
            rd->d.name, (long long)step, n - left, (double)(now - rd->wait_since_ns) * 1e-9);
    }
    return left == 0;
}
