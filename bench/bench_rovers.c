/* bench_rovers: speed of the Pioneer team simulation (figures printed,
 * nothing asserted).
 *  1. in-process, one core: tandem-sim's rover model (ODE world, hash space
 *     broad phase, full 8-transducer sonar rings fired in the Pioneer
 *     sequence, camera) stepped at 1 kHz for N = 3, 10, 30, 100 robots that
 *     drive and turn; simulated seconds per wall second and sonar rays cast
 *     per wall second.
 *  2. the whole system in lockstep over LCM: tandem-sim + one tandem-rover
 *     process hosting all N robots, with the sensor/command link per robot
 *     and batched, in turn. make bench runs this program under
 *     `taskset -c 0`, so the daemons share one core and the wall figure is
 *     a one-core figure.
 * Usage: bench_rovers [SIM_SECONDS] [BIN_DIR]  (default 20 s, build/bin)
 */
/* NOLINTBEGIN(bugprone-suspicious-include): the simulator's sources, statics and all */
#include "sim_world.c"
#include "sim_lockstep.c"
#include "sim_rovers.c"
#include "sim_rovers_sense.c"
/* NOLINTEND(bugprone-suspicious-include) */
#include <time.h>
#include <sys/resource.h>
#include <unistd.h> /* getpid */
#include "auth_bus.h"
#include "proc.h"

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static double children_cpu_s(void)
{
    struct rusage ru;
    getrusage(RUSAGE_CHILDREN, &ru);
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

static double wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void in_process(int n, double sim_s)
{
    static sim_world w;
    static sim_rovers team;
    sim_config cfg;
    const int64_t steps = (int64_t)(sim_s / SIM_DT_S);
    int64_t k;
    double t0, t1, c0, c1;
    int i;
    memset(&w, 0, sizeof w);
    memset(&cfg, 0, sizeof cfg);
    w.seed = 1;
    w.lockstep = 1;
    cfg.rovers = n;
    snprintf(cfg.rover_world, sizeof cfg.rover_world, "obstacles");
    sim_world_create(&w);
    if (sim_rovers_ops.create(&team, &w, &cfg) != 0)
        return;
    t0 = wall_s();
    c0 = cpu_s();
    for (k = 0; k < steps; k++) {
        if (k % 50 == 0) /* a 20 Hz "controller": drive and weave */
            for (i = 1; i <= n; i++)
                sim_rovers_set_command(&team, i, 0.4, 0.5 * sin(0.5 * (double)k * SIM_DT_S + i),
                                       w.step);
        sim_rovers_ops.before_step(&team, &w);
        sim_world_step(&w);
        sim_rovers_ops.after_step(&team, &w);
    }
    t1 = wall_s();
    c1 = cpu_s();
    printf("  N = %3d: %5.1f s simulated: %6.2f s CPU = %7.1fx real time per core "
           "(%6.2f s wall = %6.1fx), %9.0f sonar rays per CPU second\n",
           n, sim_s, c1 - c0, sim_s / (c1 - c0), t1 - t0, sim_s / (t1 - t0),
           (double)sim_rovers_rays_cast(&team) / (c1 - c0));
    sim_rovers_ops.destroy(&team, &w);
    sim_world_destroy(&w);
}

/* tandem-sim (rovers only) and one tandem-rover hosting all N robots, in
 * lockstep over a private udpm bus, for sim_s simulated seconds (they
 * inherit the bench's CPU affinity). */
static void lockstep_system(auth_bus *bus, int n, double sim_s, const char *bin, int batch)
{
    char n_s[16], ids[32], steps_s[32], url[128];
    const char *sim[] = { "tandem-sim", "--lockstep", "--no-arms", "--rovers",
                          n_s,          "--world",    "open",      "--expect",
                          "1",          "--steps",    steps_s,     batch ? "--rover-batch" : NULL,
                          NULL };
    const char *rover[] = {
        "tandem-rover",           "--id", ids, "--robots", n_s, "--world", "open", "--lockstep",
        batch ? "--batch" : NULL, NULL
    };
    proc_set ps;
    pid_t sim_pid;
    int status = -1, k;
    double w0, w1, c0 = children_cpu_s(), cpu;
    snprintf(n_s, sizeof n_s, "%d", n);
    snprintf(ids, sizeof ids, "1-%d", n);
    snprintf(steps_s, sizeof steps_s, "%ld", (long)llround(sim_s / SIM_DT_S));
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0&recv_buf_size=4194304",
             20000 + (int)(getpid() % 10000));
    /* the role files this bus gives its children name rovers 1..n and the
     * host of them all (auth_bus_roster), as tandem-scenario formation's do */
    auth_bus_roster(bus, n);
    proc_init(&ps, bus, bin);
    w0 = wall_s();
    if (proc_spawn(&ps, rover, url, "/dev/null", "/dev/null") < 0 ||
        (sim_pid = proc_spawn(&ps, sim, url, "/dev/null", "/dev/null")) < 0) {
        printf("  N = %3d: could not start the daemons from %s\n", n, bin);
        proc_kill_all(&ps, 1.0);
        return;
    }
    /* no unbounded wait: give up at 1 simulated second per wall second */
    for (k = 0; k < (int)(sim_s * 1000.0) + 10000 && proc_poll(&ps, sim_pid, &status) == 0; k++)
        nanosleep(&(struct timespec){ 0, 1000000L }, NULL);
    w1 = wall_s();
    proc_kill_all(&ps, 2.0);
    cpu = children_cpu_s() - c0;
    if (status != 0) {
        printf("  N = %3d: tandem-sim did not finish (status %d)\n", n, status);
        return;
    }
    printf("  N = %3d, %-9s: %5.1f s simulated: %6.2f s CPU in both = %6.1fx real time per core "
           "(%6.2f s wall = %5.1fx)\n",
           n, batch ? "batched" : "per robot", sim_s, cpu, sim_s / cpu, w1 - w0, sim_s / (w1 - w0));
}

int main(int argc, char **argv)
{
    static const int ns[] = { 3, 10, 30, 100 };
    const double sim_s = argc > 1 ? atof(argv[1]) : 20.0;
    const char *bin = argc > 2 ? argv[2] : "build/bin";
    static auth_bus bus; /* the bench's: the cell's key (TANDEM_KEY_FILE), or --insecure by env */
    size_t i;
    printf("rover simulation, in process (physics + sonar rings + camera, no LCM), one core:\n");
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++)
        in_process(ns[i], sim_s);
    auth_bus_init(&bus);
    auth_bus_identity(&bus, AUTH_ROLE_TOOL, 0, 0); /* it signs nothing; it starts the daemons */
    if (auth_bus_start(&bus, "bench_rovers") != 0)
        return 1;
    printf("whole system in lockstep over LCM (tandem-sim + tandem-rover --id 1-N), sensor link\n"
           "per robot (ROVERk_*) and batched (ROVERS_*, --rover-batch / --batch) in turn:\n");
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        lockstep_system(&bus, ns[i], sim_s, bin, 0);
        lockstep_system(&bus, ns[i], sim_s, bin, 1);
    }
    return 0;
}
