/* tandem-scenario sweep NAME --seeds A-B [--jobs J] [--keys K,..] --out DIR
 *                   [NAME's options]
 *
 * Runs scenario NAME once per seed A..B, J runs at a time, each as its own
 * tandem-scenario process (own private bus, own daemons) with
 * `--seed S --out DIR/seed-S` added to NAME's options; its output goes to
 * DIR/seed-S/scenario.log. While it runs, a progress line per finished
 * seed. Then a table with one row per seed (exit status and the summary
 * keys of the scenario's column list, or --keys), totals (passed runs,
 * and min / mean / max of each numeric column) and DIR/sweep.csv.
 * Exit status: 0 when every run exited 0, 3 otherwise (1 on errors).
 *
 * tandem-scenario sweep formation --world random --world-seeds A-B [--seeds S]
 * sweeps worlds instead: run W gets --world-seed W (and noise seed S,
 * default 1) into DIR/world-W, which keeps the world it flew; the worlds
 * whose run failed are listed in DIR/failing_worlds.txt with the command
 * that flies each again from its file (sweep_worlds.c).
 */
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include "options.h"
#include "scenario.h"
#include "scen_status.h"
#include "sweep_worlds.h"

#define SWEEP_MAX_SEEDS 10000
#define SWEEP_MAX_JOBS 64
#define SWEEP_MAX_ARGS 128

/* Failures of the sweep's own steps (0 = ok) */
#define SWEEP_NOT_RUN (-1) /* sweep_run.status: not run, or ended by a signal */

/* Default columns per scenario (summary.json keys). */
static const struct {
    const char *scenario, *keys;
} default_keys[] = {
    { "carry",
      "workpieces_delivered,workpieces_dropped,joint_limit_violations,max_joint_speed_ratio,"
      "max_contact_force_10ms_N,settled_force_max_N,resume_latency_max_s,stalls,sim_time_s,exit_reason" },
    { "formation", "robots,formation,reached_goal,time_to_goal_s,collisions,formation_changes,"
                   "dead_zone_escapes,max_formation_err_m,loc_err_max_m,exit_reason" },
    { "singularity", "max_pos_err_m,exit_reason" },
    { "liquid", "joint_limit_violations,exit_reason" },
};

typedef struct sweep {
    const char *name, *out;
    long seed_a, seed_b;
    long world_a, world_b; /* --world-seeds */
    int worlds_given;
    int jobs;
    const char *keys_arg; /* --keys, NULL: the scenario's default */
    int seeds_given, out_given;
    char keys_buf[1024];
    const char *key[SWEEP_MAX_KEYS];
    int n_keys;
    const char *pass[SWEEP_MAX_ARGS]; /* NAME's own options, passed through */
    int n_pass;
    char self[1024];
    sweep_run *run;
    int n_run;
} sweep;

static volatile sig_atomic_t sweep_interrupted;
static void sweep_on_sigint(int s)
{
    (void)s;
    sweep_interrupted = 1;
}

static int split_keys(sweep *w, const char *list)
{
    char *tok, *save = NULL;
    snprintf(w->keys_buf, sizeof w->keys_buf, "%s", list);
    w->n_keys = 0;
    for (tok = strtok_r(w->keys_buf, ",", &save); tok; tok = strtok_r(NULL, ",", &save)) {
        if (w->n_keys >= SWEEP_MAX_KEYS)
            return SWEEP_ERR_FULL;
        w->key[w->n_keys++] = tok;
    }
    return 0;
}

/* A-B (or A) into *a, *b. */
static int seed_range(const char *prog, const char *opt, char *v, long *a, long *b)
{
    char *end;
    *a = strtol(v, &end, 10);
    *b = *end == '-' ? strtol(end + 1, &end, 10) : *a;
    if (*end || *a < 0 || *b < *a || *b - *a >= SWEEP_MAX_SEEDS) {
        fprintf(stderr, "%s: %s: '%s' is not A-B (0 <= A <= B, at most %d seeds)\n", prog, opt, v,
                SWEEP_MAX_SEEDS);
        return OPTIONS_ERR_SAID;
    }
    return 0;
}

/* --seeds A-B (or A) */
static int option_seeds(const char *prog, void *dest, char *v)
{
    sweep *w = dest;
    return seed_range(prog, "--seeds", v, &w->seed_a, &w->seed_b);
}

/* --world-seeds A-B (or A) */
static int option_world_seeds(const char *prog, void *dest, char *v)
{
    sweep *w = dest;
    w->worlds_given = 1;
    return seed_range(prog, "--world-seeds", v, &w->world_a, &w->world_b);
}

static int option_seed(const char *prog, void *dest, char *v)
{
    (void)dest;
    (void)v;
    fprintf(stderr, "%s: --seed is set per run; use --seeds A-B\n", prog);
    return OPTIONS_ERR_SAID;
}

/* Everything that is not the sweep's own goes to NAME. */
static int pass_on(void *user, const char *word)
{
    sweep *w = user;
    if (w->n_pass >= SWEEP_MAX_ARGS - 8) {
        fprintf(stderr, "tandem-scenario sweep: more than %d arguments for the scenario\n",
                SWEEP_MAX_ARGS - 8);
        return OPTIONS_ERR_VALUE;
    }
    w->pass[w->n_pass++] = word;
    return 0;
}

static const option_entry sweep_table[] = {
    { .name = "seeds",
      .type = OPTION_CALL,
      OPTION_ALL(sweep),
      .call = option_seeds,
      .meta = "A-B",
      .help =
          "run NAME for every seed A..B (0 <= A <= B, at most 10000 seeds) with --seed S --out DIR/seed-S "
          "(with --world-seeds: the one noise seed of every run, default 1)",
      OPTION_SEEN(sweep, seeds_given) },
    { .name = "world-seeds",
      .type = OPTION_CALL,
      OPTION_ALL(sweep),
      .call = option_world_seeds,
      .meta = "A-B",
      .help =
          "formation --world random: run every world seed A..B with --world-seed W --out DIR/world-W; "
          "the failing worlds go to DIR/failing_worlds.txt with the command that flies each again" },
    { .name = "jobs",
      .type = OPTION_INT,
      OPTION_AT(sweep, jobs),
      .min = 1,
      .max = SWEEP_MAX_JOBS,
      .meta = "J",
      .help = "runs at a time",
      .def = "1" },
    { .name = "keys",
      .type = OPTION_STRING,
      OPTION_AT(sweep, keys_arg),
      .meta = "K1,K2,..",
      .help = "summary.json keys to tabulate",
      .def = "per scenario" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(sweep, out),
      OPTION_SEEN(sweep, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "output directory: DIR/seed-S per run, DIR/sweep.csv" },
    { .name = "seed",
      .type = OPTION_CALL,
      .call = option_seed,
      .meta = "S",
      .help = "refused: the sweep sets it per run" },
    { .name = NULL }
};

static const option_program sweep_program = {
    .name = "tandem-scenario sweep",
    .usage =
        "usage: tandem-scenario sweep NAME --seeds A-B [--jobs J] [--keys K1,K2,..]\n"
        "         --out DIR [NAME's options]\n"
        "       tandem-scenario sweep formation --world random --world-seeds A-B [--seeds S] ...\n"
        "         [--robots N1,N2,..] [--formation F1,F2,..] [--world-kind K1,K2,..]\n"
        "Runs scenario NAME for every seed A..B (J at a time, default 1), each with\n"
        "--seed S --out DIR/seed-S, and prints one row per seed (exit status and\n"
        "summary.json keys), totals and DIR/sweep.csv. Exit 0 when every run\n"
        "exited 0, 3 otherwise. Every other option goes to NAME; --robots, --formation\n"
        "and --world-kind may be lists, run i (from 0) taking item i mod n of each.\n\n",
    .groups = { { sweep_table, NULL } }, /* the base is the caller's sweep */
    .n_groups = 1,
};

/* Options of the sweep itself; everything else goes to NAME. */
static int parse(sweep *w, int argc, char **argv)
{
    option_program prog = sweep_program;
    const char *keys;
    size_t k;
    if (argc < 2 || argv[1][0] == '-')
        return SWEEP_ERR_USAGE;
    w->name = argv[1];
    prog.groups[0].base = w;
    prog.other = pass_on;
    prog.other_user = w;
    if (options_parse(&prog, argc, argv, 2) < 0)
        return SWEEP_ERR_USAGE;
    if (!w->seeds_given && !w->worlds_given) {
        fprintf(stderr, "tandem-scenario sweep: --seeds A-B or --world-seeds A-B is required\n");
        return SWEEP_ERR_USAGE;
    }
    if (w->worlds_given && w->seeds_given && w->seed_a != w->seed_b) {
        fprintf(stderr, "tandem-scenario sweep: with --world-seeds, --seeds is one noise seed\n");
        return SWEEP_ERR_USAGE;
    }
    if (w->worlds_given && !w->seeds_given)
        w->seed_a = w->seed_b = 1;
    keys = w->keys_arg;
    for (k = 0; !keys && k < sizeof default_keys / sizeof default_keys[0]; k++)
        if (!strcmp(default_keys[k].scenario, w->name))
            keys = default_keys[k].keys;
    if (split_keys(w, keys ? keys : "exit_reason") != 0) {
        fprintf(stderr, "tandem-scenario sweep: at most %d keys\n", SWEEP_MAX_KEYS);
        return SWEEP_ERR_USAGE;
    }
    return 0;
}

static pid_t spawn_seed(const sweep *w, const sweep_run *r)
{
    char dir[1024], seed[32], log[1100], wseed[32], item[SWEEP_MAX_ARGS][64];
    const char *argv[SWEEP_MAX_ARGS + 8];
    int n = 0, i;
    pid_t pid;
    sweep_run_dir(dir, sizeof dir, w->out, w->worlds_given, r->seed);
    snprintf(seed, sizeof seed, "%ld", w->worlds_given ? w->seed_a : r->seed);
    snprintf(wseed, sizeof wseed, "%ld", r->seed);
    snprintf(log, sizeof log, "%s/scenario.log", dir);
    if (scenario_mkdir(dir) != 0)
        return SWEEP_ERR_RUN;
    argv[n++] = "tandem-scenario";
    argv[n++] = w->name;
    for (i = 0; i < w->n_pass; i++)
        argv[n++] = sweep_in_turn(w->pass, i, (int)(r - w->run), item[i], sizeof item[i]);
    argv[n++] = "--seed";
    argv[n++] = seed;
    if (w->worlds_given) {
        argv[n++] = "--world-seed";
        argv[n++] = wseed;
    }
    argv[n++] = "--out";
    argv[n++] = dir;
    argv[n] = NULL;
    pid = fork();
    if (pid == 0) {
        FILE *f = freopen(log, "w", stdout);
        if (!f || dup2(fileno(stdout), 2) < 0)
            _exit(1);
        signal(SIGINT, SIG_DFL);
        execv(w->self, (char *const *)argv);
        fprintf(stderr, "tandem-scenario sweep: cannot run %s: %s\n", w->self, strerror(errno));
        _exit(1);
    }
    return pid;
}

/* Value of key in a flat summary.json ("key": value), as text without
 * quotes; "-" when missing. */
static void json_value(const char *json, const char *key, char *out, size_t cap)
{
    char pat[80];
    const char *p, *e;
    size_t n;
    snprintf(pat, sizeof pat, "\"%s\":", key);
    snprintf(out, cap, "-");
    if (!json || !(p = strstr(json, pat)))
        return;
    p += strlen(pat);
    while (*p == ' ')
        p++;
    if (*p == '"') {
        e = strchr(++p, '"');
    } else {
        for (e = p; *e && *e != ',' && *e != '\n' && *e != '}'; e++)
            ;
    }
    if (!e)
        return;
    n = (size_t)(e - p) < cap - 1 ? (size_t)(e - p) : cap - 1;
    memcpy(out, p, n);
    out[n] = '\0';
    if (n == 0)
        snprintf(out, cap, "\"\"");
}

static void read_summary(const sweep *w, sweep_run *r)
{
    char path[1100], buf[65536];
    size_t n = 0;
    int k;
    FILE *f;
    sweep_run_dir(path, sizeof path - 16, w->out, w->worlds_given, r->seed);
    strcat(path, "/summary.json");
    f = fopen(path, "r");
    if (f) {
        n = fread(buf, 1, sizeof buf - 1, f);
        fclose(f);
    }
    buf[n] = '\0';
    for (k = 0; k < w->n_keys; k++)
        json_value(f ? buf : NULL, w->key[k], r->val[k], sizeof r->val[k]);
}

static void print_row(FILE *o, const sweep *w, const sweep_run *r, const char *sep)
{
    int k;
    fprintf(o, "%ld%s%d", r->seed, sep, r->status);
    for (k = 0; k < w->n_keys; k++)
        fprintf(o, "%s%s", sep, r->val[k]);
    fprintf(o, "\n");
}

static void print_totals(const sweep *w, int passed, int ran)
{
    int k, i, i_lo = 0, i_hi = 0;
    printf("passed (exit 0): %d/%d\n", passed, w->n_run);
    if (ran < w->n_run)
        printf("not run (interrupted): %d\n", w->n_run - ran);
    for (k = 0; k < w->n_keys; k++) {
        double lo = INFINITY, hi = -INFINITY, sum = 0.0;
        int n = 0;
        for (i = 0; i < w->n_run; i++) {
            char *end;
            const double v = strtod(w->run[i].val[k], &end);
            if (!w->run[i].done || end == w->run[i].val[k] || *end)
                continue;
            if (v < lo) {
                lo = v;
                i_lo = i;
            }
            if (v > hi) {
                hi = v;
                i_hi = i;
            }
            sum += v;
            n++;
        }
        /* the worst cases: which run had the min and the max */
        if (n)
            printf(
                "  %-28s min %-12.4g mean %-12.4g max %-12.4g (%d runs; min at %s %ld, max at %ld)\n",
                w->key[k], lo, sum / n, hi, n, w->worlds_given ? "world" : "seed",
                w->run[i_lo].seed, w->run[i_hi].seed);
    }
}

static void print_header(FILE *o, const sweep *w, const char *sep)
{
    int k;
    fprintf(o, "%s%sexit", w->worlds_given ? "world_seed" : "seed", sep);
    for (k = 0; k < w->n_keys; k++)
        fprintf(o, "%s%s", sep, w->key[k]);
    fprintf(o, "\n");
}

static int run_all(sweep *w, double wall0)
{
    int next = 0, running = 0, finished = 0, passed = 0;
    while ((next < w->n_run && !sweep_interrupted) || running > 0) {
        int st, i;
        pid_t pid;
        while (next < w->n_run && running < w->jobs && !sweep_interrupted) {
            w->run[next].pid = spawn_seed(w, &w->run[next]);
            if (w->run[next].pid < 0)
                return SWEEP_ERR_RUN;
            next++;
            running++;
        }
        pid = waitpid(-1, &st, 0);
        if (pid < 0) {
            if (errno == EINTR)
                continue;
            return SWEEP_ERR_RUN;
        }
        for (i = 0; i < next; i++)
            if (w->run[i].pid == pid && !w->run[i].done) {
                sweep_run *r = &w->run[i];
                const double el = scenario_wall_s() - wall0;
                r->done = 1;
                r->status = WIFEXITED(st) ? WEXITSTATUS(st) : SWEEP_NOT_RUN;
                read_summary(w, r);
                running--;
                finished++;
                passed += r->status == 0;
                fprintf(
                    stderr,
                    "sweep %s: %s %ld exit %d | %d/%d done, %d passed, %.0f s elapsed, ~%.0f s left\n",
                    w->name, w->worlds_given ? "world" : "seed", r->seed, r->status, finished,
                    w->n_run, passed, el, el / finished * (w->n_run - finished));
            }
    }
    return finished;
}

static int run(int argc, char **argv)
{
    sweep w;
    FILE *csv;
    int i, ran, passed = 0;
    ssize_t n;
    const double wall0 = scenario_wall_s();
    memset(&w, 0, sizeof w);
    w.jobs = 1;
    w.seed_b = -1;
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        options_print_help(&sweep_program, stdout);
        return 0;
    }
    if (parse(&w, argc, argv) != 0) {
        options_print_help(&sweep_program, stderr);
        return 2;
    }
    n = readlink("/proc/self/exe", w.self, sizeof w.self - 1);
    if (n <= 0) {
        fprintf(stderr, "tandem-scenario sweep: cannot find my own program\n");
        return 1;
    }
    w.self[n] = '\0';
    if (scenario_mkdir(w.out) != 0)
        return 1;
    w.n_run = w.worlds_given ? (int)(w.world_b - w.world_a + 1) : (int)(w.seed_b - w.seed_a + 1);
    w.run = calloc((size_t)w.n_run, sizeof *w.run);
    if (!w.run)
        return 1;
    for (i = 0; i < w.n_run; i++) {
        w.run[i].seed = (w.worlds_given ? w.world_a : w.seed_a) + i;
        w.run[i].status = SWEEP_NOT_RUN;
    }
    signal(SIGINT, sweep_on_sigint);
    signal(SIGTERM, sweep_on_sigint);
    if (w.worlds_given)
        fprintf(stderr, "sweep %s: worlds %ld-%ld (noise seed %ld), %d at a time, into %s\n",
                w.name, w.world_a, w.world_b, w.seed_a, w.jobs, w.out);
    else
        fprintf(stderr, "sweep %s: seeds %ld-%ld, %d at a time, into %s\n", w.name, w.seed_a,
                w.seed_b, w.jobs, w.out);
    ran = run_all(&w, wall0);
    if (ran < 0) {
        fprintf(stderr, "tandem-scenario sweep: cannot run the scenario\n");
        free(w.run);
        return 1;
    }
    csv = scenario_fopen(w.out, "sweep.csv");
    print_header(stdout, &w, "\t");
    if (csv)
        print_header(csv, &w, ",");
    for (i = 0; i < w.n_run; i++) {
        if (!w.run[i].done)
            continue;
        passed += w.run[i].status == 0;
        print_row(stdout, &w, &w.run[i], "\t");
        if (csv)
            print_row(csv, &w, &w.run[i], ",");
    }
    if (csv)
        fclose(csv);
    print_totals(&w, passed, ran);
    if (w.worlds_given)
        sweep_list_failing(w.out, w.run, w.n_run, w.seed_a, w.pass, w.n_pass);
    printf("sweep %s: %d/%d runs passed, %.0f s\n", w.name, passed, w.n_run,
           scenario_wall_s() - wall0);
    free(w.run);
    return passed == w.n_run ? 0 : 3;
}

const scenario_def scenario_sweep = {
    "sweep", "runs a scenario over a range of seeds (J at a time): table, totals, sweep.csv", run
};
