/* sim_arms: the two PUMA 560 arms in ODE (docs/method/lockstep.md §3). Shared with
 * sim_workpieces (gripper attach/release needs the flange bodies). */
#ifndef TANDEM_SIM_ARMS_H
#define TANDEM_SIM_ARMS_H

#include "sim.h"
#include "arm_model.h"

#define SIM_ARMS 2
/* Tool point (between the gripper fingers) on the flange z axis. */
#define SIM_TOOL_LENGTH_M 0.10
/* Contact force filter of the stick's force sensor: 10 steps = 10 ms. */
#define SIM_FORCE_AVG_STEPS 10

typedef struct sim_arm {
    const arm_model *model;
    double base_xyz_m[3];
    double base_yaw_rad;
    double T_world_mount[16]; /* world -> arm mounting surface */
    double q_init[ARM_NJ];    /* ODE hinge angles are relative to this */
    dBodyID link[ARM_NJ];
    dJointID joint[ARM_NJ];
    dJointID stop[ARM_NJ]; /* angular motor carrying the range stops */
    dGeomID geom[ARM_NJ][2];
    /* held command (zero-order hold) */
    double tau_cmd[ARM_NJ];
    int mode; /* arm_command_t MODE_* */
    int gripper_closed;
    int64_t cmd_step; /* state step the held command answered */
    int have_cmd;
    int stale;
    double tau_applied[ARM_NJ];
    double q[ARM_NJ], qd[ARM_NJ];
    double contact_N[ARM_NJ]; /* raw, this 1 ms step */
    double max_contact_N;
    double contact_hist_N[ARM_NJ][SIM_FORCE_AVG_STEPS]; /* ring of raw forces */
    double contact_avg_N[ARM_NJ];                       /* SIM_FORCE_AVG_STEPS moving average */
    double max_contact_avg_N;
    int64_t limit_stops;  /* steps a joint sat on a range stop */
    int64_t speed_brakes; /* steps a drive braked at its speed limit */
    int32_t holding;      /* workpiece id or -1 */
    int64_t seq;
} sim_arm;

/* One arm's command channel: the subscription and what its handler is
 * handed (the model and the arm the channel belongs to). */
typedef struct sim_arms_channel {
    struct sim_arms *arms;
    int k; /* 0-based arm index */
} sim_arms_channel;

/* The arm model's state (sim_arms_ops). The stick belongs here: it is
 * placed against the arms' links and refused where it would touch them. */
typedef struct sim_arms {
    sim_arm pair[SIM_ARMS];
    const sim_config *cfg;
    sim_world *w; /* the world the arms live in */
    sim_arms_channel chan[SIM_ARMS];
    dGeomID stick; /* NULL: no stick (cleared with the world) */
    int stick_target, stick_link;
} sim_arms;

/* The tables arm k (0-based) is built from: arm 1's as configured, the
 * PUMA 560's otherwise. */
const arm_model *sim_arms_model(const sim_config *cfg, int k);

/* Arm k (0-based, < SIM_ARMS) of the pair. */
sim_arm *sim_arms_arm(sim_arms *arms, int k);

/* Tool point of arm a (0-based) in world coordinates, and the flange rotation. */
void sim_arm_tool(const sim_arm *a, double p_world[3], double R_world[9]);
/* Radius of each link's capsules (collision shape, stick placement). */
extern const double sim_arm_link_radius_m[ARM_NJ];

/* The stick (sim_stick.c): INSERT_STICK / REMOVE_STICK, and its part of
 * SIM_STATUS. The arm model's control and status hooks. */
int sim_stick_control(sim_arms *arms, sim_world *w, const tandem_sim_control_t *c);
void sim_stick_status(const sim_arms *arms, tandem_sim_status_t *s);
void sim_stick_remove(sim_arms *arms);

#endif
