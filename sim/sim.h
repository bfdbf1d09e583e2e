/* tandem-sim: the ODE world shared by every simulated model (docs/method/lockstep.md §1, §3).
 *
 * One world, one fixed 1 kHz step, two timing modes: real time (steps on
 * the wall clock, zero-order hold of the last command, stale-command
 * watchdog) and lockstep (step k+1 only after every registered controller
 * has answered step k). Models (the PUMA pair, the Pioneer team) add bodies
 * to this world and hook into the step through sim_model_ops.
 */
#ifndef TANDEM_SIM_H
#define TANDEM_SIM_H

#include <stddef.h>
#include <stdint.h>
#include <ode/ode.h>
#include <lcm/lcm.h>
#include "daemon.h"
#include "peer.h"
#include "rover_world.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

#define SIM_DT_S 0.001
#define SIM_MAX_CONTACTS 1024
#define SIM_MAX_PARTICIPANTS 16
/* the arm cell's bodies and three per Pioneer */
#define SIM_MAX_BODIES (2048 + 3 * ROVER_WORLD_MAX_ROBOTS)

/* The stick is a hand-held rod with a force sensor, not a rigid wall: its
 * contact is a spring-damper (a firm grip: 20 N per mm, damped near
 * critically for the 2-10 kg a PUMA link presents at the contact). The
 * figures are split over the contact points ODE generates for one pair. */
#define SIM_STICK_STIFFNESS_NPM 2.0e4
#define SIM_STICK_DAMPING_NSPM 600.0

/* Collision categories (geom category bits) so models can filter pairs. */
enum {
    SIM_CAT_GROUND = 1u << 0,
    SIM_CAT_ARM = 1u << 1,
    SIM_CAT_TABLE = 1u << 2,
    SIM_CAT_WORKPIECE = 1u << 3,
    SIM_CAT_STICK = 1u << 4,
    SIM_CAT_ROVER = 1u << 5,
    SIM_CAT_OBSTACLE = 1u << 6
};

/* Failures of the world and its models (0 = ok). */
#define SIM_OK 0
#define SIM_ERR_CREATE (-1)  /* the world or a model cannot be built (said on stderr) */
#define SIM_ERR_CONTROL (-2) /* a control message for this model, but invalid (refused) */

typedef struct sim_contact {
    dBodyID b1, b2;
    dJointFeedback fb;
} sim_contact;

typedef struct sim_participant {
    char name[DAEMON_NAME_MAX];
    int32_t period_steps;
    int64_t last_ack;  /* last step answered */
    int64_t first_ack; /* the step it joined on (its first answer) */
    int active;
    peer_watch peer;       /* its pid (from its acks) and when last heard */
    int64_t answer_ns_avg; /* wall time from a due step's announcement to its
                              answer, averaged over ~16 answers (re-announce timer) */
} sim_participant;

typedef struct sim_world {
    dWorldID world;
    dSpaceID space;
    dJointGroupID contacts;
    dGeomID ground;
    int64_t step;
    double time_s;
    uint64_t seed;
    int lockstep;
    int paused;
    daemon d; /* options, counters, health, loop stats; its
                                      LCM handle (d.lcm) is renewed under a flood
                                      of channel names (daemon_names_watch): read
                                      it there each time, keep no copy */
    sim_contact contact[SIM_MAX_CONTACTS];
    int n_contacts;
    int64_t contacts_dropped;
    sim_participant part[SIM_MAX_PARTICIPANTS];
    int n_part;
    int64_t lockstep_timeouts;
    int64_t lockstep_reannounced; /* steps announced again (an answer late or lost) */
    int64_t step_announced_ns;    /* wall time the current step was first announced */
    double lockstep_timeout_s;
    int64_t stale_commands;
    int64_t stick_refused; /* insertions refused: no pose clear of the arms */
    int64_t status_seq, clock_seq;
    dBodyID bodies[SIM_MAX_BODIES]; /* every body, in creation order (hashing) */
    int n_bodies;
} sim_world;

int sim_world_create(sim_world *w);
void sim_world_destroy(sim_world *w);
/* Registers a body for the state hash; models call this for every body. */
dBodyID sim_body_create(sim_world *w);
void sim_world_step(sim_world *w);
/* Sum of contact-force magnitudes acting on body b during the last step. */
double sim_contact_force_on(const sim_world *w, dBodyID b);
/* Soft ERP/CFM of a contact that acts as spring k (N/m) and damper c (N s/m). */
void sim_surface_spring(dSurfaceParameters *s, double k_Npm, double c_Nspm);
/* Row-major 3x3 rotation -> ODE's 3x4 dMatrix3. */
void sim_ode_rotation(dMatrix3 out, const double R[9]);
/* ODE's 3x4 rotation (dBodyGetRotation) -> row-major 3x3. */
void sim_from_ode_rotation(double R[9], const dReal *ode);
/* A rotation taking the z axis onto the unit vector axis (capsules and
 * cylinders in ODE lie along their z axis). */
void sim_rot_z_to(double R[9], const double axis[3]);
/* FNV-1a over every body's position, rotation and velocities, bit for bit
 * (sim_app_state_hash adds the state models keep outside the bodies). */
uint64_t sim_state_hash(const sim_world *w);
/* FNV-1a of n more bytes onto hash h. */
uint64_t sim_hash_bytes(uint64_t h, const void *p, size_t n);

/* Configuration of the simulated models (command line of tandem-sim). */
typedef struct sim_config {
    int arms;                             /* 1: the PUMA 560 pair, table, workpieces */
    int workpieces;                       /* workpieces to feed (0 = endless stream) */
    int handover_stand;                   /* 1: a stand with two places (the hand-over,
                                  cell stand_b_center_m), a buffer a task sets
                                  workpieces down on */
    int magazine;                         /* 1: arm 2's magazine (cell magazine_center_m) */
    double arm_friction_viscous;          /* N m s / rad */
    double arm_friction_coulomb;          /* N m */
    int rovers;                           /* number of Pioneer robots (0 = none) */
    char rover_world[32];                 /* open | obstacles | corridor | deadzone */
    const char *rover_world_file;         /* --world-file (world_file.h), NULL: rover_world */
    const char *rover_start, *rover_goal; /* --start, --goal with it (NULL: the file's) */
    int rover_formation;                  /* FORMATION_* the team starts in (0 = line) */
    int rover_batch;                      /* 1: ROVERS_* batched sensor messages */
    int rover_far_kinematic;              /* --rover-far kinematic (sim_rovers_free.c) */
    int rover_teams;                      /* --teams: teams in the world (fleet.h), 1 */
    int rover_per_team;                   /* --robots-per-team with rover_teams > 1 */
    int rover_team_goals;                 /* --team-goals: ROVER_FLEET_GOALS_* */
    const struct arm_model *arm1_model;   /* arm 1's tables; NULL = PUMA 560 */
    int arm1_q0_set;                      /* 1: arm 1 starts at arm1_q0_rad, not at home */
    double arm1_q0_rad[6];
} sim_config;

/* A simulated model plugs into the step through these hooks. Each hook
 * gets the model's own state first (the struct named in its header:
 * sim_arms, sim_workpieces, sim_rovers), which the simulator owns and
 * hands over through sim_model. */
typedef struct sim_model_ops {
    const char *name;
    int (*create)(void *model, sim_world *w, const sim_config *cfg);
    void (*destroy)(void *model, sim_world *w);
    void (*before_step)(void *model, sim_world *w); /* apply held commands, watchdogs */
    void (*after_step)(void *model, sim_world *w);  /* sensors; publish states. May be
                                            called again for the same step (lockstep
                                            start-up, pause): no side effects beyond
                                            publishing */
    /* 1 if the control message was for this model (and applied), 0 if not,
     * SIM_ERR_CONTROL if it was for this model but invalid. */
    int (*control)(void *model, sim_world *w, const tandem_sim_control_t *c);
    void (*status)(const void *model, const sim_world *w, tandem_sim_status_t *s); /* may be NULL */
    /* lockstep: 1 when every output this model waits for at step k (the
     * controllers' commands answering k) is in; the simulator announces
     * k again until it is (lost messages), up to the participant timeout.
     * NULL: nothing to wait for. */
    int (*ready)(const void *model, const sim_world *w, int64_t k);
    /* the state the model keeps outside ODE's bodies, folded onto the
     * state hash h (sim_hash_bytes). NULL: none. */
    uint64_t (*hash)(const void *model, uint64_t h);
} sim_model_ops;

/* One model in the step: its hooks and the state they are handed. */
typedef struct sim_model {
    const sim_model_ops *ops;
    void *state;
} sim_model;

extern const sim_model_ops sim_arms_ops;       /* state: sim_arms (sim_arms.h) */
extern const sim_model_ops sim_workpieces_ops; /* table, bars, camera, grippers: sim_workpieces */
extern const sim_model_ops sim_rovers_ops;     /* state: sim_rovers (sim_rovers.h) */

/* lockstep registry (sim_lockstep.c) */
void sim_lockstep_on_ack(sim_world *w, const char *name, int64_t step, int32_t period, int leaving,
                         int32_t pid);
/* The step from which participant name's outputs at step k are owed (k
 * rounded down to its period, if it is active and had joined by then),
 * or -1: nothing owed (not a participant, left, dropped, or joined
 * later). */
int64_t sim_lockstep_owed_step(const sim_world *w, const char *name, int64_t k);
/* 1 when every participant due at step k has answered it. */
int sim_lockstep_ready(const sim_world *w, int64_t k);
/* 1 if some participant must answer step k. */
int sim_lockstep_due(const sim_world *w, int64_t k);
/* 1 if some participant due at k has not answered it. */
int sim_lockstep_late(const sim_world *w, int64_t k);
/* The longest typical answer time of the participants due at step k (0
 * before any answered): the re-announce timer is a few of these. */
int64_t sim_lockstep_answer_ns(const sim_world *w, int64_t k);
/* Drops the participants due at k that have not answered it and are dead
 * (peer_dead: process gone, or not stopped and silent for the lockstep
 * timeout); a live one, however slow or stopped, is waited for. Returns
 * how many were dropped. */
int sim_lockstep_drop_dead(sim_world *w, int64_t k);
/* 0 when the participant that hosts robot id ("tandem-rover-K" or
 * "tandem-rover-A-B") has left or was dropped and no active one hosts it:
 * its commands are not waited for. 1 otherwise (hosted, or by nobody the
 * simulator knows of: a controller of another name is waited for as
 * before). */
int sim_lockstep_robot_hosted(const sim_world *w, int32_t id);

#endif
