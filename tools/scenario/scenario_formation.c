/* tandem-scenario formation: the seed-003 Pioneer team (docs/method/formation.md, §6).
 *
 * Spawns tandem-sim (lockstep, rovers only) and the rover daemons as
 * children on a private LCM bus, registers itself as a lockstep participant
 * (every 50 steps) so it sees the simulator's ground truth deterministically,
 * and writes DIR/summary.json, CSV time series and PNG plots. Every metric
 * comes from ROVER_TRUTH (ground truth) except the protocol counts
 * (formation changes, dead-zone escapes), which are what the robots did,
 * read from their ROVERk_STATE.
 */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "formation.h"
#include "rover_world.h"
#include "scenario.h"
#include "daemon.h"
#include "options.h"
#include "tandem_clock_ack_t.h"
#include "tandem_rover_state_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_rover_truth_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"

#define FM_MAX     ROVER_WORLD_MAX_ROBOTS
#define FM_PERIOD  50
#define FM_PROCS   (FM_MAX + 2)
#define FM_RING    4            /* states kept per robot */
#define FM_OUT_TOL 0.3          /* d_r: a robot further than this from its slot is out */

typedef struct {
    /* options */
    int    formation, world, blend, robots, single, batch;
    int    law_kanayama, ref_goal, localize_off;   /* --formation-law, --ref-heading, --localize */
    char   timeout_ms[24];                     /* --lockstep-timeout-ms */
    long   timeout_ms_given;
    scenario_drop drop;                        /* --drop-rate */
    const char *drop_arg;
    long   seed;
    double max_time_s;
    int    kill_id;
    double kill_t_s;
    scenario_fault faults[SCENARIO_MAX_FAULTS];   /* --fault kill:roverK:T[:R] */
    int    n_faults, kills, restarts;
    int64_t rover_ack[FM_MAX + 1];    /* the last step each rover process answered */
    double hold_since_s;              /* wall time a restart began holding the step */
    int64_t down_after[FM_MAX + 1];   /* --fault: robot k's process answered no step in */
    int64_t up_at[FM_MAX + 1];        /* (down_after, up_at): no states then */
    const char *out, *url;
    int    out_given;
    char   url_buf[160];
    char   bindir[512];
    /* children */
    pid_t  pid[FM_PROCS];
    int    n_pid;
    pid_t  rover_pid[FM_MAX + 1];     /* process hosting robot k (separate mode) */
    /* lcm */
    lcm_t *lcm;
    lcm_subscription_t *sub_clock, *sub_truth, *sub_state, *sub_states, *sub_ack;
    int64_t clock_step, answered, ack_seq, last_clock_ns;
    int    have_clock;
    /* layout and truth */
    rover_world_config layout;
    int    type_now;                  /* formation reported by the lowest alive id */
    double scale_now;
    int    mode[FM_MAX];
    int    state_type[FM_MAX];
    double state_scale[FM_MAX];
    double weight[FM_MAX][4];
    pose2 est[FM_MAX];              /* the robot's own odometry, world frame */
    int    have_state[FM_MAX];
    /* the robots' last states by step: truth at step k is read with the
     * states of the cycle before (k - FM_PERIOD), whatever arrived since */
    tandem_rover_state_t ring[FM_MAX][FM_RING];
    int    clock_repeat;             /* the simulator announced an answered step again */
    /* metrics */
    int    samples, out_samples;
    double sum_sq_err, max_err, min_clear, path[FM_MAX];
    double prev_x[FM_MAX], prev_y[FM_MAX], prev_th[FM_MAX], prev_w[FM_MAX];
    int    have_prev[FM_MAX], have_prev_w[FM_MAX];
    double sum_dw; long n_dw;
    double loc_sum_sq, loc_max; long loc_n;     /* own estimate vs truth */
    int    collisions, formation_changes, escapes;
    int    reached;
    double time_to_goal, sim_time;
    int    killed;
    FILE  *truth_csv, *err_csv, *w_csv, *snap_csv;
    double last_snap_t;
    int64_t last_truth_step;
    char   failed[256];          /* failed success criteria (formation_criteria) */
    int    n_failed;
    int    lost_lockstep;        /* the simulator dropped us: not the seed's run */
    int    restart_failed;       /* a --fault restart did not rejoin within 60 s */
} fm_t;

static fm_t F;

/* --kill K:T */
static int option_kill(const char *prog, void *dest, char *v)
{
    fm_t *f = dest;
    char *e;
    long k = strtol(v, &e, 10);
    double t;
    (void)prog;
    if (*e != ':')
        return -1;
    t = strtod(e + 1, &e);
    if (*e || k < 1 || !isfinite(t) || t < 0)
        return -1;
    f->kill_id = (int)k;
    f->kill_t_s = t;
    return 0;
}

/* --fault kill:roverK:T[:R], repeatable */
static int option_fault(const char *prog, void *dest, char *v)
{
    fm_t *fm = dest;
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
    { .name = "formation", .type = OPTION_CHOICE, OPTION_AT(fm_t, formation), .choices = options_formation_names,
      .values = options_formation_values, .help = "the team's formation", .def = "line" },
    { .name = "world", .type = OPTION_CHOICE, OPTION_AT(fm_t, world), .choices = options_world_names,
      .values = options_world_values, .help = "the rover world", .def = "open" },
    { .name = "blend", .type = OPTION_CHOICE, OPTION_AT(fm_t, blend), .choices = blends,
      .help = "how the behaviours' outputs are blended", .def = "weighted" },
    { .name = "formation-law", .type = OPTION_CHOICE, OPTION_AT(fm_t, law_kanayama), .choices = laws,
      .help = "the formation behaviour flown", .def = "seed" },
    { .name = "ref-heading", .type = OPTION_CHOICE, OPTION_AT(fm_t, ref_goal), .choices = ref_headings,
      .help = "the team reference heading: goal (bearing of the goal) or mean (the seed's mean of the headings)",
      .def = "goal" },
    { .name = "localize", .type = OPTION_CHOICE, OPTION_AT(fm_t, localize_off), .choices = options_on_off,
      .help = "robots fuse the world's LED landmarks", .def = "on" },
    { .name = "lockstep-timeout-ms", .type = OPTION_INT, OPTION_AT(fm_t, timeout_ms_given), .min = 100,
      .max = 3600000, .meta = "MS", .help = "the simulator drops a participant silent this long (wall); on a "
      "heavily loaded machine a starved controller would be dropped and the run no longer be the deterministic "
      "one: raise it for sweeps there", .def = "10000" },
    { .name = "robots", .type = OPTION_INT, OPTION_AT(fm_t, robots), .min = 1, .max = FM_MAX, .meta = "N",
      .help = "team size", .def = "3" },
    { .name = "seed", .type = OPTION_INT, OPTION_AT(fm_t, seed), .min = 0, .max = 2147483647.0, .meta = "S",
      .help = "noise seed", .def = "1" },
    { .name = "kill", .type = OPTION_CALL, OPTION_ALL(fm_t), .call = option_kill, .meta = "K:T",
      .help = "kill robot K (its process and its body) at sim time T s" },
    { .name = "fault", .type = OPTION_CALL, OPTION_ALL(fm_t), .call = option_fault, .repeatable = 1,
      .meta = "kill:roverK:T[:R]", .help = "kill robot K's process (SIGKILL; its body stands) at T s of "
      "simulated time and, with R, start it again at R s: it resumes from its journal. Deterministic (the "
      "lockstep is held while it rejoins)" },
    { .name = "drop-rate", .type = OPTION_STRING, OPTION_AT(fm_t, drop_arg), .meta = "P",
      .help = "fault injection: every daemon drops received messages with probability P (0 <= P < 1, "
      "deterministic for the seed); the run is the same as without loss, only slower", .def = "0" },
    { .name = "procs", .type = OPTION_CHOICE, OPTION_AT(fm_t, single), .choices = procs,
      .help = "separate: one tandem-rover per robot; single: one process hosting all",
      .def = "separate up to 10 robots" },
    { .name = "link", .type = OPTION_CHOICE, OPTION_AT(fm_t, batch), .choices = links,
      .help = "robot: ROVERk_* channels per robot; batch: ROVERS_*, one message per tick for all robots. "
      "Same run either way", .def = "batch with --procs single, robot otherwise" },
    { .name = "max-time", .type = OPTION_DOUBLE, OPTION_AT(fm_t, max_time_s), .min = 0.0, .max = 3600.0,
      .meta = "S", .help = "give up after S simulated seconds (S > 0)", .def = "150" },
    { .name = "lcm-url", .type = OPTION_STRING, OPTION_AT(fm_t, url), .meta = "URL",
      .help = "bus for the children", .def = "a private udpm port" },
    { .name = "out", .type = OPTION_STRING, OPTION_AT(fm_t, out), OPTION_SEEN(fm_t, out_given), .required = 1,
      .meta = "DIR", .help = "output directory" },
    { .name = "help", .letter = 'h', .type = OPTION_HELP, .help = "this text" },
    { .name = NULL }
};

static int parse(int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-scenario formation",
        .usage = "usage: tandem-scenario formation [options] --out DIR\n"
                 "Pioneer team to the goal in formation (seed 003), lockstep, ground-truth metrics.\n\n",
        .groups = { { formation_table, &F } }, .n_groups = 1,
    };
    int i, rc;
    F.formation = FORMATION_LINE;
    F.world = ROVER_WORLD_OPEN;
    F.blend = 0;
    F.ref_goal = 1;
    F.timeout_ms_given = 10000;
    F.robots = 3;
    F.seed = 1;
    F.max_time_s = 150.0;
    F.kill_id = -1;
    F.single = -1;
    F.batch = -1;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc == OPTIONS_EXIT)
        exit(0);
    if (rc < 0)
        return -1;
    snprintf(F.timeout_ms, sizeof F.timeout_ms, "%ld", F.timeout_ms_given);
    if (!(F.max_time_s > 0)) { fprintf(stderr, "formation: --max-time: '%g'\n", F.max_time_s); return -1; }
    if (F.kill_id > F.robots) { fprintf(stderr, "formation: --kill: robot %d not in the team\n", F.kill_id); return -1; }
    for (i = 0; i < F.n_faults; i++)
        if (F.faults[i].slot > F.robots) {
            fprintf(stderr, "formation: --fault: robot %d not in the team\n", F.faults[i].slot);
            return -1;
        }
    if (scenario_parse_drop(&F.drop, F.drop_arg ? F.drop_arg : "0", F.seed) != 0) return -1;
    if (F.single < 0) F.single = F.robots > 10;
    if (F.batch < 0) F.batch = F.single;
    if (F.n_faults > 0 && F.single) {
        fprintf(stderr, "formation: --fault kill:roverK needs one process per robot (--procs separate)\n");
        return -1;
    }
    return 0;
}

/* ---- children ----------------------------------------------------------------- */

static pid_t spawn(char *const argv[])
{
    pid_t p = fork();
    if (p == 0) {
        char path[700];
        int fd;
        setenv("LCM_DEFAULT_URL", F.url, 1);
        /* children's chatter goes to DIR/children.log */
        snprintf(path, sizeof path, "%s/children.log", F.out);
        fd = open(path, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) { dup2(fd, 1); dup2(fd, 2); close(fd); }
        snprintf(path, sizeof path, "%s/%s", F.bindir, argv[0]);
        execv(path, argv);
        _exit(127);
    }
    if (p > 0 && F.n_pid < FM_PROCS) F.pid[F.n_pid++] = p;
    return p;
}

static void stop_children(void)
{
    int i, k;
    for (i = 0; i < F.n_pid; i++) if (F.pid[i] > 0) kill(F.pid[i], SIGTERM);
    for (k = 0; k < 50; k++) {
        int left = 0;
        for (i = 0; i < F.n_pid; i++) {
            if (F.pid[i] <= 0) continue;
            if (waitpid(F.pid[i], NULL, WNOHANG) == F.pid[i]) F.pid[i] = -1;
            else left++;
        }
        if (!left) return;
        {
            struct timespec ts = { 0, 100000000L };
            nanosleep(&ts, NULL);
        }
    }
    for (i = 0; i < F.n_pid; i++)
        if (F.pid[i] > 0) { kill(F.pid[i], SIGKILL); waitpid(F.pid[i], NULL, 0); }
}

static const char *fname(int f) { return f == 0 ? "line" : f == 1 ? "triangle" : "column"; }
static const char *bname(int b) { return b == 0 ? "weighted" : b == 1 ? "subsumption" : "vecsum"; }

/* A robot's journal: only for a robot a --fault restarts. */
static int journaled(int k)
{
    int i;
    for (i = 0; i < F.n_faults; i++)
        if (F.faults[i].slot == k) return 1;
    return 0;
}

/* The tandem-rover process of robot k (all robots with --procs single). */
static pid_t spawn_rover(int k)
{
    char n_s[16], w_s[32], id_s[32], journal[700];
    char *fo = (char *)fname(F.formation), *bl = (char *)bname(F.blend);
    char *rv[32] = { "tandem-rover", "--id", id_s, "--robots", n_s, "--world", w_s,
                     "--formation", fo, "--blend", bl, "--lockstep",
                     "--formation-law", F.law_kanayama ? "kanayama" : "seed",
                     "--ref-heading", F.ref_goal ? "goal" : "mean",
                     "--localize", F.localize_off ? "off" : "on" };
    int n = 18;
    snprintf(n_s, sizeof n_s, "%d", F.robots);
    snprintf(w_s, sizeof w_s, "%s", rover_world_name(F.world));
    if (F.batch) rv[n++] = "--batch";
    if (journaled(k)) {
        snprintf(journal, sizeof journal, "%s/rover_%d.journal", F.out, k);
        rv[n++] = "--journal";
        rv[n++] = journal;
    }
    scenario_argv_drop(&F.drop, rv, &n, 32);
    if (F.single) snprintf(id_s, sizeof id_s, "1-%d", F.robots);
    else snprintf(id_s, sizeof id_s, "%d", k);
    return spawn(rv);
}

static int start_children(void)
{
    char n_s[16], w_s[32], seed_s[24], expect_s[16];
    int k, procs = F.single ? 1 : F.robots;
    snprintf(n_s, sizeof n_s, "%d", F.robots);
    snprintf(w_s, sizeof w_s, "%s", rover_world_name(F.world));
    snprintf(seed_s, sizeof seed_s, "%ld", F.seed);
    snprintf(expect_s, sizeof expect_s, "%d", procs + 1);
    {
        char *sim[32] = { "tandem-sim", "--lockstep", "--no-arms", "--rovers", n_s, "--world", w_s,
                          "--formation", (char *)fname(F.formation),
                          "--seed", seed_s, "--expect", expect_s, "--timeout-ms", F.timeout_ms };
        int n = 15;
        if (F.batch) sim[n++] = "--rover-batch";
        scenario_argv_drop(&F.drop, sim, &n, 32);
        if (spawn(sim) <= 0) return -1;
    }
    for (k = 1; k <= procs; k++) {
        F.rover_pid[k] = spawn_rover(k);
        if (F.rover_pid[k] <= 0) return -1;
    }
    return 0;
}

/* ---- lockstep ---------------------------------------------------------------- */

static void ack(int64_t step)
{
    lockstep_ack(F.lcm, "tandem-scenario", F.ack_seq++, step, FM_PERIOD, 0);
}

static int64_t mono_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_clock_t *m, void *u)
{
    (void)rb; (void)ch; (void)u;
    if (m->step < F.clock_step) return;
    if (m->step == F.answered) F.clock_repeat = 1;
    F.clock_step = m->step;
    F.sim_time = m->sim_time_s;
    F.have_clock = 1;
    F.last_clock_ns = mono_ns();
}

/* When the last clock seen is a step everyone answers and nothing has
 * moved for a while, the simulator is waiting there: answer that step
 * again in case our ack was lost. (The simulator itself re-announces a
 * step whose answers are missing, sim_main.c; only it may publish
 * SIM_CLOCK, auth_acl.c.) */
static void nudge(void)
{
    const int64_t k = F.clock_step;
    if (k % FM_PERIOD) return;
    ack(k);
}

/* ---- metrics from ground truth ------------------------------------------------- */

static int alive_ids(const tandem_rover_truth_t *m, int32_t *ids)
{
    int i, n = 0;
    for (i = 0; i < m->n; i++) if (m->alive[i]) ids[n++] = m->robot[i];
    return n;
}

static void take_state(const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    if (i < 0 || i >= F.robots) return;
    if (F.have_state[i] && m->mode == TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE && F.mode[i] != TANDEM_ROVER_STATE_T_MODE_DEAD_ZONE)
        F.escapes++;
    F.mode[i] = m->mode;
    F.state_type[i] = m->formation;
    if (isfinite(m->formation_scale) && m->formation_scale > 0.0) F.state_scale[i] = m->formation_scale;
    memcpy(F.weight[i], m->weight, sizeof F.weight[i]);
    {
        const pose2 team = { m->x_m, m->y_m, m->theta_rad };
        rover_world_from_team(&F.layout, &team, &F.est[i]);
    }
    F.have_state[i] = 1;
}

static void ring_put(const tandem_rover_state_t *m)
{
    const int i = m->robot - 1;
    if (i < 0 || i >= F.robots || m->step < 0) return;
    F.ring[i][(m->step / FM_PERIOD) % FM_RING] = *m;
}

/* Robot i's state of step k from the ring, or NULL. */
static const tandem_rover_state_t *ring_get(int i, int64_t k)
{
    const tandem_rover_state_t *m = &F.ring[i][(k / FM_PERIOD) % FM_RING];
    return m->step == k && m->robot == i + 1 ? m : NULL;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_state_t *m, void *u)
{
    (void)rb; (void)ch; (void)u;
    ring_put(m);
}

static void on_states(const lcm_recv_buf_t *rb, const char *ch, const tandem_rovers_state_t *m, void *u)
{
    int i;
    (void)rb; (void)ch; (void)u;
    for (i = 0; i < m->n; i++) ring_put(&m->state[i]);
}

/* Truth at step k is taken with every live robot's state of the cycle
 * before; 0 while one of them is missing (lost: the simulator announces
 * k again and the robots publish it again). */
/* --fault: robot id's process was down at step k (it published no state). */
static int process_down(int id, int64_t k)
{
    return id >= 1 && id <= FM_MAX && k > F.down_after[id] && k < F.up_at[id];
}

static int states_for_truth(const tandem_rover_truth_t *m)
{
    const int64_t k = m->step - FM_PERIOD;
    int i;
    if (k < FM_PERIOD) return 1;               /* robots start at their first period */
    for (i = 0; i < m->n; i++) {
        const int r = m->robot[i] - 1;
        if (m->alive[i] && r >= 0 && r < F.robots && !(F.killed && r + 1 == F.kill_id) && !process_down(r + 1, k) &&
            !ring_get(r, k))
            return 0;
    }
    for (i = 0; i < F.robots; i++) {
        const tandem_rover_state_t *st = ring_get(i, k);
        if (st) take_state(st);
    }
    return 1;
}

static void on_truth(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_truth_t *m, void *u)
{
    int32_t ids[FM_MAX];
    int i, n, lowest = -1;
    double cx = 0, cy = 0, s = 0, c = 0, th0, sq = 0, mx = 0, t = m->sim_time_s;
    int all_at = 1;
    (void)rb; (void)ch; (void)u;
    if (m->n != F.robots || m->step <= F.last_truth_step || !states_for_truth(m)) return;
    F.last_truth_step = m->step;
    n = alive_ids(m, ids);
    if (n == 0) return;
    for (i = 0; i < m->n; i++) {
        if (!m->alive[i]) continue;
        if (lowest < 0) lowest = i;
        cx += m->x_m[i]; cy += m->y_m[i];
        s += sin(m->theta_rad[i]); c += cos(m->theta_rad[i]);
        if (m->min_clearance_m[i] < F.min_clear) F.min_clear = m->min_clearance_m[i];
        /* path and smoothness (mean |dw/dt|) */
        if (F.have_prev[i]) {
            const double w = vec2_angle_diff_rad(m->theta_rad[i], F.prev_th[i]) / (FM_PERIOD * 1e-3);
            F.path[i] += hypot(m->x_m[i] - F.prev_x[i], m->y_m[i] - F.prev_y[i]);
            if (F.have_prev_w[i] && !F.reached) {
                F.sum_dw += fabs(w - F.prev_w[i]) / (FM_PERIOD * 1e-3);
                F.n_dw++;
            }
            F.prev_w[i] = w;
            F.have_prev_w[i] = 1;
        }
        F.prev_x[i] = m->x_m[i]; F.prev_y[i] = m->y_m[i]; F.prev_th[i] = m->theta_rad[i];
        F.have_prev[i] = 1;
        if (F.have_state[i] && !process_down(m->robot[i], m->step - FM_PERIOD)) {
            /* localization error: the robot's own estimate of O against
             * the truth (both world frame); none while its process is down */
            const double e = hypot(F.est[i].x_m - m->x_m[i], F.est[i].y_m - m->y_m[i]);
            F.loc_sum_sq += e * e;
            F.loc_n++;
            if (e > F.loc_max) F.loc_max = e;
        }
        if (F.truth_csv)
            fprintf(F.truth_csv, "%.3f,%d,%.4f,%.4f,%.4f,%.4f,%d,%.4f,%.4f,%.4f\n", t, m->robot[i],
                    m->x_m[i], m->y_m[i], m->theta_rad[i], m->min_clearance_m[i], m->collisions[i],
                    F.est[i].x_m, F.est[i].y_m, F.est[i].theta_rad);
    }
    cx /= n; cy /= n;
    th0 = atan2(s, c);
    if (lowest >= 0 && F.have_state[lowest]) F.type_now = F.state_type[lowest];
    if (lowest >= 0 && F.have_state[lowest]) F.scale_now = F.state_scale[lowest];
    /* formation error: slots of the formation the team is flying now around
     * the true centroid and mean heading; robot slots by sorted alive id */
    for (i = 0; i < m->n; i++) {
        double xy[2], r[2], e, gx, gy;
        int rank;
        if (!m->alive[i]) continue;
        rank = formation_slot_of(ids, n, m->robot[i]);
        formation_slot_xy(xy, F.type_now, n, rover_world_slot(F.type_now, n, rank), 1.0, F.scale_now);
        vec2_rotate(r, xy[0], xy[1], th0);
        e = hypot(m->x_m[i] - cx - r[0], m->y_m[i] - cy - r[1]);
        sq += e * e;
        if (e > mx) mx = e;
        /* at the goal: every robot near its nominal slot around the goal */
        formation_slot_xy(xy, F.formation, n, rover_world_slot(F.formation, n, rank), 1.0, 1.0);
        gx = F.layout.goal_m[0] + xy[0];
        gy = F.layout.goal_m[1] + xy[1];
        if (hypot(m->x_m[i] - gx, m->y_m[i] - gy) > 0.75) all_at = 0;
    }
    if (!F.reached) {
        F.samples++;
        F.sum_sq_err += sq / n;
        if (mx > F.max_err) F.max_err = mx;
        if (mx > FM_OUT_TOL) F.out_samples++;
    }
    if (F.err_csv) fprintf(F.err_csv, "%.3f,%.4f,%.4f,%d\n", t, sqrt(sq / n), mx, F.type_now);
    if (F.w_csv && lowest >= 0)
        fprintf(F.w_csv, "%.3f,%.3f,%.3f,%.3f,%.3f,%d\n", t, F.weight[lowest][0], F.weight[lowest][1],
                F.weight[lowest][2], F.weight[lowest][3], F.mode[lowest]);
    if (F.snap_csv && t - F.last_snap_t >= 5.0 - 1e-9) {
        F.last_snap_t = t;
        for (i = 0; i < m->n; i++)
            if (m->alive[i]) fprintf(F.snap_csv, "%.4f,%.4f\n", m->x_m[i], m->y_m[i]);
        if (lowest >= 0) fprintf(F.snap_csv, "%.4f,%.4f\n", m->x_m[lowest], m->y_m[lowest]);
        fprintf(F.snap_csv, "\n");
    }
    F.collisions = 0;
    for (i = 0; i < m->n; i++) F.collisions += m->collisions[i];
    if (!F.reached && all_at && hypot(cx - F.layout.goal_m[0], cy - F.layout.goal_m[1]) < 0.5) {
        F.reached = 1;
        F.time_to_goal = t;
    }
}

/* ---- output -------------------------------------------------------------------- */

static void write_plots(void)
{
    FILE *g = scenario_fopen(F.out, "plots.gp");
    int i;
    if (!g) return;
    fprintf(g, "set datafile separator ','\nset terminal pngcairo size 1100,700\n");
    fprintf(g, "set output 'paths.png'\nset size ratio -1\nset title 'formation %s, world %s, blend %s: paths (ground truth), snapshots every 5 s'\n",
            fname(F.formation), rover_world_name(F.world), bname(F.blend));
    /* the whole world with the goal disc inside it; the key below the plot,
     * where it covers nothing */
    fprintf(g, "set xlabel 'x (m)'\nset ylabel 'y (m)'\nset key below horizontal\n"
               "set xrange [%g:%g]\nset yrange [%g:%g]\n",
            F.layout.x_min_m, F.layout.x_max_m, F.layout.y_min_m, F.layout.y_max_m);
    for (i = 0; i < F.layout.n_obst; i++) {
        const rover_obstacle *o = &F.layout.obst[i];
        if (o->kind == ROVER_OBST_CIRCLE) {
            fprintf(g, "set object %d circle at %g,%g size %g fc rgb 'gray40' fs solid\n", i + 1,
                    o->cx_m, o->cy_m, o->r_m);
        } else {
            const double c = cos(o->angle_rad), s = sin(o->angle_rad);
            fprintf(g, "set object %d polygon from %g,%g to %g,%g to %g,%g to %g,%g to %g,%g fc rgb 'gray40' fs solid\n",
                    i + 1,
                    o->cx_m + o->hx_m * c - o->hy_m * s, o->cy_m + o->hx_m * s + o->hy_m * c,
                    o->cx_m - o->hx_m * c - o->hy_m * s, o->cy_m - o->hx_m * s + o->hy_m * c,
                    o->cx_m - o->hx_m * c + o->hy_m * s, o->cy_m - o->hx_m * s - o->hy_m * c,
                    o->cx_m + o->hx_m * c + o->hy_m * s, o->cy_m + o->hx_m * s - o->hy_m * c,
                    o->cx_m + o->hx_m * c - o->hy_m * s, o->cy_m + o->hx_m * s + o->hy_m * c);
        }
    }
    fprintf(g, "set object %d circle at %g,%g size 0.3 fc rgb 'green' fs transparent solid 0.4\n",
            F.layout.n_obst + 1, F.layout.goal_m[0], F.layout.goal_m[1]);
    fprintf(g, "plot ");
    for (i = 1; i <= F.robots && i <= 12; i++)
        fprintf(g, "'truth.csv' using ($2==%d?$3:1/0):4 with points pt 7 ps 0.25 title 'robot %d', ", i, i);
    fprintf(g, "'snapshots.csv' using 1:2 with linespoints lc rgb 'black' pt 7 ps 0.6 dt 2 title 'formation every 5 s'\n");
    /* the time plots carry none of the world's discs and their own ranges */
    fprintf(g, "unset object\nset autoscale xy\nset key default\n");
    fprintf(g, "set output 'formation_error.png'\nset size noratio\nset title 'formation error (ground truth)'\n"
               "set xlabel 't (s)'\nset ylabel 'formation error (m)'\n"
               "set y2label 'formation type (0 line, 1 triangle, 2 column)'\n"
               "set y2range [-0.2:2.2]\nset y2tics 0,1,2\n"
               "plot 'formation_error.csv' using 1:2 with lines lw 2 title 'rms over robots', "
               "'' using 1:3 with lines title 'max over robots', '' using 1:4 axes x1y2 with steps title 'formation type'\n");
    fprintf(g, "set output 'weights.png'\nunset y2label\nunset y2tics\nset title 'behaviour weights of the lowest-id robot (normalised)'\n"
               "set ylabel 'normalised weight (1)'\nset yrange [-0.05:1.05]\n"
               "plot 'weights.csv' using 1:2 with lines title 'goal', '' using 1:3 with lines title 'formation', "
               "'' using 1:4 with lines title 'avoid', '' using 1:5 with lines title 'exception'\n");
    fclose(g);
    scenario_gnuplot(F.out, "plots.gp");
}

/* The run's success criteria (the seed-003 must-show figures): the team
 * reached the goal without a collision, each robot's own pose estimate
 * within 0.25 m of the truth, >= 2 formation changes in the corridor and
 * >= 1 dead-zone escape in the dead zone. Appends the failed ones to buf;
 * returns how many failed. */
static int formation_criteria(char *buf, size_t cap)
{
    const scenario_criterion k[] = {
        { !F.reached, "reached_goal" },
        { F.collisions != 0, "collisions" },
        { F.loc_n && !(F.loc_max <= 0.25), "loc_err_max_m" },
        { F.world == ROVER_WORLD_CORRIDOR && F.formation_changes < 2, "formation_changes" },
        { F.world == ROVER_WORLD_DEADZONE && F.escapes < 1, "dead_zone_escapes" },
        { F.lost_lockstep, "lockstep" },
        { F.restart_failed, "restarts" },
    };
    return scenario_failed_criteria(k, (int)(sizeof k / sizeof k[0]), buf, cap);
}

static void write_summary(double wall_s)
{
    json_out j;
    double path = 0.0;
    int i, n = 0;
    if (json_open(&j, F.out, "summary.json") != 0) return;
    for (i = 0; i < F.robots; i++)
        if (F.have_prev[i] && i + 1 != F.kill_id) { path += F.path[i]; n++; }
    json_str(&j, "scenario", "formation");
    json_str(&j, "formation", fname(F.formation));
    json_str(&j, "world", rover_world_name(F.world));
    json_str(&j, "blend", bname(F.blend));
    json_str(&j, "formation_law", F.law_kanayama ? "kanayama" : "seed");
    json_str(&j, "ref_heading", F.ref_goal ? "goal" : "mean");
    json_bool(&j, "localize", !F.localize_off);
    json_int(&j, "robots", F.robots);
    json_int(&j, "seed", F.seed);
    json_int(&j, "killed_robot", F.kill_id > 0 && F.killed ? F.kill_id : 0);
    json_bool(&j, "reached_goal", F.reached);
    json_num(&j, "time_to_goal_s", F.reached ? F.time_to_goal : NAN);
    json_num(&j, "rms_formation_err_m", F.samples ? sqrt(F.sum_sq_err / F.samples) : NAN);
    json_num(&j, "max_formation_err_m", F.max_err);
    json_num(&j, "time_out_of_formation_frac", F.samples ? (double)F.out_samples / F.samples : NAN);
    json_num(&j, "min_clearance_m", F.min_clear);
    json_int(&j, "collisions", F.collisions);
    json_int(&j, "kills", F.kills);
    json_int(&j, "restarts", F.restarts);
    json_int(&j, "formation_changes", F.formation_changes);
    json_int(&j, "dead_zone_escapes", F.escapes);
    json_num(&j, "path_length_m", n ? path / n : NAN);
    json_num(&j, "smoothness", F.n_dw ? F.sum_dw / F.n_dw : NAN);
    json_num(&j, "loc_err_rms_m", F.loc_n ? sqrt(F.loc_sum_sq / F.loc_n) : NAN);
    json_num(&j, "loc_err_max_m", F.loc_n ? F.loc_max : NAN);
    json_num(&j, "sim_time_s", F.sim_time);
    json_num(&j, "wall_time_s", wall_s);
    json_str(&j, "exit_reason", F.restart_failed ? "restart_failed" : F.lost_lockstep ? "lockstep_lost" :
                                F.reached ? "completed" : "goal_not_reached");
    json_str(&j, "failed_criteria", F.failed);
    json_close(&j);
}

/* Checked subscriptions (auth_bus_subscribe) of the typed handlers above. */
/* SIM_ACK: the last step each rover process answered (--fault). */
static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const tandem_clock_ack_t *m, void *u)
{
    char *e;
    long k;
    (void)rb; (void)ch; (void)u;
    if (m->leaving || strncmp(m->name, "tandem-rover-", 13) != 0) return;
    k = strtol(m->name + 13, &e, 10);
    if (*e || k < 1 || k > FM_MAX) return;
    if (m->step > F.rover_ack[k]) F.rover_ack[k] = m->step;
}

/* --fault kill:roverK:T[:R], at a step due to be answered (every robot's
 * cycle runs at these steps). Kill once the robot's process has answered
 * the step (so its journal holds this cycle: the same state whatever the
 * machine's speed) and tell the simulator it left; restart at the first
 * such step after R and hold the step until the new process has run its
 * cycle of it (its state is in). 1: go on, 0: hold the step, -1: the
 * restart failed. */
static int faults_step(void)
{
    int i, j;
    for (i = 0; i < F.n_faults; i++) {
        scenario_fault *f = &F.faults[i];
        const int k = f->slot;
        char name[64];
        snprintf(name, sizeof name, "tandem-rover-%d", k);
        if (f->stage == 0 && F.sim_time >= f->kill_s) {
            if (F.rover_ack[k] < F.clock_step || !ring_get(k - 1, F.clock_step)) return 0;
            kill(F.rover_pid[k], SIGKILL);
            waitpid(F.rover_pid[k], NULL, 0);
            for (j = 0; j < F.n_pid; j++)
                if (F.pid[j] == F.rover_pid[k]) F.pid[j] = -1;   /* reaped: its pid may be reused */
            F.rover_pid[k] = -1;
            F.rover_ack[k] = -1;
            F.down_after[k] = F.clock_step;
            F.up_at[k] = INT64_MAX;
            lockstep_ack(F.lcm, name, 0, F.clock_step, FM_PERIOD, 1);
            fprintf(stderr, "formation: fault: rover %d's process killed at t = %.2f s\n", k, F.sim_time);
            F.kills++;
            f->stage = f->restart_s >= 0.0 ? 1 : 3;
        }
        if (f->stage == 1 && F.sim_time >= f->restart_s) {
            F.rover_pid[k] = spawn_rover(k);
            if (F.rover_pid[k] <= 0) return -1;
            fprintf(stderr, "formation: fault: rover %d's process restarted at t = %.2f s\n", k, F.sim_time);
            F.hold_since_s = scenario_wall_s();
            f->stage = 2;
        }
        if (f->stage == 2) {
            /* its ack and its state of this step (published after its
             * command): the simulator waits for no command from a robot
             * silent this long, so the step must not move on before it */
            if (F.rover_ack[k] < F.clock_step || !ring_get(k - 1, F.clock_step)) {
                if (scenario_wall_s() - F.hold_since_s > 60.0) {
                    fprintf(stderr, "formation: fault: rover %d did not rejoin within 60 s\n", k);
                    return -1;
                }
                return 0;
            }
            F.up_at[k] = F.clock_step;
            F.restarts++;
            f->stage = 3;
        }
    }
    return 1;
}

AUTH_TYPED_HANDLER(tandem_clock_ack_t, raw_on_ack, on_ack)
AUTH_TYPED_HANDLER(tandem_sim_clock_t, raw_on_clock, on_clock)
AUTH_TYPED_HANDLER(tandem_rover_truth_t, raw_on_truth, on_truth)
AUTH_TYPED_HANDLER(tandem_rover_state_t, raw_on_state, on_state)
AUTH_TYPED_HANDLER(tandem_rovers_state_t, raw_on_states, on_states)

/* ---- run ------------------------------------------------------------------------- */

static void on_sig(int s) { (void)s; }

static int run(int argc, char **argv)
{
    double wall0, next_progress;
    int i, last_type = -1, changes = 0;
    char self[512];
    ssize_t len;
    memset(&F, 0, sizeof F);
    F.min_clear = INFINITY;
    F.scale_now = 1.0;
    F.clock_step = -1;
    F.answered = -1;
    F.last_truth_step = -1;
    F.last_snap_t = -1e9;
    if (parse(argc, argv) != 0) return 2;
    if (scenario_mkdir(F.out) != 0) return 1;
    len = readlink("/proc/self/exe", self, sizeof self - 1);
    if (len <= 0) { fprintf(stderr, "formation: cannot find my own binary\n"); return 1; }
    self[len] = '\0';
    snprintf(F.bindir, sizeof F.bindir, "%s", self);
    if (strrchr(F.bindir, '/')) *strrchr(F.bindir, '/') = '\0';
    if (!F.url) {
        snprintf(F.url_buf, sizeof F.url_buf, "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=4194304",
                 20000 + (int)(getpid() % 20000));
        F.url = F.url_buf;
    }
    if (rover_world_layout(&F.layout, F.world, F.robots, 1.0, F.formation) != 0) return 2;
    F.type_now = F.formation;
    F.lcm = lcm_create(F.url);
    if (!F.lcm) { fprintf(stderr, "formation: cannot open LCM at %s\n", F.url); return 1; }
    F.sub_clock = auth_bus_subscribe(F.lcm, "SIM_CLOCK", raw_on_clock, NULL);
    F.sub_truth = auth_bus_subscribe(F.lcm, "ROVER_TRUTH", raw_on_truth, NULL);
    F.sub_state = auth_bus_subscribe(F.lcm, "ROVER[0-9]+_STATE", raw_on_state, NULL);
    F.sub_states = auth_bus_subscribe(F.lcm, "ROVERS_STATE", raw_on_states, NULL);
    F.sub_ack = auth_bus_subscribe(F.lcm, "SIM_ACK", raw_on_ack, NULL);
    lcm_subscription_set_queue_capacity(F.sub_ack, 100000);
    lcm_subscription_set_queue_capacity(F.sub_clock, 0);
    lcm_subscription_set_queue_capacity(F.sub_truth, 100000);
    lcm_subscription_set_queue_capacity(F.sub_state, 100000);
    lcm_subscription_set_queue_capacity(F.sub_states, 100000);
    F.truth_csv = scenario_fopen(F.out, "truth.csv");
    F.err_csv = scenario_fopen(F.out, "formation_error.csv");
    F.w_csv = scenario_fopen(F.out, "weights.csv");
    F.snap_csv = scenario_fopen(F.out, "snapshots.csv");
    {
        char p[700];
        snprintf(p, sizeof p, "%s/children.log", F.out);
        remove(p);
        for (i = 1; i <= F.robots; i++) {   /* a fresh run: a restart reads what this one wrote */
            snprintf(p, sizeof p, "%s/rover_%d.journal", F.out, i);
            remove(p);
        }
    }
    for (i = 0; i <= FM_MAX; i++) {
        F.rover_ack[i] = -1;
        F.down_after[i] = INT64_MAX;
        F.up_at[i] = INT64_MAX;
    }
    signal(SIGPIPE, SIG_IGN);
    signal(SIGINT, on_sig);
    wall0 = scenario_wall_s();
    next_progress = wall0 + 5.0;
    if (start_children() != 0) { stop_children(); return 1; }
    fprintf(stderr, "formation: %d robots, %s, world %s, blend %s, seed %ld on %s\n", F.robots,
            fname(F.formation), rover_world_name(F.world), bname(F.blend), F.seed, F.url);
    F.last_clock_ns = mono_ns();
    /* register before the first step (the sim waits for --expect participants) */
    while (scenario_wall_s() - wall0 < 30.0) {
        ack(0);
        lcm_handle_timeout(F.lcm, 100);
        if (F.have_clock) break;
    }
    for (;;) {
        const int rc = lcm_handle_timeout(F.lcm, 50);
        const int64_t due = F.clock_step - F.clock_step % FM_PERIOD;
        if (rc < 0) break;
        if (F.clock_repeat) {
            F.clock_repeat = 0;          /* our ack was lost: answer again */
            if (F.answered >= 0) ack(F.answered);
        }
        int fault_rc = 1;
        if (F.have_clock && due > F.answered && F.clock_step % FM_PERIOD == 0 &&
            F.last_truth_step >= F.clock_step && (fault_rc = faults_step()) < 0) {
            F.restart_failed = 1;
            break;
        }
        if (fault_rc == 1 && F.have_clock && due > F.answered && F.clock_step % FM_PERIOD == 0 &&
            F.last_truth_step >= F.clock_step) {
            /* robot states of the last cycle: protocol counts */
            int lo = -1;
            for (i = 0; i < F.robots; i++)
                if (F.have_state[i] && (i + 1 != F.kill_id || !F.killed)) { lo = i; break; }
            if (lo >= 0) {
                if (last_type >= 0 && F.state_type[lo] != last_type) changes++;
                last_type = F.state_type[lo];
            }
            F.formation_changes = changes;
            if (F.kill_id > 0 && !F.killed && F.sim_time >= F.kill_t_s) {
                tandem_sim_control_t c;
                memset(&c, 0, sizeof c);
                c.command = TANDEM_SIM_CONTROL_T_KILL_ROBOT;
                c.target = F.kill_id;
                AUTH_PUBLISH(tandem_sim_control_t, F.lcm, "SIM_CONTROL", &c);
                if (!F.single && F.rover_pid[F.kill_id] > 0) {
                    /* the process dies without a word; tell the simulator it
                     * left rather than make it wait for its lockstep timeout */
                    char name[64];
                    kill(F.rover_pid[F.kill_id], SIGKILL);
                    snprintf(name, sizeof name, "tandem-rover-%d", F.kill_id);
                    lockstep_ack(F.lcm, name, 0, F.clock_step, FM_PERIOD, 1);
                }
                F.killed = 1;
                fprintf(stderr, "formation: killed robot %d at t = %.2f s\n", F.kill_id, F.sim_time);
            }
            F.answered = F.clock_step;
            if (F.reached || F.sim_time >= F.max_time_s) break;
            ack(F.clock_step);
        } else if (F.have_clock && mono_ns() - F.last_clock_ns > 500000000LL) {
            nudge();
            F.last_clock_ns = mono_ns();
        }
        if (scenario_wall_s() >= next_progress) {
            /* one line every few seconds of wall time */
            const double wall = scenario_wall_s() - wall0;
            next_progress += 5.0;
            fprintf(stderr, "formation: t %.1f s (%.1fx real time), collisions %d, formation changes %d, "
                            "dead-zone escapes %d%s\n", F.sim_time, wall > 0.0 ? F.sim_time / wall : 0.0,
                    F.collisions, F.formation_changes, F.escapes, F.reached ? ", at the goal" : "");
        }
        if (F.sim_time > F.max_time_s + 5.0) {
            /* the world ran past the limit without us: every participant
             * was dropped (a machine too loaded for --lockstep-timeout-ms) */
            fprintf(stderr, "formation: the simulator went on without the lockstep participants; giving up\n");
            F.lost_lockstep = 1;
            break;
        }
                if (scenario_wall_s() - wall0 > 20.0 * F.max_time_s + 60.0) {
            fprintf(stderr, "formation: no progress; giving up\n");
            break;
        }
    }
    stop_children();
    if (F.truth_csv) fclose(F.truth_csv);
    if (F.err_csv) fclose(F.err_csv);
    if (F.w_csv) fclose(F.w_csv);
    if (F.snap_csv) fclose(F.snap_csv);
    F.truth_csv = F.err_csv = F.w_csv = F.snap_csv = NULL;
    F.n_failed = formation_criteria(F.failed, sizeof F.failed);
    write_summary(scenario_wall_s() - wall0);
    write_plots();
    lcm_unsubscribe(F.lcm, F.sub_clock);
    lcm_unsubscribe(F.lcm, F.sub_truth);
    lcm_unsubscribe(F.lcm, F.sub_state);
    lcm_unsubscribe(F.lcm, F.sub_states);
    lcm_unsubscribe(F.lcm, F.sub_ack);
    lcm_destroy(F.lcm);
    printf("formation %s world %s blend %s law %s robots %d seed %ld: reached_goal=%d time_to_goal_s=%.2f "
           "rms_formation_err_m=%.3f max_formation_err_m=%.3f min_clearance_m=%.3f collisions=%d "
           "formation_changes=%d dead_zone_escapes=%d loc_err_max_m=%.3f sim_time_s=%.1f wall_time_s=%.1f\n",
           fname(F.formation), rover_world_name(F.world), bname(F.blend),
           F.law_kanayama ? "kanayama" : "seed", F.robots, F.seed,
           F.reached, F.reached ? F.time_to_goal : NAN,
           F.samples ? sqrt(F.sum_sq_err / F.samples) : NAN, F.max_err, F.min_clear,
           F.collisions, F.formation_changes, F.escapes, F.loc_n ? F.loc_max : NAN, F.sim_time,
           scenario_wall_s() - wall0);
    if (F.n_failed) {
        printf("formation: FAILED %d criteria: %s\n", F.n_failed, F.failed);
        return 3;
    }
    printf("formation: all criteria met\n");
    return 0;
}

const scenario_def scenario_formation = {
    "formation",
    "Pioneer team in line/triangle/column formation to a goal (seed 003)",
    run
};
