/* tandem-sim: the ODE simulator daemon (docs/method/lockstep.md §1, §3).
 * Owns the world, the clock and every model's state (sim_app.h); models
 * (arms, workpieces, rovers) plug in through sim_model_ops. This file: the
 * command line, the checks of the constant tables the models are built
 * from, start-up and shutdown; the step and the timing modes are in
 * sim_loop.c.
 */
#include "sim_app.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "arm_model.h"
#include "cell.h"
#include "formation.h"
#include "options.h"
#include "sonar.h"
#include "world_file.h"

/* --friction V,C: both in [0, 100] */
static int parse_friction(const char *prog, void *dest, char *value)
{
    sim_config *cfg = dest;
    char *comma = strchr(value, ',');
    if (!comma) {
        fprintf(stderr, "%s: --friction: expected VISCOUS,COULOMB\n", prog);
        return OPTIONS_ERR_SAID;
    }
    *comma = '\0';
    if (parse_double_opt(prog, "--friction (viscous)", value, 0.0, 100.0,
                         &cfg->arm_friction_viscous) < 0 ||
        parse_double_opt(prog, "--friction (Coulomb)", comma + 1, 0.0, 100.0,
                         &cfg->arm_friction_coulomb) < 0)
        return OPTIONS_ERR_SAID;
    return 0;
}

/* --arm-q0 Q1,..,Q6: six angles in [-10, 10] rad (the joint ranges are
 * checked once the arm model is known) */
static int parse_q0(const char *prog, void *dest, char *value)
{
    sim_config *cfg = dest;
    char *tok = strtok(value, ",");
    int i;
    for (i = 0; i < ARM_NJ; i++, tok = strtok(NULL, ","))
        if (!tok ||
            parse_double_opt(prog, "--arm-q0", tok, -10.0, 10.0, &cfg->arm1_q0_rad[i]) < 0) {
            if (!tok)
                fprintf(stderr, "%s: --arm-q0: expected 6 comma-separated angles (rad)\n", prog);
            return OPTIONS_ERR_SAID;
        }
    if (tok) {
        fprintf(stderr, "%s: --arm-q0: more than 6 angles\n", prog);
        return OPTIONS_ERR_SAID;
    }
    cfg->arm1_q0_set = 1;
    return 0;
}

/* --rover-far: how a robot far from everything is stepped (index = cfg.rover_far_kinematic) */
static const char *const rover_far_names[] = { "ode", "kinematic", NULL };

static const option_entry sim_options[] = {
    { .name = "seed",
      .type = OPTION_INT,
      OPTION_AT(sim_app, w.seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "S",
      .help = "random seed (noise, workpiece stream)",
      .def = "1" },
    { .name = "steps",
      .type = OPTION_INT,
      OPTION_AT(sim_app, max_steps),
      .min = 0,
      .max = 2000000000.0,
      .meta = "N",
      .help = "stop after N steps (0 = run until stopped)",
      .def = "0" },
    { .name = "expect",
      .type = OPTION_INT,
      OPTION_AT(sim_app, expect),
      .min = 0,
      .max = SIM_MAX_PARTICIPANTS,
      .meta = "N",
      .help = "lockstep: wait for N controllers before the first step",
      .def = "0" },
    { .name = "timeout-ms",
      .type = OPTION_DOUBLE,
      OPTION_AT(sim_app, w.lockstep_timeout_s),
      .min = 10.0,
      .max = 600000.0,
      .scale = 1e-3,
      .meta = "MS",
      .help = "lockstep: drop a controller silent this long whose process is gone or "
              "ran without answering (a live, slow or stopped one is waited for)",
      .def = "2000" },
    { .name = "no-arms",
      .type = OPTION_FLAG,
      OPTION_AT(sim_app, no_arms),
      .help = "leave the PUMA pair out" },
    { .name = "workpieces",
      .type = OPTION_INT,
      OPTION_AT(sim_app, cfg.workpieces),
      .min = 0,
      .max = 100000,
      .meta = "N",
      .help = "workpieces to feed (0 = endless)",
      .def = "0" },
    { .name = "handover-stand",
      .type = OPTION_FLAG,
      OPTION_AT(sim_app, cfg.handover_stand),
      .help =
          "a stand on the table with two places, under the hand-over and 0.12 m behind it: a workpiece set "
          "down at either rests on it until an arm takes it (the buffer of tasks/carry_buffer, "
          "docs/tasks.md §6)" },
    { .name = "magazine",
      .type = OPTION_FLAG,
      OPTION_AT(sim_app, cfg.magazine),
      .help =
          "arm 2's magazine on the table: it presents a bar (one of --workpieces) when arm 2 comes "
          "above it empty (tasks/carry_solo, docs/tasks.md §8)" },
    { .name = "friction",
      .type = OPTION_CALL,
      OPTION_AT(sim_app, cfg),
      .call = parse_friction,
      .meta = "V,C",
      .help = "arm joint viscous (N m s/rad) and Coulomb (N m) friction, each 0..100",
      .def = "0,0" },
    { .name = "rovers",
      .type = OPTION_INT,
      OPTION_AT(sim_app, cfg.rovers),
      .min = 0,
      .max = ROVER_WORLD_MAX_ROBOTS,
      .meta = "N",
      .help = "number of Pioneer robots",
      .def = "0" },
    { .name = "world",
      .type = OPTION_CHOICE,
      OPTION_AT(sim_app, world),
      .choices = options_world_names,
      .meta = "NAME",
      .help = "rover world",
      .def = "open" },
    WORLD_FILE_OPTIONS(sim_app, wopt),
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(sim_app, cfg.rover_formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .meta = "F",
      .help = "rover team's start formation",
      .def = "line" },
    FLEET_OPTIONS(sim_app, cfg.rover_teams, cfg.rover_per_team, cfg.rover_team_goals),
    { .name = "rover-batch",
      .type = OPTION_FLAG,
      OPTION_AT(sim_app, cfg.rover_batch),
      .help =
          "all robots' sensors in one message per tick (ROVERS_SENSORS, ROVERS_BEACONS; a fleet "
          "of more than 128 in several) instead of ROVERk_SENSORS/_SONAR/_BEACONS" },
    { .name = "rover-far",
      .type = OPTION_CHOICE,
      OPTION_AT(sim_app, cfg.rover_far_kinematic),
      .choices = rover_far_names,
      .meta = "HOW",
      .help = "a robot clear of everything: ode, the full model; kinematic, moved by its wheels "
              "outside the solver (a large fleet's physics; docs/formation.md, far robots)",
      .def = "ode" },
    { .name = "arm-model",
      .type = OPTION_CHOICE,
      OPTION_AT(sim_app, arm_model),
      .choices = options_arm_model_names,
      .meta = "NAME",
      .help = "arm 1's model (seed002: seed 002's arm)",
      .def = "puma560" },
    { .name = "arm-q0",
      .type = OPTION_CALL,
      OPTION_AT(sim_app, cfg),
      .call = parse_q0,
      .meta = "Q1,..,Q6",
      .help = "arm 1 starts at these joint angles (rad, -10..10) instead of home" },
    { .name = NULL }
};

static int parse_args(sim_app *app, int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-sim",
        .usage = "usage: tandem-sim [options]\n"
                 "ODE simulator of the tandem world: two PUMA 560 arms with a table,\n"
                 "workpieces, vision camera and stick; Pioneer robots with sonar and\n"
                 "beacons. Steps at 1 kHz on the wall clock, or in lockstep.\n\n",
        .groups = { { sim_options, app }, { options_daemon_common, &app->w.d } },
        .n_groups = 2,
    };
    int rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return rc;
    if (app->no_arms)
        app->cfg.arms = 0;
    snprintf(app->cfg.rover_world, sizeof app->cfg.rover_world, "%s",
             options_world_names[app->world]);
    app->cfg.rover_world_file = app->wopt.file;
    if (app->cfg.rover_teams > 1) {
        if ((long)app->cfg.rover_teams * app->cfg.rover_per_team > ROVER_WORLD_MAX_ROBOTS) {
            fprintf(stderr,
                    "tandem-sim: --teams %d --robots-per-team %d: more than %d robots "
                    "(ROVER_WORLD_MAX_ROBOTS)\n",
                    app->cfg.rover_teams, app->cfg.rover_per_team, ROVER_WORLD_MAX_ROBOTS);
            return OPTIONS_ERR_ARG;
        }
        app->cfg.rovers = app->cfg.rover_teams * app->cfg.rover_per_team;
    }
    app->cfg.rover_start = app->wopt.start;
    app->cfg.rover_goal = app->wopt.goal;
    if (app->arm_model >= 0)
        app->cfg.arm1_model = arm_model_by_name(options_arm_model_names[app->arm_model]);
    if (app->cfg.arm1_q0_set &&
        arm_q_outside_limits(app->cfg.arm1_model ? app->cfg.arm1_model : &arm_model_puma560,
                             app->cfg.arm1_q0_rad)) {
        fprintf(stderr, "tandem-sim: --arm-q0: outside arm 1's joint ranges\n");
        return OPTIONS_ERR_ARG;
    }
    return 0;
}

/* A constant table refused by its validator: said with the table and the
 * code's name. The module's codes are the first n_codes of -1 ARG,
 * -2 NONFINITE, -3 RANGE, -4 INCONSISTENT (arm_model.h and cell.h have all
 * four, sonar.h ARG alone). */
static int table_refused(const char *table, const char *module, int n_codes, int rc)
{
    static const char *const why[] = { "ARG", "NONFINITE", "RANGE", "INCONSISTENT" };
    const char *name = rc <= -1 && rc >= -n_codes ? why[-rc - 1] : "?";
    fprintf(stderr, "tandem-sim: %s refused by its validator: %s_ERR_%s (%d)\n", table, module,
            name, rc);
    return rc;
}

/* The constant tables the models are built from: the arm models of the
 * pair, the cell layout, the robots' sonar model. */
static int check_tables(const sim_app *app)
{
    sonar_model sm;
    char what[64];
    int k, rc;
    for (k = 0; k < SIM_ARMS; k++) {
        const arm_model *m = sim_arms_model(&app->cfg, k);
        snprintf(what, sizeof what, "arm %d's model '%s'", k + 1, m->name ? m->name : "");
        if ((rc = arm_model_validate(m)) != 0)
            return table_refused(what, "ARM_MODEL", 4, rc);
    }
    if ((rc = cell_layout_validate(&cell_default)) != 0)
        return table_refused("cell layout cell_default", "CELL", 4, rc);
    sim_rovers_sonar_model(&sm);
    if ((rc = sonar_model_validate(&sm)) != 0)
        return table_refused("the Pioneer sonar model", "SONAR", 1, rc);
    return 0;
}

/* A world file (or --start, --goal) that cannot give the team's layout:
 * said, before anything starts. */
static int world_refused(sim_app *app)
{
    rover_world_config *w = malloc(sizeof *w);
    rover_fleet f;
    int rc;
    app->wopt.world = rover_world_id(app->cfg.rover_world);
    if (!w)
        return 1;
    rc = world_opts_fleet_layout(w, &f, &app->wopt, app->cfg.rovers, app->cfg.rover_teams,
                                 app->cfg.rover_per_team, app->cfg.rover_team_goals,
                                 app->cfg.rover_formation, "tandem-sim");
    free(w);
    return rc != 0;
}

/* setup: do not run, exit with *status */
#define SETUP_EXIT (-1)

/* Defaults, the command line, the tables, the models in step order. 0 to
 * run; SETUP_EXIT (--help, a bad option, a bad table). */
static int setup(sim_app *app, int argc, char **argv, int *status)
{
    int rc;
    daemon_defaults(&app->w.d, "tandem-sim", SIM_DT_S);
    app->w.seed = 1;
    app->w.lockstep_timeout_s = 2.0;
    app->cfg.arms = 1;
    snprintf(app->cfg.rover_world, sizeof app->cfg.rover_world, "open");
    app->cfg.rover_formation = FORMATION_LINE;
    app->cfg.rover_teams = 1;
    app->cfg.rover_per_team = 3;
    app->cfg.rover_team_goals = ROVER_FLEET_GOALS_CROSS;
    app->arm_model = -1;
    rc = parse_args(app, argc, argv);
    if (rc < 0) {
        *status = options_exit_status(rc);
        return SETUP_EXIT;
    }
    if (check_tables(app) != 0) {
        *status = 2;
        return SETUP_EXIT;
    }
    if (app->cfg.rovers > 0 && world_refused(app)) {
        *status = 2;
        return SETUP_EXIT;
    }
    app->w.d.fleet_robots = app->cfg.rovers;
    app->w.lockstep = app->w.d.lockstep;
    app->w.d.period_s = SIM_DT_S;
    app->w.d.clock_source = 1;
    app->workpieces.arms = &app->arms;
    if (app->cfg.arms) {
        app->models[app->n_models++] = (sim_model){ &sim_arms_ops, &app->arms };
        /* after the arms: needs their joints */
        app->models[app->n_models++] = (sim_model){ &sim_workpieces_ops, &app->workpieces };
    }
    if (app->cfg.rovers > 0)
        app->models[app->n_models++] = (sim_model){ &sim_rovers_ops, &app->rovers };
    return 0;
}

int main(int argc, char **argv)
{
    static sim_app the_app; /* static: too large for the stack */
    sim_app *app = &the_app;
    int status = 0;
    if (setup(app, argc, argv, &status) != 0)
        return status;
    auth_bus_identity(&app->w.d.bus, AUTH_ROLE_SIM, 0, 0);
    daemon_queue_for_burst(&app->w.d, app->cfg.rovers); /* a fleet's commands, acks */
    if (daemon_start(&app->w.d) != 0)
        return 1;
    sim_subscribe(app);
    if (sim_build_world(app) != 0)
        return 1;
    if (app->w.lockstep)
        sim_run_lockstep(app);
    else
        sim_run_realtime(app);
    printf("tandem-sim: stopped at step %lld state_hash=%016llx rejected=%lld lcm_renewals=%lld "
           "reannounced=%lld\n",
           (long long)app->w.step, (unsigned long long)sim_app_state_hash(app),
           (long long)app->w.d.msgs.rejected, (long long)app->w.d.names.renewals,
           (long long)app->w.lockstep_reannounced);
    fflush(stdout);
    sim_publish_status(app);
    sim_destroy_world(app);
    daemon_finish(&app->w.d);
    return 0;
}
