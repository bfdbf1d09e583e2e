/* shared_run: what the scenarios that start daemons and run with them in
 * lockstep (carry, formation; docs/method/lockstep.md §8) share beyond
 * scenario.h: the scenario's own lockstep answer, telling the simulator a
 * killed daemon has left, the stages of a --fault and its rejoin wait, the
 * progress-line cadence, the gnuplot script's frame, and the exit status
 * from the success criteria.
 */
#ifndef TANDEM_SHARED_RUN_H
#define TANDEM_SHARED_RUN_H

#include <stdint.h>
#include <stdio.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "scenario.h"

/* scenario_fault.stage */
enum {
    SCENARIO_FAULT_ARMED = 0,      /* waiting for its kill time */
    SCENARIO_FAULT_KILLED = 1,     /* killed, waiting for its restart time */
    SCENARIO_FAULT_RESTARTING = 2, /* restarted, the step held until it answers */
    SCENARIO_FAULT_DONE = 3        /* rejoined, or left down for good */
};

/* A restarted daemon that has not answered the held step within this much
 * wall time will not: the run gives up (restart_failed). */
#define SCENARIO_REJOIN_WALL_S 60.0

/* The scenario's own answer to lockstep step `step` ("tandem-scenario",
 * every period_steps steps; leaving = 1 unregisters); *seq counts them. */
void scenario_ack(auth_bus *bus, lcm_t *lcm, int64_t *seq, int64_t step, int32_t period_steps,
                  int leaving);
/* Tells the simulator that the lockstep participant `name` (a daemon just
 * killed without a goodbye) has left, so it does not wait out its timeout. */
void scenario_daemon_left(auth_bus *bus, lcm_t *lcm, const char *name, int64_t step,
                          int32_t period_steps);
/* A killed daemon's leave, sent again until the simulator has taken it
 * (--drop-rate drops the simulator's received messages too, and a lost
 * leave would hold the lockstep for the participant timeout): taken once
 * the simulator announces a step after the one of the kill, which it
 * does only without the daemon. Sent again at most every
 * SCENARIO_LEAVE_AGAIN_S of wall time; the restart ends the re-sending
 * (the new process's answers make it a participant again). */
#define SCENARIO_LEAVE_AGAIN_S 0.3
typedef struct scenario_leave {
    char name[48];
    int64_t step; /* the step announced at the kill */
    int32_t period_steps;
    double sent_s; /* wall time of the last send */
    int on;        /* 1 until taken or the daemon restarted */
} scenario_leave;
/* Sends the leave of `name` now (scenario_daemon_left) and keeps it. */
void scenario_leave_send(scenario_leave *l, auth_bus *bus, lcm_t *lcm, const char *name,
                         int64_t step, int32_t period_steps);
/* With the latest step the simulator announced: 1 when the leave was sent
 * again (it was not taken yet), 0 otherwise. */
int scenario_leave_confirm(scenario_leave *l, auth_bus *bus, lcm_t *lcm, int64_t clock_step);
/* The daemon is started again: no more leaves. */
void scenario_leave_end(scenario_leave *l);
/* After the fault's kill: restarting later, or left down. */
void scenario_fault_killed(scenario_fault *f);
/* 1 when a restart begun at wall time hold_since_s has waited longer than
 * SCENARIO_REJOIN_WALL_S. */
int scenario_rejoin_overdue(double hold_since_s);

/* 1 (and *next_s advanced by every_s) when the wall clock has reached
 * *next_s: time for the next progress line. */
int scenario_progress_due(double *next_s, double every_s);
/* Simulated seconds per wall second, 0 before any wall time has passed. */
double scenario_realtime_factor(double sim_s, double wall_s);

/* Opens dir/plots.gp with the lines every plot script starts with (CSV
 * input, PNG output of width x height pixels); NULL on failure. */
FILE *scenario_plot_open(const char *dir, int width, int height);
/* Closes the script and runs gnuplot on it (scenario_gnuplot). */
void scenario_plot_run(const char *dir, FILE *g);

/* The last line of a run: "NAME: FAILED n criteria: ..." or "NAME: all
 * criteria met". Returns the exit status, 3 or 0. */
int scenario_exit_status(const char *name, int n_failed, const char *failed);

#endif
