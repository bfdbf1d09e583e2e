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
#include "daemon.h"
#include "tandem_sim_control_t.h"

static pid_t spawn(fm_state *fm, char *const argv[])
{
    pid_t p = fork();
    if (p == 0) {
        char path[700];
        int fd;
        setenv("LCM_DEFAULT_URL", fm->url, 1);
        /* children's chatter goes to DIR/children.log */
        snprintf(path, sizeof path, "%s/children.log", fm->out);
        fd = open(path, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) { dup2(fd, 1); dup2(fd, 2); close(fd); }
        snprintf(path, sizeof path, "%s/%s", fm->bindir, argv[0]);
        execv(path, argv);
        _exit(127);
    }
    if (p > 0 && fm->n_pid < FM_PROCS) fm->pid[fm->n_pid++] = p;
    return p;
}

void fm_stop_children(fm_state *fm)
{
    int i, k;
    for (i = 0; i < fm->n_pid; i++) if (fm->pid[i] > 0) kill(fm->pid[i], SIGTERM);
    for (k = 0; k < 50; k++) {
        int left = 0;
        for (i = 0; i < fm->n_pid; i++) {
            if (fm->pid[i] <= 0) continue;
            if (waitpid(fm->pid[i], NULL, WNOHANG) == fm->pid[i]) fm->pid[i] = -1;
            else left++;
        }
        if (!left) return;
        {
            struct timespec ts = { 0, 100000000L };
            nanosleep(&ts, NULL);
        }
    }
    for (i = 0; i < fm->n_pid; i++)
        if (fm->pid[i] > 0) { kill(fm->pid[i], SIGKILL); waitpid(fm->pid[i], NULL, 0); }
}

/* A robot's journal: only for a robot a --fault restarts. */
static int journaled(const fm_state *fm, int k)
{
    int i;
    for (i = 0; i < fm->n_faults; i++)
        if (fm->faults[i].slot == k) return 1;
    return 0;
}

/* The tandem-rover process of robot k (all robots with --procs single). */
static pid_t spawn_rover(fm_state *fm, int k)
{
    char n_s[16], w_s[32], id_s[32], arrive_s[32], journal[700];
    char *fo = (char *)fm_formation_name(fm->formation), *bl = (char *)fm_blend_name(fm->blend);
    char *rv[32] = { "tandem-rover", "--id", id_s, "--robots", n_s, "--world", w_s,
                     "--formation", fo, "--blend", bl, "--lockstep",
                     "--formation-law", fm->law_kanayama ? "kanayama" : "seed",
                     "--ref-heading", fm->ref_goal ? "goal" : "mean",
                     "--localize", fm->localize_off ? "off" : "on", "--ref-arrive", arrive_s };
    int n = 20;
    snprintf(n_s, sizeof n_s, "%d", fm->robots);
    snprintf(arrive_s, sizeof arrive_s, "%.17g", fm->ref_arrive_m);
    snprintf(w_s, sizeof w_s, "%s", fm_world_arg(fm));
    if (fm->batch) rv[n++] = "--batch";
    world_opts_argv(&fm->child_world, rv, &n, 32);
    if (journaled(fm, k)) {
        snprintf(journal, sizeof journal, "%s/rover_%d.journal", fm->out, k);
        rv[n++] = "--journal";
        rv[n++] = journal;
    }
    scenario_argv_drop(&fm->drop, rv, &n, 32);
    if (fm->single) snprintf(id_s, sizeof id_s, "1-%d", fm->robots);
    else snprintf(id_s, sizeof id_s, "%d", k);
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
    {
        char *sim[32] = { "tandem-sim", "--lockstep", "--no-arms", "--rovers", n_s, "--world", w_s,
                          "--formation", (char *)fm_formation_name(fm->formation),
                          "--seed", seed_s, "--expect", expect_s, "--timeout-ms", fm->timeout_ms };
        int n = 15;
        if (fm->batch) sim[n++] = "--rover-batch";
        world_opts_argv(&fm->child_world, sim, &n, 32);
        scenario_argv_drop(&fm->drop, sim, &n, 32);
        if (spawn(fm, sim) <= 0) return FM_ERR_START;
    }
    for (k = 1; k <= procs; k++) {
        fm->rover_pid[k] = spawn_rover(fm, k);
        if (fm->rover_pid[k] <= 0) return FM_ERR_START;
    }
    return 0;
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
            if (fm->rover_ack[k] < fm->clock_step || !fm_ring_get(fm, k - 1, fm->clock_step)) return 0;
            kill(fm->rover_pid[k], SIGKILL);
            waitpid(fm->rover_pid[k], NULL, 0);
            for (j = 0; j < fm->n_pid; j++)
                if (fm->pid[j] == fm->rover_pid[k]) fm->pid[j] = -1;   /* reaped: its pid may be reused */
            fm->rover_pid[k] = -1;
            fm->rover_ack[k] = -1;
            fm->down_after[k] = fm->clock_step;
            fm->up_at[k] = INT64_MAX;
            scenario_daemon_left(fm->lcm, name, fm->clock_step, FM_PERIOD);
            fprintf(stderr, "formation: fault: rover %d's process killed at t = %.2f s\n", k, fm->sim_time);
            fm->kills++;
            scenario_fault_killed(f);
        }
        if (f->stage == SCENARIO_FAULT_KILLED && fm->sim_time >= f->restart_s) {
            fm->rover_pid[k] = spawn_rover(fm, k);
            if (fm->rover_pid[k] <= 0) return FM_ERR_FAULT;
            fprintf(stderr, "formation: fault: rover %d's process restarted at t = %.2f s\n", k, fm->sim_time);
            fm->hold_since_s = scenario_wall_s();
            f->stage = SCENARIO_FAULT_RESTARTING;
        }
        if (f->stage == SCENARIO_FAULT_RESTARTING) {
            /* its ack and its state of this step (published after its
             * command): the simulator waits for no command from a robot
             * silent this long, so the step must not move on before it */
            if (fm->rover_ack[k] < fm->clock_step || !fm_ring_get(fm, k - 1, fm->clock_step)) {
                if (scenario_rejoin_overdue(fm->hold_since_s)) {
                    fprintf(stderr, "formation: fault: rover %d did not rejoin within 60 s\n", k);
                    return FM_ERR_FAULT;
                }
                return 0;
            }
            fm->up_at[k] = fm->clock_step;
            fm->restarts++;
            f->stage = SCENARIO_FAULT_DONE;
        }
    }
    return 1;
}

void fm_kill_robot(fm_state *fm)
{
    tandem_sim_control_t c;
    if (!(fm->kill_id > 0 && !fm->killed && fm->sim_time >= fm->kill_t_s))
        return;
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_KILL_ROBOT;
    c.target = fm->kill_id;
    AUTH_PUBLISH(tandem_sim_control_t, fm->lcm, "SIM_CONTROL", &c);
    if (!fm->single && fm->rover_pid[fm->kill_id] > 0) {
        /* the process dies without a word; tell the simulator it
         * left rather than make it wait for its lockstep timeout */
        char name[64];
        kill(fm->rover_pid[fm->kill_id], SIGKILL);
        snprintf(name, sizeof name, "tandem-rover-%d", fm->kill_id);
        scenario_daemon_left(fm->lcm, name, fm->clock_step, FM_PERIOD);
    }
    fm->killed = 1;
    fprintf(stderr, "formation: killed robot %d at t = %.2f s\n", fm->kill_id, fm->sim_time);
}
