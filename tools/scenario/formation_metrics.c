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
static void robot_truth(fm_state *fm, const tandem_rover_truth_t *m, int i, double t)
{
    /* path and smoothness (mean |dw/dt|) */
    if (fm->have_prev[i]) {
        const double w = vec2_angle_diff_rad(m->theta_rad[i], fm->prev_th[i]) / (FM_PERIOD * 1e-3);
        fm->path[i] += hypot(m->x_m[i] - fm->prev_x[i], m->y_m[i] - fm->prev_y[i]);
        if (fm->have_prev_w[i] && !fm->reached) {
            fm->sum_dw += fabs(w - fm->prev_w[i]) / (FM_PERIOD * 1e-3);
            fm->n_dw++;
        }
        fm->prev_w[i] = w;
        fm->have_prev_w[i] = 1;
    }
    fm->prev_x[i] = m->x_m[i];
    fm->prev_y[i] = m->y_m[i];
    fm->prev_th[i] = m->theta_rad[i];
    fm->have_prev[i] = 1;
    if (fm->have_state[i] && !fm_process_down(fm, m->robot[i], m->step - FM_PERIOD)) {
        /* localization error: the robot's own estimate of O against
         * the truth (both world frame); none while its process is down */
        const double e = hypot(fm->est[i].x_m - m->x_m[i], fm->est[i].y_m - m->y_m[i]);
        fm->loc_sum_sq += e * e;
        fm->loc_n++;
        if (e > fm->loc_max)
            fm->loc_max = e;
    }
    if (fm->truth_csv)
        fprintf(fm->truth_csv, "%.3f,%d,%.4f,%.4f,%.4f,%.4f,%d,%.4f,%.4f,%.4f\n", t, m->robot[i],
                m->x_m[i], m->y_m[i], m->theta_rad[i], m->min_clearance_m[i], m->collisions[i],
                fm->est[i].x_m, fm->est[i].y_m, fm->est[i].theta_rad);
}

/* Centre of robot i's body box (world frame): O is ROVER_BEACON_D_M from
 * C along the heading, the box centre ROVER_BODY_OFFSET_M from C. */
static void body_centre(const tandem_rover_truth_t *m, int i, double *x, double *y)
{
    const double d = ROVER_BODY_OFFSET_M - ROVER_BEACON_D_M;
    *x = m->x_m[i] + d * cos(m->theta_rad[i]);
    *y = m->y_m[i] + d * sin(m->theta_rad[i]);
}

/* 1 if another live robot's body is within reach of robot i's: their box
 * centres closer than the box diagonal plus 2 cm (two boxes farther apart
 * cannot touch whatever their headings). */
static int mate_within_reach(const tandem_rover_truth_t *m, int i)
{
    const double reach_m = hypot(ROVER_BODY_LENGTH_M, ROVER_BODY_WIDTH_M) + 0.02;
    double xi, yi, xj, yj;
    int j;
    body_centre(m, i, &xi, &yi);
    for (j = 0; j < m->n; j++) {
        if (j == i || !m->alive[j])
            continue;
        body_centre(m, j, &xj, &yj);
        if (hypot(xj - xi, yj - yi) < reach_m)
            return 1;
    }
    return 0;
}

/* The new contact events of each robot since the last sample, counted on
 * mates if a mate is within reach, else on walls (docs/formation.md). */
static void split_contacts(fm_state *fm, const tandem_rover_truth_t *m)
{
    int i;
    for (i = 0; i < m->n && i < FM_MAX; i++) {
        const int d = m->collisions[i] - fm->coll_prev[i];
        if (d <= 0)
            continue;
        fm->coll_prev[i] = m->collisions[i];
        if (mate_within_reach(m, i))
            fm->collisions_mates += d;
        else
            fm->collisions_walls += d;
    }
}

/* Every live robot's truth; the team's centroid and mean heading. Returns
 * the index of the lowest live robot, -1 none. */
static int team_truth(fm_state *fm, const tandem_rover_truth_t *m, int n, double t, team_pose *tp)
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
        if (m->min_clearance_m[i] < fm->min_clear)
            fm->min_clear = m->min_clearance_m[i];
        robot_truth(fm, m, i, t);
    }
    cx /= n;
    cy /= n;
    tp->cx = cx;
    tp->cy = cy;
    tp->th0 = atan2(s, c);
    return lowest;
}

/* Formation error: slots of the formation the team is flying now around
 * the true centroid and mean heading; robot slots by sorted alive id.
 * *sq: sum of the squared errors, *mx: the largest. Returns 1 when the
 * nominal slots around the goal (the slot frame headed along the goal's
 * bearing from the team origin, as the robots place it) are held: each
 * by its own robot within 0.75 m, whichever robot (the robots take the
 * goal's slots in the order they arrive). */
static int formation_error(const fm_state *fm, const tandem_rover_truth_t *m, const int32_t *ids,
                           int n, const team_pose *tp, double *sq, double *mx)
{
    double at[ROVER_TEAM_MAX][2], goal_slot[ROVER_TEAM_MAX][2];
    const double heading = atan2(fm->layout.goal_m[1] - fm->layout.team_origin.y_m,
                                 fm->layout.goal_m[0] - fm->layout.team_origin.x_m);
    int i, k = 0;
    for (i = 0; i < m->n; i++) {
        double xy[2], r[2], e;
        int rank;
        if (!m->alive[i])
            continue;
        rank = formation_slot_of(ids, n, m->robot[i]);
        formation_slot_xy(xy, fm->type_now, n, rover_world_slot(fm->type_now, n, rank), 1.0,
                          fm->scale_now);
        vec2_rotate(r, xy[0], xy[1], tp->th0);
        e = hypot(m->x_m[i] - tp->cx - r[0], m->y_m[i] - tp->cy - r[1]);
        *sq += e * e;
        if (e > *mx)
            *mx = e;
        if (k >= n || k >= ROVER_TEAM_MAX)
            return 0;
        formation_slot_xy(xy, fm->formation, n, k, 1.0, 1.0);
        vec2_rotate(r, xy[0], xy[1], heading);
        goal_slot[k][0] = fm->layout.goal_m[0] + r[0];
        goal_slot[k][1] = fm->layout.goal_m[1] + r[1];
        at[k][0] = m->x_m[i];
        at[k][1] = m->y_m[i];
        k++;
    }
    return k == n && formation_slots_held((const double(*)[2])at, (const double(*)[2])goal_slot, n,
                                          0.75) == 1;
}

/* formation_error.csv, weights.csv (the lowest live robot's), and
 * snapshots.csv every 5 s. */
static void truth_series(fm_state *fm, const tandem_rover_truth_t *m, double t, double sq,
                         double mx, int n, int lowest)
{
    int i;
    if (fm->err_csv)
        fprintf(fm->err_csv, "%.3f,%.4f,%.4f,%d\n", t, sqrt(sq / n), mx, fm->type_now);
    if (fm->w_csv && lowest >= 0)
        fprintf(fm->w_csv, "%.3f,%.3f,%.3f,%.3f,%.3f,%d\n", t, fm->weight[lowest][0],
                fm->weight[lowest][1], fm->weight[lowest][2], fm->weight[lowest][3],
                fm->mode[lowest]);
    if (fm->snap_csv && t - fm->last_snap_t >= 5.0 - 1e-9) {
        fm->last_snap_t = t;
        for (i = 0; i < m->n; i++)
            if (m->alive[i])
                fprintf(fm->snap_csv, "%.4f,%.4f\n", m->x_m[i], m->y_m[i]);
        if (lowest >= 0)
            fprintf(fm->snap_csv, "%.4f,%.4f\n", m->x_m[lowest], m->y_m[lowest]);
        fprintf(fm->snap_csv, "\n");
    }
}

void fm_on_truth(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_truth_t *m, void *u)
{
    fm_state *fm = u;
    int32_t ids[FM_MAX];
    int i, n, lowest, all_at;
    double sq = 0, mx = 0, t = m->sim_time_s;
    team_pose tp;
    (void)rb;
    (void)ch;
    for (i = 0; i < m->n && fm->killed; i++) /* the --kill taken (fm_kill_robot) */
        if (m->robot[i] == fm->kill_id && !m->alive[i])
            fm->kill_seen = 1;
    if (m->n != fm->robots || m->step <= fm->last_truth_step || !fm_states_for_truth(fm, m))
        return;
    fm->last_truth_step = m->step;
    n = alive_ids(m, ids);
    if (n == 0)
        return;
    lowest = team_truth(fm, m, n, t, &tp);
    if (lowest >= 0 && fm->have_state[lowest])
        fm->type_now = fm->state_type[lowest];
    if (lowest >= 0 && fm->have_state[lowest])
        fm->scale_now = fm->state_scale[lowest];
    all_at = formation_error(fm, m, ids, n, &tp, &sq, &mx);
    if (!fm->reached) {
        fm->samples++;
        fm->sum_sq_err += sq / n;
        if (mx > fm->max_err)
            fm->max_err = mx;
        if (mx > FM_OUT_TOL)
            fm->out_samples++;
    }
    truth_series(fm, m, t, sq, mx, n, lowest);
    fm->collisions = 0;
    for (i = 0; i < m->n; i++)
        fm->collisions += m->collisions[i];
    split_contacts(fm, m);
    if (!fm->reached && all_at &&
        hypot(tp.cx - fm->layout.goal_m[0], tp.cy - fm->layout.goal_m[1]) < 0.5) {
        fm->reached = 1;
        fm->time_to_goal = t;
    }
}
