/* cycles: the core work of one period of each daemon, as the daemons do
 * it, with the LCM in and out left out (that is the platform's). These are
 * the entry points make budget measures: their stack depth from the call
 * graph and, on the 68040, their instruction count under emulation.
 *   arm, joint segment   src/daemons/arm/tandem_arm.c cycle(): jtraj reference +
 *                        computed torque with the held bar
 *   arm, Cartesian (ER)  cart_cycle(): one kinematics pass (cartctl_state_at),
 *                        tool point, s, s* of the pair, cartseg_step_at
 *                        (erlaw law, damped inverse, RNE)
 *   arm, TDSD            tdsd_cycle(): tdsd_seg_step, velocity limit,
 *                        computed torque, done test
 *   supervisor           cycle(): one completion event, enable scan and
 *                        starts, dead test, invariant check
 *   rover                ROVERk_SENSORS/SONAR in, team messages of two
 *                        mates, rover_ctl_step
 * Pure core only (no I/O), so it builds for every target.
 */
#ifndef TANDEM_BUDGET_CYCLES_H
#define TANDEM_BUDGET_CYCLES_H

#include "carry_net.h"
#include "cartseg.h"
#include "jointctl.h"
#include "jtraj.h"
#include "petri.h"
#include "rover_ctl.h"
#include "sync_ref.h"
#include "tdsd_seg.h"

#define BUDGET_ARM_DT_S 0.001
#define BUDGET_ROVER_DT_S 0.05
#define BUDGET_MATES 2

typedef struct budget_arm {
    const arm_model *model;
    jointctl_gains gains;
    arm_tool tool;
    arm_payload bar;
    double T_world_base[16];
    double q[ARM_NJ], qd[ARM_NJ]; /* measured state fed to the cycle */
    jtraj traj;
    double t_s; /* time into the joint segment */
    cartseg cart;
    double s_f_m, partner_s_m, partner_s_f_m;
    tdsd_seg tdsd;
    double tau_Nm[ARM_NJ]; /* last command */
} budget_arm;

typedef struct budget_supervisor {
    petri net;
    int completed; /* the last event's transition */
} budget_supervisor;

typedef struct budget_rover {
    rover_ctl_state ctl;
    double t_s, enc_rad[2];
    double range_m[BEH_SONAR_N];
    rover_team_msg mate[BUDGET_MATES];
    rover_ctl_out out;
} budget_rover;

int budget_arm_joint_cycle(budget_arm *a);
int budget_arm_cart_cycle(budget_arm *a);
int budget_arm_tdsd_cycle(budget_arm *a);
int budget_supervisor_step(budget_supervisor *s);
int budget_rover_step(budget_rover *r);

#endif
