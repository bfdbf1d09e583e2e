/* budget_main: sets the per-cycle entry points of cycles.h in a state
 * they meet in operation and runs each once between two calls of
 * budget_probe, so a trace of the executed instructions (cross/budget.sh
 * runs it under qemu-m68k with one instruction per translation block)
 * can count them. Prints the names of the regions in order first; the
 * state set-up before each region is not counted.
 *   arm: PUMA 560 of arm 1 at its home pose, tool down, holding the bar,
 *        5 cycles into a 0.2 m Cartesian move (kinematic plant: q += qd dt)
 *   supervisor: the carry net 7 events into the task
 *   rover: robot 1 of 3 in the obstacles world, 1 s into the run, sonar
 *        ring cast from the obstacles and its mates
 */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cell.h"
#include "cycles.h"
#include "rover_world.h"
#include "sonar.h"
#include "unicycle.h"
#include "vec3.h"

#define WARM_CYCLES 5
#define ROVER_WARM_S 1.0

/* Marks a region boundary in the trace; noinline keeps its address. */
__attribute__((noinline)) void budget_probe(int region);
__attribute__((noinline)) void budget_probe(int region)
{
    __asm__ volatile("" : : "r"(region) : "memory");
}

static budget_arm arm;
static budget_supervisor sup;
static budget_rover rov;
static sonar_world sw;

static void plant_step(budget_arm *a)
{
    int j;
    for (j = 0; j < ARM_NJ; j++)
        a->q[j] += a->qd[j] * BUDGET_ARM_DT_S;
}

static int arm_setup(budget_arm *a)
{
    const double off[3] = { 0.0, 0.0, CELL_TOOL_LENGTH_M };
    const double q_ref[ARM_NJ] = { 0.0, 0.6, 2.9, 0.0, -0.4, 0.0 };
    const double com[3] = { 0.1, 0.0, CELL_TOOL_LENGTH_M };
    double Rb[9], T[16], Tinv[16], Rinv[9], p[3], R1[9], p1[3], q1[ARM_NJ];
    arm_ik_result r;
    int j;
    memset(a, 0, sizeof *a);
    a->model = &arm_model_puma560;
    a->gains.wn_radps = 2.0 * 3.141592653589793 * 8.0; /* tandem-arm's default --wn 8 */
    a->gains.zeta = 1.0;
    arm_tool_offset(&a->tool, off);
    arm_payload_point(&a->bar, cell_default.workpiece_mass_kg, com);
    cell_world_from_arm(&cell_default, 0, a->T_world_base);
    tf_inverse(Tinv, a->T_world_base);
    tf_rot(Rinv, Tinv);
    rot_apply(p, Rinv, cell_default.home_tool_m[0]);
    p[0] += Tinv[3];
    p[1] += Tinv[7];
    p[2] += Tinv[11];
    cell_tool_down_R(&cell_default, 0, Rb);
    tf_from_rot_pos(T, Rb, p);
    if (arm_ik(a->model, &a->tool, T, &r) != 0)
        return -1;
    memcpy(a->q, r.branch[arm_ik_nearest(&r, q_ref)].q_rad, sizeof a->q);
    for (j = 0; j < ARM_NJ; j++) {
        a->qd[j] = 0.05 * (double)(j + 1);
        q1[j] = a->q[j] + 0.3;
    }
    vec3_set(R1, 1, 0, 0);
    vec3_set(R1 + 3, 0, -1, 0);
    vec3_set(R1 + 6, 0, 0, -1);
    vec3_copy(p1, cell_default.home_tool_m[0]);
    p1[0] -= 0.2;
    p1[2] -= 0.1;
    if (jtraj_plan(&a->traj, a->model, a->q, q1, 0.5, 2.0) != 0 ||
        cartseg_start(&a->cart, a->model, &a->tool, a->T_world_base, a->q, p1, R1,
                      &carry_table[0].lin, ERLAW_REF_MEASURED) != 0)
        return -1;
    {
        tdsd_seg_params par;
        tdsd_seg_default_params(&par, carry_table[0].lin.v_m, carry_table[0].lin.a_m,
                                carry_table[0].lin.u_m);
        if (tdsd_seg_start(&a->tdsd, a->model, &a->tool, a->T_world_base, a->q, p1, R1, &par) != 0)
            return -1;
    }
    a->s_f_m = erlaw_channel_length(&a->cart.line.ch);
    a->partner_s_f_m = a->s_f_m;
    a->partner_s_m = 0.02;
    a->t_s = 0.5 * a->traj.duration_s;
    return 0;
}

typedef int (*arm_cycle_fn)(budget_arm *);

static int arm_region(int region, arm_cycle_fn cycle)
{
    int k, rc;
    if (arm_setup(&arm) != 0)
        return -1;
    for (k = 0; k < WARM_CYCLES; k++) {
        if (cycle(&arm) < 0)
            return -1;
        plant_step(&arm);
    }
    budget_probe(region);
    rc = cycle(&arm);
    budget_probe(region);
    return rc < 0 ? -1 : 0;
}

static int supervisor_region(int region)
{
    int k;
    if (petri_init(&sup.net, &carry_net) != 0)
        return -1;
    for (k = 0; k < 7; k++)
        if (budget_supervisor_step(&sup) < 0)
            return -1;
    budget_probe(region);
    k = budget_supervisor_step(&sup);
    budget_probe(region);
    return k < 0 ? -1 : 0;
}

/* Sonar world of the obstacles and every robot but `self`. */
static void rover_sonar_world(const rover_world_config *w, const pose2 *c, int self)
{
    int i;
    sonar_world_init(&sw);
    for (i = 0; i < w->n_obst; i++) {
        const rover_obstacle *o = &w->obst[i];
        if (o->kind == ROVER_OBST_CIRCLE)
            sonar_world_add_circle(&sw, o->cx_m, o->cy_m, o->r_m, 0.0, o->height_m);
        else
            sonar_world_add_box(&sw, o->cx_m, o->cy_m, o->hx_m, o->hy_m, o->angle_rad, 0.0,
                                o->height_m);
    }
    for (i = 0; i < w->n_robots; i++)
        if (i != self)
            sonar_world_add_box(&sw, c[i].x_m + ROVER_BODY_OFFSET_M * cos(c[i].theta_rad),
                                c[i].y_m + ROVER_BODY_OFFSET_M * sin(c[i].theta_rad),
                                0.5 * ROVER_BODY_LENGTH_M, 0.5 * ROVER_BODY_WIDTH_M, c[i].theta_rad,
                                0.03, 0.25);
    sonar_world_build(&sw);
}

/* Robot 1 drives under its controller; its two mates drive straight at
 * 0.3 m/s and report their true pose every period. */
static int rover_plant_step(budget_rover *r, const rover_world_config *w, pose2 *c,
                            const sonar_model *sm)
{
    const double b = ODOMETRY_P2DX_AXLE_TRACK_M, rw = ODOMETRY_P2DX_WHEEL_RADIUS_M;
    int i;
    r->enc_rad[0] += (r->out.u.v_mps - 0.5 * b * r->out.u.w_radps) / rw * BUDGET_ROVER_DT_S;
    r->enc_rad[1] += (r->out.u.v_mps + 0.5 * b * r->out.u.w_radps) / rw * BUDGET_ROVER_DT_S;
    unicycle_step_exact(&c[0], r->out.u.v_mps, r->out.u.w_radps, BUDGET_ROVER_DT_S);
    for (i = 1; i <= BUDGET_MATES; i++) {
        pose2 o, t;
        unicycle_step_exact(&c[i], 0.3, 0.0, BUDGET_ROVER_DT_S);
        unicycle_o_from_c(&o, &c[i], ROVER_BEACON_D_M);
        rover_world_to_team(w, &o, &t);
        r->mate[i - 1].m.x_m = t.x_m;
        r->mate[i - 1].m.y_m = t.y_m;
        r->mate[i - 1].m.theta_rad = t.theta_rad;
        r->mate[i - 1].m.v_mps = 0.3;
        r->mate[i - 1].m.t_s = r->t_s + BUDGET_ROVER_DT_S;
    }
    rover_sonar_world(w, c, 0);
    return sonar_ring(r->range_m, &sw, sm, &c[0], NULL) < 0 ? -1 : 0;
}

static int rover_region(int region)
{
    static rover_world_config w;
    rover_ctl_params p;
    sonar_model sm;
    pose2 c[1 + BUDGET_MATES], st, gw = { 0, 0, 0 }, gt;
    double goal[2];
    int i, rc;
    if (rover_world_layout(&w, ROVER_WORLD_OBSTACLES, 1 + BUDGET_MATES, 1.0, FORMATION_LINE) != 0)
        return -1;
    rover_ctl_params_default(&p);
    sonar_model_default(&sm);
    sm.noise_sd_m = 0.0;
    gw.x_m = w.goal_m[0];
    gw.y_m = w.goal_m[1];
    rover_world_to_team(&w, &gw, &gt);
    goal[0] = gt.x_m;
    goal[1] = gt.y_m;
    memset(&rov, 0, sizeof rov);
    for (i = 0; i <= BUDGET_MATES; i++)
        c[i] = w.start_c[i];
    rover_world_to_team(&w, &c[0], &st);
    if (rover_ctl_init(&rov.ctl, &p, 1, &st, goal) != 0)
        return -1;
    for (i = 0; i < BUDGET_MATES; i++) {
        rov.mate[i].m.robot = i + 2;
        rov.mate[i].m.formation = p.formation;
        rov.mate[i].m.scale = 1.0;
        rov.mate[i].goal_m[0] = goal[0];
        rov.mate[i].goal_m[1] = goal[1];
    }
    while (rov.t_s < ROVER_WARM_S) {
        if (rover_plant_step(&rov, &w, c, &sm) != 0 || budget_rover_step(&rov) != 0)
            return -1;
    }
    if (rover_plant_step(&rov, &w, c, &sm) != 0)
        return -1;
    budget_probe(region);
    rc = budget_rover_step(&rov);
    budget_probe(region);
    return rc;
}

int main(void)
{
    static const char *const names[] = { "arm cycle, joint segment", "arm cycle, Cartesian (ER)",
                                         "arm cycle, TDSD", "supervisor step", "rover step" };
    size_t k;
    for (k = 0; k < sizeof names / sizeof names[0]; k++)
        printf("region %u: %s\n", (unsigned)k + 1, names[k]);
    fflush(stdout);
    if (arm_region(1, budget_arm_joint_cycle) != 0 || arm_region(2, budget_arm_cart_cycle) != 0 ||
        arm_region(3, budget_arm_tdsd_cycle) != 0 || supervisor_region(4) != 0 ||
        rover_region(5) != 0) {
        fprintf(stderr, "budget: a cycle failed in its set-up state\n");
        return 1;
    }
    printf(
        "budget: arm tau %.3f %.3f %.3f Nm, rover v %.3f m/s w %.3f rad/s mode %d, net fired %ld\n",
        arm.tau_Nm[0], arm.tau_Nm[1], arm.tau_Nm[2], rov.out.u.v_mps, rov.out.u.w_radps,
        rov.out.mode, sup.net.fired_count);
    return 0;
}
