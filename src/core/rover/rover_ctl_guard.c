/* rover_ctl_guard: the formation controller's collision guard and its
 * view of a narrow passage (docs/method/formation.md: narrow passage protocol,
 * left + right + robot width against formation width + safety). The guard
 * is the last line of defence behind eq. 11's avoidance: it caps forward
 * speed short of an echo in the way and keeps the robot from turning into
 * a near one. The passage width and the rearmost test feed the formation
 * protocol (formation_fsm_step): which robot sees walls on both sides,
 * and which robot, last through, may restore the formation.
 */
#include "rover_ctl_internal.h"
#include "navfield.h"
#include "rover_world.h"
#include "sonar.h"

#include <math.h>

/* Nearest echo in the robot's way: of the front transducers, those whose
 * cone reaches within guard_lane_m of the line the chassis sweeps driving
 * straight (the edge of the cone nearest the heading, from the mounting
 * point), the smallest range. A side-front echo off that lane (a mate
 * driving alongside, a wall being passed) is not in the way; counting it
 * kept two robots that ended up side by side crawling along together. */
static double range_in_way(const double range_m[BEH_SONAR_N], const rover_ctl_params *p)
{
    const double half_cone = 12.5 * VEC2_PI / 180.0;
    double best = INFINITY;
    int k;
    for (k = 1; k < BEH_SONAR_N - 1; k++) {
        const sonar_transducer *tr = &sonar_p2dx_front[k];
        const double b = fmax(fabs(tr->angle_rad) - half_cone, 0.0);
        const double lat = fabs(tr->y_m) + range_m[k] * sin(b);
        if (lat < 0.5 * ROVER_BODY_WIDTH_M + p->guard_lane_m && range_m[k] < best)
            best = range_m[k];
    }
    return best;
}

/* The guard's first rule alone: forward speed falls to zero guard_stop_m
 * short of the nearest echo in the way (range_in_way, which it returns).
 * Also used while giving way, where the boundary follower sees walls only. */
double rover_ctl_guard_speed(unicycle_cmd *u, const double range_m[BEH_SONAR_N],
                             const rover_ctl_params *p)
{
    const double near = range_in_way(range_m, p);
    if (near < p->guard_m) {
        double vmax = p->beh.k_v * (near - p->guard_stop_m);
        if (vmax < 0.0)
            vmax = 0.0;
        if (u->v_mps > vmax)
            u->v_mps = vmax;
    }
    return near;
}

/* Every echo of the ring lies outside the circle the chassis sweeps
 * turning on the spot, by SPIN_CLEAR_M: each transducer's cone at its
 * range (its axis and both edges) seen from the axle C. A turn on the
 * spot can hit nothing else the sonar sees; the rear, which has no
 * sonar, is the way the robot came. */
#define SPIN_CLEAR_M 0.05
int rover_ctl_spin_clear(const double range_m[BEH_SONAR_N])
{
    const double half_cone = 12.5 * VEC2_PI / 180.0,
                 reach = rover_ctl_turn_reach_m() + SPIN_CLEAR_M;
    int k, e;
    for (k = 0; k < BEH_SONAR_N; k++) {
        const sonar_transducer *tr = &sonar_p2dx_front[k];
        for (e = -1; e <= 1; e++) {
            const double a = tr->angle_rad + e * half_cone;
            if (hypot(tr->x_m + range_m[k] * cos(a), tr->y_m + range_m[k] * sin(a)) < reach)
                return 0;
        }
    }
    return 1;
}

/* The rear has no sonar, and it is not always the way the robot came: a
 * robot stalled at a room's corner that had turned there, then turned on
 * the spot toward its way, swung its rear corner into the wall (generated
 * corridor worlds 16 and 64, 8 in line). Walls stand where the map has
 * them, and the localizer holds the pose within about 5 cm, so with a map
 * a turn on the spot also needs the walls' clearance at C beyond the
 * circle by SPIN_CLEAR_M. Mates are not on the map; the callers keep a
 * turn out of a mate's box (deconflict, spin_into_mate). */
int rover_ctl_spin_free(const rover_ctl_state *c, const pose2 *o)
{
    pose2 cpos;
    double at[2];
    if (!rover_ctl_spin_clear(c->range_m))
        return 0;
    if (!c->nav)
        return 1;
    unicycle_c_from_o(&cpos, o, c->p.beh.d_m);
    at[0] = cpos.x_m;
    at[1] = cpos.y_m;
    return navfield_clearance_m(c->nav, at) >= rover_ctl_turn_reach_m() + SPIN_CLEAR_M;
}

/* The map's graze guard. A turn swings the chassis's corners out to the
 * sides and behind, where no transducer looks: a robot in FOLLOW with its
 * tail in a corridor bend's apex turned on the spot to and fro and ground
 * its rear corner into the wall 9 times (generated corridor world 196,
 * 8 in column). With a map, a turn (w) that moves a corner toward a wall
 * the map puts within GRAZE_M of it (navfield's lower bound: the localizer
 * holds the pose within about 5 cm) faster than GRAZE_TOWARD_MPS is not
 * made. Only the turn: driving straight, the rear corners pass where the
 * front ones did, and the front is the sonar's. Nothing within the
 * turning circle plus GRAZE_M of C: no corner can graze, and the grid is
 * not read further. */
#define GRAZE_M 0.05
#define GRAZE_TOWARD_MPS 0.01
int rover_ctl_turn_grazes(const rover_ctl_state *c, const pose2 *o, double w_radps)
{
    static const double corner_m[4][2] = {
        { ROVER_BODY_OFFSET_M + 0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M },
        { ROVER_BODY_OFFSET_M + 0.5 * ROVER_BODY_LENGTH_M, -0.5 * ROVER_BODY_WIDTH_M },
        { ROVER_BODY_OFFSET_M - 0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M },
        { ROVER_BODY_OFFSET_M - 0.5 * ROVER_BODY_LENGTH_M, -0.5 * ROVER_BODY_WIDTH_M },
    };
    pose2 cp;
    double at[2], slope[2], r[2];
    int k;
    if (!c->nav || !c->p.map_graze || w_radps == 0.0)
        return 0;
    unicycle_c_from_o(&cp, o, c->p.beh.d_m);
    at[0] = cp.x_m;
    at[1] = cp.y_m;
    if (navfield_clearance_m(c->nav, at) >= rover_ctl_turn_reach_m() + GRAZE_M)
        return 0;
    for (k = 0; k < 4; k++) {
        vec2_rotate(r, corner_m[k][0], corner_m[k][1], cp.theta_rad);
        at[0] = cp.x_m + r[0];
        at[1] = cp.y_m + r[1];
        /* the corner's velocity w x r along the way the clearance grows */
        if (navfield_clearance_slope_m(c->nav, at, slope) < GRAZE_M &&
            w_radps * (-r[1] * slope[0] + r[0] * slope[1]) < -GRAZE_TOWARD_MPS)
            return 1;
    }
    return 0;
}

/* Backing straight, the sides of the chassis slide along themselves and
 * only the rear edge sweeps new floor: with a map, 1 if the rear edge,
 * moved BACK_LOOK_M behind the chassis (each period re-reads it; a creep
 * covers a few mm), keeps GRAZE_M from every wall the map
 * has that backing comes toward (navfield_clearance_slope_m's bound and
 * slope: more than BACK_TOWARD_COS of the motion toward it; a wall
 * alongside that the flank slides along is no bar), else 0. No map: 0,
 * there is nothing to tell the way back by. The edge is read every
 * BACK_SAMPLE_M or closer: a wall point within GRAZE_M - BACK_SAMPLE_M / 2
 * of the edge lies within GRAZE_M of one sample. */
#define BACK_SAMPLE_M 0.05
#define BACK_TOWARD_COS 0.2
#define BACK_LOOK_M 0.1
int rover_ctl_back_clear_of_map(const rover_ctl_state *c, const pose2 *o)
{
    const double rear_m = ROVER_BODY_OFFSET_M - 0.5 * ROVER_BODY_LENGTH_M - BACK_LOOK_M;
    const int n = (int)ceil(ROVER_BODY_WIDTH_M / BACK_SAMPLE_M);
    double slope[2];
    pose2 cp;
    int k;
    if (!c->nav)
        return 0;
    unicycle_c_from_o(&cp, o, c->p.beh.d_m);
    for (k = 0; k <= n; k++) {
        double r[2], at[2];
        vec2_rotate(r, rear_m, ROVER_BODY_WIDTH_M * ((double)k / n - 0.5), cp.theta_rad);
        at[0] = cp.x_m + r[0];
        at[1] = cp.y_m + r[1];
        /* backing moves the edge along -heading */
        if (navfield_clearance_slope_m(c->nav, at, slope) < GRAZE_M &&
            cos(cp.theta_rad) * slope[0] + sin(cp.theta_rad) * slope[1] > BACK_TOWARD_COS)
            return 0;
    }
    return 1;
}

/* Eq. 11 only weights avoidance by d_st / range; goal and formation keep
 * pushing, so a robot can creep into an obstacle dead ahead (and with
 * S_LF = S_RF the seed's turn is zero). Last line of defence: forward speed
 * falls to zero guard_stop_m short of the nearest echo in the way
 * (range_in_way); inside guard_m the robot never turns toward the nearer
 * front-side echo (a robot whose formation slot lay beyond a post kept
 * turning into it, the guard held it, and the weighted sum of "toward the
 * slot" and "away from the post" came to nothing: it stood there for the
 * rest of the run); and a robot the guard has stopped that is not turning
 * turns toward the freer side (toward its goal on a tie); an echo alongside
 * within side_guard_m turns it away. It works on the
 * raw ranges: a mate is masked out of the avoid behaviour (or a line would
 * flee its own members), but one in our way is still something to stop
 * short of (two robots closing head-on at full speed met, each taking the
 * other's echo for a mate's). */
void rover_ctl_guard(unicycle_cmd *u, const double range_m[BEH_SONAR_N], const pose2 *o,
                     const double goal[2], const rover_ctl_params *p)
{
    sonar_groups g;
    const double near = rover_ctl_guard_speed(u, range_m, p);
    double side;
    behaviour_sonar_groups(&g, range_m);
    side = g.left_front_m - g.right_front_m;
    if (fabs(side) < 0.05)
        side = vec2_angle_diff_rad(atan2(goal[1] - o->y_m, goal[0] - o->x_m), o->theta_rad);
    if (fmin(g.left_front_m, g.right_front_m) < p->guard_m && u->w_radps * side < 0.0)
        u->w_radps = 0.0;
    if (near < p->guard_m && fabs(u->w_radps) < 0.2 && (g.front_m < p->guard_m || u->v_mps < 0.05))
        u->w_radps = side >= 0.0 ? 0.5 : -0.5;
    {
        /* something alongside within side_guard_m (a mate squeezed toward
         * us past an obstacle: eq. 11's avoidance looks ahead only): turn
         * away from it, if nothing is close ahead on the other side */
        const double l = g.left_m, r = g.right_m;
        if (l < p->side_guard_m && l < r && g.right_front_m >= p->guard_m &&
            u->w_radps > -p->side_turn_radps)
            u->w_radps = -p->side_turn_radps;
        else if (r < p->side_guard_m && r <= l && g.left_front_m >= p->guard_m &&
                 u->w_radps < p->side_turn_radps)
            u->w_radps = p->side_turn_radps;
    }
}

/* Lateral offset of a point from the team's centre line (R0 position,
 * R0 heading), positive to the left. */
static double lateral_m(const unicycle_state *ref, double x, double y)
{
    return -(x - ref->x_m) * sin(ref->theta_rad) + (y - ref->y_m) * cos(ref->theta_rad);
}

enum { SIDE_UNKNOWN = 0, SIDE_OPEN = 1, SIDE_WALL = 2 };

/* What side transducer k (0 right, BEH_SONAR_N - 1 left) says about a
 * passage wall on its side: a mate's echo hides the wall (unknown); no echo
 * within passage_sense_max_m is an open side; an echo is a passage wall
 * only if it lies beyond every mate on that side of the team's centre
 * line. An obstacle with a mate further out lies inside the formation: the
 * team splits round it, it does not squeeze the formation (scattered
 * posts read as walls made the line shrink and change type among them);
 * unknown. */
static int side_wall(const rover_ctl_state *c, const pose2 *cpos, const unicycle_state *ref,
                     const double masked[BEH_SONAR_N], int k)
{
    const sonar_transducer *tr = &sonar_p2dx_front[k];
    const double r = c->range_m[k], side = k == 0 ? -1.0 : 1.0;
    const double ct = cos(cpos->theta_rad), st = sin(cpos->theta_rad);
    const double a = cpos->theta_rad + tr->angle_rad;
    double lat;
    int i;
    if (masked[k] != r)
        return SIDE_UNKNOWN;
    if (r >= c->p.passage_sense_max_m)
        return SIDE_OPEN;
    lat = lateral_m(ref, cpos->x_m + tr->x_m * ct - tr->y_m * st + r * cos(a),
                    cpos->y_m + tr->x_m * st + tr->y_m * ct + r * sin(a));
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (team_position(&c->team, c->team.m[i].robot, xy) != 0)
            continue;
        if (side * (lateral_m(ref, xy[0], xy[1]) - lat) > -0.5 * ROVER_BODY_WIDTH_M)
            return SIDE_UNKNOWN;
    }
    return SIDE_WALL;
}

/* Width of the passage the team is in, for the passage protocol (docs/method/formation.md:
 * left + right + robot width against formation width + safety):
 * INFINITY when a side is really open, NAN when this robot cannot tell
 * (a side hidden by a mate or an obstacle inside the formation, see
 * side_wall; the front closed within passage_front_min_m: walls on three
 * sides are a trap, the dead-zone exception's business, not a passage; or
 * the robot turned more than 45 deg off the team's heading, its side
 * transducers no longer looking across the way). */
double rover_ctl_passage_width(const rover_ctl_state *c, const pose2 *o, const unicycle_state *ref,
                               const sonar_groups *gw, const double masked[BEH_SONAR_N])
{
    pose2 cpos;
    int right, left;
    if (gw->front_m <= c->p.passage_front_min_m ||
        fabs(vec2_angle_diff_rad(o->theta_rad, ref->theta_rad)) > 0.25 * VEC2_PI)
        return NAN;
    unicycle_c_from_o(&cpos, o, c->p.beh.d_m);
    right = side_wall(c, &cpos, ref, masked, 0);
    left = side_wall(c, &cpos, ref, masked, BEH_SONAR_N - 1);
    if (right == SIDE_OPEN || left == SIDE_OPEN)
        return INFINITY;
    if (right == SIDE_WALL && left == SIDE_WALL)
        return c->range_m[0] + c->range_m[BEH_SONAR_N - 1] + c->p.beh.robot_width_m;
    return NAN;
}

/* This robot is the last of the team along the direction of travel (from
 * the team's mean position toward the goal), within 0.1 m: only the last
 * robot through a passage may restore the formation. Mates that announced
 * LEAVE or GIVE_WAY are out of the formation and do not count (their fsm is idle while
 * they escape; one left behind in a dead zone held the team in a column
 * all the way to the goal). */
static int counts_in_formation(const team_member *m)
{
    return !formation_ann_out(m->announce);
}

int rover_ctl_is_rearmost(const rover_ctl_state *c, const pose2 *o)
{
    double mx = o->x_m, my = o->y_m, ex, ey, len, own;
    int i, n = 1;
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (!counts_in_formation(&c->team.m[i]) ||
            team_position(&c->team, c->team.m[i].robot, xy) != 0)
            continue;
        mx += xy[0];
        my += xy[1];
        n++;
    }
    mx /= n;
    my /= n;
    ex = c->goal_m[0] - mx;
    ey = c->goal_m[1] - my;
    len = hypot(ex, ey);
    if (!(len > 1e-6))
        return 1;
    own = (o->x_m * ex + o->y_m * ey) / len;
    for (i = 0; i < c->team.n; i++) {
        double xy[2];
        if (!counts_in_formation(&c->team.m[i]) ||
            team_position(&c->team, c->team.m[i].robot, xy) != 0)
            continue;
        if ((xy[0] * ex + xy[1] * ey) / len < own - 0.1)
            return 0;
    }
    return 1;
}
