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
 */
#ifndef TANDEM_FORMATION_SCEN_H
#define TANDEM_FORMATION_SCEN_H

#include <stdint.h>
#include <stdio.h>
#include <sys/types.h>
#include <lcm/lcm.h>
#include "auth_child.h"
#include "daemon.h"
#include "hang_watch.h"
#include "rover_world.h"
#include "world_file.h"
#include "scenario.h"
#include "shared_run.h"
#include "tandem_rover_state_t.h"
#include "tandem_rover_truth_t.h"

#define FM_MAX ROVER_TEAM_MAX
#define FM_PERIOD 50
#define FM_PROCS (FM_MAX + 2)
#define FM_RING 4      /* states kept per robot */
#define FM_OUT_TOL 0.3 /* d_r: a robot further than this from its slot is out */

/* Failures of the children (0 = ok). */
#define FM_ERR_START (-1) /* the simulator or a rover process did not start */
#define FM_ERR_FAULT (-2) /* --fault or hung: a rover not restarted, or not back within 60 s */
#define FM_ERR_HUNG (-3)  /* the simulator, or the one process of all rovers, hung: killed */

/* fm_state.hung_stage */
enum { FM_HUNG_NONE = 0, FM_HUNG_KILLED = 1, FM_HUNG_RESTARTING = 2 };

typedef struct fm_state {
    /* options */
    int formation, world, blend, robots, single, batch;
    int law_kanayama, ref_goal, localize_off; /* --formation-law, --ref-heading, --localize */
    double ref_arrive_m;                      /* --ref-arrive */
    char timeout_ms[24];                      /* --lockstep-timeout-ms */
    long timeout_ms_given;
    scenario_drop drop; /* --drop-rate */
    const char *drop_arg;
    long seed;
    double max_time_s; /* --max-time; 0: fm_time_limit_s of the way */
    double way_m;      /* fm_way_length_m of the layout (NAN: no way found) */
    double passage_m;  /* fm_passage_width_m of the layout */
    int kill_id;
    double kill_t_s;
    scenario_fault faults[SCENARIO_MAX_FAULTS]; /* --fault kill:roverK:T[:R] */
    int n_faults, kills, restarts;
    int64_t rover_ack[FM_MAX + 1];  /* the last step each rover process answered */
    double hold_since_s;            /* wall time a restart began holding the step */
    int64_t down_after[FM_MAX + 1]; /* --fault: robot k's process answered no step in */
    int64_t up_at[FM_MAX + 1];      /* (down_after, up_at): no states then */
    const char *out, *url;
    int out_given;
    char url_buf[160];
    char bindir[512];
    /* children */
    pid_t pid[FM_PROCS];
    int n_pid;
    auth_child_keys keys;        /* the children's role files */
    pid_t rover_pid[FM_MAX + 1]; /* process hosting robot k (separate mode) */
    /* lcm */
    lcm_t *lcm;
    names_watch names; /* the bound on LCM's table of channel names */
    int64_t clock_step, answered, ack_seq, last_clock_ns;
    int have_clock;
    world_opts wopt;        /* --world-file, --start, --goal (world_file.h) */
    int world_kind;         /* --world-kind (WORLDGEN_*) */
    long world_seed;        /* --world-seed */
    const char *world_size; /* --world-size WxH */
    world_opts child_world; /* what the children get: OUT/world.yaml for a file world */
    char world_copy[700];
    /* layout and truth */
    rover_world_config layout;
    int type_now; /* formation reported by the lowest alive id */
    double scale_now;
    int mode[FM_MAX];
    int state_type[FM_MAX];
    double state_scale[FM_MAX];
    double weight[FM_MAX][4];
    pose2 est[FM_MAX]; /* the robot's own odometry, world frame */
    int have_state[FM_MAX];
    /* the robots' last states by step: truth at step k is read with the
     * states of the cycle before (k - FM_PERIOD), whatever arrived since */
    tandem_rover_state_t ring[FM_MAX][FM_RING];
    int clock_repeat; /* the simulator announced an answered step again */
    int last_type;    /* formation of the lowest live robot at the last cycle, -1 none */
    /* metrics */
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
    double time_to_goal, sim_time;
    int killed;
    FILE *truth_csv, *err_csv, *w_csv, *snap_csv;
    double last_snap_t;
    int64_t last_truth_step;
    char failed[256]; /* failed success criteria (fm_criteria) */
    int n_failed;
    int lost_lockstep;  /* the simulator dropped us: not the seed's run */
    int restart_failed; /* a --fault restart did not rejoin within 60 s */
    /* --hang-s: children alive but silent on their health channels. Slot
     * 0 the simulator, slot k robot k's process (slot 1 the one process
     * of all with --procs single); a hung rover is restarted as a --fault
     * restart (HUNG_* stages, the step announced at its kill) */
    double hang_s;
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
} fm_state;

/* scenario_formation.c: the names of the --formation and --blend choices */
const char *fm_formation_name(int f);
const char *fm_blend_name(int b);

/* formation_procs.c */
/* Starts the simulator and the rover processes; 0 ok, FM_ERR_START. */
int fm_start_children(fm_state *fm);
/* SIGTERM to every child, SIGKILL to those still there after 5 s. */
/* formation_world.c: a file world kept in the output directory as
 * world.yaml + world.pgm, which the children then read. 0, or 1 (said). */
int fm_keep_world(fm_state *fm);
/* --world random: the world generated (--world-kind, --world-seed,
 * --world-size, the team), written as OUT/world.yaml + .pgm and taken as
 * the run's --world-file. 0, or an exit status (said). */
int fm_random_world(fm_state *fm);
#define FM_WORLD_RANDOM 101                /* --world random */
extern const char *const fm_world_names[]; /* the built-ins and "random" */
extern const int fm_world_values[];
extern const char *const fm_world_kinds[]; /* worldgen's kinds, in WORLDGEN_* order */
/* The --world word for the children ("open" under a --world-file). */
const char *fm_world_arg(const fm_state *fm);
void fm_stop_children(fm_state *fm);
/* --fault at a step due to be answered: 1 go on, 0 hold the step,
 * FM_ERR_FAULT. */
int fm_faults_step(fm_state *fm);
/* --kill K:T once T is reached: the robot's body and its process; the
 * command sent again every cycle until ROVER_TRUTH shows the robot dead,
 * the process's leave until the simulator takes it. */
void fm_kill_robot(fm_state *fm);
/* --hang-s, between steps: watches the children (hang_watch) from now;
 * hung ones are killed. 0 go on, FM_ERR_HUNG: the run is to stop. */
void fm_hang_start(fm_state *fm);
int fm_hung_watch(fm_state *fm);
/* A hung rover's restart at a step due to be answered: 1 go on, 0 hold
 * the step, FM_ERR_FAULT. */
int fm_hung_step(fm_state *fm);
const char *fm_strerror(int err);

/* formation_bus.c */
/* Subscribes the handlers (fm as their user pointer), deep queues but the clock's. */
void fm_subscribe(fm_state *fm);
void fm_unsubscribe(fm_state *fm);
void fm_ack(fm_state *fm, int64_t step);
/* Answers the last clock again if it is a step everyone answers. */
void fm_nudge(fm_state *fm);
int64_t fm_mono_ns(void);
/* Robot i's state of step k from the ring, or NULL. */
const tandem_rover_state_t *fm_ring_get(const fm_state *fm, int i, int64_t k);
/* --fault: robot id's process was down at step k (it published no state). */
int fm_process_down(const fm_state *fm, int id, int64_t k);
/* Truth at step k is taken with every live robot's state of the cycle
 * before; 0 while one of them is missing. */
int fm_states_for_truth(fm_state *fm, const tandem_rover_truth_t *m);

/* formation_metrics.c: ROVER_TRUTH (typed handler, fm as user) */
void fm_on_truth(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_truth_t *m, void *u);

/* formation_report.c */
/* Appends the failed success criteria to buf; returns how many failed. */
int fm_criteria(const fm_state *fm, char *buf, size_t cap);
/* The widest way's bottleneck from the start to the goal (m): twice the
 * largest clearance a disc keeps on some way; 10 when 5 m is kept, 0 when
 * not even the robot body finds a way. */
double fm_passage_width_m(const rover_world_config *w);
/* Width the team's formation needs (formation width + the FSM's margin). */
double fm_needed_width_m(const fm_state *fm);
/* The start formation's width without that margin: below it a change is demanded. */
double fm_formation_width_m(const fm_state *fm);
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
void fm_write_summary(const fm_state *fm, double wall_s);
void fm_write_plots(const fm_state *fm);

#endif
