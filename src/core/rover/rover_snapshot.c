/* rover_snapshot: what a restarted formation controller takes back
 * (rover_ctl_snapshot / rover_ctl_resume, see rover_ctl.h): its own pose
 * (odometry, frame correction, the landmark filter), the formation
 * protocol (docs/method/formation.md §9), the dead-zone escape (eq. 2) and the counters, as
 * a vector of numbers for tandem-rover's journal. One const table names
 * every field once, for both directions; rover_snapshot_validate checks
 * it (sizes, no field twice, the count the header promises).
 */
#include "rover_ctl.h"
#include <math.h>
#include <stddef.h>
#include <string.h>

enum { SNAP_DOUBLE, SNAP_INT, SNAP_INT32, SNAP_LONG };

typedef struct {
    size_t offset;
    int kind;
    size_t size;
} snap_field;

#define F_D(m)                                                                       \
    {                                                                                \
        offsetof(rover_ctl_state, m), SNAP_DOUBLE, sizeof(((rover_ctl_state *)0)->m) \
    }
#define F_I(m)                                                                    \
    {                                                                             \
        offsetof(rover_ctl_state, m), SNAP_INT, sizeof(((rover_ctl_state *)0)->m) \
    }
#define F_I32(m)                                                                    \
    {                                                                               \
        offsetof(rover_ctl_state, m), SNAP_INT32, sizeof(((rover_ctl_state *)0)->m) \
    }
#define F_CRUMB(k) F_D(crumb_m[k][0]), F_D(crumb_m[k][1])
#define F_L(m)                                                                     \
    {                                                                              \
        offsetof(rover_ctl_state, m), SNAP_LONG, sizeof(((rover_ctl_state *)0)->m) \
    }

/* The id first (a snapshot names its robot), then have_enc. */
static const snap_field snap_table[] = {
    F_I32(id),
    F_I(have_enc),
    /* own pose */
    F_D(odo.last_left_rad),
    F_D(odo.last_right_rad),
    F_D(odo.dist_m),
    F_D(odo.c.x_m),
    F_D(odo.c.y_m),
    F_D(odo.c.theta_rad),
    F_D(corr_m[0]),
    F_D(corr_m[1]),
    F_D(loc.s[0]),
    F_D(loc.s[1]),
    F_D(loc.s[2]),
    F_D(loc.P[0]),
    F_D(loc.P[1]),
    F_D(loc.P[2]),
    F_D(loc.P[3]),
    F_D(loc.P[4]),
    F_D(loc.P[5]),
    F_D(loc.P[6]),
    F_D(loc.P[7]),
    F_D(loc.P[8]),
    F_L(loc.accepted),
    F_L(loc.rejected),
    F_L(loc.resets),
    F_I(loc.rejected_run),
    F_D(enc_t_s),
    F_D(prev_enc_t_s),
    F_D(v_est_mps),
    F_D(w_est_radps),
    /* formation protocol */
    F_I(fsm.type),
    F_D(fsm.scale),
    F_I(fsm.phase),
    F_I32(fsm.seq),
    F_I32(fsm.origin),
    F_I(fsm.code),
    F_I32(fsm.seq_max_seen),
    F_D(fsm.phase_s),
    F_D(fsm.clear_s),
    F_D(fsm.narrow_s),
    F_I(fsm.witnessed),
    F_I(ann_code),
    F_I32(ann_seq),
    F_D(team_tx_t_s),
    F_I(formation_changes),
    /* dead-zone escape */
    F_D(exc.blocked_s),
    F_I(exc.active),
    F_I(exc.entries),
    F_I(esc.phase),
    F_I(esc.side),
    F_I(esc.yield),
    F_I(esc.turn),
    F_D(esc.hit_dist_m),
    F_D(esc.s),
    F_D(esc.lost_s),
    F_D(esc.wait_s),
    F_I(escapes),
    F_D(hold_s),
    F_D(esc.back_m),
    F_I(holding),
    F_I(arrive_turn),
    F_D(stall_xy_m[0]),
    F_D(stall_xy_m[1]),
    F_D(stall_t_s),
    F_D(esc.wedge_s),
    F_I(esc.turned_back),
    F_I(crumb_n),
    F_CRUMB(0),
    F_CRUMB(1),
    F_CRUMB(2),
    F_CRUMB(3),
    F_CRUMB(4),
    F_CRUMB(5),
    F_CRUMB(6),
    F_CRUMB(7),
};
#define SNAP_N ((int)(sizeof snap_table / sizeof snap_table[0]))
/* the table above lists crumbs 0..7: it must list every one */
typedef char snap_lists_every_crumb[ROVER_CRUMBS == 8 ? 1 : -1];

static int size_fits(const snap_field *f)
{
    switch (f->kind) {
    case SNAP_DOUBLE: return f->size == sizeof(double);
    case SNAP_INT: return f->size == sizeof(int);
    case SNAP_INT32: return f->size == sizeof(int32_t);
    case SNAP_LONG: return f->size == sizeof(long);
    default: return 0;
    }
}

int rover_snapshot_validate(void)
{
    int i, k;
    if (SNAP_N != ROVER_CTL_SNAPSHOT_VALUES)
        return ROVER_CTL_ERR_SNAPSHOT;
    for (i = 0; i < SNAP_N; i++) {
        if (!size_fits(&snap_table[i]) ||
            snap_table[i].offset + snap_table[i].size > sizeof(rover_ctl_state))
            return ROVER_CTL_ERR_SNAPSHOT;
        for (k = 0; k < i; k++)
            if (snap_table[k].offset == snap_table[i].offset)
                return ROVER_CTL_ERR_SNAPSHOT;
    }
    return ROVER_CTL_OK;
}

static double get(const rover_ctl_state *c, const snap_field *f)
{
    const char *p = (const char *)c + f->offset;
    switch (f->kind) {
    case SNAP_DOUBLE: return *(const double *)(const void *)p;
    case SNAP_INT: return (double)*(const int *)(const void *)p;
    case SNAP_INT32: return (double)*(const int32_t *)(const void *)p;
    default: return (double)*(const long *)(const void *)p;
    }
}

/* Integers travel as doubles: exact up to 2^53, far above any counter. */
static int put(rover_ctl_state *c, const snap_field *f, double v)
{
    char *p = (char *)c + f->offset;
    if (!isfinite(v))
        return ROVER_CTL_ERR_SNAPSHOT;
    if (f->kind == SNAP_DOUBLE) {
        *(double *)(void *)p = v;
        return 0;
    }
    if (v != floor(v) || fabs(v) > 2147483647.0)
        return ROVER_CTL_ERR_SNAPSHOT;
    if (f->kind == SNAP_INT)
        *(int *)(void *)p = (int)v;
    else if (f->kind == SNAP_INT32)
        *(int32_t *)(void *)p = (int32_t)v;
    else
        *(long *)(void *)p = (long)v;
    return 0;
}

int rover_ctl_snapshot(const rover_ctl_state *c, double v[ROVER_CTL_SNAPSHOT_VALUES])
{
    int i;
    if (!c || !v || !c->have_enc || rover_snapshot_validate() != ROVER_CTL_OK)
        return ROVER_CTL_ERR_ARG;
    for (i = 0; i < SNAP_N; i++)
        v[i] = get(c, &snap_table[i]);
    return ROVER_CTL_OK;
}

/* A state the controller could have reached: its robot, after the first
 * encoder reading, a formation it knows, a positive filter covariance. */
static int plausible(const rover_ctl_state *c, int32_t id)
{
    return c->id == id && c->have_enc == 1 && c->fsm.type >= FORMATION_LINE &&
           c->fsm.type <= FORMATION_COLUMN && c->fsm.scale > 0.0 && c->loc.P[0] > 0.0 &&
           c->loc.P[4] > 0.0 && c->loc.P[8] > 0.0 && c->enc_t_s >= c->prev_enc_t_s &&
           c->crumb_n >= 0 && c->crumb_n <= ROVER_CRUMBS;
}

int rover_ctl_resume(rover_ctl_state *c, const double v[ROVER_CTL_SNAPSHOT_VALUES])
{
    rover_ctl_state r;
    int i;
    if (!c || !v || rover_snapshot_validate() != ROVER_CTL_OK)
        return ROVER_CTL_ERR_ARG;
    r = *c;
    /* the first encoder reading sets up what the launch configuration
     * gives (odometry geometry, the filter's parameters and landmarks);
     * the snapshot then overwrites the state */
    if (!r.have_enc && rover_ctl_encoders(&r, 0.0, 0.0, 0.0) != 0)
        return ROVER_CTL_ERR_ARG;
    for (i = 0; i < SNAP_N; i++)
        if (put(&r, &snap_table[i], v[i]) != 0)
            return ROVER_CTL_ERR_SNAPSHOT;
    if (!plausible(&r, c->id))
        return ROVER_CTL_ERR_SNAPSHOT;
    *c = r;
    return ROVER_CTL_OK;
}
