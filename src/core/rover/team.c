/* team: team-mate table from team messages, heartbeat timeout, late join,
 * the team-average reference R0 of docs/method/formation.md (keep formation) and
 * a complementary-filter fusion of camera beacon observations.
 */
#include "team.h"
#include "formation.h"

#include <math.h>
#include <string.h>

int team_init(team_table *t, int32_t self_id, double timeout_s)
{
    if (!t || !isfinite(timeout_s) || !(timeout_s > 0.0))
        return TEAM_ERR_ARG;
    t->self_id = self_id;
    t->timeout_s = timeout_s;
    t->n = 0;
    return 0;
}

static int index_of(const team_table *t, int32_t robot, int *ins)
{
    int lo = 0, hi = t->n;
    while (lo < hi) {
        const int mid = (lo + hi) / 2;
        if (t->m[mid].robot < robot)
            lo = mid + 1;
        else
            hi = mid;
    }
    if (ins)
        *ins = lo;
    return (lo < t->n && t->m[lo].robot == robot) ? lo : TEAM_ERR_UNKNOWN;
}

static int msg_ok(const team_table *t, const team_member *m)
{
    return m->robot != t->self_id && vec2_finite3(m->x_m, m->y_m, m->theta_rad) &&
           isfinite(m->v_mps) && isfinite(m->w_radps) && isfinite(m->t_s) && isfinite(m->scale) &&
           m->scale > 0.0 && m->formation >= FORMATION_LINE && m->formation <= FORMATION_COLUMN &&
           formation_ann_valid(m->announce);
}

int team_update(team_table *t, const team_member *msg)
{
    int ins, i;
    double ox = 0.0, oy = 0.0, ot = -INFINITY, orng = INFINITY;
    int obs = 0, added = 0;
    if (!t || !msg || !msg_ok(t, msg))
        return TEAM_ERR_ARG;
    i = index_of(t, msg->robot, &ins);
    if (i >= 0) {
        if (msg->t_s < t->m[i].t_s)
            return 0; /* out of order */
        ox = t->m[i].off_x_m;
        oy = t->m[i].off_y_m;
        obs = t->m[i].observed;
        ot = t->m[i].obs_t_s;
        orng = t->m[i].obs_range_m;
    } else {
        if (t->n >= TEAM_MAX)
            return TEAM_ERR_FULL;
        memmove(&t->m[ins + 1], &t->m[ins], (size_t)(t->n - ins) * sizeof t->m[0]);
        t->n++;
        i = ins;
        added = 1;
    }
    t->m[i] = *msg;
    t->m[i].theta_rad = vec2_wrap_rad(msg->theta_rad);
    t->m[i].off_x_m = ox;
    t->m[i].off_y_m = oy;
    t->m[i].observed = obs;
    t->m[i].obs_t_s = ot;
    t->m[i].obs_range_m = orng;
    return added;
}

int team_expire(team_table *t, double now_s)
{
    int i, j = 0, dropped;
    if (!isfinite(now_s))
        return 0;
    for (i = 0; i < t->n; i++)
        if (!(now_s - t->m[i].t_s > t->timeout_s))
            t->m[j++] = t->m[i];
    dropped = t->n - j;
    t->n = j;
    return dropped;
}

const team_member *team_find(const team_table *t, int32_t robot)
{
    const int i = index_of(t, robot, NULL);
    return i >= 0 ? &t->m[i] : NULL;
}

int team_ids(const team_table *t, int32_t *ids, int cap)
{
    int i = 0, k = 0, self_done = 0;
    while (k < cap && (i < t->n || !self_done)) {
        if (!self_done && (i == t->n || t->m[i].robot > t->self_id)) {
            ids[k++] = t->self_id;
            self_done = 1;
        } else {
            ids[k++] = t->m[i++].robot;
        }
    }
    return k;
}

int team_position(const team_table *t, int32_t robot, double xy_m[2])
{
    const team_member *m = team_find(t, robot);
    if (!m)
        return TEAM_ERR_UNKNOWN;
    xy_m[0] = m->x_m + m->off_x_m;
    xy_m[1] = m->y_m + m->off_y_m;
    return 0;
}

int team_observe(team_table *t, int32_t robot, const pose2 *own_o, double range_m,
                 double bearing_rad, double alpha, double now_s)
{
    const int i = index_of(t, robot, NULL);
    double ox, oy;
    team_member *m;
    if (i < 0 || !vec2_pose_finite(own_o) || !isfinite(range_m) || range_m < 0.0 ||
        !isfinite(bearing_rad) || !isfinite(alpha) || alpha < 0.0 || alpha > 1.0 ||
        !isfinite(now_s))
        return TEAM_ERR_ARG;
    m = &t->m[i];
    ox = own_o->x_m + range_m * cos(own_o->theta_rad + bearing_rad) - m->x_m;
    oy = own_o->y_m + range_m * sin(own_o->theta_rad + bearing_rad) - m->y_m;
    /* First sighting: take it whole so the filter does not start from 0. */
    if (m->observed == 0)
        alpha = 1.0;
    m->off_x_m += alpha * (ox - m->off_x_m);
    m->off_y_m += alpha * (oy - m->off_y_m);
    m->observed++;
    m->obs_t_s = now_s;
    m->obs_range_m = range_m;
    return 0;
}

int team_mean_offset(const team_table *t, double now_s, double max_age_s, double max_range_m,
                     double off_m[2])
{
    int i, n = 0;
    off_m[0] = off_m[1] = 0.0;
    for (i = 0; i < t->n; i++) {
        const team_member *m = &t->m[i];
        double ox = m->off_x_m, oy = m->off_y_m;
        if (m->observed == 0 || !(now_s - m->obs_t_s <= max_age_s) ||
            !(m->obs_range_m <= max_range_m))
            continue;
        if (fabs(m->v_mps) > TEAM_STILL_MPS) {
            /* a moving mate's report is older than the sighting (transport,
             * control period): along its heading the offset holds v times
             * that lag, the same for every robot of a team on the move, and
             * the consensus would pull the whole frame back; across it the
             * offset is drift alone */
            const double hx = cos(m->theta_rad), hy = sin(m->theta_rad), a = ox * hx + oy * hy;
            ox -= a * hx;
            oy -= a * hy;
        }
        off_m[0] += ox;
        off_m[1] += oy;
        n++;
    }
    if (n > 0) {
        off_m[0] /= n;
        off_m[1] /= n;
    }
    return n;
}

void team_shift_offsets(team_table *t, double dx_m, double dy_m)
{
    int i;
    for (i = 0; i < t->n; i++) {
        t->m[i].off_x_m += dx_m;
        t->m[i].off_y_m += dy_m;
    }
}

/* Move a reported O pose forward by age along its (V, w). */
static void extrapolate(pose2 *o, double v, double w, double d_m, double age_s)
{
    pose2 c;
    unicycle_c_from_o(&c, o, d_m);
    unicycle_step_exact(&c, v, w, age_s);
    unicycle_o_from_c(o, &c, d_m);
}

typedef struct {
    double x, y, s, c, v, w;
    int n;
} ref_acc_t;

static void acc_add(ref_acc_t *a, const pose2 *o, double v, double w)
{
    a->x += o->x_m;
    a->y += o->y_m;
    a->s += sin(o->theta_rad);
    a->c += cos(o->theta_rad);
    a->v += v;
    a->w += w;
    a->n++;
}

int team_reference(unicycle_state *ref, const team_table *t, const unicycle_state *self,
                   int self_left, double d_m, double now_s)
{
    ref_acc_t a = { 0, 0, 0, 0, 0, 0, 0 };
    int i;
    if (!ref || !t || !isfinite(now_s) || !isfinite(d_m))
        return TEAM_ERR_ARG;
    if (self && !self_left) {
        const pose2 o = { self->x_m, self->y_m, self->theta_rad };
        if (!vec2_pose_finite(&o) || !isfinite(self->v_mps) || !isfinite(self->w_radps))
            return TEAM_ERR_ARG;
        acc_add(&a, &o, self->v_mps, self->w_radps);
    }
    for (i = 0; i < t->n; i++) {
        const team_member *m = &t->m[i];
        double age = now_s - m->t_s;
        pose2 o;
        if (age > t->timeout_s || formation_ann_out(m->announce))
            continue;
        if (age < 0.0)
            age = 0.0;
        o.x_m = m->x_m + m->off_x_m;
        o.y_m = m->y_m + m->off_y_m;
        o.theta_rad = m->theta_rad;
        extrapolate(&o, m->v_mps, m->w_radps, d_m, age);
        acc_add(&a, &o, m->v_mps, m->w_radps);
    }
    if (a.n == 0)
        return TEAM_ERR_UNKNOWN;
    ref->x_m = a.x / a.n;
    ref->y_m = a.y / a.n;
    /* Opposed headings have no mean; keep self's (or 0) rather than noise. */
    if (hypot(a.s, a.c) > 1e-9 * a.n)
        ref->theta_rad = atan2(a.s, a.c);
    else
        ref->theta_rad = self ? vec2_wrap_rad(self->theta_rad) : 0.0;
    ref->v_mps = a.v / a.n;
    ref->w_radps = a.w / a.n;
    return a.n;
}
