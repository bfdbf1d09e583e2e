/* tdsd_scen: shared glue of the TDSD scenarios (see tdsd_scen.h). */
#include "tdsd_scen.h"
#include "tdsd_ode.h"
#include "daemon.h"
#include "options.h"
#include <math.h>
#include <string.h>

#define RAD2DEG (180.0 / 3.14159265358979323846)

static const char *const plants[] = { "kin", "ode", NULL };

int tdsd_scen_args(tdsd_scen *s, int argc, char **argv, const tdsd_scen_usage *u)
{
    const option_entry table[] = {
        { .name = "method",
          .type = OPTION_CHOICE,
          OPTION_AT(tdsd_scen, method_index),
          .choices = u->methods,
          .help = u->method_help,
          .def = u->methods[0] },
        { .name = "plant",
          .type = OPTION_CHOICE,
          OPTION_AT(tdsd_scen, plant_ode),
          .choices = plants,
          .help =
              "kin: integrate dq at 1 kHz; ode: tandem-sim + tandem-arm tracking ARM1_JOINT_REF in lockstep",
          .def = "kin" },
        { .name = "servo-hz",
          .type = OPTION_DOUBLE,
          OPTION_AT(tdsd_scen, servo_hz),
          .min = 0.5,
          .max = 50.0,
          .meta = "HZ",
          .help = "ode: tandem-arm joint servo bandwidth",
          .def = "15" },
        { .name = "out",
          .type = OPTION_STRING,
          OPTION_AT(tdsd_scen, out),
          OPTION_SEEN(tdsd_scen, out_given),
          .required = 1,
          .meta = "DIR",
          .help = "output directory" },
        OPTION_HELP_ENTRY(0),
        { .name = NULL }
    };
    char name[64];
    option_program prog = { .name = name,
                            .usage = u->usage,
                            .epilog = u->epilog,
                            .groups = { { table, s } },
                            .n_groups = 1 };
    int rc;
    snprintf(name, sizeof name, "tandem-scenario %s", s->name);
    s->method_index = 0;
    s->plant_ode = 0;
    s->out = NULL;
    s->out_given = 0;
    s->servo_hz = 15.0;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return rc == OPTIONS_EXIT ? 1 : TDSD_SCEN_ERR_ARG;
    s->method = u->methods[s->method_index];
    return scenario_mkdir(s->out) == 0 ? 0 : TDSD_SCEN_ERR_IO;
}

/* ---- series.csv ----------------------------------------------------------- */

typedef struct csv_ctx {
    FILE *f;
    const arm_model *model;
} csv_ctx;

static void csv_header(FILE *f)
{
    int i;
    fputs("t_s,s,lambda,Q1,Q2,pos_err_mm,ex_mm,ey_mm,ez_mm,ori_err_deg,tilt_deg", f);
    for (i = 1; i <= ARM_NJ; i++)
        fprintf(f, ",q%d_deg", i);
    for (i = 1; i <= ARM_NJ; i++)
        fprintf(f, ",dq%d_ratio", i);
    fputs(",demand_ratio,wrist_axis_mm,sigma_min_J,time_scaled\n", f);
}

static void csv_row(void *user, const tdsdrun_sample *s, const double q[ARM_NJ])
{
    const csv_ctx *c = user;
    double demand = 0.0;
    int i;
    fprintf(c->f, "%.4f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f,%.5f", s->t_s, s->s, s->lambda,
            s->Q1, s->Q2, s->pos_err_m * 1e3, (s->p_d_m[0] - s->p_m[0]) * 1e3,
            (s->p_d_m[1] - s->p_m[1]) * 1e3, (s->p_d_m[2] - s->p_m[2]) * 1e3,
            s->ori_err_rad * RAD2DEG, s->tilt_rad * RAD2DEG);
    for (i = 0; i < ARM_NJ; i++)
        fprintf(c->f, ",%.4f", q[i] * RAD2DEG);
    for (i = 0; i < ARM_NJ; i++) {
        const double r = fabs(s->dq_demand_radps[i]) / c->model->qd_max_radps[i];
        fprintf(c->f, ",%.5f", s->dq_radps[i] / c->model->qd_max_radps[i]);
        if (r > demand)
            demand = r;
    }
    fprintf(c->f, ",%.5g,%.4f,%.6g,%d\n", demand, s->wrist_axis_m * 1e3, s->sigma_min_J,
            s->time_scaled);
}

int tdsd_scen_run(tdsd_scen *s)
{
    csv_ctx cc;
    const double wall0 = scenario_wall_s();
    const double t_max = 4.0 * tdsdrun_path_length_s(&s->path) + 10.0;
    cc.f = scenario_fopen(s->out, "series.csv");
    cc.model = s->cfg.model;
    if (!cc.f)
        return TDSD_SCEN_ERR_IO;
    csv_header(cc.f);
    tdsdrun_metrics_init(&s->m, s->cfg.region_m);
    if (s->plant_ode) {
        tdsd_ode_opts o;
        /* the simulated drives stop at qd_max: a plan at the limit leaves
         * the joint servo nothing to catch up with (tandem-arm's TDSD
         * segments plan at 0.9 too) */
        s->cfg.speed_frac = TDSD_ODE_SPEED_FRAC;
        o.out_dir = s->out;
        o.servo_hz = s->servo_hz;
        o.settle_s = 0.3;
        o.t_max_s = t_max;
        s->duration_s = tdsd_ode_run(&s->cfg, &s->path, s->q0_rad, &o, &s->m, csv_row, &cc);
    } else {
        s->duration_s = tdsdrun_kin(&s->cfg, &s->path, s->q0_rad, t_max, &s->m, csv_row, &cc);
    }
    fclose(cc.f);
    s->wall_s = scenario_wall_s() - wall0;
    return s->duration_s < 0.0 ? TDSD_SCEN_ERR_RUN : 0;
}

/* ---- summary.json --------------------------------------------------------- */

int tdsd_scen_criteria(const tdsd_scen *s, char *buf, size_t cap)
{
    const tdsdrun_metrics *m = &s->m;
    const double pos_tol_m = s->plant_ode ? TDSD_POS_TOL_ODE_M : TDSD_POS_TOL_KIN_M;
    const scenario_criterion k[] = {
        { !(m->max_pos_err_m <= pos_tol_m), "max_pos_err_mm" },
        { m->joint_limit_violations != 0, "joint_limit_violations" },
        { !(m->max_speed_ratio <= 1.0 + 1e-9), "max_joint_speed_ratio" },
        { !strcmp(s->name, "liquid") && !(m->max_tilt_rad <= TDSD_TILT_TOL_RAD), "max_tilt_deg" },
    };
    return scenario_failed_criteria(k, (int)(sizeof k / sizeof k[0]), buf, cap);
}

int tdsd_scen_finish(const tdsd_scen *s, json_out *j)
{
    char failed[128];
    const int n = tdsd_scen_criteria(s, failed, sizeof failed);
    json_str(j, "exit_reason", "completed");
    json_str(j, "failed_criteria", failed);
    json_close(j);
    return n;
}

int tdsd_scen_exit(const tdsd_scen *s)
{
    char failed[128];
    const int n = tdsd_scen_criteria(s, failed, sizeof failed);
    if (n) {
        printf("%s: FAILED %d criteria: %s\n", s->name, n, failed);
        return 3;
    }
    printf("%s: all criteria met\n", s->name);
    return 0;
}

void tdsd_scen_summary(const tdsd_scen *s, json_out *j)
{
    const tdsdrun_metrics *m = &s->m;
    char key[48];
    int i, worst = -1;
    json_str(j, "scenario", s->name);
    json_str(j, "method", s->method);
    json_str(j, "plant", s->plant_ode ? "ode" : "kin");
    json_str(j, "arm_model", s->cfg.model->name);
    json_num(j, "max_pos_err_mm", m->max_pos_err_m * 1e3);
    json_num(j, "rms_pos_err_mm", m->n ? sqrt(m->sum_sq_pos_err / (double)m->n) * 1e3 : NAN);
    json_num(j, "max_ori_err_deg", m->max_ori_err_rad * RAD2DEG);
    json_num(j, "max_tilt_deg", m->max_tilt_rad * RAD2DEG);
    json_num(j, "max_joint_speed_ratio", m->max_speed_ratio);
    json_num(j, "max_demand_speed_ratio", m->max_demand_ratio);
    json_num(j, "min_q1", m->min_Q1);
    json_num(j, "t_min_q1_s", m->t_min_Q1_s);
    json_num(j, "min_q1_outside_region", m->min_Q1_outside);
    json_num(j, "region_mm", s->cfg.region_m * 1e3);
    json_num(j, "t_region_in_s", m->t_region_in_s);
    json_num(j, "t_region_out_s", m->t_region_out_s);
    json_num(j, "min_wrist_axis_mm", m->min_wrist_axis_m * 1e3);
    json_num(j, "t_ori_recovered_s", m->t_ori_recovered_s);
    json_num(j, "ori_err_end_deg", m->ori_err_end_rad * RAD2DEG);
    json_num(j, "tilt_end_deg", m->tilt_end_rad * RAD2DEG);
    json_int(j, "joint_limit_violations", m->joint_limit_violations);
    for (i = 0; i < ARM_NJ; i++) {
        snprintf(key, sizeof key, "q%d_excess_deg", i + 1);
        json_num(j, key, m->max_excess_rad[i] * RAD2DEG);
        if (m->max_excess_rad[i] > 0.0 &&
            (worst < 0 || m->max_excess_rad[i] > m->max_excess_rad[worst]))
            worst = i;
    }
    if (worst >= 0) {
        snprintf(key, sizeof key, "q%d", worst + 1);
        json_str(j, "worst_joint_out_of_range", key);
    } else {
        json_str(j, "worst_joint_out_of_range", "none");
    }
    for (i = 0; i < ARM_NJ; i++) {
        snprintf(key, sizeof key, "q%d_min_deg", i + 1);
        json_num(j, key, m->q_lo_rad[i] * RAD2DEG);
        snprintf(key, sizeof key, "q%d_max_deg", i + 1);
        json_num(j, key, m->q_hi_rad[i] * RAD2DEG);
    }
    json_num(j, "min_path_rate", m->min_lambda);
    json_int(j, "resolver_errors", m->resolver_errors);
    json_num(j, "nominal_duration_s", tdsdrun_path_length_s(&s->path));
    json_num(j, "duration_s", s->duration_s);
    json_num(j, "K_p", s->cfg.K_p);
    json_num(j, "K_o", s->cfg.K_o);
    if (s->plant_ode)
        json_num(j, "servo_hz", s->servo_hz);
    json_num(j, "wall_s", s->wall_s);
}

/* ---- plots ---------------------------------------------------------------- */

int tdsd_scen_plots(const tdsd_scen *s, const char *title)
{
    FILE *f = scenario_fopen(s->out, "plots.gp");
    int i;
    if (!f)
        return TDSD_SCEN_ERR_IO;
    fprintf(f, "set datafile separator ','\nset key outside right\nset grid\n"
               "set xlabel 't (s)'\n");
    /* Fig. 4: tool position and orientation errors */
    fprintf(
        f,
        "set terminal pngcairo size 900,700\nset output 'fig4_errors.png'\n"
        "set multiplot layout 2,1 title '%s: tool errors (%s, %s plant)'\n"
        "set ylabel 'position error (mm)'\n"
        "plot 'series.csv' u 1:7 w l t 'e_x', '' u 1:8 w l t 'e_y', '' u 1:9 w l t 'e_z', "
        "'' u 1:6 w l lw 2 t '|e_p|'\n"
        "set ylabel 'orientation error (deg)'\n"
        "plot 'series.csv' u 1:10 w l lw 2 t 'angle(R_d R^T)', '' u 1:11 w l t 'tool-axis tilt'\n"
        "unset multiplot\n",
        title, s->method, s->plant_ode ? "ode" : "kin");
    /* Fig. 5: joint angles */
    fprintf(f,
            "set terminal pngcairo size 900,500\nset output 'fig5_joints.png'\n"
            "set title '%s: joint angles (%s, %s plant)'\nset ylabel 'q (deg)'\nplot ",
            title, s->method, s->plant_ode ? "ode" : "kin");
    for (i = 0; i < ARM_NJ; i++)
        fprintf(f, "%s'series.csv' u 1:%d w l lw 2 t 'q%d'", i ? ", " : "", 12 + i, i + 1);
    /* Fig. 6: Q1 (and the path rate) */
    fprintf(f,
            "\nset output 'fig6_q1.png'\nset title '%s: speed distribution (%s, %s plant)'\n"
            "set ylabel 'factor'\nset yrange [-0.05:1.1]\n"
            "set y2label 'wrist centre to joint-1 axis (mm)'\nset y2tics\n"
            "plot 'series.csv' u 1:4 w l lw 2 t 'Q1', '' u 1:3 w l t 'path rate lambda', "
            "'' u 1:25 axes x1y2 w l dt 2 t 'wrist-axis distance'\n"
            "unset y2label\nunset y2tics\nset autoscale y\n",
            title, s->method, s->plant_ode ? "ode" : "kin");
    /* Fig. 8: every joint against its range */
    fprintf(f,
            "set terminal pngcairo size 1000,900\nset output 'fig8_joint_ranges.png'\nunset title\n"
            "set multiplot layout 3,2 title '%s: joints against their ranges (%s, %s plant)'\n",
            title, s->method, s->plant_ode ? "ode" : "kin");
    for (i = 0; i < ARM_NJ; i++) {
        const double lo = s->cfg.model->q_min_rad[i] * RAD2DEG,
                     hi = s->cfg.model->q_max_rad[i] * RAD2DEG;
        fprintf(f,
                "set ylabel 'q%d (deg)'\nset yrange [%g:%g]\n"
                "plot 'series.csv' u 1:%d w l lw 2 t 'q%d', %g w l dt 2 lc rgb 'red' t 'min', "
                "%g w l dt 2 lc rgb 'red' t 'max'\n",
                i + 1, lo - 0.25 * (hi - lo), hi + 0.25 * (hi - lo), 12 + i, i + 1, lo, hi);
    }
    fprintf(f, "unset multiplot\n");
    fclose(f);
    return scenario_gnuplot(s->out, "plots.gp");
}
