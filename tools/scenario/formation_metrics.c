/* formation_metrics: the metrics of a formation run from ground truth
 * (ROVER_TRUTH every FM_PERIOD steps; docs/method/formation.md §6): path
 * length and smoothness (mean |dw/dt|), clearance, collisions, each
 * robot's own pose estimate against the truth, the formation error (the
 * slots of the formation the team flies now, around the true centroid and
 * mean heading), whether the team has reached the goal; and the time
 * series truth.csv, formation_error.csv, weights.csv, snapshots.csv.
 */
#include <math.h>
#include <stdio.h>
#include "formation_scen.h"
#include "formation.h"
#include "vec2.h"

/* The live robots' centroid and mean heading. */
typedef struct team_pose {
    double cx, cy, th0;
} team_pose;

static int alive_ids(const tandem_rover_truth_t *m, int32_t *ids)
{
    int i, n = 0;
    for (i = 0; i < m->n; i++)
        if (m->alive[i])
            ids[n++] = m->robot[i];
    return n;
}

/* Robot i (index in m, alive): path and smoothness, localization error,
 * its line of truth.csv. */
static void robot_truth(fm_metrics *mt, const fm_bus *bus, const fm_procs *pr,
                        const tandem_rover_truth_t *m, int i, double t)
{
    /* path and smoothness (mean |dw/dt|) */
    if (mt->have_prev[i]) {
        const double w = vec2_angle_diff_rad(m->theta_rad[i], mt->prev_th[i]) / (FM_PERIOD * 1e-3);
        mt->path[i] += hypot(m->x_m[i] - mt->prev_x[i], m->y_m[i] - mt->prev_y[i]);
        if (mt->have_prev_w[i] && !mt->reached) {
            mt->sum_dw += fabs(w - mt->prev_w[i]) / (FM_PERIOD * 1e-3);
            mt->n_dw++;
        }
        mt->prev_w[i] = w;
        mt->have_prev_w[i] = 1;
    }
    mt->prev_x[i] = m->x_m[i];
    mt->prev_y[i] = m->y_m[i];
    mt->prev_th[i] = m->theta_rad[i];
    mt->have_prev[i] = 1;
    if (bus->have_state[i] && !fm_process_down(pr, m->robot[i], m->step - FM_PERIOD)) {
        /* localization error: the robot's own estimate of O against
         * the truth (both world frame); none while its process is down */
        const double e = hypot(bus->est[i].x_m - m->x_m[i], bus->est[i].y_m - m->y_m[i]);
        mt->loc_sum_sq += e * e;
        mt->loc_n++;
        if (e > mt->loc_max)
            mt->loc_max = e;
    }
    if (mt->truth_csv)
        fprintf(mt->truth_csv, "%.3f,%d,%.4f,%.4f,%.4f,%.4f,%d,%.4f,%.4f,%.4f\n", t, m->robot[i],
                m->x_m[i], m->y_m[i], m->theta_rad[i], m->min_clearance_m[i], m->collisions[i],
                bus->est[i].x_m, bus->est[i].y_m, bus->est[i].theta_rad);
}

/* Centre of robot i's body box (world frame) from its truth pose, which
 * is O's (rover_body_centre_of_o). The sign of O's offset from C was taken
 * the wrong way here once: every box 0.30 m off along its heading, and
 * robots that touched counted as touching walls (1,000 robots crossing:
 * contacts between teams at 0.47-0.58 m between true box centres read as
 * 0.66-1.09 m). */
static void body_centre(const tandem_rover_truth_t *m, int i, double *x, double *y)
{
    const pose2 o = { m->x_m[i], m->y_m[i], m->theta_rad[i] };
    double xy[2];
    rover_body_centre_of_o(&o, xy);
    *x = xy[0];
    *y = xy[1];
}

/* The nearest other live robot whose body is within reach of robot i's
 * (their box centres closer than the box diagonal plus 2 cm: two boxes
 * farther apart cannot touch whatever their headings): its index, or -1
 * none. */
static int robot_within_reach(const tandem_rover_truth_t *m, int i)
{
    double near_m = hypot(ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M) + 0.02;
    double xi, yi, xj, yj;
    int j, nearest = -1;
    body_centre(m, i, &xi, &yi);
    for (j = 0; j < m->n; j++) {
        if (j == i || !m->alive[j])
            continue;
        body_centre(m, j, &xj, &yj);
        if (hypot(xj - xi, yj - yi) < near_m) {
            near_m = hypot(xj - xi, yj - yi);
            nearest = j;
        }
    }
    return nearest;
}

/* The new contact events of each robot since the last sample, counted on
 * mates if a mate is within reach, else on walls (docs/formation.md); with
 * many teams also on the robot's team, as its own mate's or another
 * team's robot's. */
static void split_contacts(fm_metrics *mt, const fm_cfg *cfg, const tandem_rover_truth_t *m)
{
    const rover_fleet *f = cfg->teams > 1 ? &cfg->fleet : NULL;
    int i;
    for (i = 0; i < m->n && i < FM_MAX; i++) {
        const int d = m->collisions[i] - mt->coll_prev[i];
        int j, ti;
        if (d <= 0)
            continue;
        mt->coll_prev[i] = m->collisions[i];
        j = robot_within_reach(m, i);
        if (j >= 0)
            mt->collisions_mates += d;
        else
            mt->collisions_walls += d;
        if (!f || (ti = rover_fleet_team_of(f, m->robot[i])) < 0)
            continue;
        if (j >= 0 && rover_fleet_team_of(f, m->robot[j]) == ti)
            mt->team[ti].collisions_mates += d;
        else if (j >= 0) {
            mt->team[ti].collisions_others += d;
            mt->collisions_teams += d;
        }
    }
}

/* Every live robot's truth; the team's centroid and mean heading. Returns
 * the index of the lowest live robot, -1 none. */
static int team_truth(fm_metrics *mt, const fm_bus *bus, const fm_procs *pr,
                      const tandem_rover_truth_t *m, int n, double t, team_pose *tp)
{
    double cx = 0, cy = 0, s = 0, c = 0;
    int i, lowest = -1;
    for (i = 0; i < m->n; i++) {
        if (!m->alive[i])
            continue;
        if (lowest < 0)
            lowest = i;
        cx += m->x_m[i];
        cy += m->y_m[i];
        s += sin(m->theta_rad[i]);
        c += cos(m->theta_rad[i]);
        if (m->min_clearance_m[i] < mt->min_clear)
            mt->min_clear = m->min_clearance_m[i];
        robot_truth(mt, bus, pr, m, i, t);
    }
    cx /= n;
    cy /= n;
    tp->cx = cx;
    tp->cy = cy;
    tp->th0 = atan2(s, c);
    return lowest;
}

/* The formation a team flies and where it is bound: the type and scale
 * its lowest live robot reports, its start formation, its goal and the
 * heading of the goal's slot frame (the goal's bearing from the origin of
 * its team frame, as the robots place it). */
typedef struct team_aim {
    int type, formation;
    double scale, goal[2], heading;
} team_aim;

/* Formation error: slots of the formation the team is flying now around
 * the true centroid and mean heading; robot slots by sorted alive id.
 * The team's robots are the n truth indices idx (alive, their ids ids).
 * *sq: sum of the squared errors, *mx: the largest. Returns 1 when the
 * nominal slots around the goal (the slot frame headed along a->heading)
 * are held: each by its own robot within 0.75 m, whichever robot (the
 * robots take the goal's slots in the order they arrive). */
static int formation_error(const team_aim *a, const tandem_rover_truth_t *m, const int *idx,
                           const int32_t *ids, int n, const team_pose *tp, double *sq, double *mx)
{
    double at[ROVER_TEAM_MAX][2], goal_slot[ROVER_TEAM_MAX][2];
    int q, k = 0;
    for (q = 0; q < n; q++) {
        const int i = idx[q];
        double xy[2], r[2], e;
        int rank;
        rank = formation_slot_of(ids, n, m->robot[i]);
        formation_slot_xy(xy, a->type, n, rover_world_slot(a->type, n, rank), 1.0, a->scale);
        vec2_rotate(r, xy[0], xy[1], tp->th0);
        e = hypot(m->x_m[i] - tp->cx - r[0], m->y_m[i] - tp->cy - r[1]);
        *sq += e * e;
        if (e > *mx)
            *mx = e;
        if (k >= n || k >= ROVER_TEAM_MAX)
            return 0;
        formation_slot_xy(xy, a->formation, n, k, 1.0, 1.0);
        vec2_rotate(r, xy[0], xy[1], a->heading);
        goal_slot[k][0] = a->goal[0] + r[0];
        goal_slot[k][1] = a->goal[1] + r[1];
        at[k][0] = m->x_m[i];
        at[k][1] = m->y_m[i];
        k++;
    }
    return k == n && formation_slots_held((const double(*)[2])at, (const double(*)[2])goal_slot, n,
                                          0.75) == 1;
}

/* The team of the n truth indices idx: centroid and mean heading. */
static void members_pose(const tandem_rover_truth_t *m, const int *idx, int n, team_pose *tp)
{
    double cx = 0, cy = 0, s = 0, c = 0;
    int q;
    for (q = 0; q < n; q++) {
        cx += m->x_m[idx[q]];
        cy += m->y_m[idx[q]];
        s += sin(m->theta_rad[idx[q]]);
        c += cos(m->theta_rad[idx[q]]);
    }
    tp->cx = cx / n;
    tp->cy = cy / n;
    tp->th0 = atan2(s, c);
}

/* A sample of the formation error taken (n robots, sq their squared
 * errors summed, mx the largest): its mean square, its largest, and
 * whether a robot was out of formation (FM_OUT_TOL). */
static void error_sample(int *samples, int *out_samples, double *sum_sq_err, double *max_err,
                         double sq, double mx, int n)
{
    (*samples)++;
    *sum_sq_err += sq / n;
    if (mx > *max_err)
        *max_err = mx;
    if (mx > FM_OUT_TOL)
        (*out_samples)++;
}

/* Team t's sample (its live robots: the n truth indices idx, ids ids):
 * its formation error, contacts, clearance and arrival. */
static void team_sample(fm_team_metrics *tm, const fm_cfg *cfg, const fm_bus *bus,
                        const tandem_rover_truth_t *m, int t, const int *idx, const int32_t *ids,
                        int n, double *sq, double *mx)
{
    const int lowest = idx[0];
    double tsq = 0.0, tmx = 0.0;
    team_aim a;
    team_pose tp;
    int q, at;
    if (bus->have_state[lowest]) {
        tm->type_now = bus->state_type[lowest];
        tm->scale_now = bus->state_scale[lowest];
    }
    a.type = tm->type_now;
    a.scale = tm->scale_now;
    a.formation = cfg->formation;
    a.goal[0] = cfg->fleet.goal_m[t][0];
    a.goal[1] = cfg->fleet.goal_m[t][1];
    a.heading = atan2(a.goal[1] - cfg->fleet.origin[t].y_m, a.goal[0] - cfg->fleet.origin[t].x_m);
    members_pose(m, idx, n, &tp);
    at = formation_error(&a, m, idx, ids, n, &tp, &tsq, &tmx);
    *sq += tsq;
    if (tmx > *mx)
        *mx = tmx;
    tm->collisions = 0;
    for (q = 0; q < n; q++) {
        tm->collisions += m->collisions[idx[q]];
        if (m->min_clearance_m[idx[q]] < tm->min_clear)
            tm->min_clear = m->min_clearance_m[idx[q]];
    }
    if (tm->reached)
        return;
    error_sample(&tm->samples, &tm->out_samples, &tm->sum_sq_err, &tm->max_err, tsq, tmx, n);
    if (at && hypot(tp.cx - a.goal[0], tp.cy - a.goal[1]) < 0.5) {
        tm->reached = 1;
        tm->time_to_goal = m->sim_time_s;
    }
}

/* Many teams: every team's sample, its live robots taken from the truth
 * in one pass (bucketed by team). *sq, *mx: the fleet's, each robot's
 * error from its own team's slot. Returns 1 when every team has reached
 * its goal. */
static int fleet_truth(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus,
                       const tandem_rover_truth_t *m, double *sq, double *mx)
{
    int first[ROVER_FLEET_MAX_TEAMS + 1], fill[ROVER_FLEET_MAX_TEAMS], idx[FM_MAX];
    int32_t ids[FM_MAX];
    int i, t, all = 1;
    for (t = 0; t <= cfg->teams; t++)
        first[t] = 0;
    for (i = 0; i < m->n && i < FM_MAX; i++)
        if (m->alive[i] && (t = rover_fleet_team_of(&cfg->fleet, m->robot[i])) >= 0)
            first[t + 1]++;
    for (t = 0; t < cfg->teams; t++) {
        first[t + 1] += first[t];
        fill[t] = first[t];
    }
    for (i = 0; i < m->n && i < FM_MAX; i++)
        if (m->alive[i] && (t = rover_fleet_team_of(&cfg->fleet, m->robot[i])) >= 0) {
            idx[fill[t]] = i;
            ids[fill[t]++] = m->robot[i];
        }
    for (t = 0; t < cfg->teams; t++) {
        const int n = first[t + 1] - first[t];
        if (n > 0)
            team_sample(&mt->team[t], cfg, bus, m, t, idx + first[t], ids + first[t], n, sq, mx);
        all = all && mt->team[t].reached;
    }
    return all;
}

/* formation_error.csv, weights.csv (the lowest live robot's), and
 * snapshots.csv every 5 s. */
static void truth_series(fm_metrics *mt, const fm_bus *bus, const tandem_rover_truth_t *m, double t,
                         double sq, double mx, int n, int lowest)
{
    int i;
    if (mt->err_csv)
        fprintf(mt->err_csv, "%.3f,%.4f,%.4f,%d\n", t, sqrt(sq / n), mx, mt->type_now);
    if (mt->w_csv && lowest >= 0)
        fprintf(mt->w_csv, "%.3f,%.3f,%.3f,%.3f,%.3f,%d\n", t, bus->weight[lowest][0],
                bus->weight[lowest][1], bus->weight[lowest][2], bus->weight[lowest][3],
                bus->mode[lowest]);
    if (mt->snap_csv && t - mt->last_snap_t >= 5.0 - 1e-9) {
        mt->last_snap_t = t;
        for (i = 0; i < m->n; i++)
            if (m->alive[i])
                fprintf(mt->snap_csv, "%.4f,%.4f\n", m->x_m[i], m->y_m[i]);
        if (lowest >= 0)
            fprintf(mt->snap_csv, "%.4f,%.4f\n", m->x_m[lowest], m->y_m[lowest]);
        fprintf(mt->snap_csv, "\n");
    }
}

void fm_metrics_truth(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus, const fm_procs *pr,
                      const tandem_rover_truth_t *m, int dz_entries)
{
    int32_t ids[FM_MAX];
    int i, n, lowest, all_at;
    double sq = 0, mx = 0, t = m->sim_time_s;
    team_pose tp;
    mt->escapes += dz_entries;
    n = alive_ids(m, ids);
    if (n == 0)
        return;
    lowest = team_truth(mt, bus, pr, m, n, t, &tp);
    if (lowest >= 0 && bus->have_state[lowest])
        mt->type_now = bus->state_type[lowest];
    if (lowest >= 0 && bus->have_state[lowest])
        mt->scale_now = bus->state_scale[lowest];
    if (cfg->teams > 1) {
        all_at = fleet_truth(mt, cfg, bus, m, &sq, &mx);
    } else {
        int idx[FM_MAX], q = 0;
        team_aim a;
        a.type = mt->type_now;
        a.scale = mt->scale_now;
        a.formation = cfg->formation;
        a.goal[0] = cfg->layout.goal_m[0];
        a.goal[1] = cfg->layout.goal_m[1];
        a.heading = atan2(cfg->layout.goal_m[1] - cfg->layout.team_origin.y_m,
                          cfg->layout.goal_m[0] - cfg->layout.team_origin.x_m);
        for (i = 0; i < m->n && q < FM_MAX; i++)
            if (m->alive[i])
                idx[q++] = i;
        all_at = formation_error(&a, m, idx, ids, n, &tp, &sq, &mx);
    }
    if (!mt->reached)
        error_sample(&mt->samples, &mt->out_samples, &mt->sum_sq_err, &mt->max_err, sq, mx, n);
    truth_series(mt, bus, m, t, sq, mx, n, lowest);
    mt->collisions = 0;
    for (i = 0; i < m->n; i++)
        mt->collisions += m->collisions[i];
    split_contacts(mt, cfg, m);
    if (!mt->reached && all_at &&
        (cfg->teams > 1 ||
         hypot(tp.cx - cfg->layout.goal_m[0], tp.cy - cfg->layout.goal_m[1]) < 0.5)) {
        mt->reached = 1;
        mt->time_to_goal = t;
    }
}

void fm_metrics_init(fm_metrics *mt, const fm_cfg *cfg)
{
    int t;
    mt->type_now = cfg->formation;
    mt->scale_now = 1.0;
    mt->last_type = -1;
    mt->min_clear = INFINITY;
    mt->last_snap_t = -1e9;
    for (t = 0; t < ROVER_FLEET_MAX_TEAMS; t++) {
        mt->team[t].type_now = cfg->formation;
        mt->team[t].scale_now = 1.0;
        mt->team[t].last_type = -1;
        mt->team[t].min_clear = INFINITY;
    }
}

void fm_metrics_open(fm_metrics *mt, const char *out)
{
    mt->truth_csv = scenario_fopen(out, "truth.csv");
    mt->err_csv = scenario_fopen(out, "formation_error.csv");
    mt->w_csv = scenario_fopen(out, "weights.csv");
    mt->snap_csv = scenario_fopen(out, "snapshots.csv");
}

void fm_metrics_close(fm_metrics *mt)
{
    if (mt->truth_csv)
        fclose(mt->truth_csv);
    if (mt->err_csv)
        fclose(mt->err_csv);
    if (mt->w_csv)
        fclose(mt->w_csv);
    if (mt->snap_csv)
        fclose(mt->snap_csv);
    mt->truth_csv = mt->err_csv = mt->w_csv = mt->snap_csv = NULL;
}

/* Many teams: each team's changes of formation (its lowest live robot's),
 * the run's their sum. */
static void fleet_cycle(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus, const fm_procs *pr)
{
    int t;
    mt->formation_changes = 0;
    for (t = 0; t < cfg->teams; t++) {
        fm_team_metrics *tm = &mt->team[t];
        int32_t lo, hi, k;
        rover_fleet_members(&cfg->fleet, t, &lo, &hi);
        for (k = lo; k <= hi; k++)
            if (bus->have_state[k - 1] && (k != cfg->kill_id || !pr->killed))
                break;
        if (k <= hi) {
            if (tm->last_type >= 0 && bus->state_type[k - 1] != tm->last_type)
                tm->formation_changes++;
            tm->last_type = bus->state_type[k - 1];
        }
        mt->formation_changes += tm->formation_changes;
    }
}

void fm_metrics_cycle(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus, const fm_procs *pr)
{
    int i, lo = -1;
    if (cfg->teams > 1) {
        fleet_cycle(mt, cfg, bus, pr);
        return;
    }
    for (i = 0; i < cfg->robots; i++)
        if (bus->have_state[i] && (i + 1 != cfg->kill_id || !pr->killed)) {
            lo = i;
            break;
        }
    if (lo < 0)
        return;
    if (mt->last_type >= 0 && bus->state_type[lo] != mt->last_type)
        mt->formation_changes++;
    mt->last_type = bus->state_type[lo];
}
