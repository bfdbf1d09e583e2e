/* rover_ctl: one Pioneer's distributed formation controller (docs/method/
 * formation.md: team-average reference, behaviours, eq. 11 blend, narrow
 * passage protocol, dead-zone escape, heartbeat membership; section 7: safe
 * stop on stale input). Glue over odometry, team, formation and behaviour;
 * the pieces of its own are the escape's boundary following, giving way to
 * a mate that escapes, the mate mask of the sonar ring, the collision guard
 * and the frame consensus (see rover_ctl.h and each function).
 *
 * This file: init and the control period (rover_ctl_step) as named steps,
 * the team reference and own goal slot they use, and the outputs (drive
 * command, mode, own team message). The other concerns live beside it
 * (rover_ctl_internal.h lists them).
 */
#include "rover_ctl_internal.h"
#include "slot_assign.h"
#include "rover_world.h"

#include <math.h>
#include <string.h>

int rover_ctl_init(rover_ctl_state *c, const rover_ctl_params *p, int32_t id, const pose2 *start_c,
                   const double goal_m[2])
{
    if (!c || rover_ctl_params_validate(p) != 0 ||
        rover_esc_table_validate(rover_esc_table, ROVER_ESC_COUNT) != ROVER_CTL_OK || !start_c ||
        !vec2_pose_finite(start_c) || !goal_m || !isfinite(goal_m[0]) || !isfinite(goal_m[1]) ||
        id < 0)
        return ROVER_CTL_ERR_ARG;
    memset(c, 0, sizeof *c);
    c->id = id;
    c->team_lo = 0;
    c->team_hi = INT32_MAX;
    c->p = *p;
    c->start_c = *start_c;
    c->goal_m[0] = goal_m[0];
    c->goal_m[1] = goal_m[1];
    if (team_init(&c->team, id, p->team_timeout_s) != 0)
        return ROVER_CTL_ERR_ARG;
    if (formation_fsm_init(&c->fsm, p->formation, 1.0) != 0)
        return ROVER_CTL_ERR_ARG;
    behaviour_exception_init(&c->exc);
    c->team_tx_t_s = -INFINITY;
    {
        pose2 o;
        unicycle_o_from_c(&o, start_c, p->beh.d_m);
        c->tx_xy_m[0] = o.x_m;
        c->tx_xy_m[1] = o.y_m;
    }
    return ROVER_CTL_OK;
}

int rover_ctl_set_team(rover_ctl_state *c, int32_t lo, int32_t hi)
{
    if (!c || lo > hi || c->id < lo || c->id > hi)
        return ROVER_CTL_ERR_ARG;
    c->team_lo = lo;
    c->team_hi = hi;
    return ROVER_CTL_OK;
}

void rover_ctl_set_navfield(rover_ctl_state *c, const navfield *f)
{
    if (c)
        c->nav = f;
}

/* The point to steer for from (x, y) toward `goal`: the goal itself
 * without a navigation function or where the straight way to it is clear
 * (the seed's behaviour), else a point of the field's descent
 * (navfield_waypoint, docs/method/formation.md §14). 1 when it is the
 * goal. */
static int steer_point(const rover_ctl_state *c, double x_m, double y_m, const double goal[2],
                       double out[2])
{
    const double from[2] = { x_m, y_m };
    out[0] = goal[0];
    out[1] = goal[1];
    if (!c->nav)
        return 1;
    return navfield_waypoint(c->nav, from, goal, out) != NAVFIELD_DESCENT;
}

/* R0's heading: the seed's circular mean of the robots' headings couples
 * every slot to every robot's turning (a robot that turns rotates the
 * frame, its slot moves sideways, it turns more): long formations (a
 * column) drift round in a slow spiral. With goal_heading_gain g > 0 the
 * heading used is the mean heading pulled toward the bearing of the goal
 * from R0 (of R0's point steered for, steer_point: the goal itself in
 * plain view) by the fraction g (1: that bearing alone), and its rate w0 is
 * dropped in the same proportion. Within a metre of the goal the bearing
 * swings about, so the heading of the goal's own slot frame (own_goal) is
 * used: there the mean heading of robots that have stopped anyhow turned
 * the formation round, and a robot whose slot came to lie behind it
 * circled the goal chasing it. */
static void ref_heading_to_goal(const rover_ctl_state *c, const double steer[2],
                                unicycle_state *ref)
{
    const double g = c->p.goal_heading_gain;
    const double dx = c->goal_m[0] - ref->x_m, dy = c->goal_m[1] - ref->y_m;
    const double to = hypot(dx, dy) < 1.0 ? atan2(c->goal_m[1], c->goal_m[0])
                                          : atan2(steer[1] - ref->y_m, steer[0] - ref->x_m);
    if (!(g > 0.0))
        return;
    ref->theta_rad = vec2_wrap_rad(ref->theta_rad + g * vec2_angle_diff_rad(to, ref->theta_rad));
    ref->w_radps *= 1.0 - g;
}

/* Arrival: within arrive_m of the goal R0 is drawn onto the goal's own
 * slot frame, by the fraction lam = 1 - dist / arrive_m of the way (its
 * position, its heading; V0 and w0 fade by 1 - lam), so that at the goal
 * the formation the robots keep round R0 is the one their goal behaviour
 * drives them to. Without it the two behaviours ask for two formations
 * near the goal, one round the team's mean turned to the goal's bearing
 * and one round the goal, and a team that came back together there after
 * a dead-zone escape facing away from the goal settled on neither: its
 * rear robots drove back to their slots behind, the mean followed them,
 * and the whole team crept off away from the goal for the rest of the
 * run. arrive_m 0: the reference as it is.
 *   The turn onto the goal's frame is made only as far as the goal lies
 * ahead along that frame (the fraction s, 1 while the bearing of the goal
 * is within 60 deg of the frame's heading, 0 from 90 deg on). Past the
 * goal the bearing points back, opposite the frame: a turn by lam of the
 * way from one to the other took its sign from the centimetres R0 lay
 * beside the goal line, the slots swung from side to side with it every
 * period, and a robot standing beyond the goal, its slot behind it, turned
 * back and forth on the spot for the rest of the run. Headed back along
 * the bearing the team comes back to the goal, and the turn comes once it
 * is ahead again. */
static void ref_arrive(const rover_ctl_state *c, unicycle_state *ref)
{
    const double dx = c->goal_m[0] - ref->x_m, dy = c->goal_m[1] - ref->y_m;
    const double dist = hypot(dx, dy), frame = atan2(c->goal_m[1], c->goal_m[0]);
    double lam, s;
    if (!(c->p.arrive_m > 0.0) || !(dist < c->p.arrive_m))
        return;
    lam = 1.0 - dist / c->p.arrive_m;
    s = dist > 0.0 ? 2.0 * (dx * cos(frame) + dy * sin(frame)) / dist : 1.0;
    s = s < 0.0 ? 0.0 : s > 1.0 ? 1.0 : s;
    ref->theta_rad = vec2_wrap_rad(ref->theta_rad +
                                   s * lam * vec2_angle_diff_rad(frame, ref->theta_rad));
    ref->v_mps *= 1.0 - lam;
    ref->w_radps *= 1.0 - lam;
}

/* The own slot k of the formation flown (of n robots) placed at
 * `centre`, the slot frame headed heading_rad; k < 0: the centre. */
static void slot_placed(const rover_ctl_state *c, int n, int k, const double centre[2],
                        double heading_rad, double out[2])
{
    double xy[2] = { 0.0, 0.0 }, r[2];
    if (k >= 0)
        formation_slot_xy(xy, c->fsm.type, n, k, c->p.fsm.spacing_m, c->fsm.scale);
    vec2_rotate(r, xy[0], xy[1], heading_rad);
    out[0] = centre[0] + r[0];
    out[1] = centre[1] + r[1];
}

/* Own goal: the own slot of the formation flown, placed at the team goal
 * (the slot frame headed along the goal's bearing from the origin). */
static void own_goal(const rover_ctl_state *c, int n, int k, double g[2])
{
    slot_placed(c, n, k, c->goal_m, atan2(c->goal_m[1], c->goal_m[0]), g);
}

static void stop_out(rover_ctl_out *out, int mode)
{
    memset(out, 0, sizeof *out);
    out->mode = mode;
}

/* Sensors missing or older than stale_s (docs/method/lockstep.md §6). */
static int sensors_stale(const rover_ctl_state *c, double t_s)
{
    return !c->have_enc || !c->have_sonar || t_s - c->enc_t_s > c->p.stale_s ||
           t_s - c->sonar_t_s > c->p.stale_s;
}

/* What one control period works from, filled in by the steps of
 * rover_ctl_step in their order. */
typedef struct {
    pose2 o;                    /* own O pose */
    unicycle_state self;        /* own pose and measured speeds */
    unicycle_state ref;         /* team reference R0 */
    int32_t ids[TEAM_MAX + 1];  /* the team's ids, own included */
    int n;                      /* team size, self included */
    sonar_groups g;             /* near mates kept (avoidance) */
    sonar_groups gw;            /* every mate masked (walls only) */
    double masked[BEH_SONAR_N]; /* the ranges gw is made of */
    double goal[2];             /* own goal slot */
    double team_steer[2];       /* R0's point steered for toward the team goal */
    int team_direct;            /* 1: that is the team goal itself */
    double steer[2];            /* what the goal behaviour drives to (own_steer) */
    int steer_goal;             /* 1: steer is the own goal slot itself */
    int steer_seen;             /* 1: steer is own_steer's target itself (in plain view) */
    int escaping;               /* rover_ctl_escape_step's verdict */
    behaviour_inputs in;        /* the behaviours' commands for the blend */
    double R_d;                 /* own slot error */
    int rc_goal;                /* behaviour_goal's result */
    int arriving;               /* arriving(): the same all through the step */
    int slot;                   /* own slot for slot_type and slot_scale */
    int slot_type;              /* the formation slot was found for (-1: none yet) */
    double slot_scale;
} step_view;

/* Where robot ids[j] is, from the team messages (our own last one for
 * ourselves): the numbers every robot of the team holds alike. */
static int sent_xy(const rover_ctl_state *c, int32_t id, double xy[2])
{
    const team_member *m;
    if (id == c->id) {
        xy[0] = c->tx_xy_m[0];
        xy[1] = c->tx_xy_m[1];
        return 0;
    }
    m = team_find(&c->team, id);
    if (!m)
        return -1;
    xy[0] = m->x_m;
    xy[1] = m->y_m;
    return 0;
}

static double sq_dist(const double a[2], const double b[2])
{
    return (a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]);
}

/* The assignment of least summed squares: on one axis (the x of each
 * point) by sorting, else by the Hungarian method. */
static int least_sq(const double xy[][2], const double sl[][2], int n, int one_axis, int *best,
                    double *best_m2)
{
    double x[TEAM_MAX + 1], s[TEAM_MAX + 1];
    int j;
    if (!one_axis)
        return slot_assign_min_sq(xy, sl, n, best, best_m2);
    for (j = 0; j < n && j < TEAM_MAX + 1; j++) {
        x[j] = xy[j][0];
        s[j] = sl[j][0];
    }
    return slot_assign_sorted(x, s, n, best, best_m2);
}

/* Our slot in the assignment of least sum of squared distances of the
 * robots (at xy, in the order of v->ids) to the slots (sl)
 * (least_sq), unless it beats the slots by id by no more than
 * arrival_swap_m2. Both choices hold themselves: robots driving to the
 * slots of either make that assignment's cost fall fastest, so noise in
 * the team messages does not flip a near tie to and fro. Every robot
 * computes it from the same team messages; our slot, or -1. */
static int slot_least_sq(const rover_ctl_state *c, const step_view *v, const double xy[][2],
                         const double sl[][2], int one_axis)
{
    double by_id_m2 = 0.0, best_m2;
    int by_id[TEAM_MAX + 1], best[TEAM_MAX + 1], j;
    const int *slot = by_id;
    for (j = 0; j < v->n; j++) {
        by_id[j] = rover_world_slot(c->fsm.type, v->n, j); /* ids sorted: j is the rank */
        if (by_id[j] < 0)
            return -1;
        by_id_m2 += sq_dist(xy[j], sl[by_id[j]]);
    }
    if (least_sq(xy, sl, v->n, one_axis, best, &best_m2) == SLOT_ASSIGN_OK &&
        best_m2 < by_id_m2 - c->p.arrival_swap_m2)
        slot = best;
    for (j = 0; j < v->n; j++)
        if (v->ids[j] == c->id)
            return slot[j];
    return -1;
}

/* The formation's slots in its own frame (centred), or all zero as
 * formation_slot_xy's untouched output was. */
static void own_pattern(const rover_ctl_state *c, const step_view *v, double s[][2])
{
    if (v->n > TEAM_MAX + 1 ||
        formation_slots_xy(s, c->fsm.type, v->n, c->p.fsm.spacing_m, c->fsm.scale) != 0)
        memset(s, 0, (size_t)(TEAM_MAX + 1) * sizeof s[0]);
}

/* The formation's slots, laid round centre facing heading, by where the
 * robots are (docs/method/formation.md §6, "Arrival"; slot_least_sq). */
static int slot_by_place(const rover_ctl_state *c, const step_view *v, const double centre[2],
                         double heading)
{
    double xy[TEAM_MAX + 1][2], sl[TEAM_MAX + 1][2], s[TEAM_MAX + 1][2];
    int j;
    own_pattern(c, v, s);
    for (j = 0; j < v->n; j++) {
        if (sent_xy(c, v->ids[j], xy[j]) != 0)
            return -1;
        vec2_rotate(sl[j], s[j][0], s[j][1], heading);
        sl[j][0] += centre[0];
        sl[j][1] += centre[1];
    }
    return slot_least_sq(c, v, (const double(*)[2])xy, (const double(*)[2])sl, 0);
}

/* A column's slots by how far along the way the robots are
 * (docs/method/formation.md §6, "On the way, a column by where the robots
 * are"): each robot at its way to the goal (navfield_way_from), slot k at
 * the mean of those plus its place behind the column's centre, matched
 * as slot_by_place matches points, on that one axis (where the least sum
 * of squares is the sorted order, slot_assign_sorted: the robot nearest
 * the goal along the way heads the column). Round a bend the way is what
 * orders the robots; slots laid straight back from R0 along its heading
 * lie across the leg the column is still on, and the robots behind took
 * one another's slots there (generated corridor world 58, 6 in triangle:
 * the column stood in a 100 deg bend, touching 10 times). The way is in the field's weighted
 * metres, at most (1 + pen_gain) times the length, which moves the
 * assignment's margin, not its order. Our slot, or -1 (a mate's position
 * unknown or without a way). */
static int slot_by_way(const rover_ctl_state *c, const step_view *v)
{
    double xy[TEAM_MAX + 1][2], sl[TEAM_MAX + 1][2], s[TEAM_MAX + 1][2], mean = 0.0;
    int j;
    own_pattern(c, v, s);
    for (j = 0; j < v->n; j++) {
        if (sent_xy(c, v->ids[j], xy[j]) != 0)
            return -1;
        xy[j][0] = navfield_way_from(c->nav, xy[j]);
        xy[j][1] = 0.0;
        if (!isfinite(xy[j][0]))
            return -1;
        mean += xy[j][0] / (double)v->n;
    }
    for (j = 0; j < v->n; j++) {
        sl[j][0] = mean - s[j][0];
        sl[j][1] = 0.0;
    }
    return slot_least_sq(c, v, (const double(*)[2])xy, (const double(*)[2])sl, 1);
}

/* The goal's slots by where the robots are. */
static int arrival_slot(const rover_ctl_state *c, const step_view *v)
{
    return slot_by_place(c, v, c->goal_m, atan2(c->goal_m[1], c->goal_m[0]));
}

/* On the way, a column's slots by where the robots are
 * (docs/method/formation.md §6, "On the way, a column by where the robots
 * are"): in the order by id (the middle robot of the line first, then
 * the others from alternate sides) a robot that reached a passage before
 * its predecessor in that order had to fall back behind it, and in a
 * passage one robot wide that is turning back into the mates behind: two
 * robots stood nose to nose in a bend for good, touching (generated
 * corridor world 11, 4 in line). By place, the robot farthest along the
 * way takes the column's head, and no robot overtakes another to reach
 * its slot: along the world's way to the goal where the robots have one
 * (slot_by_way), else the slots round R0 along its heading (slot_by_place,
 * the way's direction, so also in a hairpin that turns the column away
 * from the goal). Only a column the passage protocol formed: a team flown
 * as a column starts in its order by id and keeps it nose to tail, and by
 * place it did worse in the dead zone (12 in column: 9/10 reached and 3
 * runs with contacts, against 10/10 and none). After
 * reference_and_passage (R0 is this period's); our slot, or -1 (arriving,
 * not such a column, or a mate's position unknown). */
static int way_slot(const rover_ctl_state *c, const step_view *v)
{
    const double centre[2] = { v->ref.x_m, v->ref.y_m };
    if (!c->p.column_by_place || v->arriving || c->fsm.type != FORMATION_COLUMN ||
        c->p.formation == FORMATION_COLUMN || v->n < 2)
        return -1;
    if (c->nav)
        return slot_by_way(c, v);
    return slot_by_place(c, v, centre, v->ref.theta_rad);
}

static int arriving(const rover_ctl_state *c, const step_view *v)
{
    double mx = 0.0, my = 0.0, xy[2];
    int j;
    if (!(c->p.arrival_m > 0.0))
        return 0;
    for (j = 0; j < v->n; j++) {
        if (sent_xy(c, v->ids[j], xy) != 0)
            return 0;
        mx += xy[0];
        my += xy[1];
    }
    return hypot(mx / v->n - c->goal_m[0], my / v->n - c->goal_m[1]) <
           0.5 * (v->n - 1) * c->p.fsm.spacing_m + c->p.arrival_m;
}

/* Own slot index in the formation flown (-1: none): found once per step
 * and formation (arrival_slot is the costly part), again only when the
 * formation changed within the step. */
static int own_slot(const rover_ctl_state *c, step_view *v)
{
    int k = -1;
    if (v->slot_type == c->fsm.type && v->slot_scale == c->fsm.scale)
        return v->slot;
    if (v->arriving)
        k = arrival_slot(c, v);
    if (k < 0)
        k = rover_world_slot(c->fsm.type, v->n, formation_slot_of(v->ids, v->n, c->id));
    v->slot = k;
    v->slot_type = c->fsm.type;
    v->slot_scale = c->fsm.scale;
    return k;
}

/* Own pose, team and sonar as this period sees them, and the own goal. */
static void perceive(rover_ctl_state *c, double t_s, double dt_s, step_view *v)
{
    int k;
    team_expire(&c->team, t_s);
    rover_ctl_frame_consensus(c, t_s, dt_s);
    rover_ctl_own_pose(c, &v->o);
    v->self.x_m = v->o.x_m;
    v->self.y_m = v->o.y_m;
    v->self.theta_rad = v->o.theta_rad;
    v->self.v_mps = c->v_est_mps;
    v->self.w_radps = c->w_est_radps;
    v->n = team_ids(&c->team, v->ids, TEAM_MAX + 1);
    v->arriving = arriving(c, v);
    v->slot_type = -1;
    k = own_slot(c, v);
    /* avoid sees mates that come too near; the passage and dead-zone
     * tests never take a mate for a wall */
    rover_ctl_mask_mates(c, &v->o, c->p.mate_keep_m, v->masked);
    behaviour_sonar_groups(&v->g, v->masked);
    rover_ctl_mask_mates(c, &v->o, 0.0, v->masked);
    behaviour_sonar_groups(&v->gw, v->masked);
    own_goal(c, v->n, k, v->goal);
}

/* With the map (docs/method/formation.md §9): the narrowest width of the
 * way within passage_ahead_m of `from` (INFINITY: none narrower than
 * q->below_m), and in *is_short whether it is narrower than that for less
 * than passage_short_m of the way's length. */
static double map_passage_at(const rover_ctl_state *c, const double from[2],
                             const navfield_passage_query *q, int *is_short)
{
    navfield_passage out;
    *is_short = 0;
    if (navfield_passage_ahead(c->nav, from, q, &out) != NAVFIELD_OK)
        return INFINITY;
    *is_short = isfinite(out.narrowest_m) && out.below_len_m < c->p.passage_short_m;
    return out.narrowest_m;
}

/* The passage width the protocol takes, the sonar's `sensed` and the
 * map's (§9):
 * - a passage too short for the sonar's test, read off R0's way ahead.
 *   The side sonars confirm a passage by walls on both sides for
 *   confirm_s, so one shorter along the way than passage_short_m (a gap in
 *   a thin wall) is passed before it is confirmed, and the team squeezed
 *   through such gaps a robot at a time with no formation change. The
 *   narrower of it and the sonar's reading, or it alone where the sonar
 *   cannot tell;
 * - a longer one (a corridor) where the sonar cannot tell
 *   (passage_long_by_map): at a corridor's mouth a wide team's mates
 *   stand farther out than the walls, every wall echo reads as inside the
 *   formation, and a line of eight flew a whole corridor with no change.
 *   Where the sonar reads the sides open it stands: read from the map
 *   whatever the sonar said, a line reshaped in a funnel's wide mouth and
 *   crowded there;
 * - a short one on the robot's own way only holds the protocol (unknown:
 *   neither narrow nor clear), so the rearmost restores only once it is
 *   through, and a robot whose way leads out of a pocket's mouth does not
 *   shrink the team. */
static double map_passage(const rover_ctl_state *c, const step_view *v, double sensed)
{
    const formation_fsm_params *fp = &c->p.fsm;
    const double own[2] = { v->o.x_m, v->o.y_m }, r0[2] = { v->ref.x_m, v->ref.y_m };
    navfield_passage_query q;
    double team;
    int is_short;
    if (!c->nav)
        return sensed;
    q.ahead_m = c->p.passage_ahead_m;
    q.side_m = c->p.passage_sense_max_m + 0.5 * c->p.beh.robot_width_m;
    q.below_m = formation_width(c->fsm.type, v->n, fp->spacing_m, c->fsm.scale, fp->robot_width_m) +
                fp->safety_m;
    q.beyond_m = c->p.passage_short_m;
    team = map_passage_at(c, r0, &q, &is_short);
    if (is_short)
        return isnan(sensed) ? team : fmin(sensed, team);
    if (c->p.passage_long_by_map && isnan(sensed) && team < q.below_m)
        return team;
    if (map_passage_at(c, own, &q, &is_short) < q.below_m && is_short && !(sensed < q.below_m))
        return NAN;
    return sensed;
}

/* The team reference R0 and the narrow-passage protocol (not while
 * escaping: the trap is not a passage); an announcement the protocol
 * makes becomes the own one. */
static void reference_and_passage(rover_ctl_state *c, double t_s, double dt_s, step_view *v)
{
    formation_announce ann;
    double passage;
    if (team_reference(&v->ref, &c->team, &v->self, v->escaping, c->p.beh.d_m, t_s) < 0)
        v->ref = v->self;
    v->team_direct = steer_point(c, v->ref.x_m, v->ref.y_m, c->goal_m, v->team_steer);
    ref_heading_to_goal(c, v->team_steer, &v->ref);
    ref_arrive(c, &v->ref);
    passage = map_passage(c, v, rover_ctl_passage_width(c, &v->o, &v->ref, &v->gw, v->masked));
    /* arriving, the goal's slots are where the team ends: the formation
     * flown is restored as in the open (a column that came out of a
     * corridor into the goal area stayed a column there, its rear robot
     * never seeing the way clear long enough, and the team stood in
     * column slots short of the goal's line) */
    if (v->arriving)
        passage = INFINITY;
    if (!v->escaping) {
        const int before = c->fsm.type;
        if (formation_fsm_step(&c->fsm, &c->p.fsm, passage, v->n, dt_s, c->id,
                               rover_ctl_is_rearmost(c, &v->o), &ann) == 1) {
            c->ann_code = ann.code;
            c->ann_seq = ann.seq;
            if (c->fsm.type != before)
                c->formation_changes++;
        }
    }
}

/* What the goal behaviour drives to (docs/method/formation.md §14): the
 * own goal slot while R0 sees the team goal straight (the seed's
 * behaviour, and the arrival); else the own slot k of the formation placed
 * at R0's point steered for, headed from R0 toward it, so that the robots
 * keep their places across the way (each descending to the goal on the
 * field's one path from its own place bunched a line behind a post).
 * Either is then steered for from the robot's own O (a target behind an
 * obstacle from where it stands is gone round). */
static void own_steer(const rover_ctl_state *c, step_view *v, int k)
{
    double target[2];
    int at_goal = 1, seen;
    target[0] = v->goal[0];
    target[1] = v->goal[1];
    if (!v->team_direct && k >= 0) {
        slot_placed(c, v->n, k, v->team_steer,
                    atan2(v->team_steer[1] - v->ref.y_m, v->team_steer[0] - v->ref.x_m), target);
        at_goal = 0;
    }
    seen = steer_point(c, v->o.x_m, v->o.y_m, target, v->steer);
    v->steer_seen = seen;
    v->steer_goal = at_goal && seen;
}

/* A formation slot round R0 (l_d, phi_d) that eq. 8's law cannot bring
 * the robot to: the formation behaviour then drives the way to the goal
 * slot as the goal behaviour does (docs/method/formation.md §14). Eq. 8
 * drives at its slot straight, with a weight that grows with the
 * distance, and holds a robot whose slot lies beyond an obstacle against
 * it. Two cases:
 * - arriving, with neither its goal slot nor its formation slot in sight
 *   (a pocket beside the goal: the robot circled there to the time limit,
 *   the goal behaviour's way out weighing 5 %);
 * - on the way, with its formation slot out of sight and farther than
 *   cut_off_spacings formation spacings: the robot is on the wrong side of a wall the team went
 *   through a gap in. It slid along the wall, away from the goal, after
 *   a slot it could not reach (a line of four that became a column at a
 *   gap, its rear robot left 10 m down the wall: generated mixed worlds 1
 *   and 6). The goal behaviour's way is the field's way to where the team
 *   is going, so through the gap the team took.
 * Not nearer: a slot just behind an obstacle's corner is
 * reached by going round it, and there the law keeps the robots apart
 * (with every hidden slot left to the way, robots of the dead zone's
 * column of twelve, taking the field's one way together, touched, and a
 * line of three bunched onto that way: 73 s to the goal against 30 s). */
static int formation_slot_hidden(const rover_ctl_state *c, const step_view *v, double l_d,
                                 double phi_d)
{
    double slot[2], through[2];
    if (v->arriving ? (v->steer_seen || v->slot < 0) : !c->nav)
        return 0;
    slot[0] = v->ref.x_m + l_d * cos(v->ref.theta_rad + phi_d);
    slot[1] = v->ref.y_m + l_d * sin(v->ref.theta_rad + phi_d);
    if (!v->arriving && !(hypot(slot[0] - v->o.x_m, slot[1] - v->o.y_m) >
                          c->p.cut_off_spacings * c->p.fsm.spacing_m))
        return 0;
    return !steer_point(c, v->o.x_m, v->o.y_m, slot, through);
}

/* The slot the behaviours fly to this period: own_slot's (the type may
 * have changed since perceive), or way_slot's on the way in a column the
 * passage protocol formed. */
static int blend_slot(rover_ctl_state *c, step_view *v)
{
    const int k = own_slot(c, v), by_place = way_slot(c, v);
    if (by_place < 0)
        return k;
    v->slot = by_place;
    return by_place;
}

/* The four behaviours for the own slot of the (possibly new) formation
 * and their blend (eq. 11 or a baseline) into c->blend; the blend's
 * status. */
static int blend_behaviours(rover_ctl_state *c, step_view *v)
{
    const behaviour_params *bp = &c->p.beh;
    const int k = blend_slot(c, v);
    double l_d, phi_d, D;
    if (k < 0 ||
        formation_slot(&l_d, &phi_d, c->fsm.type, v->n, k, c->p.fsm.spacing_m, c->fsm.scale) != 0) {
        l_d = 0.0;
        phi_d = 0.0;
    }
    D = formation_width(c->fsm.type, v->n, c->p.fsm.spacing_m, c->fsm.scale, bp->robot_width_m);
    v->R_d = 0.0;
    own_steer(c, v, k);
    v->rc_goal = behaviour_goal(&v->in.u[BEH_GOAL], &v->o, v->steer, bp);
    /* a point of the way is passed through, never stopped at */
    if (!v->steer_goal && v->rc_goal == BEH_GOAL_REACHED)
        v->rc_goal = behaviour_goal(&v->in.u[BEH_GOAL], &v->o, v->goal, bp);
    if (c->p.formation_law == ROVER_LAW_KANAYAMA)
        behaviour_formation_track(&v->in.u[BEH_FORMATION], &v->R_d, &v->o, &v->ref, l_d, phi_d, bp);
    else
        behaviour_formation_seed(&v->in.u[BEH_FORMATION], &v->R_d, &v->o, &v->ref, l_d, phi_d, bp);
    if (formation_slot_hidden(c, v, l_d, phi_d))
        v->in.u[BEH_FORMATION] = v->in.u[BEH_GOAL];
    v->in.d_st_m = behaviour_d_st(bp, D, l_d, phi_d);
    v->in.avoid_active = behaviour_avoid(&v->in.u[BEH_AVOID], &v->g, v->self.v_mps, v->in.d_st_m,
                                         bp);
    v->in.exception_active = v->escaping;
    if (!v->escaping)
        v->in.u[BEH_EXCEPTION].v_mps = v->in.u[BEH_EXCEPTION].w_radps = 0.0;
    v->in.R_d_m = v->R_d;
    /* avoidance's weight grows with what its law answers, the echoes ahead
     * (front, left-front, right-front): a mate alongside (side transducer)
     * gave the idle behaviour, which keeps the speed and turns nowhere, most
     * of the weight, and a team facing away from its goal drove on */
    {
        const double ahead = fmin(v->g.front_m, fmin(v->g.left_front_m, v->g.right_front_m));
        v->in.min_range_m = ahead > 0.05 ? ahead : 0.05;
    }
    return behaviour_blend(&c->blend, &v->in, c->p.blend_mode, bp);
}

/* Arriving, a robot whose own slot (or the way's next point to it) lies
 * behind it turns to face it on the spot (docs/method/formation.md §6,
 * "Arrival"): the goal behaviour asks for no speed then, and the blend's
 * speed came from the others alone (avoidance's V = k S_F, a formation
 * slot round R0 that is not the goal's), whose turns cancelled the
 * goal's, so the robot crept on past its slot. 1 if it does; the turn
 * in *u. */
static int arrival_turn(const rover_ctl_state *c, const step_view *v, unicycle_cmd *u)
{
    double r, phi;
    if (v->escaping || !v->arriving || c->holding != ROVER_WAIT_NONE)
        return 0;
    if (v->rc_goal == BEH_GOAL_TURN) {
        *u = v->in.u[BEH_GOAL];
    } else {
        /* a turn begun goes on until the target lies within arrive_face_rad
         * of ahead: the goal behaviour turns only while the target is
         * behind (eq. 5's singular line), and the blend, pulling elsewhere,
         * turned the robot back over that line, to and fro for good (a
         * robot 0.4 m from its goal slot, test_cut_off_takes_the_way) */
        if (c->arrive_turn == 0 || v->rc_goal == BEH_GOAL_REACHED)
            return 0;
        behaviour_goal_polar(&r, &phi, &v->o, v->steer);
        if (!(fabs(phi) > c->p.arrive_face_rad))
            return 0;
        behaviour_goal_face(u, phi, &c->p.beh);
    }
    if (c->arrive_turn != 0)
        u->w_radps = c->arrive_turn * fabs(u->w_radps);
    return 1;
}

/* u turns on the spot (no more than ROVER_SPIN_V_MPS of speed), and the
 * turn sweeps our chassis into a mate's (rover_ctl_cmd_sweeps_mate, every
 * mate: standing for a lower mate's box costs nothing where the lower one
 * keeps out of our turning circle). */
static int spin_into_mate(const rover_ctl_state *c, const pose2 *o, const unicycle_cmd *u)
{
    return fabs(u->v_mps) <= ROVER_SPIN_V_MPS && u->w_radps != 0.0 &&
           rover_ctl_cmd_sweeps_mate(c, o, u, ROVER_SWEEP_ANY) != 0;
}

/* The map's graze guard held the turn in *u (rover_ctl_turn_grazes). In
 * formation, or escaping while driving: no turn. A turn on the spot while
 * escaping (eq. 2's and the follower's turn the other way round first
 * where that is free, graze_other_way in rover_ctl_escape.c) becomes a
 * creep straight on where the front is free of echoes within guard_m and
 * of mates: a robot whose tail is in a corner draws away from it, then
 * turns (standing is not following, so escape_max_s would not run).
 * Hemmed in ahead, it creeps straight back where the map keeps the rear
 * edge clear of walls (rover_ctl_back_clear_of_map) and no mate is in the
 * way, else it stands: a robot wedged by a mate against a corridor's jog
 * that turned as asked touched the wall (mixed world 187, 6 in line).
 * Standing cannot hold for good: a robot that came in driving forward can
 * go back the way it came unless a mate stands there, and of two robots
 * so wedged the lower one clears (deconflict in rover_ctl_escape.c: back
 * along its crumbs, or straight back on the map). */
#define GRAZE_CREEP_MPS 0.05
static void graze_hold(const rover_ctl_state *c, const step_view *v, unicycle_cmd *u)
{
    unicycle_cmd back = { -GRAZE_CREEP_MPS, 0.0 };
    u->w_radps = 0.0;
    if (!v->escaping || fabs(u->v_mps) > ROVER_SPIN_V_MPS)
        return;
    u->v_mps = 0.0;
    if (fmin(v->g.front_m, fmin(v->g.left_front_m, v->g.right_front_m)) > c->p.guard_m &&
        !rover_ctl_mate_in_lane(c, &v->o, c->p.follow_mate_ahead_m))
        u->v_mps = GRAZE_CREEP_MPS;
    else if (rover_ctl_back_clear_of_map(c, &v->o) &&
             rover_ctl_cmd_sweeps_mate(c, &v->o, &back, ROVER_SWEEP_ANY) == 0)
        *u = back;
}

/* Every echo within the guard's reach is a wall's: none explained by a
 * mate where the team table puts it (v->masked, walls only). */
static int near_echoes_are_walls(const rover_ctl_state *c, const step_view *v)
{
    int k;
    for (k = 0; k < BEH_SONAR_N; k++)
        if (c->range_m[k] < c->p.guard_m && v->masked[k] != c->range_m[k])
            return 0;
    return 1;
}

/* The guard keeps a robot from turning toward the nearer echo ahead (it
 * stops the turn, or turns it the other way); facing the U's arm with its
 * slot behind the arm's tip, the short way round was that way and the
 * robot stood still for good. So once the guard has stopped or reversed
 * the way the robot turns, it turns the other way round, and holds that
 * way until the target lies ahead (turned back, the echo left the guard's
 * reach and the short way was open again, to and fro at the boundary); a
 * way held that the guard closes in turn is given up for the other (the
 * robot stood facing the arm's tip with the held way closed). Unless the
 * turn is on the spot with every echo outside the circle it sweeps
 * (rover_ctl_spin_clear), every echo the guard heeds a wall's
 * (near_echoes_are_walls) and no mate in its sweep (spin_into_mate: the
 * sonar does not look behind): walls stay where they are, so such a turn
 * can hit nothing, and the way held is kept whatever the guard says. A
 * mate moves: one outside the circle now may not be later, so near a
 * mate's echo the guard's rule stands (two robots arriving side by side,
 * the one turning toward the other crept into its circle and both stood,
 * test_column_by_place). A robot in a U's pocket 1.1 m wide, its slot
 * behind, had each way closed by the nearer side wall in turn and turned
 * to and fro to the time limit (dead zone, 4 in line,
 * every seed). Only the arrival turn: a slow turn of the blend, kept
 * toward a wall, drove the robot's nose to it (mixed world 120). */
static void arrival_turn_other_way(rover_ctl_state *c, const step_view *v, double w_turn,
                                   unicycle_cmd *u)
{
    const double want = c->arrive_turn != 0 ? (double)c->arrive_turn : w_turn;
    if (w_turn == 0.0 || u->w_radps * want > 0.0)
        return;
    if (fabs(u->v_mps) <= ROVER_SPIN_V_MPS && rover_ctl_spin_free(c, &v->o) &&
        near_echoes_are_walls(c, v)) {
        const unicycle_cmd held = { u->v_mps, want > 0.0 ? fabs(w_turn) : -fabs(w_turn) };
        if (!spin_into_mate(c, &v->o, &held)) {
            *u = held;
            return;
        }
    }
    c->arrive_turn = want > 0.0 ? -1 : 1;
    u->w_radps = c->arrive_turn * fabs(w_turn);
}

/* The stall clock (docs/method/formation.md §10, "Stalls"): how long a
 * robot away from where it should be (arriving: its goal slot; en route:
 * its formation slot; farther than stall_near_m) has kept its axle within
 * stall_move_m of one place. Waiting for outranking mates pauses the
 * clock (a wait is bounded by hold_max_s, and a robot whose wait set
 * flickers stood for good at a corridor's bend); anything else a robot
 * that wants to move and stays put is held by walls and mates its
 * behaviours cannot get round: turning to and fro on the spot beside a
 * mate that could not back out of its turning circle (traps world 412, 8
 * in triangle), in a corridor bend's dead end with a mate standing in its
 * way out (corridor world 416, 6 in column), two left behind at the
 * start, each in the other's turning circle, while the team flew on
 * (corridor world 4, 8 in line). Eq. 2's test sees a trap only with
 * walls on three sides. The escape reads the clock
 * (rover_ctl_escape.c). */
static void stall_watch(rover_ctl_state *c, const step_view *v, double dt_s)
{
    const double away_m = v->arriving ? hypot(v->goal[0] - v->o.x_m, v->goal[1] - v->o.y_m)
                                      : v->R_d;
    const int counts = !v->escaping && v->rc_goal != BEH_GOAL_REACHED && away_m > c->p.stall_near_m;
    if (!counts ||
        hypot(v->o.x_m - c->stall_xy_m[0], v->o.y_m - c->stall_xy_m[1]) > c->p.stall_move_m) {
        c->stall_xy_m[0] = v->o.x_m;
        c->stall_xy_m[1] = v->o.y_m;
        c->stall_t_s = 0.0;
        return;
    }
    if (c->holding == ROVER_WAIT_NONE)
        c->stall_t_s += dt_s;
}

/* The drive command from the blend and the mode reported: capped while
 * the formation reshapes, zero at the goal, turned on the spot arriving
 * with the slot behind, guarded, never backwards, saturated. */
static void command_out(rover_ctl_state *c, const step_view *v, double t_s, double dt_s,
                        rover_ctl_out *out)
{
    const behaviour_params *bp = &c->p.beh;
    unicycle_cmd u = c->blend.u;
    int i, turning;
    double w_turn;
    /* while the formation reshapes for a passage, give it time */
    if (c->fsm.phase == FORMATION_PHASE_SHRINK || c->fsm.phase == FORMATION_PHASE_CHANGE)
        if (u.v_mps > c->p.v_change_mps)
            u.v_mps = c->p.v_change_mps;
    /* the escape table's mode (a robot giving way left the formation but
     * was not trapped itself) */
    out->mode = v->escaping                              ? rover_esc_table[c->esc.phase].mode
                : c->fsm.phase != FORMATION_PHASE_NORMAL ? ROVER_MODE_CHANGING
                                                         : ROVER_MODE_FORMATION;
    if (!v->escaping && v->rc_goal == BEH_GOAL_REACHED) {
        u.v_mps = u.w_radps = 0.0;
        out->mode = ROVER_MODE_AT_GOAL;
    }
    turning = arrival_turn(c, v, &u);
    w_turn = u.w_radps; /* the turn's rate, before the guard */
    if (!turning)
        c->arrive_turn = 0;
    else if (c->arrive_turn == 0 && u.w_radps != 0.0)
        c->arrive_turn = u.w_radps > 0.0 ? 1 : -1; /* the way the turn begins is held */
    /* waiting for outranking mates (method §10): stand, or back out of
     * one's way. Not guarded: the guard turns a stopped robot with an echo
     * near ahead toward the freer side, and a robot standing for a mate
     * beside it swung its nose into that mate */
    if (c->holding != ROVER_WAIT_NONE)
        u = c->wait_u;
    else if (!v->escaping)
        rover_ctl_guard(&u, c->range_m, &v->o, v->steer, &c->p);
    if (turning)
        arrival_turn_other_way(c, v, w_turn, &u);
    /* no command sweeps the chassis into a mate we wait for
     * (rover_ctl_cmd_sweeps_mate): past hold_max_s a robot flies the blend
     * again, and one standing beside a trapped mate turned toward its slot
     * and swung its tail into it (dead zone, 3 in line, seed 1). Only the
     * wait set: standing for a lower mate too wedged teams of 6 in the U */
    if (c->holding == ROVER_WAIT_NONE && !v->escaping &&
        rover_ctl_cmd_sweeps_mate(c, &v->o, &u, ROVER_SWEEP_WAITED))
        u.v_mps = u.w_radps = 0.0;
    /* nor one that meets an outranking mate flying on as it does
     * (rover_ctl_cmd_meets_mate), wait set or not: in the open nothing
     * conflicts, and two robots of a line closing into column in the
     * start room crossed paths side by side and met, each flying its
     * blend (corridor world 39, 12 in column). The lower one stands; the
     * higher drives on. Standing for every outranking mate driving our
     * way, the last robot of 12 stood so often in a corridor's mouth that
     * it reached the goal room after the time limit (corridor world 31,
     * 12 in line) */
    if (c->holding == ROVER_WAIT_NONE && !v->escaping && rover_ctl_cmd_meets_mate(c, &v->o, &u))
        u.v_mps = u.w_radps = 0.0;
    /* nor a turn on the spot into any mate's chassis: a mate within our
     * turning circle keeps out of it when we outrank it (the wait set), but
     * we are the one turning. Two robots arriving side by side, each turning
     * to its slot with the other in its circle, met tail to tail (mixed
     * world 120, 12 in line) */
    if (!v->escaping && spin_into_mate(c, &v->o, &u))
        u.w_radps = 0.0;
    /* other teams (fleet.h): stand for an outranking team's robot near
     * ahead (rover_ctl_teams.c); never with one team */
    c->giving_way_team = !v->escaping && out->mode != ROVER_MODE_AT_GOAL &&
                         rover_ctl_stranger_wait(c, &v->o, t_s, dt_s);
    if (c->giving_way_team)
        u.v_mps = u.w_radps = 0.0;
    /* no rear sonar: never back up blindly (backing out of a mate's way
     * goes the way the robot came, clear of mates) */
    if (u.v_mps < 0.0 && !c->esc.backing)
        u.v_mps = 0.0;
    unicycle_saturate(&out->u, &u, bp->v_max_mps, bp->w_max_radps, UNICYCLE_SAT_CLIP);
    /* last, on what is flown: no turn swings a corner the sonar cannot see
     * into a wall of the map; not while backing along the crumbs (the
     * chassis's own way back) */
    if (!c->esc.backing && rover_ctl_turn_grazes(c, &v->o, out->u.w_radps))
        graze_hold(c, v, &out->u);
    stall_watch(c, v, dt_s);
    out->o = v->o;
    for (i = 0; i < BEH_COUNT; i++)
        out->weight[i] = c->blend.weight[i];
    out->slot_err_m = v->R_d;
    out->team_size = v->n;
}

/* Own team message, every team_period_s: pose, speeds, the formation
 * flown and the own announcement (LEAVE throughout an escape, GIVE_WAY
 * while making room for one). */
static void team_message_out(rover_ctl_state *c, const step_view *v, double t_s, rover_ctl_out *out)
{
    team_member *m = &out->team;
    if (!(t_s - c->team_tx_t_s >= c->p.team_period_s - 1e-9))
        return;
    c->team_tx_t_s = t_s;
    out->send_team = 1;
    memset(m, 0, sizeof *m);
    m->robot = c->id;
    m->x_m = v->o.x_m;
    m->y_m = v->o.y_m;
    m->theta_rad = v->o.theta_rad;
    m->v_mps = v->self.v_mps;
    m->w_radps = v->self.w_radps;
    m->formation = c->fsm.type;
    m->scale = c->fsm.scale;
    /* the same announcement every mate ranks us by (rover_ctl_outranks) */
    m->announce = rover_ctl_own_announce(c);
    m->announce_seq = c->ann_seq;
    m->t_s = t_s;
    c->tx_xy_m[0] = m->x_m;
    c->tx_xy_m[1] = m->y_m;
}

int rover_ctl_step(rover_ctl_state *c, double t_s, double dt_s, rover_ctl_out *out)
{
    step_view v;
    if (!c || !out || !isfinite(t_s) || !isfinite(dt_s) || dt_s < 0.0) {
        if (out)
            stop_out(out, ROVER_MODE_SAFE_STOP);
        return ROVER_CTL_ERR_ARG;
    }
    if (sensors_stale(c, t_s)) {
        /* docs/method/lockstep.md §6: stop, and stay silent so the mates re-slot without us */
        stop_out(out, ROVER_MODE_SAFE_STOP);
        if (c->have_enc)
            rover_ctl_own_pose(c, &out->o);
        return ROVER_CTL_OK;
    }
    memset(out, 0, sizeof *out);
    perceive(c, t_s, dt_s, &v);
    v.escaping = rover_ctl_escape_step(c, &v.gw, &v.g, &v.o, v.goal, t_s, dt_s,
                                       &v.in.u[BEH_EXCEPTION]);
    reference_and_passage(c, t_s, dt_s, &v);
    if (blend_behaviours(c, &v) != 0) {
        stop_out(out, ROVER_MODE_SAFE_STOP);
        return ROVER_CTL_ERR_ARG;
    }
    command_out(c, &v, t_s, dt_s, out);
    team_message_out(c, &v, t_s, out);
    return ROVER_CTL_OK;
}
