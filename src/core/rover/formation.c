/* formation: slot geometry, width D and slot assignment for the line /
 * triangle / column formations, and the narrow-passage protocol of
 * docs/method/formation.md (seed 3.2.1, fig. 3: shrink, then change type in the
 * order line -> triangle -> column, restore when clear) as a state machine
 * kept consistent across robots by (announce_seq, origin) ordering.
 */
#include "formation.h"

#include <math.h>
#include <string.h>

#define FORMATION_SQRT3_2 0.86602540378443864676

static int type_ok(int type)
{
    return type == FORMATION_LINE || type == FORMATION_TRIANGLE || type == FORMATION_COLUMN;
}

static int geom_ok(int type, int n, double spacing_m, double scale)
{
    return type_ok(type) && n >= 1 && n <= FORMATION_MAX_ROBOTS && isfinite(spacing_m) &&
           spacing_m > 0.0 && isfinite(scale) && scale > 0.0;
}

/* Uncentred pattern position of slot k, unit spacing. */
static void pattern_xy(double xy[2], int type, int n, int k)
{
    if (type == FORMATION_LINE) {
        xy[0] = 0.0;
        xy[1] = 0.5 * (double)(n - 1) - (double)k;
    } else if (type == FORMATION_COLUMN) {
        xy[0] = -(double)k;
        xy[1] = 0.0;
    } else {
        const int row = (k + 1) / 2;
        const double side = (k % 2 == 1) ? 1.0 : -1.0;
        xy[0] = -(double)row * FORMATION_SQRT3_2;
        xy[1] = (k == 0) ? 0.0 : side * 0.5 * (double)row;
    }
}

static void pattern_centroid(double c[2], int type, int n)
{
    double p[2];
    int k;
    c[0] = c[1] = 0.0;
    for (k = 0; k < n; k++) {
        pattern_xy(p, type, n, k);
        c[0] += p[0];
        c[1] += p[1];
    }
    c[0] /= (double)n;
    c[1] /= (double)n;
}

int formation_slot_xy(double xy_m[2], int type, int n, int k, double spacing_m, double scale)
{
    double p[2], c[2];
    if (!geom_ok(type, n, spacing_m, scale) || k < 0 || k >= n)
        return FORMATION_ERR_ARG;
    pattern_xy(p, type, n, k);
    pattern_centroid(c, type, n);
    xy_m[0] = (p[0] - c[0]) * spacing_m * scale;
    xy_m[1] = (p[1] - c[1]) * spacing_m * scale;
    return 0;
}

int formation_slots_xy(double xy_m[][2], int type, int n, double spacing_m, double scale)
{
    double p[2], c[2];
    int k;
    if (!xy_m || !geom_ok(type, n, spacing_m, scale))
        return FORMATION_ERR_ARG;
    pattern_centroid(c, type, n);
    for (k = 0; k < n; k++) {
        pattern_xy(p, type, n, k);
        xy_m[k][0] = (p[0] - c[0]) * spacing_m * scale;
        xy_m[k][1] = (p[1] - c[1]) * spacing_m * scale;
    }
    return 0;
}

int formation_slot(double *l_d_m, double *phi_d_rad, int type, int n, int k, double spacing_m,
                   double scale)
{
    double xy[2];
    if (formation_slot_xy(xy, type, n, k, spacing_m, scale) != 0)
        return FORMATION_ERR_ARG;
    *l_d_m = hypot(xy[0], xy[1]);
    *phi_d_rad = atan2(xy[1], xy[0]);
    return 0;
}

double formation_width(int type, int n, double spacing_m, double scale, double robot_width_m)
{
    double p[2], lo = 0.0, hi = 0.0;
    int k;
    if (!geom_ok(type, n, spacing_m, scale) || !isfinite(robot_width_m) || robot_width_m < 0.0)
        return FORMATION_ERR_ARG;
    for (k = 0; k < n; k++) {
        pattern_xy(p, type, n, k);
        if (k == 0 || p[1] < lo)
            lo = p[1];
        if (k == 0 || p[1] > hi)
            hi = p[1];
    }
    return (hi - lo) * spacing_m * scale + robot_width_m;
}

int formation_next_type(int type)
{
    if (type == FORMATION_LINE)
        return FORMATION_TRIANGLE;
    return FORMATION_COLUMN;
}

int formation_slot_of(const int32_t ids[], int n, int32_t id)
{
    int k, rank = 0, found = 0;
    if (n < 0 || n > FORMATION_MAX_ROBOTS)
        return FORMATION_ERR_ARG;
    for (k = 0; k < n; k++) {
        if (ids[k] < id)
            rank++;
        else if (ids[k] == id)
            found = 1;
    }
    return found ? rank : FORMATION_ERR_ABSENT;
}

/* ---- slots held by any robots ------------------------------------------ */

typedef struct {
    const double (*xy)[2], (*slot)[2];
    int n;
    double tol_m;
    int owner[FORMATION_MAX_ROBOTS]; /* robot in slot k, or -1 */
    unsigned char seen[FORMATION_MAX_ROBOTS];
} slot_match;

/* Robot r takes a slot within reach, moving the slot's robot on to
 * another if it can (one augmenting path; depth at most n). */
static int augment(slot_match *m, int r)
{
    int k;
    for (k = 0; k < m->n; k++) {
        if (m->seen[k] ||
            hypot(m->xy[r][0] - m->slot[k][0], m->xy[r][1] - m->slot[k][1]) > m->tol_m)
            continue;
        m->seen[k] = 1;
        if (m->owner[k] < 0 || augment(m, m->owner[k])) {
            m->owner[k] = r;
            return 1;
        }
    }
    return 0;
}

int formation_slots_held(const double xy_m[][2], const double slot_m[][2], int n, double tol_m)
{
    slot_match m;
    int r;
    if (!xy_m || !slot_m || n < 1 || n > FORMATION_MAX_ROBOTS || !(tol_m >= 0.0))
        return FORMATION_ERR_ARG;
    m.xy = xy_m;
    m.slot = slot_m;
    m.n = n;
    m.tol_m = tol_m;
    for (r = 0; r < n; r++)
        m.owner[r] = -1;
    for (r = 0; r < n; r++) {
        memset(m.seen, 0, sizeof m.seen);
        if (!augment(&m, r))
            return 0;
    }
    return 1;
}

/* ---- narrow-passage protocol ------------------------------------------- */

void formation_fsm_params_default(formation_fsm_params *p)
{
    p->spacing_m = 1.0;
    p->robot_width_m = 0.38;
    p->safety_m = 0.3;
    p->shrink_scale = 0.6;
    p->dwell_s = 1.0;
    p->clear_hold_s = 4.0;
    p->confirm_s = 1.0;
}

static int params_ok(const formation_fsm_params *p)
{
    return isfinite(p->spacing_m) && p->spacing_m > 0.0 && isfinite(p->robot_width_m) &&
           p->robot_width_m >= 0.0 && isfinite(p->safety_m) && p->safety_m >= 0.0 &&
           isfinite(p->shrink_scale) && p->shrink_scale > 0.0 && p->shrink_scale <= 1.0 &&
           isfinite(p->dwell_s) && p->dwell_s >= 0.0 && isfinite(p->clear_hold_s) &&
           p->clear_hold_s >= 0.0 && isfinite(p->confirm_s) && p->confirm_s >= 0.0;
}

int formation_fsm_init(formation_fsm *f, int type, double scale)
{
    if (!type_ok(type) || !isfinite(scale) || !(scale > 0.0))
        return FORMATION_ERR_ARG;
    f->type_nominal = f->type = type;
    f->scale_nominal = f->scale = scale;
    f->phase = FORMATION_PHASE_NORMAL;
    f->seq = 0;
    f->origin = INT32_MAX;
    f->code = FORMATION_ANN_NONE;
    f->seq_max_seen = 0;
    f->phase_s = 0.0;
    f->clear_s = 0.0;
    f->narrow_s = 0.0;
    f->witnessed = 0;
    return 0;
}

int32_t formation_fsm_next_seq(formation_fsm *f)
{
    if (f->seq > f->seq_max_seen)
        f->seq_max_seen = f->seq;
    if (f->seq_max_seen < INT32_MAX)
        f->seq_max_seen++;
    return f->seq_max_seen;
}

static int code_is_protocol(int code)
{
    return code == FORMATION_ANN_SHRINK || code == FORMATION_ANN_CHANGE ||
           code == FORMATION_ANN_RESTORE;
}

static int phase_of_code(int code)
{
    if (code == FORMATION_ANN_SHRINK)
        return FORMATION_PHASE_SHRINK;
    if (code == FORMATION_ANN_CHANGE)
        return FORMATION_PHASE_CHANGE;
    return FORMATION_PHASE_RESTORE;
}

static void adopt(formation_fsm *f, const formation_announce *a)
{
    f->seq = a->seq;
    f->origin = a->origin;
    f->code = a->code;
    f->type = a->type;
    f->scale = a->scale;
    f->phase = phase_of_code(a->code);
    f->phase_s = 0.0;
    f->clear_s = 0.0;
    f->narrow_s = 0.0;
    if (a->code == FORMATION_ANN_RESTORE)
        f->witnessed = 0;
    if (a->seq > f->seq_max_seen)
        f->seq_max_seen = a->seq;
}

static void announce(formation_fsm *f, formation_announce *out, int code, int type, double scale,
                     int32_t self_id)
{
    formation_announce a;
    a.code = code;
    a.seq = formation_fsm_next_seq(f);
    a.origin = self_id;
    a.type = type;
    a.scale = scale;
    adopt(f, &a);
    *out = a;
}

int formation_ann_valid(int code)
{
    return code >= FORMATION_ANN_NONE && code <= FORMATION_ANN_GIVE_WAY;
}

int formation_ann_out(int code)
{
    return code == FORMATION_ANN_LEAVE || code == FORMATION_ANN_GIVE_WAY;
}

int formation_fsm_on_announce(formation_fsm *f, const formation_announce *a)
{
    if (!a || !isfinite(a->scale) || !(a->scale > 0.0) || !type_ok(a->type) ||
        !formation_ann_valid(a->code))
        return FORMATION_ERR_ARG;
    if (a->seq > f->seq_max_seen)
        f->seq_max_seen = a->seq;
    if (!code_is_protocol(a->code))
        return 0;
    if (a->seq < f->seq || (a->seq == f->seq && a->origin >= f->origin))
        return 0;
    adopt(f, a);
    return 1;
}

int formation_fsm_step(formation_fsm *f, const formation_fsm_params *p, double passage_width_m,
                       int n, double dt_s, int32_t self_id, int rearmost, formation_announce *out)
{
    double need_now, need_nominal;
    int narrow, clear;
    const int known = !isnan(passage_width_m);
    if (!params_ok(p) || n < 1 || n > FORMATION_MAX_ROBOTS || !isfinite(dt_s) || dt_s < 0.0 || !out)
        return FORMATION_ERR_ARG;
    need_now = formation_width(f->type, n, p->spacing_m, f->scale, p->robot_width_m) + p->safety_m;
    need_nominal = formation_width(f->type_nominal, n, p->spacing_m, f->scale_nominal,
                                   p->robot_width_m) +
                   p->safety_m;
    /* narrow only when sensed narrow for confirm_s (a known wider reading
     * starts over, an unknown one holds): a gap between two scattered
     * obstacles passes in a moment, a passage goes on */
    if (known)
        f->narrow_s = passage_width_m < need_now ? f->narrow_s + dt_s : 0.0;
    narrow = f->narrow_s > 0.0 && f->narrow_s >= p->confirm_s;
    clear = known && passage_width_m >= need_nominal;
    if (known && !clear)
        f->witnessed = 1;
    f->phase_s += dt_s;
    if (known)
        f->clear_s = clear ? f->clear_s + dt_s : 0.0;

    switch (f->phase) {
    case FORMATION_PHASE_NORMAL:
        if (narrow) {
            announce(f, out, FORMATION_ANN_SHRINK, f->type, f->scale_nominal * p->shrink_scale,
                     self_id);
            return 1;
        }
        return 0;
    case FORMATION_PHASE_SHRINK:
    case FORMATION_PHASE_CHANGE:
        if (rearmost && f->witnessed && f->clear_s >= p->clear_hold_s) {
            announce(f, out, FORMATION_ANN_RESTORE, f->type_nominal, f->scale_nominal, self_id);
            return 1;
        }
        if (narrow && f->phase_s >= p->dwell_s && f->type != FORMATION_COLUMN) {
            announce(f, out, FORMATION_ANN_CHANGE, formation_next_type(f->type), f->scale, self_id);
            return 1;
        }
        return 0;
    default: /* RESTORE */
        if (narrow) {
            announce(f, out, FORMATION_ANN_SHRINK, f->type_nominal,
                     f->scale_nominal * p->shrink_scale, self_id);
            return 1;
        }
        if (f->phase_s >= p->dwell_s) {
            f->phase = FORMATION_PHASE_NORMAL;
            f->phase_s = 0.0;
        }
        return 0;
    }
}
