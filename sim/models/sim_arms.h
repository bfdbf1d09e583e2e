/* sim_arms: the two PUMA 560 arms in ODE (SPEC.md §5). Shared with
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
    double   base_xyz_m[3];
    double   base_yaw_rad;
    double   T_world_mount[16];        /* world -> arm mounting surface */
    double   q_init[ARM_NJ];           /* ODE hinge angles are relative to this */
    dBodyID  link[ARM_NJ];
    dJointID joint[ARM_NJ];
    dJointID stop[ARM_NJ];             /* angular motor carrying the range stops */
    dGeomID  geom[ARM_NJ][2];
    /* held command (zero-order hold) */
    double   tau_cmd[ARM_NJ];
    int      mode;                     /* arm_command_t MODE_* */
    int      gripper_closed;
    int64_t  cmd_step;                 /* state step the held command answered */
    int      have_cmd;
    int      stale;
    double   tau_applied[ARM_NJ];
    double   q[ARM_NJ], qd[ARM_NJ];
    double   contact_N[ARM_NJ];        /* raw, this 1 ms step */
    double   max_contact_N;
    double   contact_hist_N[ARM_NJ][SIM_FORCE_AVG_STEPS];  /* ring of raw forces */
    double   contact_avg_N[ARM_NJ];    /* SIM_FORCE_AVG_STEPS moving average */
    double   max_contact_avg_N;
    int64_t  limit_stops;              /* steps a joint sat on a range stop */
    int64_t  speed_brakes;             /* steps a drive braked at its speed limit */
    int32_t  holding;                  /* workpiece id or -1 */
    int64_t  seq;
} sim_arm;

/* Arm k (0-based, < SIM_ARMS) of the pair. */
sim_arm *sim_arms_arm(int k);

/* Tool point of arm a (0-based) in world coordinates, and the flange rotation. */
void sim_arm_tool(const sim_arm *a, double p_world[3], double R_world[9]);
/* Home joint angles shared by the simulator and the controllers. */
extern const double sim_arm_q_home[ARM_NJ];

#endif
