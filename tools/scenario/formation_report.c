/* formation_report: what a formation run (docs/method/formation.md §6)
 * reports: its success criteria (the seed-003 must-show figures),
 * summary.json, and the gnuplot script for paths.png (the world, the
 * ground-truth paths and the formation every 5 s), formation_error.png
 * and weights.png.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include "formation_scen.h"
#include "shared_run.h"
#include "formation.h"

/* The width the team needs in its start formation: the formation's
 * width across the heading plus the FSM's safety margin (the rule
 * by which the robots themselves decide to change, formation.c). */
double fm_needed_width_m(const fm_cfg *cfg)
{
    formation_fsm_params p;
    formation_fsm_params_default(&p);
    return fm_formation_width_m(cfg) + p.safety_m;
}

/* The start formation's own width across the heading (its slots and a
 * robot's width), without the FSM's margin. */
double fm_formation_width_m(const fm_cfg *cfg)
{
    formation_fsm_params p;
    formation_fsm_params_default(&p);
    return formation_width(cfg->formation, cfg->robots, p.spacing_m, 1.0, p.robot_width_m);
}

/* The run's success criteria (the seed-003 must-show figures): the team
 * reached the goal without a collision, each robot's own pose estimate
 * within 0.25 m of the truth, >= 2 formation changes (into a narrower
 * one and back) where no way is wide enough for the formation
 * (fm_cfg.passage_m, fm_passage_width_m, below fm_formation_width_m less
 * 2 d_r: a robot within d_r, FM_OUT_TOL, of its slot is in formation, so
 * a team whose outer robots each give way by d_r passes such a gap
 * without one) and no cross-section of all the ways together is either
 * (fm_cfg.cut_m: a team may split round an obstacle and join again); between that and fm_needed_width_m, where the robots' own
 * margin may make them change, either is right), and >= 1 dead-zone
 * escape in the dead zone flown without the map (--goal-path direct:
 * with it the team steers round the U, and there is nothing to escape).
 * Appends the failed ones to buf; returns how many failed. */
int fm_criteria(const fm_cfg *cfg, const fm_procs *pr, const fm_metrics *mt, const fm_outcome *oc,
                char *buf, size_t cap)
{
    const double fits = fm_formation_width_m(cfg) - 2.0 * FM_OUT_TOL;
    const int must_change = cfg->passage_m < fits && cfg->cut_m < fits;
    const scenario_criterion k[] = {
        { !mt->reached, "reached_goal" },
        { mt->collisions != 0, "collisions" },
        { mt->loc_n && !(mt->loc_max <= 0.25), "loc_err_max_m" },
        { must_change && mt->formation_changes < 2, "formation_changes" },
        { cfg->world == ROVER_WORLD_DEADZONE && cfg->goal_direct && mt->escapes < 1,
          "dead_zone_escapes" },
        { oc->lost_lockstep, "lockstep" },
        { oc->restart_failed, "restarts" },
        { pr->hung_stopped, "hung" },
    };
    return scenario_failed_criteria(k, (int)(sizeof k / sizeof k[0]), buf, cap);
}

/* Many teams (fleet.h): the fleet's keys and each team's own criteria,
 * the array "teams" (robots first_robot..last_robot). */
static void fleet_summary(json_out *j, const fm_cfg *cfg, const fm_metrics *mt)
{
    int t, reached = 0;
    for (t = 0; t < cfg->teams; t++)
        reached += mt->team[t].reached;
    json_int(j, "teams", cfg->teams);
    json_int(j, "robots_per_team", cfg->per_team);
    json_str(j, "team_goals", rover_fleet_goals_name(cfg->team_goals));
    json_num(j, "lane_m", cfg->fleet.lane_m);
    json_int(j, "teams_reached_goal", reached);
    json_int(j, "collisions_between_teams", mt->collisions_teams);
    json_array_begin(j, "team");
    for (t = 0; t < cfg->teams; t++) {
        const fm_team_metrics *tm = &mt->team[t];
        int32_t lo, hi;
        rover_fleet_members(&cfg->fleet, t, &lo, &hi);
        json_object_begin(j);
        json_int(j, "team", t + 1);
        json_int(j, "first_robot", lo);
        json_int(j, "last_robot", hi);
        json_num(j, "goal_x_m", cfg->fleet.goal_m[t][0]);
        json_num(j, "goal_y_m", cfg->fleet.goal_m[t][1]);
        json_bool(j, "reached_goal", tm->reached);
        json_num(j, "time_to_goal_s", tm->reached ? tm->time_to_goal : NAN);
        json_num(j, "rms_formation_err_m", tm->samples ? sqrt(tm->sum_sq_err / tm->samples) : NAN);
        json_num(j, "max_formation_err_m", tm->max_err);
        json_num(j, "time_out_of_formation_frac",
                 tm->samples ? (double)tm->out_samples / tm->samples : NAN);
        json_num(j, "min_clearance_m", tm->min_clear);
        json_int(j, "collisions", tm->collisions);
        json_int(j, "collisions_mates", tm->collisions_mates);
        json_int(j, "collisions_other_teams", tm->collisions_others);
        json_int(j, "formation_changes", tm->formation_changes);
        json_object_end(j);
    }
    json_array_end(j);
}

void fm_write_summary(const fm_cfg *cfg, const fm_procs *pr, const fm_metrics *mt,
                      const fm_outcome *oc, double sim_s, double wall_s)
{
    json_out j;
    double path = 0.0;
    int i, n = 0;
    if (json_open(&j, cfg->out, "summary.json") != 0)
        return;
    for (i = 0; i < cfg->robots; i++)
        if (mt->have_prev[i] && i + 1 != cfg->kill_id) {
            path += mt->path[i];
            n++;
        }
    json_str(&j, "scenario", "formation");
    json_str(&j, "formation", fm_formation_name(cfg->formation));
    json_str(&j, "world", rover_world_name(cfg->world));
    if (cfg->wopt.world == FM_WORLD_RANDOM) { /* what generates the same world again */
        json_str(&j, "world_kind", fm_world_kinds[cfg->world_kind]);
        json_int(&j, "world_seed", cfg->world_seed);
    }
    json_str(&j, "blend", fm_blend_name(cfg->blend));
    json_str(&j, "formation_law", cfg->law_kanayama ? "kanayama" : "seed");
    json_str(&j, "ref_heading", cfg->ref_goal ? "goal" : "mean");
    json_str(&j, "goal_path", cfg->goal_direct ? "direct" : "map");
    json_num(&j, "ref_arrive_m", cfg->ref_arrive_m);
    json_bool(&j, "localize", !cfg->localize_off);
    json_int(&j, "robots", cfg->robots);
    json_int(&j, "rover_processes", fm_rover_procs(cfg)); /* --procs, --hosts */
    json_int(&j, "seed", cfg->seed);
    json_int(&j, "killed_robot", cfg->kill_id > 0 && pr->killed ? cfg->kill_id : 0);
    /* where the goal formation stands (goal_place.h): the goal given, the
     * one flown to, and whether the formation fits there */
    json_num(&j, "goal_x_m", cfg->layout.goal_m[0]);
    json_num(&j, "goal_y_m", cfg->layout.goal_m[1]);
    json_num(&j, "goal_shift_m",
             hypot(cfg->layout.goal_m[0] - cfg->layout.goal_nominal_m[0],
                   cfg->layout.goal_m[1] - cfg->layout.goal_nominal_m[1]));
    json_bool(&j, "goal_formation_fits", cfg->layout.goal_fits);
    json_bool(&j, "reached_goal", mt->reached);
    json_num(&j, "time_to_goal_s", mt->reached ? mt->time_to_goal : NAN);
    json_num(&j, "rms_formation_err_m", mt->samples ? sqrt(mt->sum_sq_err / mt->samples) : NAN);
    json_num(&j, "max_formation_err_m", mt->max_err);
    json_num(&j, "time_out_of_formation_frac",
             mt->samples ? (double)mt->out_samples / mt->samples : NAN);
    json_num(&j, "min_clearance_m", mt->min_clear);
    json_int(&j, "collisions", mt->collisions);
    json_int(&j, "collisions_walls", mt->collisions_walls);
    json_int(&j, "collisions_mates", mt->collisions_mates);
    json_int(&j, "kills", pr->kills);
    json_int(&j, "restarts", pr->restarts);
    json_num(&j, "hang_s", cfg->hang_s);
    json_int(&j, "hung_restarts", pr->hung_restarts);
    json_int(&j, "leave_resends", pr->leave_resends);
    json_int(&j, "kill_resends", pr->kill_resends);
    json_int(&j, "formation_changes", mt->formation_changes);
    json_num(&j, "passage_width_m", cfg->passage_m);
    json_num(&j, "cut_width_m", cfg->cut_m);
    json_num(&j, "needed_width_m", fm_needed_width_m(cfg));
    json_num(&j, "formation_width_m", fm_formation_width_m(cfg));
    json_int(&j, "dead_zone_escapes", mt->escapes);
    json_num(&j, "path_length_m", n ? path / n : NAN);
    json_num(&j, "way_length_m", cfg->way_m);
    json_num(&j, "max_time_s", cfg->max_time_s);
    json_num(&j, "smoothness", mt->n_dw ? mt->sum_dw / mt->n_dw : NAN);
    json_num(&j, "loc_err_rms_m", mt->loc_n ? sqrt(mt->loc_sum_sq / mt->loc_n) : NAN);
    json_num(&j, "loc_err_max_m", mt->loc_n ? mt->loc_max : NAN);
    json_num(&j, "sim_time_s", sim_s);
    json_num(&j, "wall_time_s", wall_s);
    json_str(&j, "exit_reason",
             pr->hung_stopped     ? "hung"
             : oc->restart_failed ? "restart_failed"
             : oc->lost_lockstep  ? "lockstep_lost"
             : mt->reached        ? "completed"
                                  : "goal_not_reached");
    json_str(&j, "failed_criteria", oc->failed);
    if (cfg->teams > 1)
        fleet_summary(&j, cfg, mt);
    json_close(&j);
}

void fm_write_plots(const fm_cfg *cfg)
{
    FILE *g = scenario_plot_open(cfg->out, 1100, 700);
    int i;
    if (!g)
        return;
    fprintf(
        g,
        "set output 'paths.png'\nset size ratio -1\nset title 'formation %s, world %s, blend %s: paths (ground truth), snapshots every 5 s'\n",
        fm_formation_name(cfg->formation), rover_world_name(cfg->world), fm_blend_name(cfg->blend));
    /* the whole world with the goal disc inside it; the key below the plot,
     * where it covers nothing */
    fprintf(g,
            "set xlabel 'x (m)'\nset ylabel 'y (m)'\nset key below horizontal\n"
            "set xrange [%g:%g]\nset yrange [%g:%g]\n",
            cfg->layout.x_min_m, cfg->layout.x_max_m, cfg->layout.y_min_m, cfg->layout.y_max_m);
    for (i = 0; i < cfg->layout.n_obst; i++) {
        const rover_obstacle *o = &cfg->layout.obst[i];
        if (o->kind == ROVER_OBST_CIRCLE) {
            fprintf(g, "set object %d circle at %g,%g size %g fc rgb 'gray40' fs solid\n", i + 1,
                    o->cx_m, o->cy_m, o->r_m);
        } else {
            const double c = cos(o->angle_rad), s = sin(o->angle_rad);
            fprintf(
                g,
                "set object %d polygon from %g,%g to %g,%g to %g,%g to %g,%g to %g,%g fc rgb 'gray40' fs solid\n",
                i + 1, o->cx_m + o->hx_m * c - o->hy_m * s, o->cy_m + o->hx_m * s + o->hy_m * c,
                o->cx_m - o->hx_m * c - o->hy_m * s, o->cy_m - o->hx_m * s + o->hy_m * c,
                o->cx_m - o->hx_m * c + o->hy_m * s, o->cy_m - o->hx_m * s - o->hy_m * c,
                o->cx_m + o->hx_m * c + o->hy_m * s, o->cy_m + o->hx_m * s - o->hy_m * c,
                o->cx_m + o->hx_m * c - o->hy_m * s, o->cy_m + o->hx_m * s + o->hy_m * c);
        }
    }
    fprintf(g, "set object %d circle at %g,%g size 0.3 fc rgb 'green' fs transparent solid 0.4\n",
            cfg->layout.n_obst + 1, cfg->layout.goal_m[0], cfg->layout.goal_m[1]);
    fprintf(g, "plot ");
    for (i = 1; i <= cfg->robots && i <= 12; i++)
        fprintf(g,
                "'truth.csv' using ($2==%d?$3:1/0):4 with points pt 7 ps 0.25 title 'robot %d', ",
                i, i);
    fprintf(
        g,
        "'snapshots.csv' using 1:2 with linespoints lc rgb 'black' pt 7 ps 0.6 dt 2 title 'formation every 5 s'\n");
    /* the time plots carry none of the world's discs and their own ranges */
    fprintf(g, "unset object\nset autoscale xy\nset key default\n");
    fprintf(
        g,
        "set output 'formation_error.png'\nset size noratio\nset title 'formation error (ground truth)'\n"
        "set xlabel 't (s)'\nset ylabel 'formation error (m)'\n"
        "set y2label 'formation type (0 line, 1 triangle, 2 column)'\n"
        "set y2range [-0.2:2.2]\nset y2tics 0,1,2\n"
        "plot 'formation_error.csv' using 1:2 with lines lw 2 title 'rms over robots', "
        "'' using 1:3 with lines title 'max over robots', '' using 1:4 axes x1y2 with steps title 'formation type'\n");
    fprintf(
        g,
        "set output 'weights.png'\nunset y2label\nunset y2tics\nset title 'behaviour weights of the lowest-id robot (normalised)'\n"
        "set ylabel 'normalised weight (1)'\nset yrange [-0.05:1.05]\n"
        "plot 'weights.csv' using 1:2 with lines title 'goal', '' using 1:3 with lines title 'formation', "
        "'' using 1:4 with lines title 'avoid', '' using 1:5 with lines title 'exception'\n");
    scenario_plot_run(cfg->out, g);
}
