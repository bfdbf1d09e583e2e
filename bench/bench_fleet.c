/* bench_fleet: the simulator alone with a large fleet (figures printed,
 * nothing asserted). tandem-sim's rover model in process (ODE world, hash
 * space, the Pioneer sonar sequence, camera, ground truth with its
 * clearance; no LCM) for N = 100, 300, 1000, 3000 robots on the open world's
 * start grid, each driving and weaving on a 20 Hz command, with the
 * neighbour queries through the grids and, in the same run, by the scan
 * over every robot (TANDEM_SIM_NEIGHBOURS=scan, the algorithm before).
 * Each configuration runs in its own child process so that its peak
 * memory is its own. Per row: simulated seconds per CPU second, CPU
 * microseconds per robot-step (one robot, one 1 ms step: flat across N
 * when the cost per robot does not grow with the fleet), the share of it
 * in physics and in sensing, sonar rays per CPU second, peak resident
 * memory. make bench runs it under `taskset -c 0` (one core).
 * Usage: bench_fleet [SCALE] [N...]  (SCALE multiplies the simulated time,
 * default 1: 4 s at 100 robots down to 0.4 s at 3000)
 */
/* NOLINTBEGIN(bugprone-suspicious-include): the simulator's sources, statics and all */
#include "sim_world.c"
#include "sim_lockstep.c"
#include "sim_rovers.c"
#include "sim_rovers_sense.c"
#include "sim_rovers_free.c"
/* NOLINTEND(bugprone-suspicious-include) */
#include <time.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static int run(int n, double sim_s, int scan)
{
    static sim_world w;
    static sim_rovers team;
    sim_config cfg;
    struct rusage ru;
    const int64_t steps = (int64_t)(sim_s / SIM_DT_S);
    int64_t k;
    double c0, c1, phys = 0.0, sense = 0.0, t;
    int i;
    if (scan)
        setenv("TANDEM_SIM_NEIGHBOURS", "scan", 1);
    memset(&w, 0, sizeof w);
    memset(&cfg, 0, sizeof cfg);
    w.seed = 1;
    w.lockstep = 1;
    cfg.rovers = n;
    snprintf(cfg.rover_world, sizeof cfg.rover_world, "open");
    if (sim_world_create(&w) != 0 || sim_rovers_ops.create(&team, &w, &cfg) != 0)
        return 1;
    c0 = cpu_s();
    for (k = 0; k < steps; k++) {
        if (k % 50 == 0) /* a 20 Hz "controller": drive and weave */
            for (i = 1; i <= n; i++)
                sim_rovers_set_command(&team, i, 0.4, 0.3 * sin(0.5 * (double)k * SIM_DT_S + i),
                                       w.step);
        t = cpu_s();
        sim_rovers_ops.before_step(&team, &w);
        sim_world_step(&w);
        phys += cpu_s() - t;
        t = cpu_s();
        sim_rovers_ops.after_step(&team, &w);
        sense += cpu_s() - t;
    }
    c1 = cpu_s();
    getrusage(RUSAGE_SELF, &ru);
    printf("  N = %4d %-5s %4.1f s sim: %7.2f sim-s/CPU-s, %6.3f us/robot-step "
           "(physics %4.1f %%, sensing %4.1f %%), %9.0f rays/CPU-s, peak %6.1f MB\n",
           n, scan ? "scan" : "grid", sim_s, sim_s / (c1 - c0),
           1e6 * (c1 - c0) / ((double)n * (double)steps), 100.0 * phys / (c1 - c0),
           100.0 * sense / (c1 - c0), (double)sim_rovers_rays_cast(&team) / (c1 - c0),
           (double)ru.ru_maxrss / 1024.0);
    fflush(stdout);
    sim_rovers_ops.destroy(&team, &w);
    sim_world_destroy(&w);
    return 0;
}

/* One configuration in a child process (its own peak memory). */
static void run_child(int n, double sim_s, int scan)
{
    int status;
    pid_t pid;
    fflush(stdout); /* the child must not print the parent's buffer again */
    pid = fork();
    if (pid == 0)
        _exit(run(n, sim_s, scan));
    if (pid < 0 || waitpid(pid, &status, 0) != pid || !WIFEXITED(status) ||
        WEXITSTATUS(status) != 0)
        printf("  N = %4d %-5s: did not run\n", n, scan ? "scan" : "grid");
}

int main(int argc, char **argv)
{
    static const int def_ns[] = { 100, 300, 1000, 3000 };
    const double scale = argc > 1 ? atof(argv[1]) : 1.0;
    int ns[16], count = 0, i;
    for (i = 2; i < argc && count < 16; i++)
        ns[count++] = atoi(argv[i]);
    if (count == 0)
        for (i = 0; i < 4; i++)
            ns[count++] = def_ns[i];
    printf("rover fleet, simulator alone in process (physics + sonar + camera + truth, no LCM),\n"
           "open world, one core; neighbours through the grids and by the scan (before):\n");
    for (i = 0; i < count; i++) {
        /* the same robot-steps at every size, at least 0.2 s */
        const double sim_s = fmax(0.2, scale * 400.0 / ns[i]);
        if (ns[i] < 1 || ns[i] > RV_MAX) {
            printf("  N = %d: outside 1..%d (ROVER_WORLD_MAX_ROBOTS)\n", ns[i], RV_MAX);
            continue;
        }
        run_child(ns[i], sim_s, 0);
        run_child(ns[i], sim_s, 1);
    }
    return 0;
}
