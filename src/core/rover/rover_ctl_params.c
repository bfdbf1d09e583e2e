/* rover_ctl_params: the formation controller's parameter set (docs/method/
 * formation.md: behaviours, eq. 11 blend, narrow-passage protocol, dead-zone
 * escape, heartbeat membership; section 7: safe stop on stale input), its
 * defaults, with the reasons for the values tuned in the runs, and
 * rover_ctl_params_validate.
 */
#include "rover_ctl.h"

#include <math.h>

/* One flat table of defaults, better read whole than split. */
void rover_ctl_params_default(rover_ctl_params *p)
{
    behaviour_params_default(&p->beh);
    /* 0.5 m: a column in a 1.3 m corridor (side echoes ~0.51 m) must not
     * read as a dead zone, a robot in a 1.0 m trap (~0.36 m) must. */
    p->beh.d_s_m = 0.5;
    /* at the goal slot: stop when O is this near. The behaviour's 0.3 m left
     * every robot about that far short, the whole team's centroid with it
     * (the goal test allows 0.5 m, odometry drift takes most of it); eq. 5
     * drives O forward down to d + goal_margin = 0.2 m, so a little above */
    p->beh.goal_tol_m = 0.22;
    formation_fsm_params_default(&p->fsm);
    p->fsm.shrink_scale = 0.8;
    p->fsm.clear_hold_s = 4.0; /* 10 s (the whole column out) did worse in the corridor runs */
    p->blend_mode = BEH_BLEND_WEIGHTED;
    p->formation_law = ROVER_LAW_SEED;
    p->formation = FORMATION_LINE;
    p->team_timeout_s = TEAM_TIMEOUT_S_DEFAULT;
    p->beacon_alpha = 0.2;
    p->stale_s = ROVER_CTL_STALE_MS / 1000.0;
    p->team_period_s = 0.1;
    p->wheel_radius_m = ODOMETRY_P2DX_WHEEL_RADIUS_M;
    p->axle_track_m = ODOMETRY_P2DX_AXLE_TRACK_M;
    p->follow_dist_m = 0.45;
    p->follow_v_mps = 0.25;
    p->follow_w_radps = 0.7;
    p->escape_max_s = 60.0;
    p->give_way_m = 2.0;
    p->yield_max_s = 6.0;
    p->give_way_seen_s = 1.0;
    /* two robots turning on the spot each sweep 0.314 m round the axle:
     * axles nearer than twice that and a little are in each other's way */
    p->yield_near_m = 0.75;
    /* a robot's turning circle and a body beyond the formation's extent:
     * room for the last robots to turn toward a slot they did not expect */
    p->arrival_m = 2.0;
    /* a swap must gain what 0.5 m more for one robot costs at a slot 1 m
     * away (1.5^2 - 1^2): noise in the team messages does not flip slots */
    p->arrival_swap_m2 = 1.25;
    /* a column passes a passage one robot after another: in its order by
     * id a robot already ahead of its predecessor turned back into the
     * passage to fall in behind it (docs/method/formation.md §14) */
    p->column_by_place = 1;
    /* two spacings: nearer, a slot out of sight is behind an obstacle's
     * corner the robot is going round anyway, and eq. 8's law keeps the
     * robots apart (the dead zone's team bunched on the field's one path
     * when every hidden slot was left for it) */
    p->cut_off_spacings = 2.0;
    /* 30 deg: the goal behaviour's own turn ends about 90 deg off */
    p->arrive_face_rad = 0.5;
    /* queue: a mate in formation ahead that stands or that we close on is
     * usually one about to find its pocket closed */
    p->queue_m = 1.3;
    p->queue_cone_rad = 0.6;
    p->queue_slow_mps = 0.1;
    p->queue_closing_mps = 0.1;
    /* a trapped robot turns round in the dead-zone time (2 s) and half a
     * turn at w_k (0.6 rad/s, 5.2 s) */
    p->hold_max_s = 10.0;
    p->stranger_give_m = 2.0;
    p->stranger_cone_rad = 100.0 * VEC2_PI / 180.0;
    p->stranger_seen_s = 0.5;
    p->stranger_hold_max_s = 15.0;
    /* two robots whose axles are 0.5 m apart cannot turn; 0.3 m more can */
    p->back_max_m = 0.4;
    p->back_v_mps = 0.1;
    p->wedge_max_s = 8.0;
    p->follow_lost_s = 5.0;
    p->walls_near_m = 0.8;
    p->leave_gain_m = 0.5;
    p->leave_by_way = 1;
    p->entry_by_way = 1;
    /* a corridor's width or two: more than a follower's sway round a
     * pillar, less than the legs of a generated corridor */
    p->follow_regress_m = 3.0;
    p->map_graze = 1;
    /* longer than a wait (hold_max_s) and a trapped mate's escape past
     * us; 0.3 m: a turn on the spot to and fro moves the axle less */
    p->stall_s = 15.0;
    p->stall_move_m = 0.3;
    p->stall_near_m = 1.0;
    p->follow_mate_ahead_m = 0.3;
    p->follow_moving_mps = 0.05;
    p->passage_sense_max_m = 2.5;
    p->mate_keep_m = 0.45;
    p->v_change_mps = 0.25;
    p->goal_heading_gain = 1.0;
    /* off: the seed's reference. With the dead-zone rules of method §10
     * arrival no longer changes a pass rate over the sweeps and costs a
     * little time to goal (docs/formation.md, "Results over seeds");
     * `--ref-arrive 3` (about the size of the formation) flies it */
    p->arrive_m = 0.0;
    p->guard_m = 0.5;
    p->guard_stop_m = 0.15;
    p->guard_lane_m = 0.1;
    p->side_guard_m = 0.3;
    p->side_turn_radps = 0.4;
    p->passage_front_min_m = 2.0;
    /* a change from line to column is a shrink and two types, each
     * confirmed for 1 s and held for 1 s, at 0.25-0.5 m/s */
    p->passage_ahead_m = 1.5;
    /* the side sonars confirm walls for 1 s (confirm_s), some 0.3-0.5 m
     * at the team's pace: shorter passages are passed unconfirmed */
    p->passage_short_m = 1.0;
    p->passage_long_by_map = 1;
    p->sonar_max_m = 5.0;
    p->consensus_gain = 0.2;
    p->consensus_age_s = 2.0;
    p->consensus_max_mps = 0.05;
    p->consensus_range_m = 2.5;
    p->localize = 1;
    localize_params_default(&p->loc);
    p->loc_sd0_xy_m = 0.02;
    p->loc_sd0_theta_rad = 0.01;
}

static int pos(double v)
{
    return isfinite(v) && v > 0.0;
}

int rover_ctl_params_validate(const rover_ctl_params *p)
{
    if (!p || behaviour_params_validate(&p->beh) != 0)
        return ROVER_CTL_ERR_ARG;
    if (p->blend_mode < BEH_BLEND_WEIGHTED || p->blend_mode > BEH_BLEND_VECSUM)
        return ROVER_CTL_ERR_ARG;
    if (p->formation_law != ROVER_LAW_SEED && p->formation_law != ROVER_LAW_KANAYAMA)
        return ROVER_CTL_ERR_ARG;
    if (p->formation < FORMATION_LINE || p->formation > FORMATION_COLUMN)
        return ROVER_CTL_ERR_ARG;
    if (!pos(p->team_timeout_s) || !pos(p->stale_s) || !pos(p->team_period_s) ||
        !pos(p->wheel_radius_m) || !pos(p->axle_track_m) || !pos(p->follow_dist_m) ||
        !pos(p->follow_v_mps) || !pos(p->follow_w_radps) || !pos(p->escape_max_s) ||
        !pos(p->give_way_m) || !pos(p->yield_max_s) || !pos(p->give_way_seen_s) ||
        !pos(p->yield_near_m) || !isfinite(p->arrival_m) || p->arrival_m < 0.0 ||
        !isfinite(p->arrival_swap_m2) || p->arrival_swap_m2 < 0.0 ||
        (p->column_by_place != 0 && p->column_by_place != 1) ||
        (p->leave_by_way != 0 && p->leave_by_way != 1) ||
        (p->entry_by_way != 0 && p->entry_by_way != 1) ||
        (p->map_graze != 0 && p->map_graze != 1) || !isfinite(p->follow_regress_m) ||
        p->follow_regress_m < 0.0 || (p->passage_long_by_map != 0 && p->passage_long_by_map != 1) ||
        !pos(p->cut_off_spacings) || !isfinite(p->stall_s) || p->stall_s < 0.0 ||
        !pos(p->stall_move_m) || !isfinite(p->stall_near_m) || p->stall_near_m < 0.0 ||
        !pos(p->arrive_face_rad) || p->arrive_face_rad > VEC2_PI || !pos(p->queue_m) ||
        !pos(p->queue_cone_rad) || p->queue_cone_rad > VEC2_PI || !pos(p->queue_slow_mps) ||
        !pos(p->queue_closing_mps) || !pos(p->hold_max_s) || !pos(p->walls_near_m) ||
        !pos(p->stranger_give_m) || !pos(p->stranger_cone_rad) || p->stranger_cone_rad > VEC2_PI ||
        !pos(p->stranger_seen_s) || !pos(p->stranger_hold_max_s) || !pos(p->leave_gain_m) ||
        !pos(p->follow_mate_ahead_m) || !pos(p->follow_moving_mps) || !pos(p->back_max_m) ||
        !pos(p->back_v_mps) || !pos(p->wedge_max_s) || !pos(p->follow_lost_s) ||
        !pos(p->passage_sense_max_m) || !pos(p->mate_keep_m) || !pos(p->v_change_mps) ||
        !pos(p->guard_m) || !pos(p->guard_stop_m) || !pos(p->guard_lane_m) ||
        !pos(p->side_guard_m) || !pos(p->side_turn_radps) || !isfinite(p->goal_heading_gain) ||
        p->goal_heading_gain < 0.0 || p->goal_heading_gain > 1.0 || !isfinite(p->arrive_m) ||
        p->arrive_m < 0.0 || !pos(p->passage_front_min_m) || !pos(p->passage_ahead_m) ||
        !pos(p->passage_short_m) || !pos(p->sonar_max_m) || !(p->consensus_gain >= 0.0) ||
        !isfinite(p->consensus_gain) || !pos(p->consensus_age_s) || !pos(p->consensus_max_mps) ||
        !pos(p->consensus_range_m) || !pos(p->fsm.spacing_m) ||
        !(p->fsm.shrink_scale > 0.0 && p->fsm.shrink_scale <= 1.0))
        return ROVER_CTL_ERR_ARG;
    if (!isfinite(p->beacon_alpha) || p->beacon_alpha < 0.0 || p->beacon_alpha > 1.0)
        return ROVER_CTL_ERR_ARG;
    if ((p->localize != 0 && p->localize != 1) || localize_params_validate(&p->loc) != 0 ||
        !isfinite(p->loc_sd0_xy_m) || p->loc_sd0_xy_m < 0.0 || !isfinite(p->loc_sd0_theta_rad) ||
        p->loc_sd0_theta_rad < 0.0)
        return ROVER_CTL_ERR_ARG;
    return ROVER_CTL_OK;
}
