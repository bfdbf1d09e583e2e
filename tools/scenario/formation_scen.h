/* formation_scen: NOT A PUBLIC INTERFACE. What the files of
 * `tandem-scenario formation` (docs/method/formation.md §6) share:
 *   scenario_formation.c  options and the driver (set-up, the lockstep
 *                         loop, the end of the run)
 *   formation_procs.c     the children: simulator and rover processes,
 *                         --kill and --fault
 *   formation_bus.c       the lockstep clock and answers, the robots'
 *                         states by step, the subscriptions
 *   formation_metrics.c   the metrics from ground truth (ROVER_TRUTH)
 *   formation_report.c    success criteria, summary.json, plots
 *   formation_world.c     a file world kept with the run, --world random
 * A run is in parts, each written by one file and handed to the others
 * only where they need it (as the carry scenario does): fm_cfg (the
 * options and the set-up), fm_procs (the children), fm_bus (the clock,
 * the answers, the robots' states), fm_metrics, and fm_outcome (how the
 * run ended); fm_run holds them.
 */
#ifndef TANDEM_FORMATION_SCEN_H
#define TANDEM_FORMATION_SCEN_H

#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "auth_child.h"
#include "daemon.h"
#include "hang_watch.h"
#include "rover_world.h"
#include "world_file.h"
#include "scenario.h"
#include "shared_run.h"
#include "tandem_rover_state_t.h"
#include "tandem_rover_truth_t.h"

#define FM_MAX ROVER_WORLD_MAX_ROBOTS /* the fleet; one team: ROVER_TEAM_MAX */
#define FM_PERIOD 50
#define FM_PROCS (FM_MAX + 2)
#define FM_RING 4      /* states kept per robot */
#define FM_OUT_TOL 0.3 /* d_r: a robot further than this from its slot is out */

/* Failures of the children (0 = ok). */
#define FM_ERR_START (-1) /* the simulator or a rover process did not start */
#define FM_ERR_FAULT (-2) /* --fault or hung: a rover not restarted, or not back within 60 s */
#define FM_ERR_HUNG (-3)  /* the simulator, or the one process of all rovers, hung: killed */

/* fm_procs.hung_stage */
enum { FM_HUNG_NONE = 0, FM_HUNG_KILLED = 1, FM_HUNG_RESTARTING = 2 };

/* The run as asked for (the options) and as set up from them (the world's
 * layout, the way, the time limit, the children's world). Written by
 * scenario_formation.c's parse and set-up and by formation_world.c before
 * the children start; read by every file after. */
typedef struct fm_cfg {
    int formation, world, blend, robots, single, batch;
    int far_kinematic; /* --rover-far kinematic (tandem-sim's) */
    /* --hosts H: with --procs single, H tandem-rover processes, each a run
     * of whole teams (auth_fleet_host); --host-netns P: host h runs in the
     * network namespace P<h> (/var/run/netns, made by the caller), as on
     * another machine on the bus */
    int hosts;
    const char *host_netns;
    /* --teams T --robots-per-team K --team-goals (fleet.h): robots is T K
     * and fleet the teams' lanes and goals when T > 1 */
    int teams, per_team, team_goals;
    rover_fleet fleet;
    int law_kanayama, ref_goal, localize_off; /* --formation-law, --ref-heading, --localize */
    int goal_direct;                          /* --goal-path direct (1) or map (0) */
    double ref_arrive_m;                      /* --ref-arrive */
    char timeout_ms[24];                      /* --lockstep-timeout-ms */
    long timeout_ms_given;
    scenario_drop drop; /* --drop-rate */
    const char *drop_arg;
    long seed;
    double max_time_s; /* --max-time; 0: fm_time_limit_s of the way */
    double way_m;      /* fm_way_length_m of the layout (NAN: no way found) */
    double passage_m;  /* fm_passage_width_m of the layout */
    double cut_m;      /* fm_cut_width_m of the layout */
    int kill_id;
    double kill_t_s;
    scenario_fault faults[SCENARIO_MAX_FAULTS]; /* --fault kill:roverK:T[:R] as given */
    int n_faults;
    double hang_s; /* --hang-s */
    const char *out, *url;
    int out_given;
    char url_buf[160];
    char bindir[512];
    world_opts wopt;        /* --world-file, --start, --goal (world_file.h) */
    int world_kind;         /* --world-kind (WORLDGEN_*) */
    long world_seed;        /* --world-seed */
    const char *world_size; /* --world-size WxH */
    world_opts child_world; /* what the children get: OUT/world.yaml for a file world */
    char world_copy[700];
    rover_world_config layout;
} fm_cfg;

/* The children and what is done to them: --kill, --fault, --hang-s.
 * Written by formation_procs.c alone. */
typedef struct fm_procs {
    pid_t pid[FM_PROCS];
    int n_pid;
    auth_child_keys keys;                       /* the children's role files */
    pid_t rover_pid[FM_MAX + 1];                /* process hosting robot k (separate mode) */
    scenario_fault faults[SCENARIO_MAX_FAULTS]; /* fm_cfg's, and how far each has gone */
    int n_faults, kills, restarts;
    double hold_since_s;            /* wall time a restart began holding the step */
    int64_t down_after[FM_MAX + 1]; /* --fault: robot k's process answered no step in */
    int64_t up_at[FM_MAX + 1];      /* (down_after, up_at): no states then */
    int killed;                     /* --kill done */
    /* --hang-s: children alive but silent on their health channels. Slot
     * 0 the simulator, slot k robot k's process (slot 1 the one process
     * of all with --procs single); a hung rover is restarted as a --fault
     * restart (HUNG_* stages, the step announced at its kill) */
    hang_watch hw;
    int hung_stage[FM_MAX + 1];
    int64_t hung_step[FM_MAX + 1];
    int hung_restarts;
    int hung_stopped; /* a child that cannot be restarted hung: run stopped */
    /* the kills' leaves and KILL_ROBOT, sent again until taken */
    scenario_leave leave[FM_MAX + 1];
    int leave_resends, kill_resends;
    int kill_seen;          /* ROVER_TRUTH shows the --kill robot dead */
    int64_t kill_sent_step; /* the step of the last KILL_ROBOT sent */
} fm_procs;

/* What the bus brings: the lockstep clock and our answers, each rover
 * process's last answer, the robots' states by step. Written by
 * formation_bus.c alone. */
typedef struct fm_bus {
    const fm_cfg *cfg;
    auth_bus *auth; /* the process's bus (run_key_bus) */
    hang_watch *hw; /* fm_procs's: the children's signs of life heard here */
    lcm_t *lcm;
    names_watch names; /* the bound on LCM's table of channel names */
    int64_t clock_step, answered, ack_seq, last_clock_ns;
    int have_clock;
    int clock_repeat; /* the simulator announced an answered step again */
    double sim_time;
    int64_t rover_ack[FM_MAX + 1]; /* the last step each rover process answered */
    /* the robots' last states by step: truth at step k is read with the
     * states of the cycle before (k - FM_PERIOD), whatever arrived since */
    tandem_rover_state_t ring[FM_MAX][FM_RING];
    /* the states taken with the last truth */
    int mode[FM_MAX];
    int state_type[FM_MAX];
    double state_scale[FM_MAX];
    double weight[FM_MAX][4];
    pose2 est[FM_MAX]; /* the robot's own odometry, world frame */
    int have_state[FM_MAX];
    int64_t last_truth_step;
    /* a fleet's truth of one step, gathered from its pieces (the simulator
     * sends RV_TRUTH_CHUNK robots a message, in id order) */
    struct fm_truth_parts {
        tandem_rover_truth_t m; /* the whole step's, its arrays below */
        int32_t robot[FM_MAX], collisions[FM_MAX];
        double x_m[FM_MAX], y_m[FM_MAX], theta_rad[FM_MAX], min_clearance_m[FM_MAX];
        int8_t alive[FM_MAX];
        int have;                 /* robots gathered for step m.step */
        int64_t got_step[FM_MAX]; /* the step of the piece that began at robot k */
    } parts;
} fm_bus;

/* One team's own criteria in a run of many (fleet.h): its formation
 * error about its own centroid and goal, its contacts, its arrival. */
typedef struct fm_team_metrics {
    int type_now; /* formation reported by its lowest live id */
    double scale_now;
    int last_type; /* ... at the last cycle, -1 none */
    int samples, out_samples;
    double sum_sq_err, max_err, min_clear;
    int collisions;        /* contact onsets of its robots */
    int collisions_mates;  /* ... with a robot of its own team within reach */
    int collisions_others; /* ... with a robot of another team within reach */
    int formation_changes;
    int reached;
    double time_to_goal;
} fm_team_metrics;

/* The metrics from ground truth and the robots' states, and their time
 * series. Written by formation_metrics.c alone. With many teams the
 * run's keys cover the fleet: each robot's formation error is from its
 * own team's slot, the goal is reached when every team has reached its
 * own, the formation changes are the teams' summed; team[] holds each
 * team's own. */
typedef struct fm_metrics {
    int type_now; /* formation reported by the lowest alive id */
    double scale_now;
    int last_type; /* formation of the lowest live robot at the last cycle, -1 none */
    int samples, out_samples;
    double sum_sq_err, max_err, min_clear, path[FM_MAX];
    double prev_x[FM_MAX], prev_y[FM_MAX], prev_th[FM_MAX], prev_w[FM_MAX];
    int have_prev[FM_MAX], have_prev_w[FM_MAX];
    double sum_dw;
    long n_dw;
    double loc_sum_sq, loc_max;
    long loc_n; /* own estimate vs truth */
    int collisions, formation_changes, escapes;
    /* the simulator's contact events split by what was touched: a mate
     * (another live robot's body within reach at that sample) or a wall */
    int coll_prev[FM_MAX], collisions_mates, collisions_walls;
    int reached;
    double time_to_goal;
    int collisions_teams; /* contact onsets with a robot of another team within reach */
    fm_team_metrics team[ROVER_FLEET_MAX_TEAMS];
    FILE *truth_csv, *err_csv, *w_csv, *snap_csv;
    double last_snap_t;
} fm_metrics;

/* How the run ended (scenario_formation.c). */
typedef struct fm_outcome {
    int lost_lockstep;  /* the simulator dropped us: not the seed's run */
    int restart_failed; /* a --fault restart did not rejoin within 60 s */
    char failed[256];   /* failed success criteria (fm_criteria) */
    int n_failed;
} fm_outcome;

/* A run's parts, held by scenario_formation.c; ROVER_TRUTH's handler
 * (formation_bus.c) hands each its part. */
typedef struct fm_run {
    fm_cfg cfg;
    fm_procs procs;
    fm_bus bus;
    fm_metrics metrics;
    fm_outcome outcome;
} fm_run;

/* scenario_formation.c: the names of the --formation and --blend choices */
const char *fm_formation_name(int f);
const char *fm_blend_name(int b);

/* formation_world.c: a file world kept in the output directory as
 * world.yaml + world.pgm, which the children then read. 0, or 1 (said). */
int fm_keep_world(fm_cfg *cfg);
/* --world random: the world generated (--world-kind, --world-seed,
 * --world-size, the team), written as OUT/world.yaml + .pgm and taken as
 * the run's --world-file. 0, or an exit status (said). */
int fm_random_world(fm_cfg *cfg);
#define FM_WORLD_RANDOM 101                /* --world random */
extern const char *const fm_world_names[]; /* the built-ins and "random" */
extern const int fm_world_values[];
extern const char *const fm_world_kinds[]; /* worldgen's kinds, in WORLDGEN_* order */
/* The --world word for the children ("open" under a --world-file). */
const char *fm_world_arg(const fm_cfg *cfg);

/* formation_procs.c */
/* Before the children: no process down, cfg's --fault taken. */
void fm_procs_init(fm_procs *pr, const fm_cfg *cfg);
/* Starts the simulator and the rover processes; 0 ok, FM_ERR_START. */
int fm_start_children(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus);
/* The rover processes of the run: one per robot, or its hosts (--hosts). */
int fm_rover_procs(const fm_cfg *cfg);
/* SIGTERM to every child, SIGKILL to those still there after 5 s. */
void fm_stop_children(fm_procs *pr);
/* --fault at a step due to be answered: 1 go on, 0 hold the step,
 * FM_ERR_FAULT. */
int fm_faults_step(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus);
/* --kill K:T once T is reached: the robot's body and its process; the
 * command sent again every cycle until ROVER_TRUTH shows the robot dead,
 * the process's leave until the simulator takes it. */
void fm_kill_robot(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus);
/* ROVER_TRUTH: whether it shows the --kill robot dead. */
void fm_kill_truth(fm_procs *pr, const fm_cfg *cfg, const tandem_rover_truth_t *m);
/* --fault: robot id's process was down at step k (it published no state). */
int fm_process_down(const fm_procs *pr, int id, int64_t k);
/* --hang-s, between steps: watches the children (hang_watch) from now;
 * hung ones are killed. 0 go on, FM_ERR_HUNG: the run is to stop. */
void fm_hang_start(fm_procs *pr, const fm_cfg *cfg, const fm_bus *bus);
int fm_hung_watch(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus);
void fm_hang_stop(fm_procs *pr, const fm_bus *bus);
/* A hung rover's restart at a step due to be answered: 1 go on, 0 hold
 * the step, FM_ERR_FAULT. */
int fm_hung_step(fm_procs *pr, const fm_cfg *cfg, fm_bus *bus);
const char *fm_strerror(int err);

/* formation_bus.c */
/* Opens the bus (0, or 1 said); hw: where the signs of life go. */
int fm_bus_open(fm_bus *bus, const fm_cfg *cfg, hang_watch *hw);
/* Subscribes the handlers (bus, and r for ROVER_TRUTH, as their user
 * pointers), deep queues but the clock's. */
void fm_subscribe(fm_run *r);
void fm_unsubscribe(fm_run *r);
/* Handles what arrives within ms (lcm_handle_timeout's result); a flood
 * of channel names: a new handle. */
int fm_bus_handle(fm_bus *bus, int ms);
void fm_ack(fm_bus *bus, int64_t step);
/* The clock's step answered: acked now, or (ack 0, the run is over) only
 * taken as answered. */
void fm_answer(fm_bus *bus, int ack);
/* The simulator announced an answered step again: our ack was lost,
 * answered again. */
void fm_answer_repeat(fm_bus *bus);
/* No clock for 500 ms: answers the last clock again if it is a step
 * everyone answers. fm_quiet_from_now starts that clock. */
void fm_nudge_if_quiet(fm_bus *bus);
void fm_quiet_from_now(fm_bus *bus);
/* --fault: robot k's process was killed: its answers from now on only. */
void fm_forget_ack(fm_bus *bus, int k);
int64_t fm_mono_ns(void);
/* Robot i's state of step k from the ring, or NULL. */
const tandem_rover_state_t *fm_ring_get(const fm_bus *bus, int i, int64_t k);

/* formation_metrics.c */
/* Before the run: the start formation, no clearance seen yet. */
void fm_metrics_init(fm_metrics *mt, const fm_cfg *cfg);
/* truth.csv, formation_error.csv, weights.csv, snapshots.csv in out. */
void fm_metrics_open(fm_metrics *mt, const char *out);
void fm_metrics_close(fm_metrics *mt);
/* A truth taken with the robots' states of the cycle before (bus);
 * dz_entries: the robots that entered the dead zone in them. */
void fm_metrics_truth(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus, const fm_procs *pr,
                      const tandem_rover_truth_t *m, int dz_entries);
/* At a cycle: a change of formation of the lowest live robot counted. */
void fm_metrics_cycle(fm_metrics *mt, const fm_cfg *cfg, const fm_bus *bus, const fm_procs *pr);

/* formation_report.c */
/* Appends the failed success criteria to buf; returns how many failed. */
int fm_criteria(const fm_cfg *cfg, const fm_procs *pr, const fm_metrics *mt, const fm_outcome *oc,
                char *buf, size_t cap);
/* The widest way's bottleneck from the start to the goal (m): twice the
 * largest clearance a disc keeps on some way; 10 when 5 m is kept, 0 when
 * not even the robot body finds a way. */
double fm_passage_width_m(const rover_world_config *w);
/* The narrowest cross-section of all the ways together, side by side (a
 * team splitting round an obstacle): see formation_way.c. INFINITY where
 * the way from the start to the goal is no longer than the team is wide,
 * 0 where there is none. */
double fm_cut_width_m(const rover_world_config *w, double team_width_m);
/* Width the team's formation needs (formation width + the FSM's margin). */
double fm_needed_width_m(const fm_cfg *cfg);
/* The start formation's width without that margin: below it a change is demanded. */
double fm_formation_width_m(const fm_cfg *cfg);
/* The run's time limit follows from the way (--max-time not given):
 * FM_TIME_BASE_S for the start, the formation changes and one escape,
 * plus the way at FM_TIME_SPEED_MPS (the speed a team keeps while it
 * reshapes or goes round a trap); FM_TIME_DEFAULT_S if no way was found.
 * On the built-in dead-zone world (a way of 13.3 m) this is 149 s, the
 * 150 s every world had before; its slowest 3-robot runs take 124 s. */
#define FM_TIME_BASE_S 60.0
#define FM_TIME_SPEED_MPS 0.15
#define FM_TIME_DEFAULT_S 150.0
/* Length (m) of the shortest way for the robot body (cells farther than
 * its radius about C from every obstacle, 8-connected, on a grid of at
 * least 0.1 m) from the team's start (the mean of its start poses) to the
 * goal; NAN if there is none. */
double fm_way_length_m(const rover_world_config *w);
double fm_time_limit_s(double way_m);
void fm_write_summary(const fm_cfg *cfg, const fm_procs *pr, const fm_metrics *mt,
                      const fm_outcome *oc, double sim_s, double wall_s);
void fm_write_plots(const fm_cfg *cfg);

#endif
