/* rover_ctl_escape: the formation controller's dead-zone escape and giving
 * way to it (docs/method/formation.md: dead-zone escape, eq. 2's alternating
 * +-w_k turn in behaviour_exception_step; see rover_ctl.h). After the turn
 * the robot follows the obstacle boundary until Bug2's leave rule lets it
 * rejoin; a robot in the way of a mate that escapes leaves the formation
 * too, turns away from the mate and follows the boundary out the same way.
 * Own announcements (LEAVE, REJOIN) are made here.
 */
#include "rover_ctl_internal.h"

#include <math.h>

/* Escape wall following: the nearer range on the wall side held at
 * follow_dist_m by a proportional turn. */
void rover_ctl_follow(unicycle_cmd *u, const sonar_groups *g, int side,
                      const rover_ctl_params *p)
{
    const double s = side < 0 ? -1.0 : 1.0;
    const double near_side = s < 0 ? fmin(g->right_m, g->right_front_m)
                                   : fmin(g->left_m, g->left_front_m);
    const double wmax = p->follow_w_radps;
    if (g->front_m < p->follow_dist_m + 0.1 ||
        (s < 0 ? g->right_front_m : g->left_front_m) < 0.75 * p->follow_dist_m) {
        /* blocked ahead: turn away from the wall side on the spot (creeping
         * forward while turning walked the axle toward the walls of a narrow
         * pocket until the turning tail touched one) */
        u->v_mps = 0.0;
        u->w_radps = -s * wmax;
    } else if (near_side > p->follow_dist_m + 0.8) {
        /* lost the wall (a convex corner): arc round toward it */
        u->v_mps = 0.7 * p->follow_v_mps;
        u->w_radps = s * 0.8 * wmax;
    } else {
        double w = -s * 2.0 * (p->follow_dist_m - near_side);
        if (w > wmax) w = wmax;
        if (w < -wmax) w = -wmax;
        u->v_mps = p->follow_v_mps;
        u->w_radps = w;
    }
}

/* The transducer whose bearing is nearest to b (table order, -90..90 deg). */
static double range_toward(const double range_m[BEH_SONAR_N], double b_rad)
{
    static const double deg[BEH_SONAR_N] = { -90, -50, -30, -10, 10, 30, 50, 90 };
    int i, best = 0;
    for (i = 1; i < BEH_SONAR_N; i++)
        if (fabs(deg[i] * VEC2_PI / 180.0 - b_rad) < fabs(deg[best] * VEC2_PI / 180.0 - b_rad))
            best = i;
    return range_m[best];
}

/* A new own announcement: broadcast in every team message until the next. */
static void announce_own(rover_ctl_state *c, int code)
{
    c->ann_code = code;
    c->ann_seq = formation_fsm_next_seq(&c->fsm);
}

/* The nearest mate that announced LEAVE (it is escaping a dead zone, or
 * giving way itself) within give_way_m whose bearing from our heading is
 * within cone_rad: 1 and its bearing, or 0. With seen_s > 0 only a mate
 * whose beacon the camera saw within seen_s counts (walls hide beacons: a
 * mate behind a wall is not coming our way) and only one heading our way
 * (within 90 deg of the line to us: one trapped facing the end of its
 * pocket has not turned round yet, one following a wall past us is not
 * coming through). */
static int leaving_mate(const rover_ctl_state *c, const pose2 *o, double cone_rad, double seen_s,
                        double now_s, double *bearing_rad)
{
    double best = c->p.give_way_m;
    int i, found = 0;
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        double xy[2], dist, b;
        if (m->announce != FORMATION_ANN_LEAVE ||
            (seen_s > 0.0 && !(now_s - m->obs_t_s <= seen_s)) ||
            team_position(&c->team, m->robot, xy) != 0)
            continue;
        dist = hypot(xy[0] - o->x_m, xy[1] - o->y_m);
        b = vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad);
        if (seen_s > 0.0 &&
            cos(m->theta_rad) * (o->x_m - xy[0]) + sin(m->theta_rad) * (o->y_m - xy[1]) <= 0.0)
            continue;
        if (dist < best && fabs(b) < cone_rad) {
            best = dist;
            *bearing_rad = b;
            found = 1;
        }
    }
    return found;
}

/* A lower-id mate turning on the spot (not driving) with its axle within
 * yield_clear_m of ours: a robot turning on the spot sweeps a circle of
 * ~0.31 m round its axle, two side by side that both turn sweep their
 * tails into each other; the higher id waits its turn (at most
 * yield_wait_s: the other may be spinning in place until we move). */
static int turn_blocked_by_mate(const rover_ctl_state *c, const pose2 *o)
{
    pose2 own_c;
    int i;
    unicycle_c_from_o(&own_c, o, c->p.beh.d_m);
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        const int spinning = fabs(m->v_mps) <= 0.05 && fabs(m->w_radps) >= 0.1;
        double xy[2];
        if (m->robot >= c->id || !spinning || team_position(&c->team, m->robot, xy) != 0)
            continue;
        if (hypot(xy[0] + c->p.beh.d_m * cos(m->theta_rad) - own_c.x_m,
                  xy[1] + c->p.beh.d_m * sin(m->theta_rad) - own_c.y_m) < c->p.yield_clear_m)
            return 1;
    }
    return 0;
}

/* Walls (not mates) within reach of boundary following on some side. */
static int confined(const sonar_groups *gw, const rover_ctl_params *p)
{
    return fmin(fmin(gw->left_m, gw->left_front_m), fmin(gw->right_m, gw->right_front_m)) <
           p->follow_dist_m + 0.8;
}

/* Side (-1 right, +1 left) of the nearer wall. */
static int nearer_wall_side(const sonar_groups *gw)
{
    return fmin(gw->left_m, gw->left_front_m) < fmin(gw->right_m, gw->right_front_m) ? 1 : -1;
}

/* Start giving way when a mate that announced LEAVE is ahead within
 * give_way_m and walls are near (the trapped robot's only way out is back
 * past us; nobody made room, it spun in its pocket and the team jammed):
 * leave the formation as well, turn away from the mate, then follow the
 * nearer wall out and round (the escape's boundary following, hit point
 * here). Returns 1 if it started. */
static int give_way_start(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double dist,
                          double t_s)
{
    double b;
    if (!leaving_mate(c, o, 0.5 * VEC2_PI, c->p.give_way_seen_s, t_s, &b) || !confined(gw, &c->p))
        return 0;
    c->esc_phase = ROVER_ESC_YIELD;
    c->esc_yield = 1;
    c->esc_hit_dist_m = dist;
    c->esc_s = 0.0;
    c->esc_lost_s = 0.0;
    c->esc_wait_s = 0.0;
    /* away from the mate; one dead ahead: toward the roomier side */
    if (fabs(b) > 0.2) c->esc_turn = b > 0.0 ? -1 : 1;
    else c->esc_turn = gw->left_m + gw->left_front_m >= gw->right_m + gw->right_front_m ? 1 : -1;
    announce_own(c, FORMATION_ANN_LEAVE);
    return 1;
}

/* A new dead-zone entry: LEAVE (once per escape), the hit point, and the
 * wall kept on the side the turn of eq. 2 turned away from. */
static void dead_zone_entry(rover_ctl_state *c, const unicycle_cmd *turn, double dist)
{
    if (c->esc_phase == ROVER_ESC_NONE) {
        c->esc_hit_dist_m = dist;
        announce_own(c, FORMATION_ANN_LEAVE);
    }
    c->escapes++;
    c->esc_s = 0.0;
    c->esc_lost_s = 0.0;
    c->esc_wait_s = 0.0;
    c->esc_yield = 0;
    /* turned left (+w_k): keep the wall on the right */
    c->esc_side = turn->w_radps > 0.0 ? -1 : 1;
}

/* YIELD: turn on the spot (U in *u, 1) while a leaving mate is ahead, at
 * most yield_max_s of turning, a lower-id mate turning next to us first;
 * else 0, with the nearer wall chosen to follow. */
static int yield_turn(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double t_s,
                      double dt_s, unicycle_cmd *u)
{
    double b;
    if (leaving_mate(c, o, 2.0 * VEC2_PI / 3.0, 0.0, t_s, &b) && c->esc_s < c->p.yield_max_s) {
        u->v_mps = 0.0;
        if (c->esc_wait_s < c->p.yield_wait_s && turn_blocked_by_mate(c, o)) {
            u->w_radps = 0.0;
            c->esc_wait_s += dt_s;
            c->esc_s -= dt_s;        /* waiting does not count as turning */
        } else {
            u->w_radps = c->esc_turn * c->p.follow_w_radps;
        }
        return 1;
    }
    c->esc_side = nearer_wall_side(gw);
    c->esc_s = 0.0;
    return 0;
}

/* The follower sees walls only: a robot giving way stops short of a mate
 * in the way (the echoes the team table explains), not of the wall it
 * follows round a corner. */
static void stop_short_of_mates(const rover_ctl_state *c, const pose2 *o, unicycle_cmd *u)
{
    double masked[BEH_SONAR_N], mates[BEH_SONAR_N];
    int k;
    rover_ctl_mask_mates(c, o, 0.0, masked);
    for (k = 0; k < BEH_SONAR_N; k++)
        mates[k] = masked[k] != c->range_m[k] ? c->range_m[k] : INFINITY;
    rover_ctl_guard_speed(u, mates, &c->p);
}

/* FOLLOW: the boundary on esc_side (U in *u, 1) until the leave rule or
 * open floor ends the escape (REJOIN, 0); the other way round after
 * escape_max_s. dist: own distance to the goal. */
static int follow_boundary(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                           const pose2 *o, const double goal[2], double dist, double dt_s,
                           unicycle_cmd *u)
{
    const double b = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m),
                                         o->theta_rad);
    const int free_way = fabs(b) < 0.5 * VEC2_PI && range_toward(c->range_m, b) > 1.2 &&
                         g->front_m > 0.8;
    c->esc_lost_s = confined(gw, &c->p) ? 0.0 : c->esc_lost_s + dt_s;
    if ((dist < c->esc_hit_dist_m - 0.5 && free_way) || c->esc_lost_s > c->p.follow_lost_s) {
        c->esc_phase = ROVER_ESC_NONE;
        c->esc_yield = 0;
        announce_own(c, FORMATION_ANN_REJOIN);
        return 0;
    }
    if (c->esc_s > c->p.escape_max_s) {
        c->esc_side = -c->esc_side;
        c->esc_s = 0.0;
    }
    rover_ctl_follow(u, g, c->esc_side, &c->p);
    if (c->esc_yield) stop_short_of_mates(c, o, u);
    return 1;
}

/* Dead-zone escape and give-way state machine; returns 1 while escaping
 * (U in *u).
 *   trapped (docs/method/formation.md §10: front, left, right < d_s for the dead-zone time): LEAVE,
 *     turn +-w_k alternately per entry until the front is free (eq. 2),
 *     then FOLLOW the boundary, the wall on the side turned away from;
 *   a mate escaping right ahead (give_way_start): LEAVE, YIELD (turn on
 *     the spot until no leaving mate is ahead, at most yield_max_s of
 *     turning; a lower-id mate turning next to us goes first), then FOLLOW
 *     the nearer wall;
 *   FOLLOW ends (REJOIN) when closer to the goal than where it started
 *     by 0.5 m with the way to the goal free (Bug2's leave rule), or when
 *     no wall has been in reach for follow_lost_s (open floor: nothing to
 *     follow; the follow law would circle for ever looking for it). After
 *     escape_max_s without that it follows the other way round (the
 *     alternation of eq. 2 applied to the boundary): it never rejoins
 *     short of the leave point. Rejoining on a timeout put an escaped robot
 *     back on the straight way to the goal, through the U it had left. */
int rover_ctl_escape_step(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                          const pose2 *o, const double goal[2], double t_s, double dt_s,
                          unicycle_cmd *u)
{
    unicycle_cmd turn;
    const int entries = c->exc.entries;
    const int in_dz = behaviour_exception_step(&c->exc, &turn, gw, dt_s, &c->p.beh);
    const double dist = hypot(goal[0] - o->x_m, goal[1] - o->y_m);
    if (in_dz == 1) {
        if (c->exc.entries != entries) dead_zone_entry(c, &turn, dist);
        c->esc_phase = ROVER_ESC_TURN;
        *u = turn;
        return 1;
    }
    if (c->esc_phase == ROVER_ESC_NONE && !give_way_start(c, gw, o, dist, t_s)) return 0;
    c->esc_s += dt_s;
    if (c->esc_phase == ROVER_ESC_YIELD && yield_turn(c, gw, o, t_s, dt_s, u)) return 1;
    c->esc_phase = ROVER_ESC_FOLLOW;
    return follow_boundary(c, gw, g, o, goal, dist, dt_s, u);
}
