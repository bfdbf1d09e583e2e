/* rover_daemon: the state of tandem-rover, one struct created in main and
 * handed to the cycle and to every handler (see tandem_rover.c), and the
 * calls between its files: tandem_rover.c (command line, cycle, start-up),
 * rover_inputs.c (frames and team messages in, lockstep input
 * completeness), rover_outputs.c (commands, states and team messages out,
 * the console, --journal).
 */
#ifndef TANDEM_ROVER_DAEMON_H
#define TANDEM_ROVER_DAEMON_H

#include <stdint.h>
#include "daemon.h"
#include "rover_batch.h"
#include "journal.h"
#include "peer.h"
#include "fleet.h"
#include "rover_ctl.h"
#include "rover_world.h"
#include "world_file.h"
#include "tandem_rover_command_t.h"
#include "tandem_rover_state_t.h"
#include "tandem_team_msg_t.h"

/* One process hosts up to the fleet's capacity (the build setting
 * ROVER_WORLD_MAX_ROBOTS); the mates' tables are indexed by robot id; the
 * team messages queued between two cycles, two a robot. */
#define HOST_MAX ROVER_WORLD_MAX_ROBOTS
#define MATES_MAX ROVER_WORLD_MAX_ROBOTS
#define TEAMQ_MAX (2 * ROVER_WORLD_MAX_ROBOTS)

/* --goal-path: steer by the world's navigation function, or straight for
 * the goal as the seed (docs/method/formation.md §14) */
enum { ROVER_GOAL_PATH_MAP = 0, ROVER_GOAL_PATH_DIRECT = 1 };

/* Failures of tandem-rover's own steps (0 = ok). */
#define ROVER_DAEMON_ERR_IDS (-1)     /* --id is not K or A-B inside 1..HOST_MAX robots */
#define ROVER_DAEMON_ERR_JOURNAL (-2) /* a robot's journal is refused or does not open (said) */
/* their texts are their names (what tandem-rover prints; status.h) */
#define ROVER_DAEMON_CODES(X)                       \
    X(0, "ok")                                      \
    X(ROVER_DAEMON_ERR_IDS, "ROVER_DAEMON_ERR_IDS") \
    X(ROVER_DAEMON_ERR_JOURNAL, "ROVER_DAEMON_ERR_JOURNAL")
const char *rover_daemon_strerror(int rc);

typedef struct hosted {
    rover_ctl_state c;
    int64_t cmd_seq, state_seq, team_seq;
    int64_t last_rx_ns;                         /* wall time of the last sensor message */
    int64_t sens_step, sonar_step, camera_step; /* last frames taken (-1 none) */
    /* frames taken but not yet applied: the cycle applies them in one
     * order (encoders, sonar, camera), whatever order they arrived in */
    int new_enc, new_sonar, new_cam;
    double enc_rad[2];
    double sonar_m[BEH_SONAR_N];
    int cam_n;
    int32_t cam_target[ROVER_TEAM_MAX + ROVER_WORLD_MAX_LANDMARKS];
    double cam_range_m[ROVER_TEAM_MAX + ROVER_WORLD_MAX_LANDMARKS];
    double cam_bearing_rad[ROVER_TEAM_MAX + ROVER_WORLD_MAX_LANDMARKS];
    int silent; /* lockstep: frames stopped (killed body) */
    /* the world's posts its localizer holds, ascending: its landmark k is
     * post[k] (the camera reports posts by the world's index) */
    int32_t post[ROVER_WORLD_MAX_LANDMARKS];
    int n_posts;
    tandem_team_msg_t last_team; /* for republish (robot 0: none yet) */
    int team_due;                /* --batch: last_team made this cycle, not sent yet */
    char ch_cmd[24], ch_state[24];
    int shown_mode, shown_type, shown_yield; /* last printed (-1: none yet) */
    int shown_esc;                           /* escape phase and wall side last printed */
    char journal_path[600];                  /* "" without --journal */
    journal jr;
    int journal_held; /* its record of this cycle not written: stopped */
} hosted;

typedef struct teamq_item {
    int64_t step;
    rover_team_msg m;
} teamq_item;

/* The hosted robots' commands and states of one cycle (rover_publish_outbox). */
typedef struct rover_outbox {
    tandem_rover_command_t cmd[HOST_MAX];
    tandem_rover_state_t st[HOST_MAX];
    int n;
    int64_t step, utime, batch_seq; /* step -1: empty */
} rover_outbox;

typedef struct rover_daemon {
    daemon d; /* the shell: bus, loop, counters, health */
    int32_t id_lo, id_hi;
    int robots;
    /* --teams T --robots-per-team K (fleet.h): T teams in one world; a
     * hosted robot hears only its own team, this process only the teams
     * of its robots: ids listen_lo..listen_hi (1..robots with one team) */
    int teams, per_team, team_goals;
    rover_fleet fleet;
    int32_t listen_lo, listen_hi;
    int world, formation, blend;
    rover_world_config layout;
    world_opts wopt; /* --world-file, --start, --goal */
    rover_ctl_params params;
    hosted h[HOST_MAX];
    teamq_item q[TEAMQ_MAX];
    int nq;
    double last_t_s;
    int64_t last_step;
    int64_t dropped_q;
    int batch;     /* --batch: ROVERS_COMMAND / ROVERS_STATE */
    int localize;  /* --localize: landmarks fused (1) */
    int goal_path; /* --goal-path: ROVER_GOAL_PATH_* */
    navfield nav;  /* the world's navigation function (--goal-path map) */
    int64_t batch_seq;
    /* lockstep: what each mate last said on TEAM, and what we published */
    int64_t mate_step[MATES_MAX + 1]; /* -1: nothing yet */
    int mate_gone[MATES_MAX + 1];
    peer_watch mate_peer[MATES_MAX + 1]; /* the process hosting each mate */
    int64_t wait_step, wait_since_ns;    /* incomplete inputs */
    int64_t gone_count;
    rover_outbox out[2]; /* out[cur]: the last cycle */
    /* --batch: the hosted robots' team messages of a cycle, gathered into
     * TEAMS chunks (rover_publish_teams) */
    tandem_team_msg_t teams_out[HOST_MAX];
    int64_t teams_seq;
    int cur;
    const char *journal; /* --journal PATH, NULL: none */
    int64_t first_step;  /* the first step this process ran a cycle for (-1) */
    int journal_reset;   /* --journal-reset: start fresh, emptying the journal(s) */
    int journal_failing; /* the last append failed (said once) */
    int64_t journal_errors;
} rover_daemon;

/* The hosted robot id, or NULL (another host's robot). */
hosted *rover_find_hosted(rover_daemon *rd, int32_t id);

/* rover_inputs.c */
int rover_too_early(rover_daemon *rd, int64_t step);
void rover_apply_frames(rover_daemon *rd, hosted *h);
void rover_on_sensors(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_sonar(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_beacons(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_sensors_batch(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_beacons_batch(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_team(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_on_teams(const lcm_recv_buf_t *rb, const char *ch, void *u);
/* SIM_ACK: the pid of the process hosting each mate, and that it lives. */
void rover_on_ack(const lcm_recv_buf_t *rb, const char *ch, void *u);
void rover_deliver_team(rover_daemon *rd, int64_t step, double t_s);
/* Lockstep: 1 when the cycle of step may run (its inputs are here, or
 * the missing ones are taken as gone), 0 to wait for it again. */
int rover_inputs_complete(rover_daemon *rd, int64_t step);

/* rover_outputs.c */
void rover_publish_team(rover_daemon *rd, hosted *h, const rover_ctl_out *o, int64_t step,
                        int64_t utime);
void rover_fill_outputs(hosted *h, const rover_ctl_out *o, int64_t step, int64_t utime,
                        tandem_rover_command_t *cmd, tandem_rover_state_t *st);
void rover_publish_outbox(rover_daemon *rd, rover_outbox *o);
/* --batch: the team messages made this cycle (again = 0) or every robot's
 * last one (again = 1, a repeated step) as TEAMS, BATCH_MAX a message. */
void rover_publish_teams(rover_daemon *rd, int again);
void rover_republish(daemon *d, void *user);
void rover_report_changes(hosted *h, const rover_ctl_out *o, double t_s);
/* Resumes each robot from its journal and opens it for appending: 0, or
 * ROVER_DAEMON_ERR_JOURNAL. */
int rover_journal_start(rover_daemon *rd);
/* After a cycle's outputs are made, before they go out: one record per
 * robot; returns how many robots' records were not written. */
int rover_journal_cycle(rover_daemon *rd, int64_t step);
/* The robots of the outbox whose record was not written stop (zero
 * speeds, mode SAFE_STOP) until one is: a restart would take them back
 * to the last pose written, and they must not be anywhere else. */
void rover_journal_hold(rover_daemon *rd, rover_outbox *o);
void rover_journal_stop(rover_daemon *rd);

#endif
