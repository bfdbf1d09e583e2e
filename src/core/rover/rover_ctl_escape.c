/* rover_ctl_escape: the formation controller's dead-zone escape, giving
 * way to it and waiting for mates that outrank it, as one mechanism
 * (docs/method/formation.md §10): a total priority order among mates
 * (rover_ctl_outranks: trapped before giving way before the rest, then
 * the lower id); a robot waits only for outranking mates it conflicts
 * with (rover_ctl_wait_set), so the wait-for graph is acyclic and the
 * highest-ranked robot of any conflict never waits. The escape itself
 * (eq. 2's alternating +-w_k turn in behaviour_exception_step, then
 * following the obstacle boundary until Bug2's leave rule lets it rejoin)
 * runs through the const state table rover_esc_table, checked by
 * rover_esc_table_validate. Own announcements (LEAVE, GIVE_WAY, REJOIN)
 * are made here. The escape's state, c->esc (rover_esc_state), is written
 * here alone; the controller's other files read it.
 */
#include "rover_ctl_internal.h"
#include "sonar.h"

#include <math.h>
#include <stddef.h>

/* The escape's phases (rover_ctl.h: what each field means). A trapped
 * robot turns (eq. 2) and follows the boundary; a robot in a trapped
 * mate's way turns away from it and follows the boundary out; a stalled
 * robot turns toward its way and follows the boundary. All end, through
 * `next`, in NONE: the leave rule or a lost wall. */
const rover_esc_row rover_esc_table[ROVER_ESC_COUNT] = {
    { ROVER_ESC_NONE, FORMATION_ANN_NONE, ROVER_MODE_FORMATION, ROVER_ESC_FLY_BLEND,
      ROVER_ESC_LIMIT_NONE, ROVER_ESC_NONE, ROVER_ESC_NONE },
    { ROVER_ESC_TURN, FORMATION_ANN_LEAVE, ROVER_MODE_DEAD_ZONE, ROVER_ESC_FLY_EQ2,
      ROVER_ESC_LIMIT_NONE, ROVER_ESC_FOLLOW, ROVER_ESC_TURN },
    { ROVER_ESC_FOLLOW, FORMATION_ANN_LEAVE, ROVER_MODE_DEAD_ZONE, ROVER_ESC_FLY_FOLLOW,
      ROVER_ESC_LIMIT_FOLLOW, ROVER_ESC_NONE, ROVER_ESC_FOLLOW },
    /* giving way reports CHANGING: only real traps count as escapes */
    { ROVER_ESC_YIELD, FORMATION_ANN_GIVE_WAY, ROVER_MODE_CHANGING, ROVER_ESC_FLY_SPIN,
      ROVER_ESC_LIMIT_YIELD, ROVER_ESC_CLEAR, ROVER_ESC_CLEAR },
    { ROVER_ESC_CLEAR, FORMATION_ANN_GIVE_WAY, ROVER_MODE_CHANGING, ROVER_ESC_FLY_FOLLOW,
      ROVER_ESC_LIMIT_FOLLOW, ROVER_ESC_NONE, ROVER_ESC_CLEAR },
    /* a stall: trapped as surely as by eq. 2's test, so LEAVE */
    { ROVER_ESC_FACE, FORMATION_ANN_LEAVE, ROVER_MODE_DEAD_ZONE, ROVER_ESC_FLY_SPIN,
      ROVER_ESC_LIMIT_YIELD, ROVER_ESC_FOLLOW, ROVER_ESC_FOLLOW },
};

static int phase_ok(int k)
{
    return k >= ROVER_ESC_NONE && k < ROVER_ESC_COUNT;
}

/* Following `next` from phase k reaches NONE (within ROVER_ESC_COUNT steps). */
static int ends_in_none(const rover_esc_row *t, int k)
{
    int step;
    for (step = 0; step < ROVER_ESC_COUNT && k != ROVER_ESC_NONE; step++)
        k = t[k].next;
    return k == ROVER_ESC_NONE;
}

/* One row on its own: NONE flies the blend in formation; an escaping row
 * announces itself out of the formation (LEAVE trapped, reported as a
 * dead-zone escape; GIVE_WAY, reported as changing) so that the team
 * reference leaves it out and every mate ranks it the same, and flies a
 * command of its own; a row with no limit keeps on_limit at itself. */
static int row_ok(const rover_esc_row *r, int k)
{
    if (r->phase != k || !phase_ok(r->next) || !phase_ok(r->on_limit) ||
        r->limit < ROVER_ESC_LIMIT_NONE || r->limit > ROVER_ESC_LIMIT_FOLLOW ||
        r->fly < ROVER_ESC_FLY_BLEND || r->fly > ROVER_ESC_FLY_FOLLOW ||
        (r->limit == ROVER_ESC_LIMIT_NONE && r->on_limit != k))
        return 0;
    if (k == ROVER_ESC_NONE)
        return r->announce == FORMATION_ANN_NONE && r->mode == ROVER_MODE_FORMATION &&
               r->fly == ROVER_ESC_FLY_BLEND && r->next == ROVER_ESC_NONE;
    if (r->fly == ROVER_ESC_FLY_BLEND)
        return 0;
    return (r->announce == FORMATION_ANN_LEAVE && r->mode == ROVER_MODE_DEAD_ZONE) ||
           (r->announce == FORMATION_ANN_GIVE_WAY && r->mode == ROVER_MODE_CHANGING);
}

int rover_esc_table_validate(const rover_esc_row *t, int n)
{
    int k;
    if (!t || n != ROVER_ESC_COUNT)
        return ROVER_CTL_ERR_ARG;
    for (k = 0; k < n; k++)
        if (!row_ok(&t[k], k))
            return ROVER_CTL_ERR_ARG;
    for (k = 0; k < n; k++)
        if (!ends_in_none(t, k))
            return ROVER_CTL_ERR_ARG;
    return ROVER_CTL_OK;
}

/* Escape wall following: the nearer range on the wall side held at
 * follow_dist_m by a proportional turn (FOLLOW_GAIN), blocked ahead
 * within follow_dist_m + FOLLOW_FRONT_MARGIN_M or on the wall side's
 * front within FOLLOW_SIDE_FRONT_FRAC of the distance kept, the wall lost
 * beyond follow_dist_m + FOLLOW_LOST_MARGIN_M. */
#define FOLLOW_FRONT_MARGIN_M 0.1
#define FOLLOW_SIDE_FRONT_FRAC 0.75
#define FOLLOW_LOST_MARGIN_M 0.8
#define FOLLOW_ARC_V_FRAC 0.7 /* round a lost wall's corner: of follow_v_mps */
#define FOLLOW_ARC_W_FRAC 0.8 /* ... and of follow_w_radps */
#define FOLLOW_GAIN 2.0       /* rad/s per m of distance error */
void rover_ctl_follow(unicycle_cmd *u, const sonar_groups *g, int side, const rover_ctl_params *p)
{
    const double s = side < 0 ? -1.0 : 1.0;
    const double right = fmin(g->right_m, g->right_front_m),
                 left = fmin(g->left_m, g->left_front_m);
    const double near_side = s < 0 ? right : left;
    /* in a passage narrower than twice follow_dist_m, its middle: held at
     * follow_dist_m from one wall, a robot in a 1 m dead end steered into
     * the other, found itself blocked and turned on the spot there for good */
    const double keep_m = fmin(p->follow_dist_m, 0.5 * (left + right));
    const double wmax = p->follow_w_radps;
    if (g->front_m < p->follow_dist_m + FOLLOW_FRONT_MARGIN_M ||
        (s < 0 ? g->right_front_m : g->left_front_m) < FOLLOW_SIDE_FRONT_FRAC * keep_m) {
        /* blocked ahead: turn away from the wall side on the spot (creeping
         * forward while turning walked the axle toward the walls of a narrow
         * pocket until the turning tail touched one) */
        u->v_mps = 0.0;
        u->w_radps = -s * wmax;
    } else if (near_side > p->follow_dist_m + FOLLOW_LOST_MARGIN_M) {
        /* lost the wall (a convex corner): arc round toward it */
        u->v_mps = FOLLOW_ARC_V_FRAC * p->follow_v_mps;
        u->w_radps = s * FOLLOW_ARC_W_FRAC * wmax;
    } else {
        double w = -s * FOLLOW_GAIN * (keep_m - near_side);
        if (w > wmax)
            w = wmax;
        if (w < -wmax)
            w = -wmax;
        u->v_mps = p->follow_v_mps;
        u->w_radps = w;
    }
}

/* The transducer whose bearing is nearest to b (sonar_p2dx_front, the
 * ring's one table). */
static double range_toward(const double range_m[BEH_SONAR_N], double b_rad)
{
    int i, best = 0;
    for (i = 1; i < BEH_SONAR_N; i++)
        if (fabs(sonar_p2dx_front[i].angle_rad - b_rad) <
            fabs(sonar_p2dx_front[best].angle_rad - b_rad))
            best = i;
    return range_m[best];
}

/* A new own announcement: broadcast in every team message until the next. */
static void announce_own(rover_ctl_state *c, int code)
{
    c->ann_code = code;
    c->ann_seq = formation_fsm_next_seq(&c->fsm);
}

int rover_ctl_own_announce(const rover_ctl_state *c)
{
    if (c->esc.phase > ROVER_ESC_NONE && c->esc.phase < ROVER_ESC_COUNT)
        return rover_esc_table[c->esc.phase].announce;
    return c->ann_code;
}

/* Into phase k: its announcement if it differs from the one out (REJOIN
 * back in NONE), and its clock restarted. */
static void enter(rover_ctl_state *c, int k)
{
    const int was = c->esc.phase;
    c->esc.phase = k;
    c->esc.yield = rover_esc_table[k].announce == FORMATION_ANN_GIVE_WAY;
    c->esc.s = 0.0;
    c->esc.wait_s = 0.0;
    if (k == ROVER_ESC_NONE) {
        if (was != ROVER_ESC_NONE)
            announce_own(c, FORMATION_ANN_REJOIN);
    } else if (c->ann_code != rover_esc_table[k].announce) {
        announce_own(c, rover_esc_table[k].announce);
    }
}

/* Side (-1 right, +1 left) of the nearer wall. */
static int nearer_wall_side(const sonar_groups *gw)
{
    return fmin(gw->left_m, gw->left_front_m) < fmin(gw->right_m, gw->right_front_m) ? 1 : -1;
}

/* The nearest waited-for mate that announced LEAVE and comes our way,
 * within give_way_m: 1, its bearing from our heading and its position. */
static int trapped_mate_coming(const rover_ctl_state *c, const pose2 *o, double *bearing_rad,
                               double xy_m[2])
{
    double best = c->p.give_way_m;
    int k, found = 0;
    for (k = 0; k < c->wait_n; k++) {
        const team_member *m = team_find(&c->team, c->wait_id[k]);
        double xy[2], dist;
        if (!m || m->announce != FORMATION_ANN_LEAVE ||
            team_position(&c->team, m->robot, xy) != 0 || !rover_ctl_mate_coming(m, xy, o))
            continue;
        dist = hypot(xy[0] - o->x_m, xy[1] - o->y_m);
        if (dist < best) {
            best = dist;
            *bearing_rad = vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad);
            xy_m[0] = xy[0];
            xy_m[1] = xy[1];
            found = 1;
        }
    }
    return found;
}

/* How far from the goal the point xy is, for the leave rule (rover_ctl.h): along the
 * map's way where the robot holds a navigation field and xy is joined to
 * the goal (navfield_way_from, docs/method/formation.md §14), else
 * straight (Bug2's distance). The way has no local minimum: following the
 * boundary of whatever holds the robot reaches the side where the way to
 * the goal leaves it, and there the way is shorter than at the hit point
 * by at least the length along it. The straight distance has no such
 * point round a cluster of obstacles the goal lies beyond (a robot
 * trapped in one of two pockets side by side followed their joint
 * boundary for 170 s, never nearer the goal than where it hit). */
double rover_ctl_leave_measure_m(const rover_ctl_state *c, const double xy[2], const double goal[2])
{
    const double way = c->nav && c->p.leave_by_way ? navfield_way_from(c->nav, xy) : INFINITY;
    return isfinite(way) ? way : hypot(goal[0] - xy[0], goal[1] - xy[1]);
}

#define YIELD_DEAD_AHEAD_RAD 0.2 /* a trapped mate within this of dead ahead */
/* Give way to a trapped mate that we wait for and that comes our way:
 * its only way out is back past us. YIELD (turn away from it), then
 * CLEAR (follow the nearer wall out). The leave rule's reference is the
 * trapped mate's distance to the goal, not our own: the wall we follow is
 * the one it escapes along, and a robot that gave way already past the
 * trap could never get leave_gain_m nearer than its own start along the
 * trap's wall. Returns 1 if it started. */
static int give_way_start(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o,
                          const double goal[2])
{
    double b, mate[2];
    if (!trapped_mate_coming(c, o, &b, mate))
        return 0;
    enter(c, ROVER_ESC_YIELD);
    c->esc.back_m = 0.0;
    c->esc.wedge_s = 0.0;
    c->esc.lost_s = 0.0;
    c->esc.hit_dist_m = rover_ctl_leave_measure_m(c, mate, goal);
    /* away from the mate; one dead ahead: toward the roomier side */
    if (fabs(b) > YIELD_DEAD_AHEAD_RAD)
        c->esc.turn = b > 0.0 ? -1 : 1;
    else
        c->esc.turn = gw->left_m + gw->left_front_m >= gw->right_m + gw->right_front_m ? 1 : -1;
    return 1;
}

/* Into an escape's first phase k (TURN, FACE): counted as an escape, its
 * backing, wedge and lost-wall measures started afresh. */
static void escape_begin(rover_ctl_state *c, int k)
{
    enter(c, k);
    c->escapes++;
    c->esc.back_m = 0.0;
    c->esc.wedge_s = 0.0;
    c->esc.lost_s = 0.0;
    c->esc.turned_back = 0;
}

static double way_bearing_rad(const rover_ctl_state *c, const pose2 *o, const double goal[2]);

/* A new dead-zone entry: LEAVE, the hit point (first entry of an escape),
 * eq. 2's turn direction and the wall kept on the side it turns away
 * from. With the map (entry_by_way), the first entry turns toward the
 * way and later ones alternate from there: eq. 2 turns until the front is
 * free, and the follower goes the way the robot then faces. In a
 * corridor's bend the seed's fixed first sense turned half the robots
 * until they faced back down the corridor, and they followed it the wrong
 * way (generated corridor world 44). Turning toward the way, the
 * first free heading is the one nearest the way on that side. */
static void dead_zone_entry(rover_ctl_state *c, const unicycle_cmd *turn, const pose2 *o,
                            const double goal[2])
{
    const double xy[2] = { o->x_m, o->y_m };
    int dir = turn->w_radps > 0.0 ? 1 : -1;
    if (rover_esc_table[c->esc.phase].announce != FORMATION_ANN_LEAVE)
        c->esc.hit_dist_m = rover_ctl_leave_measure_m(c, xy, goal);
    escape_begin(c, ROVER_ESC_TURN);
    if (c->nav && c->p.entry_by_way) {
        dir = way_bearing_rad(c, o, goal) > 0.0 ? 1 : -1;
        if (c->exc.entries % 2 == 0)
            dir = -dir;
    }
    c->esc.turn = dir;
    /* turned left (+w_k): keep the wall on the right */
    c->esc.side = -dir;
}

/* The bearing from the heading of the point the goal behaviour will steer
 * for: the goal, or with a navigation field the point of its descent
 * (navfield_waypoint: a goal round the corner is not ahead). */
static double way_bearing_rad(const rover_ctl_state *c, const pose2 *o, const double goal[2])
{
    const double xy[2] = { o->x_m, o->y_m };
    double to[2] = { goal[0], goal[1] };
    if (c->nav && c->p.leave_by_way &&
        navfield_waypoint(c->nav, xy, goal, to) == NAVFIELD_ERR_ARG) {
        to[0] = goal[0];
        to[1] = goal[1];
    }
    return vec2_angle_diff_rad(atan2(to[1] - o->y_m, to[0] - o->x_m), o->theta_rad);
}

/* A stall (rover_ctl.c stall_watch): escaped as a trap, LEAVE, the hit
 * point where it stands: FACE turns it toward the way, the short way
 * round, then it follows the nearer wall. Its mates rank it as trapped
 * and give way to it as to one; the leave rule brings it out. Facing
 * first: the follower goes the way the robot faces, and a robot stalled
 * in a corridor bend's dead end, facing back down the corridor, followed
 * it 11 m the wrong way (corridor world 416, 6 in column). */
static int stall_entry(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o,
                       const double goal[2])
{
    const double xy[2] = { o->x_m, o->y_m };
    if (!(c->p.stall_s > 0.0) || !(c->stall_t_s > c->p.stall_s))
        return 0;
    c->stall_t_s = 0.0;
    c->esc.hit_dist_m = rover_ctl_leave_measure_m(c, xy, goal);
    escape_begin(c, ROVER_ESC_FACE);
    c->esc.side = nearer_wall_side(gw);
    c->esc.turn = way_bearing_rad(c, o, goal) > 0.0 ? 1 : -1;
    return 1;
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
    if (c->esc.backing || (last && hypot(ax.x_m - last[0], ax.y_m - last[1]) < ROVER_CRUMB_STEP_M))
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
#define BACK_AIM_GAIN 1.5 /* 1/s: heading error to turn rate while backing */
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
    if (c->crumb_n == 0)
        return 0;
    aim = c->crumb_m[c->crumb_n - 1];
    err = vec2_angle_diff_rad(atan2(ax.y_m - aim[1], ax.x_m - aim[0]), ax.theta_rad);
    if (fabs(err) > BACK_AIM_MAX_RAD)
        return 0;
    u->v_mps = -c->p.back_v_mps;
    u->w_radps = BACK_AIM_GAIN * err;
    return 1;
}

/* Clear an outranking mate's way by backing along our crumbs (at most
 * back_max_m since the wait or escape began, only where our chassis
 * clears every mate's): 1 with the command in *u, else 0. */
static int back_out(rover_ctl_state *c, const pose2 *o, double dt_s, unicycle_cmd *u)
{
    unicycle_cmd back;
    if (!(c->esc.back_m < c->p.back_max_m) || !crumbs_back(c, o, &back) ||
        !rover_ctl_crumbs_clear(c, o, c->p.back_max_m - c->esc.back_m))
        return 0;
    *u = back;
    c->esc.backing = 1;
    c->esc.back_m += c->p.back_v_mps * dt_s;
    return 1;
}

/* Clear an outranking mate's way backing straight, where the crumbs
 * cannot be followed (the robot turned on the spot since it laid them, so
 * they lie off its tail): only with the map, which keeps the rear edge
 * clear of its walls (rover_ctl_back_clear_of_map), no mate in the way
 * back, and within back_max_m as back_out. 1 with the command in *u,
 * else 0. Two robots following a wall into a doorway's jamb stood wedged,
 * each in the other's turning circle, for 120 s: the lower one's crumbs
 * lay off its tail and nothing else would move it (generated mixed world
 * 20, 8 in triangle). */
static int back_straight_out(rover_ctl_state *c, const pose2 *o, double dt_s, unicycle_cmd *u)
{
    unicycle_cmd back;
    back.v_mps = -c->p.back_v_mps;
    back.w_radps = 0.0;
    if (!(c->esc.back_m < c->p.back_max_m) || !rover_ctl_back_clear_of_map(c, o) ||
        rover_ctl_cmd_sweeps_mate(c, o, &back, ROVER_SWEEP_ANY) != 0)
        return 0;
    *u = back;
    c->esc.backing = 1;
    c->esc.back_m += c->p.back_v_mps * dt_s;
    return 1;
}

/* Clear an outranking mate's way driving straight ahead, where backing
 * cannot (no crumbs, or the way back taken by a mate): only with the
 * front sonar groups free of walls (mates masked) beyond AHEAD_FREE_M, no
 * mate in the lane, and the drive taking us farther from mate m. 1 with the
 * command in *u, else 0. A robot giving way that stood beside the trapped
 * one, its back_max_m used and unable to turn on the spot, held both there
 * (dead zone, 3 in line, seed 1, with the lane test follow_boundary had). */
#define AHEAD_FREE_M 0.6
static int ahead_out(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o,
                     const team_member *m, unicycle_cmd *u)
{
    double xy[2];
    if (fmin(gw->front_m, fmin(gw->left_front_m, gw->right_front_m)) < AHEAD_FREE_M)
        return 0;
    if (team_position(&c->team, m->robot, xy) != 0 ||
        cos(o->theta_rad) * (o->x_m - xy[0]) + sin(o->theta_rad) * (o->y_m - xy[1]) < 0.0 ||
        rover_ctl_mate_in_lane(c, o, c->p.follow_mate_ahead_m))
        return 0;
    u->v_mps = 0.5 * c->p.follow_v_mps;
    u->w_radps = 0.0;
    return 1;
}

/* 1 if we lie in the way of a mate we wait for (its turning circle or
 * its lane ahead): ours to clear. */
static int in_way_of_waited(const rover_ctl_state *c, const pose2 *o)
{
    int k;
    for (k = 0; k < c->wait_n; k++)
        if (rover_ctl_in_way_of(c, o, c->wait_id[k], c->p.follow_mate_ahead_m))
            return 1;
    return 0;
}

/* In formation with a non-empty wait set: stand (the blend's command is
 * replaced, c->holding), or back out of the way of a waited-for mate we
 * are in, for at most hold_max_s since the set was last empty. */
static void wait_step(rover_ctl_state *c, const pose2 *o, double dt_s)
{
    if (c->wait_n == 0) {
        c->hold_s = 0.0;
        c->esc.back_m = 0.0;
        return;
    }
    c->hold_s += dt_s;
    if (c->hold_s > c->p.hold_max_s)
        return;
    c->wait_u.v_mps = c->wait_u.w_radps = 0.0;
    c->holding = in_way_of_waited(c, o) && back_out(c, o, dt_s, &c->wait_u) ? ROVER_WAIT_BACK
                                                                            : ROVER_WAIT_STAND;
}

/* Wedged: the turn rate (w or -w) whose next 0.6 rad sweeps clear of
 * every mate's box, one that grazes no wall of the map before one that
 * does (command_out's graze guard holds that); 0 if both sweep a mate. */
static double wedge_turn(const rover_ctl_state *c, const pose2 *o, double w)
{
    const int dir = w > 0.0 ? 1 : -1;
    const int free_w = !rover_ctl_turn_sweeps_mate(c, o, dir);
    const int free_back = !rover_ctl_turn_sweeps_mate(c, o, -dir);
    if (free_w && !rover_ctl_turn_grazes(c, o, w))
        return w;
    if (free_back && !rover_ctl_turn_grazes(c, o, -w))
        return -w;
    return free_w ? w : free_back ? -w : 0.0;
}

/* The escape's own motion in *u, made only where it keeps clear of the
 * mates. A turn on the spot that would sweep our chassis into a mate
 * (rover_ctl_spin_hits_mate) or a drive with a mate in the lane is not
 * made: toward a mate that outranks us we clear by backing along the
 * crumbs; otherwise we stand: the mate is lower, waits for us and clears
 * our way (wait_step). Standing wedged
 * wedge_max_s (neither could move: no crumbs, or none clear), a turn
 * whose next 0.6 rad sweeps clear of every mate's box, either way round
 * (wedge_turn).
 * Returns 1 if the motion was held back. */
static int deconflict(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double dt_s,
                      unicycle_cmd *u)
{
    const double w = u->w_radps;
    const team_member *m;
    int32_t hit;
    if (!(u->v_mps == 0.0 && w != 0.0) || (hit = rover_ctl_spin_hits_mate(c, o)) == 0) {
        c->esc.wedge_s = 0.0;
        return 0;
    }
    u->w_radps = 0.0;
    m = team_find(&c->team, hit);
    if (m && rover_ctl_outranks(m->announce, m->robot, rover_ctl_own_announce(c), c->id) &&
        (back_out(c, o, dt_s, u) || back_straight_out(c, o, dt_s, u) ||
         ahead_out(c, gw, o, m, u))) {
        c->esc.wedge_s = 0.0;
        return 1;
    }
    c->esc.wedge_s += dt_s;
    if (c->esc.wedge_s > c->p.wedge_max_s)
        u->w_radps = wedge_turn(c, o, w);
    return u->w_radps == 0.0;
}

/* The escape's turns on the spot (YIELD, FACE): while go_on, at most
 * yield_max_s of turning, turn c->esc.turn at follow_w_radps, never into a
 * mate (deconflict; standing is not turning); then the phase's next,
 * following the nearer wall. 1 with the command in *u while turning. */
static int spin_or_next(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, int go_on,
                        double dt_s, unicycle_cmd *u)
{
    if (go_on && c->esc.s < c->p.yield_max_s) {
        u->v_mps = 0.0;
        u->w_radps = c->esc.turn * c->p.follow_w_radps;
        if (deconflict(c, gw, o, dt_s, u))
            c->esc.s -= dt_s;
        return 1;
    }
    enter(c, rover_esc_table[c->esc.phase].next);
    c->esc.side = nearer_wall_side(gw);
    return 0;
}

/* a mate this far either side of the heading is ahead */
#define YIELD_AHEAD_RAD (2.0 * VEC2_PI / 3.0)
/* YIELD: turn on the spot away from the trapped mate while one that is
 * out of the formation is ahead within give_way_m, at most yield_max_s
 * of turning (the limit), never into a mate (deconflict); then CLEAR,
 * following the nearer wall. 1 with the command in *u while turning. */
static int yield_turn(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o, double dt_s,
                      unicycle_cmd *u)
{
    int k, ahead = 0;
    for (k = 0; k < c->team.n && !ahead; k++) {
        const team_member *m = &c->team.m[k];
        double xy[2];
        if (formation_ann_out(m->announce) && team_position(&c->team, m->robot, xy) == 0 &&
            hypot(xy[0] - o->x_m, xy[1] - o->y_m) < c->p.give_way_m &&
            fabs(vec2_angle_diff_rad(atan2(xy[1] - o->y_m, xy[0] - o->x_m), o->theta_rad)) <
                YIELD_AHEAD_RAD)
            ahead = 1;
    }
    return spin_or_next(c, gw, o, ahead, dt_s, u);
}

/* FACE: turn on the spot the way chosen at the stall's entry until the
 * way's point lies within arrive_face_rad of ahead, at most yield_max_s
 * of turning, never into a mate (deconflict) and only while every echo
 * lies outside the circle the turn sweeps (rover_ctl_spin_clear: a robot
 * stalled among walls ground a corner into one, 3 wall contacts in
 * traps world 160, 8 in line); then FOLLOW the nearer wall, which keeps
 * its distance. 1 with the command in *u while turning. */
static int face_turn(rover_ctl_state *c, const sonar_groups *gw, const pose2 *o,
                     const double goal[2], double dt_s, unicycle_cmd *u)
{
    const double b = way_bearing_rad(c, o, goal);
    const int facing = fabs(b) <= c->p.arrive_face_rad;
    if (spin_or_next(c, gw, o, !facing && rover_ctl_spin_free(c, o), dt_s, u))
        return 1;
    /* not facing the way (the turn was not free, or took yield_max_s):
     * the wall kept on the side away from the way, so that the follower
     * turns toward it. The nearer wall sent a robot stalled in a sharp
     * bend's apex, facing into the apex, round and back down the corridor
     * (generated corridor world 15, 6 in column) */
    if (!facing) {
        c->esc.side = b > 0.0 ? -1 : 1;
        c->esc.turned_back = 0; /* not turned: follow_regress may try again */
    }
    return 0;
}

/* FOLLOW, trapped, with the map (leave_by_way): the boundary has led
 * follow_regress_m farther along the way than the hit point, so the robot
 * follows it away from the goal: FACE, turning toward the way, then
 * follow on, the turn-back point the hit point from there. Once an
 * escape, unless the turn could not be made (face_turn): then again once
 * the way has grown follow_regress_m beyond the turn-back point. Flipping
 * the wall side is no turn in a corridor (the other wall lies alongside
 * too, the same way on), and escape_max_s of following the wrong way is
 * a corridor's length: a robot stalled in a bend followed a corridor's
 * wall back into the start room (generated corridor world 196, 8 in
 * column, before the graze guard). Why it holds: the way has no local
 * minimum, so a boundary that leads farther from the goal than the hit
 * point by follow_regress_m does so on one side of it; turned toward the
 * way, the robot descends it, and the leave rule, measured from the
 * turn-back point, ends the escape once it is leave_gain_m nearer with
 * the way free (or escape_max_s turns it, as without the map). Measured
 * from the first hit point, a robot turned back inside a V pocket
 * followed a short wall piece in it round and round for 100 s, never
 * 0.5 m nearer the goal than where it was first trapped (generated mixed
 * world 4, 12 in line). The way must have grown by driving: esc.s, the
 * time spent following on the move, at follow_v_mps covers at least
 * follow_regress_m. Read off the grid, the way of a robot standing in a
 * corridor's mouth, in cells the field leaves blocked (navfield_way_from
 * takes the best cell it sees from there), jumped 3.5 m as its pose
 * estimate moved by a centimetre; it turned back on the spot and followed
 * the start room's wall away from the goal (generated corridor worlds 3
 * and 39, 12 in column). */
static void follow_regress(rover_ctl_state *c, const pose2 *o, const double goal[2])
{
    const double xy[2] = { o->x_m, o->y_m };
    const double way_m = rover_ctl_leave_measure_m(c, xy, goal);
    if (c->esc.phase != ROVER_ESC_FOLLOW || c->esc.turned_back || !c->nav || !c->p.leave_by_way ||
        !(c->p.follow_regress_m > 0.0) || !(way_m > c->esc.hit_dist_m + c->p.follow_regress_m) ||
        !(c->esc.s * c->p.follow_v_mps >= c->p.follow_regress_m))
        return;
    enter(c, ROVER_ESC_FACE);
    c->esc.turned_back = 1;
    c->esc.turn = way_bearing_rad(c, o, goal) > 0.0 ? 1 : -1;
    c->esc.hit_dist_m = way_m;
}

/* A turn on the spot of eq. 2 (`eq2`) or of the follower would swing a
 * corner into a wall of the map (rover_ctl_turn_grazes) and the other way
 * round would not: it turns that way from now on (eq. 2: esc.turn, the
 * wall kept on the side it turns away from; the follower: the wall kept
 * on the other side, so that it turns the other way when blocked). Both
 * turn until the front is free, either way round will do. Held only for
 * the turn (command_out), a robot trapped in a V's point, its corner
 * 12 cm from one arm, was turned to and fro at the guard's edge and
 * stood there for good (test_leave_by_way); and one following with its
 * tail in a corridor bend's apex, facing the apex's other wall, turned
 * on as asked and ground its rear corner into the wall 9 times
 * (generated corridor world 196, 8 in column). */
static void graze_other_way(rover_ctl_state *c, const pose2 *o, int eq2, unicycle_cmd *u)
{
    if (fabs(u->v_mps) > ROVER_SPIN_V_MPS || !rover_ctl_turn_grazes(c, o, u->w_radps) ||
        rover_ctl_turn_grazes(c, o, -u->w_radps))
        return;
    u->w_radps = -u->w_radps;
    if (eq2) {
        c->esc.turn = u->w_radps > 0.0 ? 1 : -1;
        c->esc.side = -c->esc.turn;
    } else {
        c->esc.side = -c->esc.side;
    }
}

/* The way to the goal is free: the transducer toward the point the goal
 * behaviour will steer for (way_bearing_rad) reads beyond
 * FREE_WAY_RANGE_M and the front beyond FREE_WAY_FRONT_M. */
#define FREE_WAY_RANGE_M 1.2
#define FREE_WAY_FRONT_M 0.8
static int way_free(const rover_ctl_state *c, const sonar_groups *g, const pose2 *o,
                    const double goal[2])
{
    const double b = way_bearing_rad(c, o, goal);
    return fabs(b) < 0.5 * VEC2_PI && range_toward(c->range_m, b) > FREE_WAY_RANGE_M &&
           g->front_m > FREE_WAY_FRONT_M;
}
/* FOLLOW, CLEAR: the boundary on esc.side (U in *u, 1) until the leave
 * rule or open floor ends the escape (`next`: NONE, REJOIN, 0); the other
 * way round after escape_max_s of following (the limit). */
/* A mate that announces LEAVE within give_way_m of us. */
static int trapped_mate_near(const rover_ctl_state *c, const pose2 *o)
{
    int k;
    for (k = 0; k < c->team.n; k++) {
        const team_member *m = &c->team.m[k];
        double xy[2];
        if (m->announce == FORMATION_ANN_LEAVE && team_position(&c->team, m->robot, xy) == 0 &&
            hypot(xy[0] - o->x_m, xy[1] - o->y_m) < c->p.give_way_m)
            return 1;
    }
    return 0;
}

static int follow_boundary(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                           const pose2 *o, const double goal[2], double dt_s, unicycle_cmd *u)
{
    const rover_esc_row *row = &rover_esc_table[c->esc.phase];
    const double xy[2] = { o->x_m, o->y_m };
    const double dist = rover_ctl_leave_measure_m(c, xy, goal); /* own, from the goal */
    const int free_way = way_free(c, g, o, goal);
    c->esc.lost_s = rover_ctl_walls_near(gw, &c->p) ? 0.0 : c->esc.lost_s + dt_s;
    /* giving way ends with the trapped mate gone (rejoined, or beyond
     * give_way_m): one that cleared a corridor bend's dead end for a mate
     * stalled in it followed the corridor's wall 8 m back the way the team
     * came, toward the leave point of a mate that had long rejoined
     * (corridor world 416, 6 in column) */
    if ((dist < c->esc.hit_dist_m - c->p.leave_gain_m && free_way) ||
        c->esc.lost_s > c->p.follow_lost_s || (c->esc.yield && !trapped_mate_near(c, o))) {
        enter(c, row->next);
        return 0;
    }
    /* escape_max_s is time spent following: standing or turning on the
     * spot (in the pocket while the mates cleared its mouth) is not. A
     * robot that had spun 50 s in its pocket turned back round the U's
     * lip just where the wall it followed led on to the goal. */
    if (!(c->v_est_mps > c->p.follow_moving_mps))
        c->esc.s -= dt_s;
    if (c->esc.s > c->p.escape_max_s) {
        const int side = c->esc.side;
        enter(c, row->on_limit);
        c->esc.side = row->on_limit == c->esc.phase ? -side : side;
    }
    rover_ctl_follow(u, gw, c->esc.side, &c->p);
    if (u->v_mps > 0.0 && rover_ctl_cmd_sweeps_mate(c, o, u, ROVER_SWEEP_ANY) != 0) {
        /* the drive sweeps into a mate: turn away from the wall as at a
         * wall ahead. Not a lane test from the axle forward: a mate at the
         * flank that the drive leaves behind is not in the way (it stopped
         * a robot giving way beside the trapped one, and the three stood
         * wedged in the dead zone's mouth: 3 in line, seed 1) */
        u->v_mps = 0.0;
        u->w_radps = -(c->esc.side < 0 ? -1.0 : 1.0) * c->p.follow_w_radps;
    }
    graze_other_way(c, o, 0, u);
    deconflict(c, gw, o, dt_s, u);
    return 1;
}

/* The escape and the wait, one period; returns 1 while escaping (U in
 * *u). The wait set is computed first: every robot's own, by the same
 * order (rover_ctl_wait_set).
 *   trapped (front, left, right < d_s for the dead-zone time): TURN,
 *     +-w_k alternately per entry until the front is free (eq. 2), then
 *     FOLLOW the boundary, the wall on the side turned away from;
 *   a trapped mate we wait for coming our way: YIELD, then CLEAR (follow
 *     the nearer wall out);
 *   FOLLOW and CLEAR end (REJOIN) closer to the goal than the hit point by
 *     leave_gain_m with the way to the goal free (Bug2's leave rule), or
 *     with no wall in reach for follow_lost_s; after escape_max_s of
 *     following, the other way round (eq. 2's alternation on the
 *     boundary): never short of the leave point. Rejoining on a timeout put
 *     an escaped robot back on the straight way to the goal, through the U;
 *   in formation with a non-empty wait set: wait (wait_step). */
int rover_ctl_escape_step(rover_ctl_state *c, const sonar_groups *gw, const sonar_groups *g,
                          const pose2 *o, const double goal[2], double t_s, double dt_s,
                          unicycle_cmd *u)
{
    unicycle_cmd turn;
    const int entries = c->exc.entries;
    const int in_dz = behaviour_exception_step(&c->exc, &turn, gw, dt_s, &c->p.beh);
    crumbs_lay(c, o);
    c->esc.backing = 0;
    c->holding = ROVER_WAIT_NONE;
    c->wait_n = rover_ctl_wait_set(c, o, gw, t_s, c->wait_id);
    if (in_dz == 1) {
        if (c->exc.entries != entries)
            dead_zone_entry(c, &turn, o, goal);
        if (c->esc.turn != 0)
            turn.w_radps = c->esc.turn * fabs(turn.w_radps);
        graze_other_way(c, o, 1, &turn);
        *u = turn;
        return 1;
    }
    if (c->esc.phase == ROVER_ESC_TURN)
        enter(c, rover_esc_table[ROVER_ESC_TURN].next);
    if (c->esc.phase == ROVER_ESC_NONE && !stall_entry(c, gw, o, goal) &&
        !give_way_start(c, gw, o, goal)) {
        wait_step(c, o, dt_s);
        return 0;
    }
    follow_regress(c, o, goal);
    c->esc.s += dt_s;
    if (c->esc.phase == ROVER_ESC_YIELD && yield_turn(c, gw, o, dt_s, u))
        return 1;
    if (c->esc.phase == ROVER_ESC_FACE && face_turn(c, gw, o, goal, dt_s, u))
        return 1;
    return follow_boundary(c, gw, g, o, goal, dt_s, u);
}
