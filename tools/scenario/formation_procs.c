/* formation_procs: the children of a formation run (docs/method/formation.md
 * §6): tandem-sim (lockstep, rovers only) and the rover daemons, one
 * process per robot or one for all (--procs), started from the directory
 * of this binary with their chatter in DIR/children.log; --kill (a robot's
 * body and its process) and --fault (a robot's process killed and started
 * again from its journal, the lockstep held until it has rejoined).
 */
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "formation_scen.h"
#include "shared_run.h"
#include "run_key.h"
#include "auth_bus.h"
#include "daemon.h"
#include "tandem_sim_control_t.h"

static pid_t spawn(fm_state *fm, char *const argv[])
{
    char key[600];
    /* the child's own role file, never this process's master */
    int keyed;
    fm->keys.parent = run_key_bus(); /* fm_reset zeroed it: the roster of this run's bus */
    keyed = auth_child_key(&fm->keys, (const char *const *)argv, key, sizeof key);
    pid_t p = keyed < 0 ? -1 : fork();
    if (p == 0) {
        char path[700];
        int fd;
        setenv("LCM_DEFAULT_URL", fm->url, 1);
        if (keyed == AUTH_CHILD_OK)
            setenv(AUTH_BUS_KEY_ENV, key, 1);
        setenv(DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE, 1);
        /* children's chatter goes to DIR/children.log */
        snprintf(path, sizeof path, "%s/children.log", fm->out);
        fd = open(path, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        snprintf(path, sizeof path, "%s/%s", fm->bindir, argv[0]);
        execv(path, argv);
        _exit(127);
    }
    if (p > 0 && fm->n_pid < FM_PROCS)
        fm->pid[fm->n_pid++] = p;
    return p;
}

void fm_stop_children(fm_state *fm)
{
    int i, k;
    for (i = 0; i < fm->n_pid; i++)
        if (fm->pid[i] > 0)
            kill(fm->pid[i], SIGTERM);
    for (k = 0; k < 50; k++) {
        int left = 0;
        for (i = 0; i < fm->n_pid; i++) {
            if (fm->pid[i] <= 0)
                continue;
            if (waitpid(fm->pid[i], NULL, WNOHANG) == fm->pid[i])
                fm->pid[i] = -1;
            else
                left++;
        }
        if (!left)
            break;
        {
            struct timespec ts = { 0, 100000000L };
            nanosleep(&ts, NULL);
        }
    }
    for (i = 0; i < fm->n_pid; i++)
        if (fm->pid[i] > 0) {
            kill(fm->pid[i], SIGKILL);
            waitpid(fm->pid[i], NULL, 0);
        }
    auth_child_keys_remove(&fm->keys);
}

/* A robot's journal: for a robot a --fault restarts, and for every robot
 * of its own process while --hang-s may restart any of them. */
static int journaled(const fm_state *fm, int k)
{
    int i;
    if (fm->hang_s > 0.0 && !fm->single)
        return 1;
    for (i = 0; i < fm->n_faults; i++)
        if (fm->faults[i].slot == k)
            return 1;
    return 0;
}

/* The tandem-rover process of robot k (all robots with --procs single). */
static pid_t spawn_rover(fm_state *fm, int k)
{
    char n_s[16], w_s[32], id_s[32], arrive_s[32], journal[700];
    char *fo = (char *)fm_formation_name(fm->formation), *bl = (char *)fm_blend_name(fm->blend);
    char *rv[32] = { "tandem-rover",
                     "--id",
                     id_s,
                     "--robots",
                     n_s,
                     "--world",
                     w_s,
                     "--formation",
                     fo,
                     "--blend",
                     bl,
                     "--lockstep",
                     "--formation-law",
                     fm->law_kanayama ? "kanayama" : "seed",
                     "--ref-heading",
                     fm->ref_goal ? "goal" : "mean",
                     "--localize",
                     fm->localize_off ? "off" : "on",
                     "--ref-arrive",
                     arrive_s };
    int n = 20;
    snprintf(n_s, sizeof n_s, "%d", fm->robots);
    snprintf(arrive_s, sizeof arrive_s, "%.17g", fm->ref_arrive_m);
    snprintf(w_s, sizeof w_s, "%s", fm_world_arg(fm));
    if (fm->batch)
        rv[n++] = "--batch";
    world_opts_argv(&fm->child_world, rv, &n, 32);
    if (journaled(fm, k)) {
        snprintf(journal, sizeof journal, "%s/rover_%d.journal", fm->out, k);
        rv[n++] = "--journal";
        rv[n++] = journal;
    }
    scenario_argv_drop(&fm->drop, rv, &n, 32);
    if (fm->single)
        snprintf(id_s, sizeof id_s, "1-%d", fm->robots);
    else
        snprintf(id_s, sizeof id_s, "%d", k);
    return spawn(fm, rv);
}

int fm_start_children(fm_state *fm)
{
    char n_s[16], w_s[32], seed_s[24], expect_s[16];
    int k, procs = fm->single ? 1 : fm->robots;
    snprintf(n_s, sizeof n_s, "%d", fm->robots);
    snprintf(w_s, sizeof w_s, "%s", fm_world_arg(fm));
    snprintf(seed_s, sizeof seed_s, "%ld", fm->seed);
    snprintf(expect_s, sizeof expect_s, "%d", procs + 1);
    /* the role files name this team: rovers 1..N and the host of all N */
    auth_bus_roster(run_key_bus(), fm->robots);
    {
        char *sim[32] = { "tandem-sim",
                          "--lockstep",
                          "--no-arms",
                          "--rovers",
                          n_s,
                          "--world",
                          w_s,
                          "--formation",
                          (char *)fm_formation_name(fm->formation),
                          "--seed",
                          seed_s,
                          "--expect",
                          expect_s,
                          "--timeout-ms",
                          fm->timeout_ms };
        int n = 15;
        if (fm->batch)
            sim[n++] = "--rover-batch";
        world_opts_argv(&fm->child_world, sim, &n, 32);
        scenario_argv_drop(&fm->drop, sim, &n, 32);
        if (spawn(fm, sim) <= 0)
            return FM_ERR_START;
    }
    for (k = 1; k <= procs; k++) {
        fm->rover_pid[k] = spawn_rover(fm, k);
        if (fm->rover_pid[k] <= 0)
            return FM_ERR_START;
    }
    return 0;
}

/* Robot k's process started again (from its journal): watched again
 * from now, no more leaves; the step is held from now. 0, or
 * FM_ERR_FAULT when it did not start. */
static int restart_rover(fm_state *fm, int k)
{
    fm->rover_pid[k] = spawn_rover(fm, k);
    if (fm->rover_pid[k] <= 0)
        return FM_ERR_FAULT;
    scenario_leave_end(&fm->leave[k]);
    hang_watch_started(&fm->hw, k, scenario_wall_s());
    fm->hold_since_s = scenario_wall_s();
    return 0;
}

/* A restarted robot k is back when it has answered the held step and its
 * state of that step is in (the simulator waits for no command from a
 * robot silent this long, so the step must not move on before it):
 * 1 back (counted), 0 hold the step, FM_ERR_FAULT after 60 s. */
static int rejoined(fm_state *fm, int k, const char *why)
{
    if (fm->rover_ack[k] < fm->clock_step || !fm_ring_get(fm, k - 1, fm->clock_step)) {
        if (scenario_rejoin_overdue(fm->hold_since_s)) {
            fprintf(stderr, "formation: %s: rover %d did not rejoin within 60 s\n", why, k);
            return FM_ERR_FAULT;
        }
        return 0;
    }
    fm->up_at[k] = fm->clock_step;
    fm->restarts++;
    return 1;
}

/* --fault kill:roverK:T[:R], at a step due to be answered (every robot's
 * cycle runs at these steps). Kill once the robot's process has answered
 * the step (so its journal holds this cycle: the same state whatever the
 * machine's speed) and tell the simulator it left; restart at the first
 * such step after R and hold the step until the new process has run its
 * cycle of it (its state is in). 1: go on, 0: hold the step,
 * FM_ERR_FAULT: the restart failed. */
int fm_faults_step(fm_state *fm)
{
    int i, j;
    for (i = 0; i < fm->n_faults; i++) {
        scenario_fault *f = &fm->faults[i];
        const int k = f->slot;
        char name[64];
        snprintf(name, sizeof name, "tandem-rover-%d", k);
        if (f->stage == SCENARIO_FAULT_ARMED && fm->sim_time >= f->kill_s) {
            if (fm->rover_ack[k] < fm->clock_step || !fm_ring_get(fm, k - 1, fm->clock_step))
                return 0;
            kill(fm->rover_pid[k], SIGKILL);
            waitpid(fm->rover_pid[k], NULL, 0);
            for (j = 0; j < fm->n_pid; j++)
                if (fm->pid[j] == fm->rover_pid[k])
                    fm->pid[j] = -1; /* reaped: its pid may be reused */
            fm->rover_pid[k] = -1;
            fm->rover_ack[k] = -1;
            fm->down_after[k] = fm->clock_step;
            fm->up_at[k] = INT64_MAX;
            scenario_leave_send(&fm->leave[k], run_key_bus(), fm->lcm, name, fm->clock_step,
                                FM_PERIOD);
            hang_watch_down(&fm->hw, k);
            fprintf(stderr, "formation: fault: rover %d's process killed at t = %.2f s\n", k,
                    fm->sim_time);
            fm->kills++;
            scenario_fault_killed(f);
        }
        if (f->stage == SCENARIO_FAULT_KILLED && fm->sim_time >= f->restart_s) {
            if (restart_rover(fm, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: fault: rover %d's process restarted at t = %.2f s\n", k,
                    fm->sim_time);
            f->stage = SCENARIO_FAULT_RESTARTING;
        }
        if (f->stage == SCENARIO_FAULT_RESTARTING) {
            /* its ack and its state of this step (published after its
             * command): the simulator waits for no command from a robot
             * silent this long, so the step must not move on before it */
            const int rc = rejoined(fm, k, "fault");
            if (rc != 1)
                return rc;
            f->stage = SCENARIO_FAULT_DONE;
        }
    }
    return 1;
}

static void send_kill_robot(fm_state *fm)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_KILL_ROBOT;
    c.target = fm->kill_id;
    AUTH_PUBLISH(tandem_sim_control_t, run_key_bus(), fm->lcm, "SIM_CONTROL", &c);
    fm->kill_sent_step = fm->clock_step;
}

/* A truth this many steps after KILL_ROBOT that still shows the robot
 * alive: the command was lost (the simulator takes it at its next step). */
#define KILL_ACK_STEPS (2 * FM_PERIOD)

void fm_kill_robot(fm_state *fm)
{
    if (fm->killed && !fm->kill_seen &&
        fm->last_truth_step >= fm->kill_sent_step + KILL_ACK_STEPS) {
        fm->kill_resends++;
        fprintf(stderr,
                "formation: the kill of robot %d was lost at t = %.2f s: sending it again\n",
                fm->kill_id, fm->sim_time);
        send_kill_robot(fm);
    }
    if (!(fm->kill_id > 0 && !fm->killed && fm->sim_time >= fm->kill_t_s))
        return;
    send_kill_robot(fm);
    if (!fm->single && fm->rover_pid[fm->kill_id] > 0) {
        /* the process dies without a word; tell the simulator it
         * left rather than make it wait for its lockstep timeout */
        char name[64];
        kill(fm->rover_pid[fm->kill_id], SIGKILL);
        snprintf(name, sizeof name, "tandem-rover-%d", fm->kill_id);
        scenario_leave_send(&fm->leave[fm->kill_id], run_key_bus(), fm->lcm, name, fm->clock_step,
                            FM_PERIOD);
        hang_watch_down(&fm->hw, fm->kill_id);
    }
    fm->killed = 1;
    fprintf(stderr, "formation: killed robot %d at t = %.2f s\n", fm->kill_id, fm->sim_time);
}

/* ---- --hang-s ------------------------------------------------------------------ */

void fm_hang_start(fm_state *fm)
{
    const double now = scenario_wall_s();
    char name[64];
    int k;
    hang_watch_init(&fm->hw, fm->hang_s);
    hang_watch_add(&fm->hw, "tandem-sim", now);
    if (fm->single) {
        snprintf(name, sizeof name, "tandem-rover-1-%d", fm->robots);
        hang_watch_add(&fm->hw, name, now);
    } else {
        for (k = 1; k <= fm->robots; k++) {
            snprintf(name, sizeof name, "tandem-rover-%d", k);
            hang_watch_add(&fm->hw, name, now);
        }
    }
    hang_watch_subscribe(&fm->hw, run_key_bus(), fm->lcm);
}

/* 1 when pid is a child still running (a stopped one runs); a child
 * that exited is reaped and its entries cleared. */
static int child_alive(fm_state *fm, pid_t pid)
{
    int j;
    if (pid <= 0)
        return 0;
    if (waitpid(pid, NULL, WNOHANG) == 0)
        return 1;
    for (j = 0; j < fm->n_pid; j++)
        if (fm->pid[j] == pid)
            fm->pid[j] = -1;
    return 0;
}

/* SIGKILL to a hung child (reaped: its pid may be reused). */
static void kill_child(fm_state *fm, pid_t pid)
{
    int j;
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
    for (j = 0; j < fm->n_pid; j++)
        if (fm->pid[j] == pid)
            fm->pid[j] = -1;
}

int fm_hung_watch(fm_state *fm)
{
    const double now = scenario_wall_s();
    int k;
    for (k = 0; k < fm->hw.n; k++)
        fm->leave_resends += scenario_leave_confirm(&fm->leave[k], run_key_bus(), fm->lcm,
                                                    fm->clock_step);
    if (!hang_watch_look(&fm->hw, fm->lcm, now))
        return 0; /* messages still to read: not now */
    for (k = 0; k < fm->hw.n; k++) {
        const pid_t pid = k == 0 ? fm->pid[0] : fm->rover_pid[k];
        const int restartable = k > 0 && !fm->single;
        char name[64];
        if (fm->hung_stage[k] != FM_HUNG_NONE || !hang_watch_hung(&fm->hw, k, now) ||
            !child_alive(fm, pid))
            continue;
        snprintf(name, sizeof name, "%s", fm->hw.name[k]);
        fprintf(
            stderr,
            "formation: hung: %s alive but without health for %.1f s (--hang-s %g): killed at t = %.2f "
            "s%s\n",
            name, hang_watch_silent_s(&fm->hw, k, now), fm->hw.hang_s, fm->sim_time,
            restartable ? ", restarting" : "; it cannot be restarted: run stopped");
        fm->kills++;
        kill_child(fm, pid);
        hang_watch_down(&fm->hw, k);
        if (!restartable) {
            fm->hung_stopped = 1;
            return FM_ERR_HUNG;
        }
        fm->rover_pid[k] = -1;
        fm->down_after[k] = fm->rover_ack[k];
        fm->up_at[k] = INT64_MAX;
        fm->rover_ack[k] = -1;
        scenario_leave_send(&fm->leave[k], run_key_bus(), fm->lcm, name, fm->clock_step, FM_PERIOD);
        fm->hung_stage[k] = FM_HUNG_KILLED;
        fm->hung_step[k] = fm->clock_step;
        if (fm->clock_step <= 0) {
            /* before the first step the simulator waits for every process
             * to join: no step to hold, the new one joins as the first would */
            if (restart_rover(fm, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: hung: rover %d's process restarted at t = %.2f s\n", k,
                    fm->sim_time);
            fm->down_after[k] = fm->up_at[k] = INT64_MAX;
            fm->restarts++;
            fm->hung_restarts++;
            fm->hung_stage[k] = FM_HUNG_NONE;
        }
    }
    return 0;
}

int fm_hung_step(fm_state *fm)
{
    int k;
    for (k = 1; k < fm->hw.n && !fm->single; k++) {
        if (fm->hung_stage[k] == FM_HUNG_KILLED && fm->clock_step > fm->hung_step[k]) {
            if (restart_rover(fm, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: hung: rover %d's process restarted at t = %.2f s\n", k,
                    fm->sim_time);
            fm->hung_stage[k] = FM_HUNG_RESTARTING;
        }
        if (fm->hung_stage[k] == FM_HUNG_RESTARTING) {
            const int rc = rejoined(fm, k, "hung");
            if (rc != 1)
                return rc;
            fm->hung_restarts++;
            fm->hung_stage[k] = FM_HUNG_NONE;
        }
    }
    return 1;
}
