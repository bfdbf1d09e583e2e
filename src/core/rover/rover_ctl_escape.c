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
#include <stddef.h>

#define FOLLOW_MATE_AHEAD_M 0.3   /* a follower stops this short of a mate in its way */
#define FOLLOW_MOVING_MPS 0.05    /* slower than this a follower is not following */

/* Escape wall following: the nearer range on the wall side held at
 * follow_dist_m by a proportional turn. */
void rover_ctl_follow(unicycle_cmd *u, const sonar_groups *g, int side,
                      const rover_ctl_params *p)
{
    const double s = side < 0 ? -1.0 : 1.0;
    const double right = fmin(g->right_m, g->right_front_m), left = fmin(g->left_m, g->left_front_m);
    const double near_side = s < 0 ? right : left;
    /* in a passage narrower than twice follow_dist_m, its middle: held at
     * follow_dist_m from one wall, a robot in a 1 m dead end steered into
     * the other, found itself blocked and turned on the spot there for good */
    const double keep_m = fmin(p->follow_dist_m, 0.5 * (left + right));
    const double wmax = p->follow_w_radps;
    if (g->front_m < p->follow_dist_m + 0.1 ||
        (s < 0 ? g->right_front_m : g->left_front_m) < 0.75 * keep_m) {
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
        double w = -s * 2.0 * (keep_m - near_side);
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

/* Which mates find_mate looks for (fields left 0: not asked). */
typedef struct {
    double cone_rad;      /* bearing from our heading within this */
    double seen_s;        /* > 0: its beacon seen by the camera within this
                           * (walls hide beacons: a mate behind a wall is
                           * not coming our way) */
    int    coming;        /* 1: only one heading our way (within 90 deg of
                           * the line to us: one trapped facing the end of
                           * its pocket has not turned round yet, one
                           * following a wall past us is not coming
                           * through) */
    int    give_way;      /* 1: GIVE_WAY counts as well as LEAVE */
    double slow_mps;      /* > 0: instead, a mate in formation (no
                           * announcement) driving slower than this */
    double range_m;       /* within this (0: give_way_m) */
} mate_query;

/* The nearest mate that matches q: by default one that announced LEAVE
 * (it is escaping a dead zone; one giving way announces GIVE_WAY and makes
 * nobody else give way), within give_way_m. 1, its bearing from our
 * heading and its position, or 0. */
static int find_mate(const rover_ctl_state *c, const pose2 *o, const mate_query *q, double now_s,
                        double *bearing_rad, double mate_xy_m[2])
{
    double best = q->range_m > 0.0 ? q->range_m : c->p.give_way_m;
    int i, found = 0;
    for (i = 0; i < c->team.n; i++) {
        const team_member *m = &c->team.m[i];
        const int wanted = q->slow_mps > 0.0
            ? formation_ann_out(m->announce) == 0 && fabs(m->v_mps) < q->slow_mps
            : m->announce == FORMATION_ANN_LEAVE || (q->give_way && m->announce == FORMATION_ANN_GIVE_WAY);
        double xy[2], dist, b;
        if (!wanted ||
            (q->seen_s > 0.0 && !(now_s - m->obs_t_s <= q->seen_s)) ||
            team_position(&c->team, m->robot, xy) != 0)
            continue;
        dist = hypot(xy[0] - o->x_m, xy[1] - o->y_m);
        b = vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad);
        if (q->coming &&
            cos(m->theta_rad) * (o->x_m - xy[0]) + sin(m->theta_rad) * (o->y_m - xy[1]) <= 0.0)
            continue;
        if (dist < best && fabs(b) < q->cone_rad) {
            best = dist;
            *bearing_rad = b;
            mate_xy_m[0] = xy[0];
            mate_xy_m[1] = xy[1];
            found = 1;
        }
    }
    return found;
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
 * leave the formation as well (GIVE_WAY), turn away from the mate, then
 * follow the nearer wall out and round. The leave rule's reference is the
 * trapped mate's distance to the goal, not our own: the wall we follow is
 * the one it escapes along, and we were not stopped by it. Referenced to
 * our own start, a robot that gave way already past the trap (nearer the
 * goal than the trap's far side) could never get 0.5 m nearer still along
 * the trap's wall and followed it for the rest of the run. Returns 1 if it
 * started. */
static int give_way_start(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o,
                          const double goal[2], double t_s)
{
    const mate_query q = { .cone_rad = VEC2_PI + 0.1, .seen_s = c->p.give_way_seen_s, .coming = 1 };
    double b, mate[2];
    if (!find_mate(c, o, &q, t_s, &b, mate) || !confined(gw, &c->p)) return 0;
    c->esc_phase = ROVER_ESC_YIELD;
    c->esc_yield = 1;
    c->esc_back_m = 0.0;
    c->esc_wedge_s = 0.0;
    c->esc_hit_dist_m = hypot(goal[0] - mate[0], goal[1] - mate[1]);
    c->esc_s = 0.0;
    c->esc_lost_s = 0.0;
    c->esc_wait_s = 0.0;
    /* away from the mate; one dead ahead: toward the roomier side */
    if (fabs(b) > 0.2) c->esc_turn = b > 0.0 ? -1 : 1;
    else c->esc_turn = gw->left_m + gw->left_front_m >= gw->right_m + gw->right_front_m ? 1 : -1;
    announce_own(c, FORMATION_ANN_GIVE_WAY);
    return 1;
}

/* Hold (c->holding), with walls near, for at most hold_max_s at a time:
 *   while a mate that announced LEAVE is ahead within give_way_m, seen by
 *   the camera, but not yet coming our way: it is turning round in its
 *   pocket and will come out the way it went in. Driving on after it, the
 *   mates behind went deep into the narrowing trap, side by side with no
 *   room left to turn on the spot when it came, and the three jammed;
 *   queue: behind a mate still in formation within QUEUE_M ahead that
 *   stands (under QUEUE_SLOW_MPS) or that we close on (slower than us by
 *   QUEUE_CLOSING_MPS): usually one about to find its pocket closed, and
 *   the dead-zone time was enough for the mates to follow it into the
 *   throat; waiting for it to stand, the rear robots of a triangle, still
 *   at 0.5 m/s, stopped in the pocket's mouth right behind it. */
#define QUEUE_CONE_RAD 0.6
#define QUEUE_SLOW_MPS 0.1
#define QUEUE_M 1.3
#define QUEUE_CLOSING_MPS 0.1
static void hold_step(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double t_s,
                      double dt_s)
{
    const mate_query trapped = { .cone_rad = 0.5 * VEC2_PI, .seen_s = c->p.give_way_seen_s };
    const mate_query queue = { .cone_rad = QUEUE_CONE_RAD, .seen_s = c->p.give_way_seen_s,
                               .slow_mps = fmax(QUEUE_SLOW_MPS, c->v_est_mps - QUEUE_CLOSING_MPS),
                               .range_m = QUEUE_M };
    double b, mate[2];
    if (!(find_mate(c, o, &trapped, t_s, &b, mate) || find_mate(c, o, &queue, t_s, &b, mate)) ||
        !confined(gw, &c->p)) {
        c->holding = 0;
        c->hold_s = 0.0;
        return;
    }
    c->hold_s += dt_s;
    c->holding = c->hold_s <= c->p.hold_max_s;
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
    c->esc_back_m = 0.0;
    c->esc_wedge_s = 0.0;
    c->esc_lost_s = 0.0;
    c->esc_wait_s = 0.0;
    c->esc_yield = 0;
    /* turned left (+w_k): keep the wall on the right */
    c->esc_side = turn->w_radps > 0.0 ? -1 : 1;
}

/* The way back known free: the axle's own path (a robot has no rear
 * sonar; walls do not move, so where its chassis passed it can pass
 * again, as far as its own pose is right: the localizer holds it within
 * about 5 cm, loc_err_max_m over every sweep). A crumb is laid each
 * ROVER_CRUMB_STEP_M the axle moves from the newest, the oldest dropped
 * when the ROVER_CRUMBS are full; backing picks them up again. A turn on
 * the spot moves no axle and lays none. */
static void crumbs_lay(rover_ctl_state *c, const pose2 *o)
{
    pose2 ax;
    double *last;
    unicycle_c_from_o(&ax, o, c->p.beh.d_m);
    last = c->crumb_n > 0 ? c->crumb_m[c->crumb_n - 1] : NULL;
    if (c->esc_backing || (last && hypot(ax.x_m - last[0], ax.y_m - last[1]) < ROVER_CRUMB_STEP_M))
        return;
    if (c->crumb_n == ROVER_CRUMBS) {
        int k;
        for (k = 1; k < ROVER_CRUMBS; k++) {
            c->crumb_m[k - 1][0] = c->crumb_m[k][0];
            c->crumb_m[k - 1][1] = c->crumb_m[k][1];
        }
        c->crumb_n--;
    }
    c->crumb_m[c->crumb_n][0] = ax.x_m;
    c->crumb_m[c->crumb_n][1] = ax.y_m;
    c->crumb_n++;
}

/* Backing along the crumbs: crumbs the axle has come back to are picked
 * up, the newest left is the aim and the tail is turned onto it (the
 * heading that points the tail at it: from the aim to the axle). 1 with
 * the command in *u; 0 with the crumbs used up or the aim more than
 * BACK_AIM_MAX_RAD off the tail (a robot that turned on the spot since:
 * the chassis would swing out of the path). */
#define BACK_AIM_MAX_RAD 0.6
#define BACK_AIM_GAIN 1.5       /* 1/s: heading error to turn rate while backing */
#define CRUMB_REACHED_M 0.05
static int crumbs_back(rover_ctl_state *c, const pose2 *o, unicycle_cmd *u)
{
    pose2 ax;
    double err;
    const double *aim;
    unicycle_c_from_o(&ax, o, c->p.beh.d_m);
    while (c->crumb_n > 0 && hypot(ax.x_m - c->crumb_m[c->crumb_n - 1][0],
                                   ax.y_m - c->crumb_m[c->crumb_n - 1][1]) < CRUMB_REACHED_M)
        c->crumb_n--;
    if (c->crumb_n == 0) return 0;
    aim = c->crumb_m[c->crumb_n - 1];
    err = vec2_angle_diff_rad(atan2(ax.y_m - aim[1], ax.x_m - aim[0]), ax.theta_rad);
    if (fabs(err) > BACK_AIM_MAX_RAD) return 0;
    u->v_mps = -c->p.back_v_mps;
    u->w_radps = BACK_AIM_GAIN * err;
    return 1;
}

/* Which of two wedged robots backs: the higher id, or the lower if the
 * higher cannot (judged by the lane straight behind it, by the team
 * table), or if the higher has not started backing (its speed in the team
 * table) after we stood wedged BACK_WAIT_S: its crumbs are its own, and
 * one that had turned on the spot since it laid them could not back along
 * them while the lower id waited for it. Both backing only separates them
 * further. One that has started backing goes on (at most back_max_m). */
#define BACK_WAIT_S 2.0
#define BACKING_MPS (-0.02)
static int my_turn_to_back(const rover_ctl_state *c, const pose2 *o, int32_t wedge, int was_backing)
{
    const team_member *m = team_find(&c->team, wedge);
    return was_backing || wedge < c->id || !rover_ctl_may_back(c, o, wedge) ||
           (c->esc_wedge_s > BACK_WAIT_S && !(m && m->v_mps < BACKING_MPS));
}

/* A turn on the spot in *u next to a mate whose chassis is inside our
 * turning circle is never made (spin_hits_mate). Wedged so, the higher id
 * of the two backs out the way it came, or the lower id if the higher
 * cannot (each judges that for the other by the lane straight behind
 * it), at most back_max_m per escape, along its own crumbs (a robot that
 * backed straight after turning on the spot hit the wall of its pocket;
 * one that could back only along a straight last stretch stood wedged in
 * a pocket's throat with no stretch left, the trapped mate behind it),
 * only where our chassis clears every mate's (rover_ctl_crumbs_clear), so
 * that the other can turn; otherwise stand. Returns 1 if the turn was held
 * back. */
static int spin_or_back(rover_ctl_state *c, const pose2 *o, double dt_s, unicycle_cmd *u)
{
    const double w = u->w_radps;
    unicycle_cmd back;
    const int was_backing = c->esc_backing;
    int32_t wedge;
    c->esc_backing = 0;
    if (!(u->v_mps == 0.0 && w != 0.0) || (wedge = rover_ctl_spin_hits_mate(c, o)) == 0) {
        c->esc_wedge_s = 0.0;
        return 0;
    }
    u->w_radps = 0.0;
    if (c->esc_back_m < c->p.back_max_m && my_turn_to_back(c, o, wedge, was_backing) &&
        crumbs_back(c, o, &back) && rover_ctl_crumbs_clear(c, o, c->p.back_max_m - c->esc_back_m)) {
        *u = back;
        c->esc_backing = 1;
        c->esc_back_m += c->p.back_v_mps * dt_s;
        c->esc_wedge_s = 0.0;
        return 1;
    }
    /* standing wedged for wedge_max_s (neither may turn its whole circle
     * nor back): a turn that sweeps clear of every mate's box, either way
     * round. Two robots in a pocket's throat stood so for the rest of the
     * run while the trapped one behind them could not get out. */
    c->esc_wedge_s += dt_s;
    if (c->esc_wedge_s > c->p.wedge_max_s) {
        const int dir = w > 0.0 ? 1 : -1;
        if (!rover_ctl_turn_sweeps_mate(c, o, dir)) u->w_radps = w;
        else if (!rover_ctl_turn_sweeps_mate(c, o, -dir)) u->w_radps = -w;
    }
    return u->w_radps == 0.0;
}

/* YIELD: turn on the spot (U in *u, 1) while a leaving mate is ahead, at
 * most yield_max_s of turning, a lower-id mate turning next to us first
 * (waited out after yield_wait_s) and never into a mate (spin_or_back);
 * else 0, with the nearer wall chosen to follow. */
static int yield_turn(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double t_s,
                      double dt_s, unicycle_cmd *u)
{
    const mate_query q = { .cone_rad = 2.0 * VEC2_PI / 3.0, .give_way = 1 };
    double b, mate[2];
    if (find_mate(c, o, &q, t_s, &b, mate) && c->esc_s < c->p.yield_max_s) {
        u->v_mps = 0.0;
        u->w_radps = c->esc_turn * c->p.follow_w_radps;
        if (c->esc_wait_s < c->p.yield_wait_s && rover_ctl_turn_blocked_by_mate(c, o)) {
            u->w_radps = 0.0;
            c->esc_backing = 0;
            c->esc_wait_s += dt_s;
            c->esc_s -= dt_s;        /* waiting does not count as turning */
        } else if (spin_or_back(c, o, dt_s, u)) {
            c->esc_s -= dt_s;
        }
        return 1;
    }
    c->esc_side = nearer_wall_side(gw);
    c->esc_s = 0.0;
    c->esc_backing = 0;
    return 0;
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
    /* escape_max_s is time spent following: standing or turning on the
     * spot (in the pocket while the mates cleared its mouth) is not. A
     * robot that had spun 50 s in its pocket turned back round the U's
     * lip just where the wall it followed led on to the goal. */
    if (!(c->v_est_mps > FOLLOW_MOVING_MPS)) c->esc_s -= dt_s;
    if (c->esc_s > c->p.escape_max_s) {
        c->esc_side = -c->esc_side;
        c->esc_s = 0.0;
    }
    rover_ctl_follow(u, gw, c->esc_side, &c->p);
    if (u->v_mps > 0.0 && rover_ctl_mate_in_lane(c, o, FOLLOW_MATE_AHEAD_M)) {
        /* a mate in the way: turn away from the wall as at a wall ahead */
        u->v_mps = 0.0;
        u->w_radps = -(c->esc_side < 0 ? -1.0 : 1.0) * c->p.follow_w_radps;
    }
    spin_or_back(c, o, dt_s, u);
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
    crumbs_lay(c, o);
    if (in_dz == 1) {
        if (c->exc.entries != entries) dead_zone_entry(c, &turn, dist);
        c->esc_phase = ROVER_ESC_TURN;
        *u = turn;
        return 1;
    }
    c->holding = 0;
    if (c->esc_phase == ROVER_ESC_NONE && !give_way_start(c, gw, o, goal, t_s)) {
        hold_step(c, gw, o, t_s, dt_s);
        return 0;
    }
    c->esc_s += dt_s;
    if (c->esc_phase == ROVER_ESC_YIELD && yield_turn(c, gw, o, t_s, dt_s, u)) return 1;
    c->esc_phase = ROVER_ESC_FOLLOW;
    return follow_boundary(c, gw, g, o, goal, dist, dt_s, u);
}
