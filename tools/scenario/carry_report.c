/* carry_report: the figures of a carry run (docs/method/carry.md §8) over
 * its blocks, its success criteria (carry_criteria: the run exits 0 only
 * when every one holds), and its outputs: summary.json, blocks.csv and the
 * gnuplot script for s.png, force.png and gantt.png.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "carry_scen.h"
#include "shared_run.h"

void carry_block_figures_of(carry_block_figures *f, const carry_blocks *bl, double sim_s)
{
    double fsum = 0.0;
    long fn = 0;
    int i;
    memset(f, 0, sizeof *f);
    f->latency_max_s = f->lead_max_m = NAN;
    for (i = 0; i < bl->n; i++) {
        const block *b = &bl->b[i];
        f->max_force_N = fmax(f->max_force_N, b->max_force_N);
        f->max_lurch_mps = fmax(f->max_lurch_mps, b->lurch_mps);
        fsum += b->force_sum_N;
        fn += b->force_n;
        if (b->in_s < 0.0)
            f->skipped++;
        if (b->out_s >= 0.0) /* not resumed by the end: counted to the end */
            f->resume_max_s = fmax(f->resume_max_s,
                                   (b->resume_s >= 0.0 ? b->resume_s : sim_s) - b->resume_from_s);
        if (b->force_late_n)
            f->settled_max_N = fmax(f->settled_max_N,
                                    b->force_late_sum_N / (double)b->force_late_n);
        if (b->during_t3 && b->partner_stop_s >= 0.0) {
            f->latency_max_s = isnan(f->latency_max_s)
                                   ? b->partner_stop_s - b->self_stop_s
                                   : fmax(f->latency_max_s, b->partner_stop_s - b->self_stop_s);
            f->lead_max_m = isnan(f->lead_max_m) ? b->lead_max_m
                                                 : fmax(f->lead_max_m, b->lead_max_m);
        }
    }
    f->mean_force_N = fn ? fsum / (double)fn : 0.0;
}

/* Per block: arm, link, t3, mean contact force from 0.1 s after contact
 * and once settled (BLOCK_SETTLED_S, carry_blocks.c), max. */
static void summary_blocks(json_out *j, const carry_blocks *bl)
{
    int i;
    for (i = 0; i < bl->n; i++) {
        const block *b = &bl->b[i];
        char k[64], v[64];
        snprintf(k, sizeof k, "block%d", i + 1);
        snprintf(v, sizeof v, "arm %d link %d%s", b->arm, b->link, b->during_t3 ? " t3" : "");
        json_str(j, k, v);
        snprintf(k, sizeof k, "block%d_mean_force_N", i + 1);
        json_num(j, k, b->force_n ? b->force_sum_N / (double)b->force_n : NAN);
        snprintf(k, sizeof k, "block%d_mean_force_settled_N", i + 1);
        json_num(j, k, b->force_late_n ? b->force_late_sum_N / (double)b->force_late_n : NAN);
        snprintf(k, sizeof k, "block%d_max_force_N", i + 1);
        json_num(j, k, b->max_force_N);
    }
}

/* The net's counts, the cycle times against the serial run, the run's health. */
static void summary_run(json_out *j, const carry_cfg *c, const carry_result *res,
                        const carry_result *ser)
{
    json_int(j, "invariant_violations", res->invariant_violations);
    json_int(j, "deadlocks", res->deadlocks);
    json_int(j, "replans", res->replans);
    json_num(j, "mean_cycle_s", res->mean_cycle_s);
    json_num(j, "serial_cycle_s", ser->mean_cycle_s);
    json_num(j, "pipelining_ratio", res->mean_cycle_s / ser->mean_cycle_s);
    json_num(j, "first_delivery_s", res->first_delivery_s);
    json_num(j, "sim_time_s", res->sim_s);
    json_num(j, "wall_time_s", res->wall_s + ser->wall_s);
    json_str(j, "block_detect", c->block_detect);
    json_int(j, "joint_limit_violations", res->joint_limit_violations);
    json_int(j, "joint_stop_onsets", res->joint_stop_onsets);
    json_num(j, "min_joint_range_margin_deg", res->min_range_margin_rad * 57.29577951308232);
    json_num(j, "max_joint_speed_ratio", res->max_speed_ratio);
    json_num(j, "max_sync_backtrack_m", res->max_sync_backtrack_m);
    json_int(j, "stalls", res->stalls);
    json_int(j, "faults", res->faults);
    json_int(j, "stick_resends", res->stick_resends);
}

int carry_write_summary(const carry_cfg *c, long seed, const carry_result *res,
                        const carry_result *ser, const carry_block_figures *f, const char *failed)
{
    json_out j;
    if (json_open(&j, c->out, "summary.json") != 0)
        return SCENARIO_ERR_IO;
    json_str(&j, "scenario", "carry");
    json_str(&j, "controller", c->controller_time ? "time" : "event");
    json_str(&j, "task", c->task ? c->task : "carry (shipped tables)");
    json_int(&j, "seed", seed);
    json_int(&j, "workpieces", c->workpieces);
    json_int(&j, "workpieces_detected", res->detected);
    json_int(&j, "workpieces_delivered", res->delivered);
    json_int(&j, "workpieces_dropped", res->dropped);
    json_int(&j, "blocks_requested", c->blocks->n);
    json_int(&j, "blockages", res->blockages);
    json_num(&j, "max_contact_force_N", f->max_force_N);
    json_num(&j, "mean_contact_force_blocked_N", f->mean_force_N);
    json_num(&j, "max_tool_speed_after_release_mps", f->max_lurch_mps);
    summary_blocks(&j, c->blocks);
    json_num(&j, "t3_partner_stop_latency_max_s", f->latency_max_s);
    json_num(&j, "t3_partner_lead_max_m", f->lead_max_m);
    summary_run(&j, c, res, ser);
    json_num(&j, "resume_latency_max_s", f->resume_max_s);
    json_num(&j, "max_contact_force_10ms_N", res->max_force_10ms_N);
    json_num(&j, "max_contact_force_raw_N", res->max_force_N);
    json_num(&j, "settled_force_max_N", f->settled_max_N);
    json_int(&j, "blocks_skipped", f->skipped);
    json_num(&j, "drop_rate", c->drop.rate[0] ? atof(c->drop.rate) : 0.0);
    json_int(&j, "kills", res->kills);
    json_int(&j, "restarts", res->restarts);
    json_num(&j, "hang_s", c->hang_s);
    json_int(&j, "hung_restarts", res->hung_restarts);
    json_int(&j, "leave_resends", res->leave_resends);
    json_int(&j, "rows_reissued", res->rows_reissued);
    json_int(&j, "dones_recovered", res->dones_recovered);
    json_str(&j, "exit_reason", res->exit_reason);
    json_str(&j, "failed_criteria", failed);
    json_close(&j);
    return 0;
}

void carry_write_blocks_csv(const char *dir, const carry_blocks *bl)
{
    FILE *f = scenario_fopen(dir, "blocks.csv");
    int i;
    if (!f)
        return;
    fprintf(
        f,
        "arm,link,armed_s,in_s,out_s,duration_s,during_t3,contact_s,max_force_N,mean_force_N,"
        "blocked_stop_s,partner_stop_latency_s,partner_lead_max_m,lurch_mps,mean_force_settled_N\n");
    for (i = 0; i < bl->n; i++) {
        const block *b = &bl->b[i];
        fprintf(f, "%d,%d,%.3f,%.3f,%.3f,%.3f,%d,%.3f,%.2f,%.2f,%.3f,%.4f,%.4f,%.3f,%.2f\n", b->arm,
                b->link, b->start_s, b->in_s, b->out_s, b->dur_s, b->during_t3, b->contact_s,
                b->max_force_N, b->force_n ? b->force_sum_N / (double)b->force_n : 0.0,
                b->self_stop_s, b->partner_stop_s >= 0.0 ? b->partner_stop_s - b->self_stop_s : NAN,
                b->lead_max_m, b->lurch_mps,
                b->force_late_n ? b->force_late_sum_N / (double)b->force_late_n : NAN);
    }
    fclose(f);
}

void carry_write_plots(const char *dir, const carry_blocks *bl)
{
    FILE *g = scenario_plot_open(dir, 1200, 500);
    const block *b = bl->b;
    int i;
    if (!g)
        return;
    fprintf(g, "set key outside\n");
    for (i = 0; i < bl->n; i++)
        if (b[i].in_s >= 0.0)
            fprintf(
                g,
                "set object %d rect from %.3f, graph 0 to %.3f, graph 1 fc rgb '%s' fs solid 0.25 noborder\n",
                i + 1, b[i].in_s, b[i].out_s >= 0 ? b[i].out_s : b[i].in_s + b[i].dur_s,
                b[i].arm == 1 ? "#ff8080" : "#8080ff");
    fprintf(
        g,
        "set output 's.png'\nset title 'path length s(t) of the running segment per arm (shaded: stick in, "
        "in the colour of the arm it blocks)'\n"
        "set xlabel 'sim time (s)'\nset ylabel 's (m)'\n"
        "plot 'timeseries.csv' every ::1 using 1:2 with lines lw 1.5 lc rgb '#c00000' title 'arm 1', "
        "'' every ::1 using 1:5 with lines lw 1.5 lc rgb '#0000c0' title 'arm 2'\n");
    /* the force sensor's 10 ms average, as a real stick's sensor reads it
     * (the raw 1 ms maximum is in the CSV) */
    fprintf(g,
            "set output 'force.png'\nset title 'largest link contact force, 10 ms average'\n"
            "set ylabel 'force (N)'\nset yrange [0:*]\n"
            "plot 'timeseries.csv' every ::1 using 1:15 with lines lc rgb '#c00000' title 'arm 1', "
            "'' every ::1 using 1:16 with lines lc rgb '#0000c0' title 'arm 2'\nset autoscale y\n");
    fprintf(
        g,
        "unset object\nset output 'gantt.png'\nset title 'transitions per arm (running intervals; t3, t4 involve both arms)'\n"
        "set ylabel ''\nset ytics ('arm 1' 1, 'arm 2' 2)\nset yrange [0.3:2.9]\nset xlabel 'sim time (s)'\n"
        "a1(t) = (t==1||t==2||t==3||t==4||t==6)\na2(t) = (t==3||t==4||t==5||t==7)\n"
        "plot 'transitions.csv' every ::1 using 2:(a1($1)?1:1/0):($3-$2):(0):1 with vectors nohead lw 14 lc variable notitle, "
        "'' every ::1 using 2:(a2($1)?2:1/0):($3-$2):(0):1 with vectors nohead lw 14 lc variable notitle, "
        "'' every ::1 using (($2+$3)/2):(a1($1)?1.3:1/0):(sprintf('t%%d',$1)) with labels font ',8' notitle, "
        "'' every ::1 using (($2+$3)/2):(a2($1)?2.3:1/0):(sprintf('t%%d',$1)) with labels font ',8' notitle\n");
    scenario_plot_run(dir, g);
}

int carry_criteria(const carry_cfg *c, const carry_result *r, double resume_max_s, char *buf,
                   size_t cap)
{
    const scenario_criterion k[] = {
        { strcmp(r->exit_reason, "completed") != 0, "exit_reason" },
        { r->delivered != c->workpieces, "workpieces_delivered" },
        { r->dropped != 0, "workpieces_dropped" },
        { r->joint_limit_violations != 0, "joint_limit_violations" },
        { !(r->max_speed_ratio <= 1.0), "max_joint_speed_ratio" },
        { !(r->max_sync_backtrack_m <= CARRY_SYNC_BACKTRACK_MAX_M), "max_sync_backtrack_m" },
        { !(r->max_force_10ms_N <= CRIT_FORCE_10MS_N), "max_contact_force_10ms_N" },
        { !(resume_max_s <= CRIT_RESUME_S), "resume_latency_max_s" },
        { r->stalls != 0, "stalls" },
        { r->invariant_violations != 0, "invariant_violations" },
        { r->deadlocks != 0, "deadlocks" },
    };
    return scenario_failed_criteria(k, (int)(sizeof k / sizeof k[0]), buf, cap);
}
