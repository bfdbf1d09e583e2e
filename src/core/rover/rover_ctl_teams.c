/* rover_ctl_teams: robots of other teams in one world (fleet.h). A robot
 * hears only its own team, so another team's robots are known only as
 * echoes (obstacles to the sonar, never masked as mates) and as beacons
 * the camera sees: the last place each was seen is kept in a small table
 * (ROVER_STRANGERS, the oldest replaced). Between teams the order is the
 * teams' (the lower ids outrank: robots are numbered team by team): a
 * robot stands while a robot of an outranking team, seen lately, is near
 * and ahead of it; the outranking robot goes round it as round any
 * obstacle. A robot never waits for a team it outranks, so the waits
 * between teams form no cycle: the first team waits for none; and each
 * wait is bounded (stranger_hold_max_s, counted until the robot has had
 * nobody to stand for during STRANGER_FREE_S), after which it flies on its
 * sonar alone until it is free again.
 */
#include "rover_ctl_internal.h"

#include <math.h>

void rover_ctl_stranger_seen(rover_ctl_state *c, int32_t id, const pose2 *o, double range_m,
                             double bearing_rad, double t_s)
{
    rover_stranger *slot = &c->stranger[0];
    int k;
    for (k = 0; k < ROVER_STRANGERS; k++) {
        rover_stranger *s = &c->stranger[k];
        if (s->id == id) {
            slot = s;
            break;
        }
        if (s->id == 0 || s->t_s < slot->t_s)
            slot = s; /* a free place, else the oldest */
        if (s->id == 0)
            break;
    }
    slot->id = id;
    slot->xy_m[0] = o->x_m + range_m * cos(o->theta_rad + bearing_rad);
    slot->xy_m[1] = o->y_m + range_m * sin(o->theta_rad + bearing_rad);
    slot->t_s = t_s;
}

/* 1 if an outranking team's robot was seen lately near and ahead of o. */
static int stranger_ahead(const rover_ctl_state *c, const pose2 *o, double t_s)
{
    const double r2 = c->p.stranger_give_m * c->p.stranger_give_m;
    int k;
    for (k = 0; k < ROVER_STRANGERS; k++) {
        const rover_stranger *s = &c->stranger[k];
        const double dx = s->xy_m[0] - o->x_m, dy = s->xy_m[1] - o->y_m;
        if (s->id == 0 || s->id >= c->team_lo || t_s - s->t_s > c->p.stranger_seen_s ||
            dx * dx + dy * dy > r2)
            continue;
        if (fabs(vec2_angle_diff_rad(atan2(dy, dx), o->theta_rad)) <= c->p.stranger_cone_rad)
            return 1;
    }
    return 0;
}

/* Free to go again only after STRANGER_FREE_S with nobody to stand for:
 * a robot abreast is seen in every other camera frame, and a wait counted
 * afresh after each gap between sightings would never run out. */
#define STRANGER_FREE_S 1.0

int rover_ctl_stranger_wait(rover_ctl_state *c, const pose2 *o, double t_s, double dt_s)
{
    if (!stranger_ahead(c, o, t_s)) {
        c->stranger_free_s += dt_s;
        if (c->stranger_free_s >= STRANGER_FREE_S)
            c->stranger_hold_s = 0.0;
        return 0;
    }
    c->stranger_free_s = 0.0;
    c->stranger_hold_s += dt_s;
    return c->stranger_hold_s <= c->p.stranger_hold_max_s;
}
