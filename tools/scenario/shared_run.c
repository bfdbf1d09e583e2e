/* shared_run: the lockstep, --fault, progress, plot and exit-status
 * helpers the carry and formation scenarios share (see shared_run.h). */
#include "shared_run.h"
#include "daemon.h"

void scenario_ack(auth_bus *bus, lcm_t *lcm, int64_t *seq, int64_t step, int32_t period_steps,
                  int leaving)
{
    lockstep_ack(bus, lcm, "tandem-scenario", (*seq)++, step, period_steps, leaving);
}

void scenario_daemon_left(auth_bus *bus, lcm_t *lcm, const char *name, int64_t step,
                          int32_t period_steps)
{
    lockstep_ack(bus, lcm, name, 0, step, period_steps, 1);
}

void scenario_leave_send(scenario_leave *l, auth_bus *bus, lcm_t *lcm, const char *name,
                         int64_t step, int32_t period_steps)
{
    snprintf(l->name, sizeof l->name, "%s", name);
    l->step = step;
    l->period_steps = period_steps;
    l->sent_s = scenario_wall_s();
    l->on = 1;
    scenario_daemon_left(bus, lcm, name, step, period_steps);
}

int scenario_leave_confirm(scenario_leave *l, auth_bus *bus, lcm_t *lcm, int64_t clock_step)
{
    if (!l->on)
        return 0;
    if (clock_step > l->step) {
        l->on = 0;
        return 0;
    }
    if (scenario_wall_s() - l->sent_s < SCENARIO_LEAVE_AGAIN_S)
        return 0;
    l->sent_s = scenario_wall_s();
    fprintf(
        stderr,
        "tandem-scenario: %s's leave was lost (the simulator still waits at step %lld): sending it "
        "again\n",
        l->name, (long long)clock_step);
    scenario_daemon_left(bus, lcm, l->name, l->step, l->period_steps);
    return 1;
}

void scenario_leave_end(scenario_leave *l)
{
    l->on = 0;
}

void scenario_fault_killed(scenario_fault *f)
{
    f->stage = f->restart_s >= 0.0 ? SCENARIO_FAULT_KILLED : SCENARIO_FAULT_DONE;
}

int scenario_rejoin_overdue(double hold_since_s)
{
    return scenario_wall_s() - hold_since_s > SCENARIO_REJOIN_WALL_S;
}

int scenario_progress_due(double *next_s, double every_s)
{
    if (scenario_wall_s() < *next_s)
        return 0;
    *next_s += every_s;
    return 1;
}

double scenario_realtime_factor(double sim_s, double wall_s)
{
    return wall_s > 0.0 ? sim_s / wall_s : 0.0;
}

FILE *scenario_plot_open(const char *dir, int width, int height)
{
    FILE *g = scenario_fopen(dir, "plots.gp");
    if (g)
        fprintf(g, "set datafile separator ','\nset terminal pngcairo size %d,%d\n", width, height);
    return g;
}

void scenario_plot_run(const char *dir, FILE *g)
{
    fclose(g);
    scenario_gnuplot(dir, "plots.gp");
}

int scenario_exit_status(const char *name, int n_failed, const char *failed)
{
    if (n_failed) {
        printf("%s: FAILED %d criteria: %s\n", name, n_failed, failed);
        return 3;
    }
    printf("%s: all criteria met\n", name);
    return 0;
}
