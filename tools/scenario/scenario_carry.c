/* tandem-scenario carry: the seed-000 experiment (docs/method/carry.md §8):
 * the options and the driver.
 *
 * The run (carry_run.c) spawns the simulator, both arms and the supervisor
 * in lockstep and pushes the stick into the arms (carry_blocks.c: when a
 * block goes in, what is measured while it is in and after it comes out).
 * Then (unless --no-serial) the same task with --serial on the supervisor
 * (a new workpiece only when the previous one is delivered and both arms
 * are home), without blocks, for serial_cycle_s.
 *
 * Health of the run, from the arms' measured state every step
 * (carry_bus.c): joint range violations (onsets of a joint past its range
 * by more than ARM_RANGE_TOL_RAD), the largest |qd_i| / qd_max_i, and the
 * contact force raw (1 ms) and 10 ms-averaged. The run exits 0 only when
 * every success criterion holds (carry_criteria, carry_report.c), 3
 * otherwise with the failed criteria on its last line.
 *
 * Output: summary.json, timeseries.csv (10 ms), joints.csv (both arms'
 * joint angles, 10 ms), blocks.csv, transitions.csv, s.png, force.png,
 * gantt.png, and the daemons' logs.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "carry_scen.h"
#include "hang_watch.h"
#include "shared_run.h"
#include "netc.h"
#include "options.h"

/* What the command line sets; run() copies it out. */
typedef struct carry_options {
    carry_cfg cfg;       /* workpieces, controller_time, out, url, n_faults */
    carry_blocks blocks; /* --block, then --random-blocks */
    scenario_fault faults[SCENARIO_MAX_FAULTS];
    int block_detect; /* index in options_on_off */
    int n_random, no_serial, serial_n;
    long seed;
    double stall_s;
    const char *drop_arg;
    int out_given;
} carry_options;

/* --block A:L:S:D[:t3], repeatable: into the blocks */
static int option_block(const char *prog, void *dest, char *value)
{
    carry_blocks *bl = dest;
    if (bl->n >= MAX_BLOCKS || carry_block_parse(value, &bl->b[bl->n]) != 0) {
        fprintf(stderr,
                "%s: --block: '%s' is not ARM:LINK:START_S:DURATION_S[:t3] "
                "(arm 1-2, link 1-6, start >= 0, 0 < duration <= 3600)\n",
                prog, value);
        return OPTIONS_ERR_SAID;
    }
    bl->n++;
    return 0;
}

/* --fault kill:D:T[:R], repeatable: into cfg->faults */
static int option_fault(const char *prog, void *dest, char *value)
{
    carry_cfg *cfg = dest;
    int i;
    if (cfg->n_faults >= SCENARIO_MAX_FAULTS ||
        scenario_parse_fault(&cfg->faults[cfg->n_faults], value) != 0)
        return OPTIONS_ERR_SAID;
    for (i = 1; i < CARRY_DAEMONS &&
                strcmp(cfg->faults[cfg->n_faults].daemon, carry_daemon_fault_name[i]) != 0;
         i++)
        ;
    if (i == CARRY_DAEMONS) {
        fprintf(stderr, "%s: --fault: '%s' is not arm1|arm2|supervisor\n", prog,
                cfg->faults[cfg->n_faults].daemon);
        return OPTIONS_ERR_SAID;
    }
    cfg->faults[cfg->n_faults++].slot = i;
    return 0;
}

static const char *const controllers[] = { "event", "time", NULL };

static const option_entry carry_option_table[] = {
    { .name = "workpieces",
      .type = OPTION_INT,
      OPTION_AT(carry_options, cfg.workpieces),
      .min = 1,
      .max = 1000,
      .meta = "N",
      .help = "workpieces to carry",
      .def = "3" },
    { .name = "controller",
      .type = OPTION_CHOICE,
      OPTION_AT(carry_options, cfg.controller_time),
      .choices = controllers,
      .help = "time: the time-referenced baseline",
      .def = "event" },
    { .name = "block",
      .type = OPTION_CALL,
      OPTION_AT(carry_options, blocks),
      .call = option_block,
      .repeatable = 1,
      .meta = "A:L:S:D[:t3]",
      .help =
          "push the stick into arm A (1-2), link L (1-6) at the first step after S s (>= 0) at which arm A "
          "moves (with :t3, during t3), for D s (0 < D <= 3600); run one after the other" },
    { .name = "random-blocks",
      .type = OPTION_INT,
      OPTION_AT(carry_options, n_random),
      .min = 0,
      .max = MAX_BLOCKS,
      .meta = "K",
      .help = "K seeded random blocks (links 2-5, 0.2-60 s, every third during t3)",
      .def = "0" },
    { .name = "seed",
      .type = OPTION_INT,
      OPTION_AT(carry_options, seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "S",
      .help = "seed of the sim and the random blocks",
      .def = "1" },
    { .name = "no-serial",
      .type = OPTION_FLAG,
      OPTION_AT(carry_options, no_serial),
      .help = "skip the serial reference run (serial_cycle_s = null)" },
    { .name = "serial-workpieces",
      .type = OPTION_INT,
      OPTION_AT(carry_options, serial_n),
      .min = 2,
      .max = 1000,
      .meta = "M",
      .help = "workpieces of the serial run",
      .def = "min(N, 3)" },
    { .name = "block-detect",
      .type = OPTION_CHOICE,
      OPTION_AT(carry_options, block_detect),
      .choices = options_on_off,
      .help = "off: the arms run eq. 6-7 alone (no blocked detector)",
      .def = "on" },
    { .name = "stall-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(carry_options, stall_s),
      .min = 0.1,
      .max = 1e6,
      .meta = "S",
      .help = "the supervisor's stall limit (s); a stall stops the run",
      .def = "30" },
    { .name = "fault",
      .type = OPTION_CALL,
      OPTION_AT(carry_options, cfg),
      .call = option_fault,
      .repeatable = 1,
      .meta = "kill:D:T[:R]",
      .help = "kill daemon D (arm1, arm2, supervisor) at T s of simulated time, "
              "restart it at R s" },
    { .name = "hang-s",
      .type = OPTION_DOUBLE,
      OPTION_AT(carry_options, cfg.hang_s),
      .min = 0.0,
      .max = 3600.0,
      .meta = "S",
      .help = "a daemon alive but without health messages for S s of wall time is hung: killed "
              "(SIGKILL) and restarted (the simulator: the run stops); 0: not watched",
      .def = "5" },
    { .name = "drop-rate",
      .type = OPTION_STRING,
      OPTION_AT(carry_options, drop_arg),
      .meta = "P",
      .help = "every daemon drops received messages with probability P (0 <= P < 1)",
      .def = "0" },
    { .name = "task",
      .type = OPTION_STRING,
      OPTION_AT(carry_options, cfg.task),
      .meta = "DIR",
      .help =
          "run the task in DIR (tandem-supervisor --task: one *.pnml and rows.csv, docs/tasks.md); "
          "checked here first, and the simulator gets the hand-over stand when the task sets "
          "workpieces down there",
      .def = "the shipped carry" },
    { .name = "lcm-url",
      .type = OPTION_STRING,
      OPTION_AT(carry_options, cfg.url),
      .min = 1,
      .max = 95,
      .meta = "URL",
      .help = "bus of the run",
      .def = "a private udpm port" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(carry_options, cfg.out),
      OPTION_SEEN(carry_options, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "output directory" },
    OPTION_HELP_ENTRY(0),
    { .name = NULL }
};

static const option_program carry_program = {
    .name = "tandem-scenario carry",
    .usage =
        "usage: tandem-scenario carry [--workpieces N] [--controller event|time]\n"
        "         [--block ARM:LINK:START_S:DURATION_S[:t3]]... [--random-blocks K]\n"
        "         [--seed S] [--no-serial] [--serial-workpieces M]\n"
        "         [--block-detect on|off] [--stall-s S] [--fault kill:D:T[:R]]...\n"
        "         [--hang-s S] [--drop-rate P] [--task DIR] [--lcm-url URL] --out DIR\n"
        "Two-arm carry in lockstep with the stick pushed into the arms (docs/method/carry.md §8).\n\n",
    .epilog = "Exit status: 0 when the run met every success criterion (all delivered,\n"
              "none dropped, no joint-limit violation, speeds within the motor limits,\n"
              "10 ms contact force <= 1000 N, resumed within 1 s of every removal, no\n"
              "stall, no invariant violation or deadlock, completed); 3 otherwise, with\n"
              "the failed criteria on the last line; 1 on errors, 2 on bad options.\n",
    .groups = { { carry_option_table, NULL } }, /* the base is parse()'s carry_options */
    .n_groups = 1,
};

/* The command line into o; an exit status (>= 0) when the run is not to
 * go on (bad options, --help), SCENARIO_GO_ON otherwise. */
static int parse(carry_options *o, int argc, char **argv)
{
    option_program prog = carry_program;
    int rc;
    memset(o, 0, sizeof *o);
    o->cfg.faults = o->faults;
    o->cfg.workpieces = 3;
    o->serial_n = -1;
    o->seed = 1;
    o->stall_s = 30.0;
    o->cfg.hang_s = HANG_WATCH_DEFAULT_S;
    o->drop_arg = "0";
    prog.groups[0].base = o;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    if (o->n_random > 0 && o->blocks.n + o->n_random > MAX_BLOCKS) {
        fprintf(stderr, "tandem-scenario carry: too many blocks\n");
        return 2;
    }
    return SCENARIO_GO_ON;
}

/* --task: checked before anything starts (the supervisor would refuse it
 * the same way, but only once the simulator runs), and what the cell
 * needs for it: the hand-over stand when a row sets a workpiece down
 * there, arm 2's magazine when a row goes to it. An exit status (2: refused) or SCENARIO_GO_ON. */
static int task_setup(carry_cfg *cfg)
{
    static netc_task task;
    int t, rc;
    if (!cfg->task)
        return SCENARIO_GO_ON;
    netc_set_program("tandem-scenario carry");
    rc = netc_task_load(&task, cfg->task, NETC_BOUND_FROM_INVARIANTS, NULL, stderr, stderr);
    if (rc != NETC_OK) {
        fprintf(stderr, "tandem-scenario carry: --task %s refused: %s\n", cfg->task,
                netc_strerror(rc));
        return 2;
    }
    for (t = 0; t < task.n_transitions; t++) {
        cfg->handover_stand |= carry_row_sets_down(&task.rows[t], 0) ||
                               carry_row_sets_down(&task.rows[t], 1);
        cfg->magazine |= carry_row_uses_magazine(&task.rows[t]);
    }
    return SCENARIO_GO_ON;
}

/* The main run's configuration from the options: the blocks completed
 * with the random ones, the output directory made, the limits set. An exit
 * status (>= 0) on failure, SCENARIO_GO_ON otherwise. */
static int setup(carry_cfg *cfg, carry_options *o, char *stall_buf, size_t stall_cap)
{
    carry_blocks *bl = &o->blocks;
    double total_block_s = 0.0;
    int i;
    *cfg = o->cfg;
    cfg->block_detect = options_on_off[o->block_detect];
    carry_random_blocks(bl, o->n_random, (uint64_t)o->seed);
    for (i = 0; i < bl->n; i++) {
        bl->b[i].in_s = bl->b[i].out_s = bl->b[i].contact_s = bl->b[i].self_stop_s =
            bl->b[i].partner_stop_s = -1.0;
        bl->b[i].resume_s = -1.0;
        total_block_s += bl->b[i].dur_s;
    }
    if (scenario_parse_drop(&cfg->drop, o->drop_arg, o->seed) != 0)
        return 2;
    if (task_setup(cfg) != SCENARIO_GO_ON)
        return 2;
    if (scenario_mkdir(cfg->out) != 0)
        return 1;
    carry_catch_signals();
    cfg->seed = (uint64_t)o->seed;
    cfg->tag = "run";
    snprintf(stall_buf, stall_cap, "%g", o->stall_s);
    cfg->stall_s = stall_buf;
    cfg->max_sim_s = 60.0 * cfg->workpieces + 1.5 * total_block_s + 30.0 * bl->n + 60.0;
    cfg->blocks = bl;
    bl->cur = 0;
    bl->gap_after_s = 3.0;
    return SCENARIO_GO_ON;
}

/* The main run's time series: timeseries.csv, transitions.csv, joints.csv. */
static int open_csvs(carry_cfg *cfg)
{
    cfg->ts_csv = scenario_fopen(cfg->out, "timeseries.csv");
    cfg->tr_csv = scenario_fopen(cfg->out, "transitions.csv");
    cfg->q_csv = scenario_fopen(cfg->out, "joints.csv");
    if (!cfg->ts_csv || !cfg->tr_csv || !cfg->q_csv)
        return SCENARIO_ERR_IO;
    fprintf(cfg->q_csv, "t_s,q1_1,q1_2,q1_3,q1_4,q1_5,q1_6,q2_1,q2_2,q2_3,q2_4,q2_5,q2_6\n");
    fprintf(cfg->ts_csv,
            "t_s,s1_m,sf1_m,tr1,s2_m,sf2_m,tr2,speed1_mps,speed2_mps,force1_N,force2_N,stick_arm,"
            "delivered,dropped,force1_10ms_N,force2_10ms_N\n");
    fprintf(cfg->tr_csv, "transition,start_s,end_s\n");
    return 0;
}

static void close_csvs(carry_cfg *cfg)
{
    fclose(cfg->ts_csv);
    fclose(cfg->tr_csv);
    fclose(cfg->q_csv);
    cfg->ts_csv = cfg->tr_csv = cfg->q_csv = NULL;
}

/* The serial reference run (no blocks, no faults, no time series); its
 * mean cycle is NAN when it does not run. */
static void run_serial(const carry_cfg *cfg, int serial_n, carry_result *ser)
{
    static carry_blocks no_blocks;
    carry_cfg s = *cfg;
    s.serial = 1;
    s.tag = "serial";
    s.n_faults = 0; /* the reference runs without faults */
    s.blocks = &no_blocks;
    s.workpieces = serial_n > 0
                       ? serial_n
                       : (cfg->workpieces < 3 ? (cfg->workpieces < 2 ? 2 : cfg->workpieces) : 3);
    s.max_sim_s = 80.0 * s.workpieces + 60.0;
    fprintf(stderr, "tandem-scenario carry: serial reference run, %d workpieces\n", s.workpieces);
    carry_run_once(&s, ser);
}

static int run(int argc, char **argv)
{
    carry_options o;
    carry_cfg cfg;
    carry_result res, ser;
    carry_block_figures fig;
    char stall_buf[32], failed[512];
    int rc, n_failed;
    if ((rc = parse(&o, argc, argv)) >= 0 ||
        (rc = setup(&cfg, &o, stall_buf, sizeof stall_buf)) >= 0)
        return rc;
    if (open_csvs(&cfg) != 0)
        return 1;
    fprintf(stderr, "tandem-scenario carry: %d workpieces, %s controller, %d blocks, seed %ld\n",
            cfg.workpieces, cfg.controller_time ? "time" : "event", cfg.blocks->n, o.seed);
    if (carry_run_once(&cfg, &res) != 0 && !res.sim_s) {
        fprintf(stderr, "tandem-scenario carry: the run did not start\n");
        return 1;
    }
    close_csvs(&cfg);
    memset(&ser, 0, sizeof ser);
    ser.mean_cycle_s = NAN;
    if (!o.no_serial && !carry_interrupted())
        run_serial(&cfg, o.serial_n, &ser);
    carry_block_figures_of(&fig, cfg.blocks, res.sim_s);
    carry_write_blocks_csv(cfg.out, cfg.blocks);
    n_failed = carry_criteria(&cfg, &res, fig.resume_max_s, failed, sizeof failed);
    if (carry_write_summary(&cfg, o.seed, &res, &ser, &fig, failed) != 0)
        return 1;
    carry_write_plots(cfg.out, cfg.blocks);
    printf(
        "carry (%s): delivered %d/%d, dropped %d, blockages %d, max contact %.1f N, lurch %.3f m/s, "
        "invariant violations %ld, deadlocks %d, replans %d, mean cycle %.2f s, serial %.2f s\n",
        cfg.controller_time ? "time" : "event", res.delivered, cfg.workpieces, res.dropped,
        res.blockages, fig.max_force_N, fig.max_lurch_mps, res.invariant_violations, res.deadlocks,
        res.replans, res.mean_cycle_s, ser.mean_cycle_s);
    return scenario_exit_status("carry", n_failed, failed);
}

const scenario_def scenario_carry = {
    "carry", "two-arm carry with the stick (seed 000): event law vs time baseline", run
};
