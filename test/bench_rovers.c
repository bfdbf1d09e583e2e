/* bench_rovers: speed of the Pioneer team simulation (figures printed,
 * nothing asserted).
 *  1. in-process, one core: tandem-sim's rover model (ODE world, hash space
 *     broad phase, full 8-transducer sonar rings fired in the Pioneer
 *     sequence, camera) stepped at 1 kHz for N = 3, 10, 30, 100 robots that
 *     drive and turn; simulated seconds per wall second and sonar rays cast
 *     per wall second.
 *  2. the whole system in lockstep over LCM: tandem-sim + one tandem-rover
 *     process hosting all N robots + tandem-scenario as observer (the three
 *     take turns, so about one core), from the scenario's summary.
 * Usage: bench_rovers [SIM_SECONDS] [BIN_DIR]  (default 20 s, build/bin)
 */
#include "../sim/sim_world.c"
#include "../sim/sim_rovers.c"
#include <time.h>
#include <sys/resource.h>

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
    if (sim_rovers_ops.create(&w, &cfg) != 0) return;
    t0 = wall_s();
    c0 = cpu_s();
    for (k = 0; k < steps; k++) {
        if (k % 50 == 0)   /* a 20 Hz "controller": drive and weave */
            for (i = 1; i <= n; i++)
                sim_rovers_set_command(i, 0.4, 0.5 * sin(0.5 * (double)k * SIM_DT_S + i), w.step);
        sim_rovers_ops.before_step(&w);
        sim_world_step(&w);
        sim_rovers_ops.after_step(&w);
    }
    t1 = wall_s();
    c1 = cpu_s();
    printf("  N = %3d: %5.1f s simulated: %6.2f s CPU = %7.1fx real time per core "
           "(%6.2f s wall = %6.1fx), %9.0f sonar rays per CPU second\n",
           n, sim_s, c1 - c0, sim_s / (c1 - c0), t1 - t0, sim_s / (t1 - t0),
           (double)sim_rovers_rays_cast() / (c1 - c0));
    sim_rovers_ops.destroy(&w);
    sim_world_destroy(&w);
}

static void lockstep_system(int n, double sim_s, const char *bin)
{
    char cmd[1024], line[2048];
    FILE *p;
    double st = -1, wt = -1, c0 = children_cpu_s(), cpu;
    snprintf(cmd, sizeof cmd,
             "%s/tandem-scenario formation --world open --robots %d --procs single "
             "--max-time %g --out /tmp/bench_rovers_%d 2>/dev/null", bin, n, sim_s, n);
    p = popen(cmd, "r");
    if (!p) return;
    while (fgets(line, sizeof line, p)) {
        const char *a = strstr(line, "sim_time_s="), *b = strstr(line, "wall_time_s=");
        if (a && b) { st = atof(a + 11); wt = atof(b + 12); }
    }
    pclose(p);
    cpu = children_cpu_s() - c0;
    if (st > 0 && wt > 0)
        printf("  N = %3d: %5.1f s simulated: %6.2f s CPU in all processes = %6.1fx real time per core "
               "(%6.2f s wall = %5.1fx)\n", n, st, cpu, st / cpu, wt, st / wt);
    else
        printf("  N = %3d: run failed (see /tmp/bench_rovers_%d/children.log)\n", n, n);
}

int main(int argc, char **argv)
{
    static const int ns[] = { 3, 10, 30, 100 };
    const double sim_s = argc > 1 ? atof(argv[1]) : 20.0;
    const char *bin = argc > 2 ? argv[2] : "build/bin";
    size_t i;
    printf("rover simulation, in process (physics + sonar rings + camera, no LCM), one core:\n");
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++) in_process(ns[i], sim_s);
    printf("whole system in lockstep over LCM (tandem-sim + tandem-rover --id 1-N + scenario):\n");
    for (i = 0; i < sizeof ns / sizeof ns[0]; i++) lockstep_system(ns[i], sim_s, bin);
    return 0;
}
