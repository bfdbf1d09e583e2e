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
#include "host_netns.h"
#include "proc.h"
#include "auth.h"
#include "auth_bus.h"
#include "daemon.h"
#include "tandem_sim_control_t.h"

void fm_procs_init(fm_procs *pr, const fm_cfg *cfg)
{
    int k;
    memcpy(pr->faults, cfg->faults, sizeof pr->faults);
    pr->n_faults = cfg->n_faults;
    for (k = 0; k <= FM_MAX; k++) {
        pr->down_after[k] = INT64_MAX;
        pr->up_at[k] = INT64_MAX;
    }
}

int fm_process_down(const fm_procs *pr, int id, int64_t k)
{
    return id >= 1 && id <= FM_MAX && k > pr->down_after[id] && k < pr->up_at[id];
}

/* The roster of the run: its robots, on cfg->hosts processes of whole
 * teams with --procs single (one each with --procs separate: their own). */
static auth_fleet run_fleet(const fm_cfg *cfg)
{
    return auth_fleet_clamped(cfg->robots, cfg->single ? cfg->hosts : 1,
                              cfg->teams > 1 ? cfg->per_team : 1);
}

/* A child: argv from cfg->bindir with its own role file, its chatter in
 * DIR/children.log; host >= 1: rover host `host` (--host-netns). */
static pid_t spawn_in(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus, char *const argv[],
                      int host)
{
    char key[600];
    /* the child's own role file, never this process's master */
    int keyed;
    pr->keys.parent = bus->auth; /* fm_run_reset zeroed it: the roster of this run's bus */
    const pid_t self = getpid();
    keyed = auth_child_key(&pr->keys, (const char *const *)argv, key, sizeof key);
    pid_t p = keyed < 0 ? -1 : fork();
    if (p == 0) {
        proc_die_with_parent(self);
        char path[700];
        int fd;
        setenv("LCM_DEFAULT_URL", cfg->url, 1);
        if (keyed == AUTH_CHILD_OK)
            setenv(AUTH_BUS_KEY_ENV, key, 1);
        setenv(DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE, 1);
        /* children's chatter goes to DIR/children.log */
        snprintf(path, sizeof path, "%s/children.log", cfg->out);
        fd = open(path, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0) {
            dup2(fd, 1);
            dup2(fd, 2);
            close(fd);
        }
        if (host >= 1 && host_netns_enter(cfg->host_netns, host) != 0)
            _exit(127);
        snprintf(path, sizeof path, "%s/%s", cfg->bindir, argv[0]);
        execv(path, argv);
        _exit(127);
    }
    if (p > 0 && pr->n_pid < FM_PROCS)
        pr->pid[pr->n_pid++] = p;
    return p;
}

static pid_t spawn(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus, char *const argv[])
{
    return spawn_in(pr, cfg, bus, argv, 0);
}

void fm_stop_children(fm_procs *pr)
{
    int i, k;
    for (i = 0; i < pr->n_pid; i++)
        if (pr->pid[i] > 0)
            kill(pr->pid[i], SIGTERM);
    for (k = 0; k < 50; k++) {
        int left = 0;
        for (i = 0; i < pr->n_pid; i++) {
            if (pr->pid[i] <= 0)
                continue;
            if (waitpid(pr->pid[i], NULL, WNOHANG) == pr->pid[i])
                pr->pid[i] = -1;
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
    for (i = 0; i < pr->n_pid; i++)
        if (pr->pid[i] > 0) {
            kill(pr->pid[i], SIGKILL);
            waitpid(pr->pid[i], NULL, 0);
        }
    auth_child_keys_remove(&pr->keys);
}

/* A robot's journal: for a robot a --fault restarts, and for every robot
 * of its own process while --hang-s may restart any of them. */
static int journaled(const fm_cfg *cfg, int k)
{
    int i;
    if (cfg->hang_s > 0.0 && !cfg->single)
        return 1;
    for (i = 0; i < cfg->n_faults; i++)
        if (cfg->faults[i].slot == k)
            return 1;
    return 0;
}

#define ROVER_ARGV_MAX 40 /* tandem-rover's argv, its NULL included */

/* --teams T --robots-per-team K --team-goals G for the simulator and the
 * rovers of a run of many teams (nothing with one): appended at argv[*n];
 * t_s and k_s hold the numbers' text. */
static void fleet_argv(const fm_cfg *cfg, char **argv, int *n, char t_s[16], char k_s[16])
{
    if (cfg->teams <= 1)
        return;
    snprintf(t_s, 16, "%d", cfg->teams);
    snprintf(k_s, 16, "%d", cfg->per_team);
    argv[(*n)++] = "--teams";
    argv[(*n)++] = t_s;
    argv[(*n)++] = "--robots-per-team";
    argv[(*n)++] = k_s;
    argv[(*n)++] = "--team-goals";
    argv[(*n)++] = (char *)rover_fleet_goals_name(cfg->team_goals);
}

/* The tandem-rover process of robot k (--procs separate), or of host k's
 * robots (--procs single, --hosts). */
static pid_t spawn_rover(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus, int k)
{
    char n_s[16], w_s[32], id_s[32], arrive_s[32], journal[700], t_s[16], k_s[16];
    char *fo = (char *)fm_formation_name(cfg->formation), *bl = (char *)fm_blend_name(cfg->blend);
    char *rv[ROVER_ARGV_MAX] = { "tandem-rover",
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
                                 cfg->law_kanayama ? "kanayama" : "seed",
                                 "--ref-heading",
                                 cfg->ref_goal ? "goal" : "mean",
                                 "--localize",
                                 cfg->localize_off ? "off" : "on",
                                 "--ref-arrive",
                                 arrive_s,
                                 "--goal-path",
                                 cfg->goal_direct ? "direct" : "map" };
    int n = 22;
    /* a fleet's --robots is one team's (tandem-rover takes T K from --teams) */
    snprintf(n_s, sizeof n_s, "%d", cfg->teams > 1 ? cfg->per_team : cfg->robots);
    snprintf(arrive_s, sizeof arrive_s, "%.17g", cfg->ref_arrive_m);
    snprintf(w_s, sizeof w_s, "%s", fm_world_arg(cfg));
    if (cfg->batch)
        rv[n++] = "--batch";
    fleet_argv(cfg, rv, &n, t_s, k_s);
    world_opts_argv(&cfg->child_world, rv, &n, ROVER_ARGV_MAX);
    if (journaled(cfg, k)) {
        snprintf(journal, sizeof journal, "%s/rover_%d.journal", cfg->out, k);
        rv[n++] = "--journal";
        rv[n++] = journal;
    }
    scenario_argv_drop(&cfg->drop, rv, &n, ROVER_ARGV_MAX);
    if (cfg->single) {
        const auth_fleet f = run_fleet(cfg);
        int first = 1, last = cfg->robots;
        auth_fleet_host(&f, k - 1, &first, &last);
        snprintf(id_s, sizeof id_s, "%d-%d", first, last);
    } else {
        snprintf(id_s, sizeof id_s, "%d", k);
    }
    return spawn_in(pr, cfg, bus, rv, cfg->single ? k : 0);
}

int fm_rover_procs(const fm_cfg *cfg)
{
    return cfg->single ? run_fleet(cfg).hosts : cfg->robots;
}

int fm_start_children(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus)
{
    char n_s[16], w_s[32], seed_s[24], expect_s[16], t_s[16], k_s[16];
    const auth_fleet fleet = run_fleet(cfg);
    int k, procs = fm_rover_procs(cfg);
    snprintf(n_s, sizeof n_s, "%d", cfg->robots);
    snprintf(w_s, sizeof w_s, "%s", fm_world_arg(cfg));
    snprintf(seed_s, sizeof seed_s, "%ld", cfg->seed);
    snprintf(expect_s, sizeof expect_s, "%d", procs + 1);
    /* the role files name this team: rovers 1..N and the hosts of them */
    auth_bus_roster_fleet(bus->auth, &fleet);
    {
        char *sim[40] = { "tandem-sim",
                          "--lockstep",
                          "--no-arms",
                          "--rovers",
                          n_s,
                          "--world",
                          w_s,
                          "--formation",
                          (char *)fm_formation_name(cfg->formation),
                          "--seed",
                          seed_s,
                          "--expect",
                          expect_s,
                          "--timeout-ms",
                          (char *)cfg->timeout_ms };
        int n = 15;
        if (cfg->batch)
            sim[n++] = "--rover-batch";
        if (cfg->far_kinematic) {
            sim[n++] = "--rover-far";
            sim[n++] = "kinematic";
        }
        fleet_argv(cfg, sim, &n, t_s, k_s);
        world_opts_argv(&cfg->child_world, sim, &n, 40);
        scenario_argv_drop(&cfg->drop, sim, &n, 40);
        if (spawn(pr, cfg, bus, sim) <= 0)
            return FM_ERR_START;
    }
    for (k = 1; k <= procs; k++) {
        pr->rover_pid[k] = spawn_rover(pr, cfg, bus, k);
        if (pr->rover_pid[k] <= 0)
            return FM_ERR_START;
    }
    return 0;
}

/* Robot k's process started again (from its journal): watched again
 * from now, no more leaves; the step is held from now. 0, or
 * FM_ERR_FAULT when it did not start. */
static int restart_rover(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus, int k)
{
    pr->rover_pid[k] = spawn_rover(pr, cfg, bus, k);
    if (pr->rover_pid[k] <= 0)
        return FM_ERR_FAULT;
    scenario_leave_end(&pr->leave[k]);
    hang_watch_started(&pr->hw, k, scenario_wall_s());
    hang_watch_pid(&pr->hw, k, pr->rover_pid[k]);
    pr->hold_since_s = scenario_wall_s();
    return 0;
}

/* A restarted robot k is back when it has answered the held step and its
 * state of that step is in (the simulator waits for no command from a
 * robot silent this long, so the step must not move on before it):
 * 1 back (counted), 0 hold the step, FM_ERR_FAULT after 60 s. */
static int rejoined(fm_procs *pr, const fm_bus *bus, int k, const char *why)
{
    if (bus->rover_ack[k] < bus->clock_step || !fm_ring_get(bus, k - 1, bus->clock_step)) {
        if (scenario_rejoin_overdue(pr->hold_since_s)) {
            fprintf(stderr, "formation: %s: rover %d did not rejoin within 60 s\n", why, k);
            return FM_ERR_FAULT;
        }
        return 0;
    }
    pr->up_at[k] = bus->clock_step;
    pr->restarts++;
    return 1;
}

/* --fault kill:roverK:T[:R], at a step due to be answered (every robot's
 * cycle runs at these steps). Kill once the robot's process has answered
 * the step (so its journal holds this cycle: the same state whatever the
 * machine's speed) and tell the simulator it left; restart at the first
 * such step after R and hold the step until the new process has run its
 * cycle of it (its state is in). 1: go on, 0: hold the step,
 * FM_ERR_FAULT: the restart failed. */
int fm_faults_step(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus)
{
    int i, j;
    for (i = 0; i < pr->n_faults; i++) {
        scenario_fault *f = &pr->faults[i];
        const int k = f->slot;
        char name[64];
        snprintf(name, sizeof name, "tandem-rover-%d", k);
        if (f->stage == SCENARIO_FAULT_ARMED && bus->sim_time >= f->kill_s) {
            if (bus->rover_ack[k] < bus->clock_step || !fm_ring_get(bus, k - 1, bus->clock_step))
                return 0;
            kill(pr->rover_pid[k], SIGKILL);
            waitpid(pr->rover_pid[k], NULL, 0);
            for (j = 0; j < pr->n_pid; j++)
                if (pr->pid[j] == pr->rover_pid[k])
                    pr->pid[j] = -1; /* reaped: its pid may be reused */
            pr->rover_pid[k] = -1;
            fm_forget_ack(bus, k);
            pr->down_after[k] = bus->clock_step;
            pr->up_at[k] = INT64_MAX;
            scenario_leave_send(&pr->leave[k], bus->auth, bus->lcm, name, bus->clock_step,
                                FM_PERIOD);
            hang_watch_down(&pr->hw, k);
            fprintf(stderr, "formation: fault: rover %d's process killed at t = %.2f s\n", k,
                    bus->sim_time);
            pr->kills++;
            scenario_fault_killed(f);
        }
        if (f->stage == SCENARIO_FAULT_KILLED && bus->sim_time >= f->restart_s) {
            if (restart_rover(pr, cfg, bus, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: fault: rover %d's process restarted at t = %.2f s\n", k,
                    bus->sim_time);
            f->stage = SCENARIO_FAULT_RESTARTING;
        }
        if (f->stage == SCENARIO_FAULT_RESTARTING) {
            /* its ack and its state of this step (published after its
             * command): the simulator waits for no command from a robot
             * silent this long, so the step must not move on before it */
            const int rc = rejoined(pr, bus, k, "fault");
            if (rc != 1)
                return rc;
            f->stage = SCENARIO_FAULT_DONE;
        }
    }
    return 1;
}

static void send_kill_robot(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_KILL_ROBOT;
    c.target = cfg->kill_id;
    AUTH_PUBLISH(tandem_sim_control_t, bus->auth, bus->lcm, "SIM_CONTROL", &c);
    pr->kill_sent_step = bus->clock_step;
}

/* A truth this many steps after KILL_ROBOT that still shows the robot
 * alive: the command was lost (the simulator takes it at its next step). */
#define KILL_ACK_STEPS (2 * FM_PERIOD)

void fm_kill_robot(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus)
{
    if (pr->killed && !pr->kill_seen &&
        bus->last_truth_step >= pr->kill_sent_step + KILL_ACK_STEPS) {
        pr->kill_resends++;
        fprintf(stderr,
                "formation: the kill of robot %d was lost at t = %.2f s: sending it again\n",
                cfg->kill_id, bus->sim_time);
        send_kill_robot(pr, cfg, bus);
    }
    if (!(cfg->kill_id > 0 && !pr->killed && bus->sim_time >= cfg->kill_t_s))
        return;
    send_kill_robot(pr, cfg, bus);
    if (!cfg->single && pr->rover_pid[cfg->kill_id] > 0) {
        /* the process dies without a word; tell the simulator it
         * left rather than make it wait for its lockstep timeout */
        char name[64];
        kill(pr->rover_pid[cfg->kill_id], SIGKILL);
        snprintf(name, sizeof name, "tandem-rover-%d", cfg->kill_id);
        scenario_leave_send(&pr->leave[cfg->kill_id], bus->auth, bus->lcm, name, bus->clock_step,
                            FM_PERIOD);
        hang_watch_down(&pr->hw, cfg->kill_id);
    }
    pr->killed = 1;
    fprintf(stderr, "formation: killed robot %d at t = %.2f s\n", cfg->kill_id, bus->sim_time);
}

void fm_kill_truth(fm_procs *pr, const fm_cfg *cfg, const tandem_rover_truth_t *m)
{
    int i;
    for (i = 0; i < m->n && pr->killed; i++)
        if (m->robot[i] == cfg->kill_id && !m->alive[i])
            pr->kill_seen = 1;
}

/* ---- --hang-s ------------------------------------------------------------------ */

void fm_hang_start(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus)
{
    const double now = scenario_wall_s();
    char name[64];
    int k;
    hang_watch_init(&pr->hw, cfg->hang_s);
    hang_watch_add(&pr->hw, "tandem-sim", now);
    if (cfg->single) {
        const auth_fleet f = run_fleet(cfg);
        int first, last;
        for (k = 0; auth_fleet_host(&f, k, &first, &last) == 0; k++) {
            snprintf(name, sizeof name, "tandem-rover-%d-%d", first, last);
            hang_watch_add(&pr->hw, name, now);
        }
    } else {
        for (k = 1; k <= cfg->robots; k++) {
            snprintf(name, sizeof name, "tandem-rover-%d", k);
            hang_watch_add(&pr->hw, name, now);
        }
    }
    /* slot 0 the simulator (started first), slot k rover process k */
    for (k = 0; k < pr->hw.n; k++)
        hang_watch_pid(&pr->hw, k, k == 0 ? pr->pid[0] : pr->rover_pid[k]);
    hang_watch_subscribe(&pr->hw, bus->auth, bus->lcm);
}

void fm_hang_stop(fm_procs *pr, const fm_bus *bus)
{
    hang_watch_stop(&pr->hw, bus->lcm);
}

/* 1 when pid is a child still running (a stopped one runs); a child
 * that exited is reaped and its entries cleared. */
static int child_alive(fm_procs *pr, pid_t pid)
{
    int j;
    if (pid <= 0)
        return 0;
    if (waitpid(pid, NULL, WNOHANG) == 0)
        return 1;
    for (j = 0; j < pr->n_pid; j++)
        if (pr->pid[j] == pid)
            pr->pid[j] = -1;
    return 0;
}

/* SIGKILL to a hung child (reaped: its pid may be reused). */
static void kill_child(fm_procs *pr, pid_t pid)
{
    int j;
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
    for (j = 0; j < pr->n_pid; j++)
        if (pr->pid[j] == pid)
            pr->pid[j] = -1;
}

int fm_hung_watch(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus)
{
    const double now = scenario_wall_s();
    int k;
    for (k = 0; k < pr->hw.n; k++)
        pr->leave_resends += scenario_leave_confirm(&pr->leave[k], bus->auth, bus->lcm,
                                                    bus->clock_step);
    if (!hang_watch_look(&pr->hw, bus->lcm, now))
        return 0; /* messages still to read: not now */
    for (k = 0; k < pr->hw.n; k++) {
        const pid_t pid = k == 0 ? pr->pid[0] : pr->rover_pid[k];
        const int restartable = k > 0 && !cfg->single;
        char name[64];
        if (pr->hung_stage[k] != FM_HUNG_NONE || !hang_watch_hung(&pr->hw, k, now) ||
            !child_alive(pr, pid))
            continue;
        snprintf(name, sizeof name, "%s", pr->hw.name[k]);
        fprintf(
            stderr,
            "formation: hung: %s alive but without health for %.1f s (--hang-s %g): killed at t = %.2f "
            "s%s\n",
            name, hang_watch_silent_s(&pr->hw, k, now), pr->hw.hang_s, bus->sim_time,
            restartable ? ", restarting" : "; it cannot be restarted: run stopped");
        pr->kills++;
        kill_child(pr, pid);
        hang_watch_down(&pr->hw, k);
        if (!restartable) {
            pr->hung_stopped = 1;
            return FM_ERR_HUNG;
        }
        pr->rover_pid[k] = -1;
        pr->down_after[k] = bus->rover_ack[k];
        pr->up_at[k] = INT64_MAX;
        fm_forget_ack(bus, k);
        scenario_leave_send(&pr->leave[k], bus->auth, bus->lcm, name, bus->clock_step, FM_PERIOD);
        pr->hung_stage[k] = FM_HUNG_KILLED;
        pr->hung_step[k] = bus->clock_step;
        if (bus->clock_step <= 0) {
            /* before the first step the simulator waits for every process
             * to join: no step to hold, the new one joins as the first would */
            if (restart_rover(pr, cfg, bus, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: hung: rover %d's process restarted at t = %.2f s\n", k,
                    bus->sim_time);
            pr->down_after[k] = pr->up_at[k] = INT64_MAX;
            pr->restarts++;
            pr->hung_restarts++;
            pr->hung_stage[k] = FM_HUNG_NONE;
        }
    }
    return 0;
}

int fm_hung_step(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus)
{
    int k;
    for (k = 1; k < pr->hw.n && !cfg->single; k++) {
        if (pr->hung_stage[k] == FM_HUNG_KILLED && bus->clock_step > pr->hung_step[k]) {
            if (restart_rover(pr, cfg, bus, k) != 0)
                return FM_ERR_FAULT;
            fprintf(stderr, "formation: hung: rover %d's process restarted at t = %.2f s\n", k,
                    bus->sim_time);
            pr->hung_stage[k] = FM_HUNG_RESTARTING;
        }
        if (pr->hung_stage[k] == FM_HUNG_RESTARTING) {
            const int rc = rejoined(pr, bus, k, "hung");
            if (rc != 1)
                return rc;
            pr->hung_restarts++;
            pr->hung_stage[k] = FM_HUNG_NONE;
        }
    }
    return 1;
}
