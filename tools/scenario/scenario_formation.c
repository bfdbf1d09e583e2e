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
#include "run_key.h"
#include "shared_run.h"
#include "formation.h"
#include "rover_ctl.h"
#include "options.h"

/* The run's state: large (every robot's last states), so not on the stack. */
static fm_state F;

/* --kill K:T */
static int option_kill(const char *prog, void *dest, char *v)
{
    fm_state *f = dest;
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
    fm_state *fm = dest;
    scenario_fault *f = &fm->faults[fm->n_faults];
    char *e = NULL;
    long k;
    if (fm->n_faults >= SCENARIO_MAX_FAULTS || scenario_parse_fault(f, v) != 0)
        return OPTIONS_ERR_SAID;
    k = strncmp(f->daemon, "rover", 5) == 0 ? strtol(f->daemon + 5, &e, 10) : 0;
    if (k < 1 || k > FM_MAX || *e) {
        fprintf(stderr, "%s: --fault: '%s' is not roverK\n", prog, f->daemon);
        return OPTIONS_ERR_SAID;
    }
    f->slot = (int)k;
    fm->n_faults++;
    return 0;
}

static const char *const blends[] = { "weighted", "subsumption", "vecsum", NULL };
static const char *const laws[] = { "seed", "kanayama", NULL };
static const char *const ref_headings[] = { "mean", "goal", NULL };
static const char *const procs[] = { "separate", "single", NULL };
static const char *const links[] = { "robot", "batch", NULL };

static const option_entry formation_table[] = {
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .help = "the team's formation",
      .def = "line" },
    { .name = "world",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, world),
      .choices = fm_world_names,
      .values = fm_world_values,
      .help = "the rover world (random: generated, see --world-kind, --world-seed)",
      .def = "open" },
    { .name = "world-kind",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, world_kind),
      .choices = fm_world_kinds,
      .help = "--world random: clutter, traps (U, V, L pockets), corridor or a mix",
      .def = "mixed" },
    { .name = "world-seed",
      .type = OPTION_INT,
      OPTION_AT(fm_state, world_seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "W",
      .help = "--world random: the world's seed (the noise has --seed)",
      .def = "1" },
    { .name = "world-size",
      .type = OPTION_STRING,
      OPTION_AT(fm_state, world_size),
      .meta = "WxH",
      .help = "--world random: the map's size (m)",
      .def = "30x20" },
    WORLD_FILE_OPTIONS(fm_state, wopt),
    { .name = "blend",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, blend),
      .choices = blends,
      .help = "how the behaviours' outputs are blended",
      .def = "weighted" },
    { .name = "formation-law",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, law_kanayama),
      .choices = laws,
      .help = "the formation behaviour flown",
      .def = "seed" },
    { .name = "ref-heading",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, ref_goal),
      .choices = ref_headings,
      .help =
          "the team reference heading: goal (bearing of the goal) or mean (the seed's mean of the headings)",
      .def = "goal" },
    { .name = "ref-arrive",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_state, ref_arrive_m),
      .min = 0.0,
      .max = 100.0,
      .meta = "M",
      .help = "within M of the goal the team reference turns onto the goal's slot frame and its "
              "speed fades (0: off)",
      .def = "0" },
    { .name = "localize",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, localize_off),
      .choices = options_on_off,
      .help = "robots fuse the world's LED landmarks",
      .def = "on" },
    { .name = "lockstep-timeout-ms",
      .type = OPTION_INT,
      OPTION_AT(fm_state, timeout_ms_given),
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
      OPTION_AT(fm_state, robots),
      .min = 1,
      .max = FM_MAX,
      .meta = "N",
      .help = "team size",
      .def = "3" },
    { .name = "seed",
      .type = OPTION_INT,
      OPTION_AT(fm_state, seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "S",
      .help = "noise seed",
      .def = "1" },
    { .name = "kill",
      .type = OPTION_CALL,
      OPTION_ALL(fm_state),
      .call = option_kill,
      .meta = "K:T",
      .help = "kill robot K (its process and its body) at sim time T s" },
    { .name = "fault",
      .type = OPTION_CALL,
      OPTION_ALL(fm_state),
      .call = option_fault,
      .repeatable = 1,
      .meta = "kill:roverK:T[:R]",
      .help =
          "kill robot K's process (SIGKILL; its body stands) at T s of "
          "simulated time and, with R, start it again at R s: it resumes from its journal. Deterministic (the "
          "lockstep is held while it rejoins)" },
    { .name = "hang-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_state, hang_s),
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
      OPTION_AT(fm_state, drop_arg),
      .meta = "P",
      .help =
          "fault injection: every daemon drops received messages with probability P (0 <= P < 1, "
          "deterministic for the seed); the run is the same as without loss, only slower",
      .def = "0" },
    { .name = "procs",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, single),
      .choices = procs,
      .help = "separate: one tandem-rover per robot; single: one process hosting all",
      .def = "separate up to 10 robots" },
    { .name = "link",
      .type = OPTION_CHOICE,
      OPTION_AT(fm_state, batch),
      .choices = links,
      .help =
          "robot: ROVERk_* channels per robot; batch: ROVERS_*, one message per tick for all robots. "
          "Same run either way",
      .def = "batch with --procs single, robot otherwise" },
    { .name = "max-time",
      .type = OPTION_DOUBLE,
      OPTION_AT(fm_state, max_time_s),
      .min = 0.0,
      .max = 3600.0,
      .meta = "S",
      .help = "give up after S simulated seconds (S > 0); not given: 60 s plus the shortest "
              "way for the robot body from the start to the goal at 0.2 m/s",
      .def = "from the way" },
    { .name = "lcm-url",
      .type = OPTION_STRING,
      OPTION_AT(fm_state, url),
      .meta = "URL",
      .help = "bus for the children",
      .def = "a private udpm port" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(fm_state, out),
      OPTION_SEEN(fm_state, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "output directory" },
    OPTION_HELP_ENTRY('h'),
    { .name = NULL }
};

static int parse(fm_state *fm, int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-scenario formation",
        .usage =
            "usage: tandem-scenario formation [options] --out DIR\n"
            "Pioneer team to the goal in formation (seed 003), lockstep, ground-truth metrics.\n\n",
        .groups = { { formation_table, fm } },
        .n_groups = 1,
    };
    rover_ctl_params rp;
    int i, rc;
    fm->formation = FORMATION_LINE;
    fm->world = ROVER_WORLD_OPEN;
    fm->world_kind = 3; /* mixed */
    fm->world_seed = 1;
    fm->blend = 0;
    fm->ref_goal = 1;
    rover_ctl_params_default(&rp); /* the rovers' own default */
    fm->ref_arrive_m = rp.arrive_m;
    fm->timeout_ms_given = 10000;
    fm->robots = 3;
    fm->seed = 1;
    fm->max_time_s = -1.0; /* not given: from the way (setup) */
    fm->hang_s = HANG_WATCH_DEFAULT_S;
    fm->kill_id = -1;
    fm->single = -1;
    fm->batch = -1;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc == OPTIONS_EXIT)
        exit(0);
    if (rc < 0)
        return SCENARIO_ERR_ARG;
    snprintf(fm->timeout_ms, sizeof fm->timeout_ms, "%ld", fm->timeout_ms_given);
    if (!(fm->max_time_s > 0) && fm->max_time_s != -1.0) {
        fprintf(stderr, "formation: --max-time: '%g'\n", fm->max_time_s);
        return SCENARIO_ERR_ARG;
    }
    if (fm->kill_id > fm->robots) {
        fprintf(stderr, "formation: --kill: robot %d not in the team\n", fm->kill_id);
        return SCENARIO_ERR_ARG;
    }
    for (i = 0; i < fm->n_faults; i++)
        if (fm->faults[i].slot > fm->robots) {
            fprintf(stderr, "formation: --fault: robot %d not in the team\n", fm->faults[i].slot);
            return SCENARIO_ERR_ARG;
        }
    if (scenario_parse_drop(&fm->drop, fm->drop_arg ? fm->drop_arg : "0", fm->seed) != 0)
        return SCENARIO_ERR_ARG;
    if (fm->single < 0)
        fm->single = fm->robots > 10;
    if (fm->batch < 0)
        fm->batch = fm->single;
    if (fm->n_faults > 0 && fm->single) {
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

static void fm_reset(fm_state *fm)
{
    memset(fm, 0, sizeof *fm);
    fm->min_clear = INFINITY;
    fm->scale_now = 1.0;
    fm->clock_step = -1;
    fm->answered = -1;
    fm->last_truth_step = -1;
    fm->last_snap_t = -1e9;
    fm->last_type = -1;
}

/* find_bindir: the running binary's path is not known */
#define BINDIR_UNKNOWN (-1)

/* The children are started from this binary's directory. 0 ok. */
static int find_bindir(fm_state *fm)
{
    char self[512];
    ssize_t len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) {
        fprintf(stderr, "formation: cannot find my own binary\n");
        return BINDIR_UNKNOWN;
    }
    self[len] = '\0';
    snprintf(fm->bindir, sizeof fm->bindir, "%s", self);
    if (strrchr(fm->bindir, '/'))
        *strrchr(fm->bindir, '/') = '\0';
    return 0;
}

/* The time series, and a fresh children.log and journals (a restart reads
 * what this run wrote). */
static void open_outputs(fm_state *fm)
{
    char p[700];
    int i;
    fm->truth_csv = scenario_fopen(fm->out, "truth.csv");
    fm->err_csv = scenario_fopen(fm->out, "formation_error.csv");
    fm->w_csv = scenario_fopen(fm->out, "weights.csv");
    fm->snap_csv = scenario_fopen(fm->out, "snapshots.csv");
    snprintf(p, sizeof p, "%s/children.log", fm->out);
    remove(p);
    for (i = 1; i <= fm->robots; i++) {
        snprintf(p, sizeof p, "%s/rover_%d.journal", fm->out, i);
        remove(p);
    }
}

/* Output directory, the bus, the world's layout, the subscriptions, the
 * outputs. An exit status (>= 0) on failure, SCENARIO_GO_ON otherwise. */
static int setup(fm_state *fm)
{
    int i;
    fm->wopt.world = fm->world;
    if (fm->world == FM_WORLD_RANDOM) {
        if (fm->wopt.file) {
            fprintf(stderr, "formation: --world random and --world-file exclude each other\n");
            return 2;
        }
        if ((i = fm_random_world(fm)) != 0)
            return i;
    }
    if (world_opts_layout(&fm->layout, &fm->wopt, fm->robots, 1.0, fm->formation, "formation") != 0)
        return 2;
    fm->way_m = fm_way_length_m(&fm->layout);
    fm->passage_m = fm_passage_width_m(&fm->layout);
    if (fm->max_time_s == -1.0)
        fm->max_time_s = fm_time_limit_s(fm->way_m);
    if (scenario_mkdir(fm->out) != 0)
        return 1;
    if (fm_keep_world(fm) != 0)
        return 1;
    if (find_bindir(fm) != 0)
        return 1;
    if (!fm->url) {
        snprintf(fm->url_buf, sizeof fm->url_buf,
                 "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=4194304",
                 20000 + (int)(getpid() % 20000));
        fm->url = fm->url_buf;
    }
    fm->type_now = fm->formation;
    names_watch_init(&fm->names, "formation");
    fm->lcm = lcm_create(fm->url);
    if (!fm->lcm) {
        fprintf(stderr, "formation: cannot open LCM at %s\n", fm->url);
        return 1;
    }
    fm_subscribe(fm);
    open_outputs(fm);
    for (i = 0; i <= FM_MAX; i++) {
        fm->rover_ack[i] = -1;
        fm->down_after[i] = INT64_MAX;
        fm->up_at[i] = INT64_MAX;
    }
    return SCENARIO_GO_ON;
}

/* ---- the lockstep loop ---------------------------------------------------------------- */

static void on_sig(int s)
{
    (void)s;
}

/* A step every participant answers, its truth in, not answered yet. */
static int cycle_due(const fm_state *fm)
{
    const int64_t due = fm->clock_step - fm->clock_step % FM_PERIOD;
    return fm->have_clock && due > fm->answered && fm->clock_step % FM_PERIOD == 0 &&
           fm->last_truth_step >= fm->clock_step;
}

/* The cycle's step: the protocol counts from the robot states of the last
 * cycle, --kill, the answer. 1 when the run is over (goal or time limit). */
static int answer_cycle(fm_state *fm)
{
    int i, lo = -1;
    for (i = 0; i < fm->robots; i++)
        if (fm->have_state[i] && (i + 1 != fm->kill_id || !fm->killed)) {
            lo = i;
            break;
        }
    if (lo >= 0) {
        if (fm->last_type >= 0 && fm->state_type[lo] != fm->last_type)
            fm->formation_changes++;
        fm->last_type = fm->state_type[lo];
    }
    fm_kill_robot(fm);
    fm->answered = fm->clock_step;
    if (fm->reached || fm->sim_time >= fm->max_time_s)
        return 1;
    fm_ack(fm, fm->clock_step);
    return 0;
}

/* One line every few seconds of wall time. */
static void progress_line(const fm_state *fm, double wall0)
{
    const double wall = scenario_wall_s() - wall0;
    fprintf(stderr,
            "formation: t %.1f s (%.1fx real time), collisions %d, formation changes %d, "
            "dead-zone escapes %d%s\n",
            fm->sim_time, scenario_realtime_factor(fm->sim_time, wall), fm->collisions,
            fm->formation_changes, fm->escapes, fm->reached ? ", at the goal" : "");
}

/* Registers before the first step (the sim waits for --expect participants). */
static void register_lockstep(fm_state *fm, double wall0)
{
    while (scenario_wall_s() - wall0 < 30.0) {
        fm_ack(fm, 0);
        lcm_handle_timeout(fm->lcm, 100);
        if (fm->have_clock)
            break;
    }
}

/* Until the goal, a limit, a lost lockstep or a failed restart. */
static void lockstep_loop(fm_state *fm, double wall0)
{
    double next_progress = wall0 + 5.0;
    for (;;) {
        int fault_rc = 1, due, hung_rc;
        if (lcm_handle_timeout(fm->lcm, 50) < 0)
            break;
        /* a flood of channel names: a new handle */
        bus_names_watch(&fm->names, run_key_bus(), &fm->lcm, fm->url);
        hung_rc = fm_hung_watch(fm);
        if (hung_rc < 0) {
            if (hung_rc == FM_ERR_FAULT)
                fm->restart_failed = 1;
            break;
        }
        if (fm->clock_repeat) {
            fm->clock_repeat = 0; /* our ack was lost: answer again */
            if (fm->answered >= 0)
                fm_ack(fm, fm->answered);
        }
        due = cycle_due(fm);
        if (due && (fault_rc = fm_faults_step(fm)) == 1)
            fault_rc = fm_hung_step(fm);
        if (due && fault_rc < 0) {
            fm->restart_failed = 1;
            break;
        }
        if (fault_rc == 1 && due) {
            if (answer_cycle(fm))
                break;
        } else if (fm->have_clock && fm_mono_ns() - fm->last_clock_ns > 500000000LL) {
            fm_nudge(fm);
            fm->last_clock_ns = fm_mono_ns();
        }
        if (scenario_progress_due(&next_progress, 5.0))
            progress_line(fm, wall0);
        if (fm->sim_time > fm->max_time_s + 5.0) {
            /* the world ran past the limit without us: every participant
             * was dropped (dead or hung, docs/method/lockstep.md §3) */
            fprintf(
                stderr,
                "formation: the simulator went on without the lockstep participants; giving up\n");
            fm->lost_lockstep = 1;
            break;
        }
        if (scenario_wall_s() - wall0 > 20.0 * fm->max_time_s + 60.0) {
            fprintf(stderr, "formation: no progress; giving up\n");
            break;
        }
    }
}

/* ---- the end ------------------------------------------------------------------------ */

static void close_outputs(fm_state *fm)
{
    if (fm->truth_csv)
        fclose(fm->truth_csv);
    if (fm->err_csv)
        fclose(fm->err_csv);
    if (fm->w_csv)
        fclose(fm->w_csv);
    if (fm->snap_csv)
        fclose(fm->snap_csv);
    fm->truth_csv = fm->err_csv = fm->w_csv = fm->snap_csv = NULL;
}

static void print_result(const fm_state *fm, double wall_s)
{
    printf(
        "formation %s world %s blend %s law %s robots %d seed %ld: reached_goal=%d time_to_goal_s=%.2f "
        "rms_formation_err_m=%.3f max_formation_err_m=%.3f min_clearance_m=%.3f collisions=%d "
        "formation_changes=%d dead_zone_escapes=%d loc_err_max_m=%.3f sim_time_s=%.1f wall_time_s=%.1f\n",
        fm_formation_name(fm->formation), rover_world_name(fm->world), fm_blend_name(fm->blend),
        fm->law_kanayama ? "kanayama" : "seed", fm->robots, fm->seed, fm->reached,
        fm->reached ? fm->time_to_goal : NAN,
        fm->samples ? sqrt(fm->sum_sq_err / fm->samples) : NAN, fm->max_err, fm->min_clear,
        fm->collisions, fm->formation_changes, fm->escapes, fm->loc_n ? fm->loc_max : NAN,
        fm->sim_time, wall_s);
}

static int run(int argc, char **argv)
{
    fm_state *fm = &F;
    double wall0;
    int rc;
    fm_reset(fm);
    if (parse(fm, argc, argv) != 0)
        return 2;
    if ((rc = setup(fm)) >= 0)
        return rc;
    signal(SIGPIPE, SIG_IGN);
    signal(SIGINT, on_sig);
    wall0 = scenario_wall_s();
    if (fm_start_children(fm) != 0) {
        fm_stop_children(fm);
        return 1;
    }
    fprintf(stderr, "formation: %d robots, %s, world %s, blend %s, seed %ld on %s\n", fm->robots,
            fm_formation_name(fm->formation), rover_world_name(fm->world), fm_blend_name(fm->blend),
            fm->seed, fm->url);
    fprintf(stderr, "formation: time limit %.0f s (the way for the body: %.1f m)\n", fm->max_time_s,
            fm->way_m);
    fm->last_clock_ns = fm_mono_ns();
    fm_hang_start(fm);
    register_lockstep(fm, wall0);
    lockstep_loop(fm, wall0);
    fm_stop_children(fm);
    hang_watch_stop(&fm->hw, fm->lcm);
    close_outputs(fm);
    fm->n_failed = fm_criteria(fm, fm->failed, sizeof fm->failed);
    fm_write_summary(fm, scenario_wall_s() - wall0);
    fm_write_plots(fm);
    fm_unsubscribe(fm);
    auth_bus_close(run_key_bus(), fm->lcm);
    print_result(fm, scenario_wall_s() - wall0);
    return scenario_exit_status("formation", fm->n_failed, fm->failed);
}

const scenario_def scenario_formation = {
    "formation", "Pioneer team in line/triangle/column formation to a goal (seed 003)", run
};
