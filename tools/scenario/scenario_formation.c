/* tandem-scenario formation: the seed-003 Pioneer team
 * (docs/method/formation.md, §6): the options and the driver.
 *
 * Spawns tandem-sim (lockstep, rovers only) and the rover daemons as
 * children on a private LCM bus (formation_procs.c), registers itself as a
 * lockstep participant (every 50 steps) so it sees the simulator's ground
 * truth deterministically (formation_bus.c), and writes DIR/summary.json,
 * CSV time series and PNG plots (formation_report.c). Every metric comes
 * from ROVER_TRUTH (ground truth, formation_metrics.c) except the protocol
 * counts (formation changes, dead-zone escapes), which are what the robots
 * did, read from their ROVERk_STATE.
 */
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "formation_scen.h"
#include "auth.h"
#include "shared_run.h"
#include "formation.h"
#include "rover_ctl.h"
#include "options.h"

/* The run's state: large (every robot's last states), so not on the stack. */
static fm_run F;

/* --kill K:T */
static int option_kill(const char *prog, void *dest, char *v)
{
    fm_cfg *f = dest;
    char *e;
    long k = strtol(v, &e, 10);
    double t;
    (void)prog;
    if (*e != ':')
        return OPTIONS_ERR_VALUE;
    t = strtod(e + 1, &e);
    if (*e || k < 1 || !isfinite(t) || t < 0)
        return OPTIONS_ERR_VALUE;
    f->kill_id = (int)k;
    f->kill_t_s = t;
    return 0;
}

/* --fault kill:roverK:T[:R], repeatable */
static int option_fault(const char *prog, void *dest, char *v)
{
    fm_cfg *cfg = dest;
    scenario_fault *f = &cfg->faults[cfg->n_faults];
    char *e = NULL;
    long k;
    if (cfg->n_faults >= SCENARIO_MAX_FAULTS || scenario_parse_fault(f, v) != 0)
        return OPTIONS_ERR_SAID;
    k = strncmp(f->daemon, "rover", 5) == 0 ? strtol(f->daemon + 5, &e, 10) : 0;
    if (k < 1 || k > FM_MAX || *e) {
        fprintf(stderr, "%s: --fault: '%s' is not roverK\n", prog, f->daemon);
        return OPTIONS_ERR_SAID;
    }
    f->slot = (int)k;
    cfg->n_faults++;
    return 0;
}

static const char *const blends[] = { "weighted", "subsumption", "vecsum", NULL };
static const char *const laws[] = { "seed", "kanayama", NULL };
static const char *const ref_headings[] = { "mean", "goal", NULL };
static const char *const goal_paths[] = { "map", "direct", NULL };
static const char *const procs[] = { "separate", "single", NULL };
static const char *const links[] = { "robot", "batch", NULL };
static const char *const rover_far[] = { "ode", "kinematic", NULL }; /* tandem-sim --rover-far */

static const option_entry formation_table[] = {
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .help = "the team's formation",
      .def = "line" },
    { .name = "world",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, world),
      .choices = fm_world_names,
      .values = fm_world_values,
      .help = "the rover world (random: generated, see --world-kind, --world-seed)",
      .def = "open" },
    { .name = "world-kind",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, world_kind),
      .choices = fm_world_kinds,
      .help = "--world random: clutter, traps (U, V, L pockets), corridor or a mix",
      .def = "mixed" },
    { .name = "world-seed",
      .type = OPTION_INT,
      OPTION_AT(fm_cfg, world_seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "W",
      .help = "--world random: the world's seed (the noise has --seed)",
      .def = "1" },
    { .name = "world-size",
      .type = OPTION_STRING,
      OPTION_AT(fm_cfg, world_size),
      .meta = "WxH",
      .help = "--world random: the map's size (m)",
      .def = "30x20" },
    WORLD_FILE_OPTIONS(fm_cfg, wopt),
    { .name = "blend",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, blend),
      .choices = blends,
      .help = "how the behaviours' outputs are blended",
      .def = "weighted" },
    { .name = "formation-law",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, law_kanayama),
      .choices = laws,
      .help = "the formation behaviour flown",
      .def = "seed" },
    { .name = "goal-path",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, goal_direct),
      .choices = goal_paths,
      .help = "map: the robots steer by the world's navigation function where the goal is not in "
              "plain view; direct: for the goal straight, as the seed (the dead zone's escape)",
      .def = "map" },
    { .name = "ref-heading",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, ref_goal),
      .choices = ref_headings,
      .help =
          "the team reference heading: goal (bearing of the goal) or mean (the seed's mean of the headings)",
      .def = "goal" },
    { .name = "ref-arrive",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_cfg, ref_arrive_m),
      .min = 0.0,
      .max = 100.0,
      .meta = "M",
      .help = "within M of the goal the team reference turns onto the goal's slot frame and its "
              "speed fades (0: off)",
      .def = "0" },
    { .name = "localize",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, localize_off),
      .choices = options_on_off,
      .help = "robots fuse the world's LED landmarks",
      .def = "on" },
    { .name = "lockstep-timeout-ms",
      .type = OPTION_INT,
      OPTION_AT(fm_cfg, timeout_ms_given),
      .min = 100,
      .max = 3600000,
      .meta = "MS",
      .help =
          "the simulator drops a participant silent this long (wall) "
          "whose process is gone or hangs; one alive and slow (a loaded machine) or stopped is waited for, so the run "
          "stays the deterministic one",
      .def = "10000" },
    { .name = "robots",
      .type = OPTION_INT,
      OPTION_AT(fm_cfg, robots),
      .min = 1,
      .max = FM_MAX,
      .meta = "N",
      .help = "team size",
      .def = "3" },
    FLEET_OPTIONS(fm_cfg, teams, per_team, team_goals),
    { .name = "seed",
      .type = OPTION_INT,
      OPTION_AT(fm_cfg, seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "S",
      .help = "noise seed",
      .def = "1" },
    { .name = "kill",
      .type = OPTION_CALL,
      OPTION_ALL(fm_cfg),
      .call = option_kill,
      .meta = "K:T",
      .help = "kill robot K (its process and its body) at sim time T s" },
    { .name = "fault",
      .type = OPTION_CALL,
      OPTION_ALL(fm_cfg),
      .call = option_fault,
      .repeatable = 1,
      .meta = "kill:roverK:T[:R]",
      .help =
          "kill robot K's process (SIGKILL; its body stands) at T s of "
          "simulated time and, with R, start it again at R s: it resumes from its journal. Deterministic (the "
          "lockstep is held while it rejoins)" },
    { .name = "hang-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_cfg, hang_s),
      .min = 0.0,
      .max = 3600.0,
      .meta = "S",
      .help =
          "a child alive but without health messages for S s of wall time is hung: killed "
          "(SIGKILL); a rover's process is restarted from its journal (every robot keeps one), the simulator or "
          "the one process of --procs single stops the run; 0: not watched",
      .def = "5" },
    { .name = "drop-rate",
      .type = OPTION_STRING,
      OPTION_AT(fm_cfg, drop_arg),
      .meta = "P",
      .help =
          "fault injection: every daemon drops received messages with probability P (0 <= P < 1, "
          "deterministic for the seed); the run is the same as without loss, only slower",
      .def = "0" },
    { .name = "procs",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, single),
      .choices = procs,
      .help = "separate: one tandem-rover per robot; single: one process hosting all",
      .def = "separate up to 10 robots" },
    { .name = "hosts",
      .type = OPTION_INT,
      OPTION_AT(fm_cfg, hosts),
      .min = 1,
      .max = AUTH_FLEET_HOSTS_MAX,
      .meta = "H",
      .help =
          "with --procs single: the robots split over H tandem-rover processes (--id A-B, whole "
          "teams each, as even as the teams allow), as H machines would host them; the same run",
      .def = "1" },
    { .name = "host-netns",
      .type = OPTION_STRING,
      OPTION_AT(fm_cfg, host_netns),
      .meta = "P",
      .help = "rover host h (1..H) runs in the network namespace P<h> (ip netns add P<h>; needs "
              "root and an --lcm-url with ttl=1 that reaches it): a host on another machine",
      .def = "this namespace" },
    { .name = "link",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, batch),
      .choices = links,
      .help =
          "robot: ROVERk_* channels per robot; batch: ROVERS_*, one message per tick for all robots. "
          "Same run either way",
      .def = "batch with --procs single, robot otherwise" },
    { .name = "rover-far",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_cfg, far_kinematic),
      .choices = rover_far,
      .meta = "HOW",
      .help = "tandem-sim --rover-far: a robot clear of everything in the full ODE model (ode) or "
              "moved by its wheels outside the solver (kinematic: a large fleet's physics)",
      .def = "ode" },
    { .name = "max-time",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_cfg, max_time_s),
      .min = 0.0,
      .max = 3600.0,
      .meta = "S",
      .help = "give up after S simulated seconds (S > 0); not given: 60 s plus the shortest "
              "way for the robot body from the start to the goal at 0.2 m/s",
      .def = "from the way" },
    { .name = "lcm-url",
      .type = OPTION_STRING,
      OPTION_AT(fm_cfg, url),
      .meta = "URL",
      .help = "bus for the children",
      .def = "a private udpm port" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(fm_cfg, out),
      OPTION_SEEN(fm_cfg, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "output directory" },
    OPTION_HELP_ENTRY('h'),
    { .name = NULL }
};

static int parse(fm_cfg *cfg, int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-scenario formation",
        .usage =
            "usage: tandem-scenario formation [options] --out DIR\n"
            "Pioneer team to the goal in formation (seed 003), lockstep, ground-truth metrics.\n\n",
        .groups = { { formation_table, cfg } },
        .n_groups = 1,
    };
    rover_ctl_params rp;
    int i, rc;
    cfg->formation = FORMATION_LINE;
    cfg->world = ROVER_WORLD_OPEN;
    cfg->world_kind = 3; /* mixed */
    cfg->world_seed = 1;
    cfg->blend = 0;
    cfg->ref_goal = 1;
    rover_ctl_params_default(&rp); /* the rovers' own default */
    cfg->ref_arrive_m = rp.arrive_m;
    cfg->timeout_ms_given = 10000;
    cfg->robots = 3;
    cfg->teams = 1;
    cfg->per_team = 3;
    cfg->team_goals = ROVER_FLEET_GOALS_CROSS;
    cfg->seed = 1;
    cfg->max_time_s = -1.0; /* not given: from the way (setup) */
    cfg->hang_s = HANG_WATCH_DEFAULT_S;
    cfg->kill_id = -1;
    cfg->single = -1;
    cfg->batch = -1;
    cfg->hosts = 1;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc == OPTIONS_EXIT)
        exit(0);
    if (rc < 0)
        return SCENARIO_ERR_ARG;
    snprintf(cfg->timeout_ms, sizeof cfg->timeout_ms, "%ld", cfg->timeout_ms_given);
    if (cfg->teams > 1) {
        const long n = (long)cfg->teams * cfg->per_team;
        if (n > FM_MAX) {
            fprintf(stderr,
                    "formation: --teams %d --robots-per-team %d: %ld robots, more than a run "
                    "holds (FM_MAX = ROVER_WORLD_MAX_ROBOTS = %d)\n",
                    cfg->teams, cfg->per_team, n, FM_MAX);
            return SCENARIO_ERR_ARG;
        }
        cfg->robots = (int)n;
        cfg->goal_direct = 1; /* the open world: each goal in plain view */
    }
    if (!(cfg->max_time_s > 0) && cfg->max_time_s != -1.0) {
        fprintf(stderr, "formation: --max-time: '%g'\n", cfg->max_time_s);
        return SCENARIO_ERR_ARG;
    }
    if (cfg->kill_id > cfg->robots) {
        fprintf(stderr, "formation: --kill: robot %d not in the team\n", cfg->kill_id);
        return SCENARIO_ERR_ARG;
    }
    for (i = 0; i < cfg->n_faults; i++)
        if (cfg->faults[i].slot > cfg->robots) {
            fprintf(stderr, "formation: --fault: robot %d not in the team\n", cfg->faults[i].slot);
            return SCENARIO_ERR_ARG;
        }
    if (scenario_parse_drop(&cfg->drop, cfg->drop_arg ? cfg->drop_arg : "0", cfg->seed) != 0)
        return SCENARIO_ERR_ARG;
    if (cfg->hosts > 1 && cfg->single == 0) {
        fprintf(stderr,
                "formation: --hosts %d needs --procs single (each host a range of robots)\n",
                cfg->hosts);
        return SCENARIO_ERR_ARG;
    }
    if (cfg->single < 0)
        cfg->single = cfg->robots > 10 || cfg->hosts > 1;
    if (cfg->batch < 0)
        cfg->batch = cfg->single;
    if (cfg->n_faults > 0 && cfg->single) {
        fprintf(stderr,
                "formation: --fault kill:roverK needs one process per robot (--procs separate)\n");
        return SCENARIO_ERR_ARG;
    }
    return 0;
}

const char *fm_formation_name(int f)
{
    return f == 0 ? "line" : f == 1 ? "triangle" : "column";
}
const char *fm_blend_name(int b)
{
    return b == 0 ? "weighted" : b == 1 ? "subsumption" : "vecsum";
}

/* ---- set-up ----------------------------------------------------------------------- */

/* Zeroes the run's parts. */
static void fm_run_reset(fm_run *r)
{
    memset(r, 0, sizeof *r);
}

/* find_bindir: the running binary's path is not known */
#define BINDIR_UNKNOWN (-1)

/* The children are started from this binary's directory. 0 ok. */
static int find_bindir(fm_cfg *cfg)
{
    char self[512];
    ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) {
        fprintf(stderr, "formation: cannot find my own binary\n");
        return BINDIR_UNKNOWN;
    }
    self[len] = '\0';
    snprintf(cfg->bindir, sizeof cfg->bindir, "%s", self);
    if (strrchr(cfg->bindir, '/'))
        *strrchr(cfg->bindir, '/') = '\0';
    return 0;
}

/* The time series, and a fresh children.log and journals (a restart reads
 * what this run wrote). */
static void open_outputs(const fm_cfg *cfg, fm_metrics *mt)
{
    char p[700];
    int i;
    fm_metrics_open(mt, cfg->out);
    snprintf(p, sizeof p, "%s/children.log", cfg->out);
    remove(p);
    for (i = 1; i <= cfg->robots; i++) {
        snprintf(p, sizeof p, "%s/rover_%d.journal", cfg->out, i);
        remove(p);
    }
}

/* Many teams (fleet.h) on the open world: the longest of the teams' ways,
 * each straight from its start (its frame's origin) to its goal (nothing
 * stands between them but the other teams). */
static double fleet_way_m(const fm_cfg *cfg)
{
    double way = 0.0;
    int t;
    for (t = 0; t < cfg->teams; t++)
        way = fmax(way, hypot(cfg->fleet.goal_m[t][0] - cfg->fleet.origin[t].x_m,
                              cfg->fleet.goal_m[t][1] - cfg->fleet.origin[t].y_m));
    return way;
}

/* The world, the way, the time limit, the output directory, where the
 * children are and the bus's URL. An exit status (>= 0) on failure,
 * SCENARIO_GO_ON otherwise. */
static int setup_cfg(fm_cfg *cfg)
{
    int i;
    cfg->wopt.world = cfg->world;
    if (cfg->world == FM_WORLD_RANDOM) {
        if (cfg->wopt.file) {
            fprintf(stderr, "formation: --world random and --world-file exclude each other\n");
            return 2;
        }
        if ((i = fm_random_world(cfg)) != 0)
            return i;
    }
    if (world_opts_fleet_layout(&cfg->layout, &cfg->fleet, &cfg->wopt, cfg->robots, cfg->teams,
                                cfg->per_team, cfg->team_goals, cfg->formation, "formation") != 0)
        return 2;
    if (!cfg->layout.goal_fits)
        printf("formation: no place near the goal (%.2f, %.2f) fits the goal formation; flying to "
               "it as given\n",
               cfg->layout.goal_m[0], cfg->layout.goal_m[1]);
    else if (cfg->layout.goal_m[0] != cfg->layout.goal_nominal_m[0] ||
             cfg->layout.goal_m[1] != cfg->layout.goal_nominal_m[1])
        printf("formation: the goal formation does not fit at (%.2f, %.2f); placed at (%.2f, %.2f) "
               "(docs/method/formation.md §15)\n",
               cfg->layout.goal_nominal_m[0], cfg->layout.goal_nominal_m[1], cfg->layout.goal_m[0],
               cfg->layout.goal_m[1]);
    cfg->way_m = cfg->teams > 1 ? fleet_way_m(cfg) : fm_way_length_m(&cfg->layout);
    cfg->passage_m = fm_passage_width_m(&cfg->layout);
    cfg->cut_m = fm_cut_width_m(&cfg->layout, fm_formation_width_m(cfg));
    if (cfg->max_time_s == -1.0)
        cfg->max_time_s = fm_time_limit_s(cfg->way_m);
    if (scenario_mkdir(cfg->out) != 0)
        return 1;
    if (fm_keep_world(cfg) != 0)
        return 1;
    if (find_bindir(cfg) != 0)
        return 1;
    if (!cfg->url) {
        snprintf(cfg->url_buf, sizeof cfg->url_buf,
                 "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=4194304",
                 20000 + (int)(getpid() % 20000));
        cfg->url = cfg->url_buf;
    }
    return SCENARIO_GO_ON;
}

/* The configuration, then the other parts from it: the bus, the
 * subscriptions, the outputs. An exit status (>= 0) on failure,
 * SCENARIO_GO_ON otherwise. */
static int setup(fm_run *r)
{
    const int rc = setup_cfg(&r->cfg);
    if (rc != SCENARIO_GO_ON)
        return rc;
    fm_metrics_init(&r->metrics, &r->cfg);
    if (fm_bus_open(&r->bus, &r->cfg, &r->procs.hw) != 0)
        return 1;
    fm_subscribe(r);
    open_outputs(&r->cfg, &r->metrics);
    fm_procs_init(&r->procs, &r->cfg);
    return SCENARIO_GO_ON;
}

/* ---- the lockstep loop ---------------------------------------------------------------- */

static void on_sig(int s)
{
    (void)s;
}

/* A step every participant answers, its truth in, not answered yet. */
static int cycle_due(const fm_bus *bus)
{
    const int64_t due = bus->clock_step - bus->clock_step % FM_PERIOD;
    return bus->have_clock && due > bus->answered && bus->clock_step % FM_PERIOD == 0 &&
           bus->last_truth_step >= bus->clock_step;
}

/* The cycle's step: the protocol counts from the robot states of the last
 * cycle, --kill, the answer. 1 when the run is over (goal or time limit). */
static int answer_cycle(fm_run *r)
{
    int over;
    fm_metrics_cycle(&r->metrics, &r->cfg, &r->bus, &r->procs);
    fm_kill_robot(&r->procs, &r->cfg, &r->bus);
    over = r->metrics.reached || r->bus.sim_time >= r->cfg.max_time_s;
    fm_answer(&r->bus, !over);
    return over;
}

/* One line every few seconds of wall time. */
static void progress_line(const fm_run *r, double wall0)
{
    const double wall = scenario_wall_s() - wall0;
    const fm_metrics *mt = &r->metrics;
    fprintf(stderr,
            "formation: t %.1f s (%.1fx real time), collisions %d, formation changes %d, "
            "dead-zone escapes %d%s\n",
            r->bus.sim_time, scenario_realtime_factor(r->bus.sim_time, wall), mt->collisions,
            mt->formation_changes, mt->escapes, mt->reached ? ", at the goal" : "");
}

/* Registers before the first step (the sim waits for --expect participants). */
static void register_lockstep(fm_bus *bus, double wall0)
{
    while (scenario_wall_s() - wall0 < 30.0) {
        fm_ack(bus, 0);
        lcm_handle_timeout(bus->lcm, 100);
        if (bus->have_clock)
            break;
    }
}

/* --fault and hung restarts at a due step: 1 go on, 0 hold the step,
 * FM_ERR_FAULT. */
static int restarts_step(fm_run *r)
{
    int rc = fm_faults_step(&r->procs, &r->cfg, &r->bus);
    if (rc == 1)
        rc = fm_hung_step(&r->procs, &r->cfg, &r->bus);
    return rc;
}

/* A run that gains no simulated time for this long of wall time is
 * stuck, however slow the machine (a hung child is found sooner, by
 * --hang-s). Not a multiple of --max-time: 10,000 robots on one core run
 * at 0.06x real time, and 20x the run plus a minute cut them off. */
#define FM_STALL_WALL_S 300.0

/* Until the goal, a limit, a lost lockstep or a failed restart. */
static void lockstep_loop(fm_run *r, double wall0)
{
    const fm_cfg *cfg = &r->cfg;
    fm_bus *bus = &r->bus;
    double next_progress = wall0 + 5.0, last_sim_s = -1.0, last_gain_wall = wall0;
    for (;;) {
        int fault_rc = 1, due, hung_rc;
        if (fm_bus_handle(bus, 50) < 0)
            break;
        hung_rc = fm_hung_watch(&r->procs, cfg, bus);
        if (hung_rc < 0) {
            if (hung_rc == FM_ERR_FAULT)
                r->outcome.restart_failed = 1;
            break;
        }
        fm_answer_repeat(bus);
        due = cycle_due(bus);
        if (due)
            fault_rc = restarts_step(r);
        if (due && fault_rc < 0) {
            r->outcome.restart_failed = 1;
            break;
        }
        if (fault_rc == 1 && due) {
            if (answer_cycle(r))
                break;
        } else {
            fm_nudge_if_quiet(bus);
        }
        if (scenario_progress_due(&next_progress, 5.0))
            progress_line(r, wall0);
        if (bus->sim_time > cfg->max_time_s + 5.0) {
            /* the world ran past the limit without us: every participant
             * was dropped (dead or hung, docs/method/lockstep.md §3) */
            fprintf(
                stderr,
                "formation: the simulator went on without the lockstep participants; giving up\n");
            r->outcome.lost_lockstep = 1;
            break;
        }
        if (bus->sim_time > last_sim_s) {
            last_sim_s = bus->sim_time;
            last_gain_wall = scenario_wall_s();
        } else if (scenario_wall_s() - last_gain_wall > FM_STALL_WALL_S) {
            fprintf(
                stderr,
                "formation: no simulated time gained for %.0f s of wall time at t = %.2f s; giving up\n",
                FM_STALL_WALL_S, bus->sim_time);
            break;
        }
    }
}

/* ---- the end ------------------------------------------------------------------------ */

static void print_result(const fm_run *r, double wall_s)
{
    const fm_cfg *cfg = &r->cfg;
    const fm_metrics *mt = &r->metrics;
    printf(
        "formation %s world %s blend %s law %s robots %d seed %ld: reached_goal=%d time_to_goal_s=%.2f "
        "rms_formation_err_m=%.3f max_formation_err_m=%.3f min_clearance_m=%.3f collisions=%d "
        "formation_changes=%d dead_zone_escapes=%d loc_err_max_m=%.3f sim_time_s=%.1f wall_time_s=%.1f\n",
        fm_formation_name(cfg->formation), rover_world_name(cfg->world), fm_blend_name(cfg->blend),
        cfg->law_kanayama ? "kanayama" : "seed", cfg->robots, cfg->seed, mt->reached,
        mt->reached ? mt->time_to_goal : NAN,
        mt->samples ? sqrt(mt->sum_sq_err / mt->samples) : NAN, mt->max_err, mt->min_clear,
        mt->collisions, mt->formation_changes, mt->escapes, mt->loc_n ? mt->loc_max : NAN,
        r->bus.sim_time, wall_s);
}

/* The children stopped, the outputs closed, the criteria, summary.json
 * and the plots. */
static void finish(fm_run *r, double wall0)
{
    fm_outcome *oc = &r->outcome;
    fm_stop_children(&r->procs);
    fm_hang_stop(&r->procs, &r->bus);
    fm_metrics_close(&r->metrics);
    oc->n_failed = fm_criteria(&r->cfg, &r->procs, &r->metrics, oc, oc->failed, sizeof oc->failed);
    fm_write_summary(&r->cfg, &r->procs, &r->metrics, oc, r->bus.sim_time,
                     scenario_wall_s() - wall0);
    fm_write_plots(&r->cfg);
    fm_unsubscribe(r);
    auth_bus_close(r->bus.auth, r->bus.lcm);
    print_result(r, scenario_wall_s() - wall0);
}

static int run(int argc, char **argv)
{
    fm_run *r = &F;
    const fm_cfg *cfg = &r->cfg;
    double wall0;
    int rc;
    fm_run_reset(r);
    if (parse(&r->cfg, argc, argv) != 0)
        return 2;
    if ((rc = setup(r)) >= 0)
        return rc;
    signal(SIGPIPE, SIG_IGN);
    signal(SIGINT, on_sig);
    wall0 = scenario_wall_s();
    if (fm_start_children(&r->procs, cfg, &r->bus) != 0) {
        fm_stop_children(&r->procs);
        return 1;
    }
    fprintf(stderr, "formation: %d robots, %s, world %s, blend %s, seed %ld on %s\n", cfg->robots,
            fm_formation_name(cfg->formation), rover_world_name(cfg->world),
            fm_blend_name(cfg->blend), cfg->seed, cfg->url);
    fprintf(stderr, "formation: time limit %.0f s (the way for the body: %.1f m)\n",
            cfg->max_time_s, cfg->way_m);
    fm_quiet_from_now(&r->bus);
    fm_hang_start(&r->procs, cfg, &r->bus);
    register_lockstep(&r->bus, wall0);
    lockstep_loop(r, wall0);
    finish(r, wall0);
    return scenario_exit_status("formation", r->outcome.n_failed, r->outcome.failed);
}

const scenario_def scenario_formation = {
    "formation", "Pioneer team in line/triangle/column formation to a goal (seed 003)", run
};
