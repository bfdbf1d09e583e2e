/* tdsd_ode: TDSD resolved in the loop against the ODE arm (docs/method/tdsd.md,
 * --plant ode; see tdsd_ode.h).
 *
 * Per simulator step k: ARM1_STATE(k) -> tdsdrun_step on the measured q ->
 * q_ref += dq dt, publish ARM1_JOINT_REF(q_ref, dq, d(dq)/dt) -> ack k.
 * The reference integrates the resolved rates (tandem-arm's joint servo
 * closes the inner loop), while TDSD's Cartesian feedback K_p e_p, K_o e_o
 * acts on the measured pose (the outer loop).
 */
#include "tdsd_ode.h"
#include "scenario.h"
#include "proc.h"
#include "run_key.h"
#include <libgen.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "tandem_arm_joint_ref_t.h"
#include "tandem_arm_state_t.h"
#include "daemon.h"
#include "tandem_clock_ack_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"

#define ODE_DT_S 0.001

static struct {
    lcm_t *lcm;
    auth_bus *bus;    /* the process's bus (run_key_bus) */
    int64_t pending;  /* SIM_CLOCK step to answer, -1 none */
    int64_t answered; /* last step answered */
    tandem_arm_state_t st;
    int have_state;
    int64_t ack_seq, ref_seq;
} O;

static void on_clock(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_clock_t m;
    (void)ch;
    (void)u;
    if (tandem_sim_clock_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    if (m.mode == TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP && m.step > O.answered)
        O.pending = m.step;
    tandem_sim_clock_t_decode_cleanup(&m);
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_arm_state_t m;
    (void)ch;
    (void)u;
    if (tandem_arm_state_t_decode(rb->data, 0, rb->data_size, &m) < 0)
        return;
    if (m.arm == 1 && arm_q_finite(m.q_rad) == 0 && (!O.have_state || m.step >= O.st.step)) {
        O.st = m;
        O.have_state = 1;
    }
    tandem_arm_state_t_decode_cleanup(&m);
}

static void ack(int64_t step, int leaving)
{
    lockstep_ack(O.bus, O.lcm, "tandem-scenario", O.ack_seq++, step, 1, leaving);
}

static void publish_ref(int64_t step, const double q[ARM_NJ], const double qd[ARM_NJ],
                        const double qdd[ARM_NJ])
{
    tandem_arm_joint_ref_t r;
    memset(&r, 0, sizeof r);
    r.seq = O.ref_seq++;
    r.step = step;
    r.arm = 1;
    memcpy(r.q_rad, q, sizeof r.q_rad);
    memcpy(r.qd_radps, qd, sizeof r.qd_radps);
    memcpy(r.qdd_radps2, qdd, sizeof r.qdd_radps2);
    AUTH_PUBLISH(tandem_arm_joint_ref_t, O.bus, O.lcm, "ARM1_JOINT_REF", &r);
}

static void send_quit(void)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_QUIT;
    AUTH_PUBLISH(tandem_sim_control_t, O.bus, O.lcm, "SIM_CONTROL", &c);
}

/* The programs sit beside tandem-scenario (build/bin). */
static void bin_dir(char *dir, size_t cap)
{
    char exe[768];
    const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0) {
        snprintf(dir, cap, "build/bin");
        return;
    }
    exe[n] = '\0';
    snprintf(dir, cap, "%s", dirname(exe));
}

/* start_children: tandem-sim or tandem-arm did not start (said) */
#define CHILDREN_NOT_STARTED (-1)

static int start_children(proc_set *ps, const char *url, const tdsdrun_cfg *c,
                          const double q0[ARM_NJ], const tdsd_ode_opts *o)
{
    char q0s[256], hz[32], dir[512], log_sim[1024], log_arm[1024], log_err[1024];
    const char *sim_argv[] = { "tandem-sim",   "--lockstep", "--expect",    "2",
                               "--timeout-ms", "20000",      "--arm-model", c->model->name,
                               "--arm-q0",     q0s,          NULL };
    const char *arm_argv[] = { "tandem-arm",   "--arm", "1", "--lockstep", "--arm-model",
                               c->model->name, "--wn",  hz,  NULL };
    snprintf(q0s, sizeof q0s, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", q0[0], q0[1], q0[2], q0[3],
             q0[4], q0[5]);
    snprintf(hz, sizeof hz, "%g", o->servo_hz);
    snprintf(log_sim, sizeof log_sim, "%s/ode_sim.log", o->out_dir);
    snprintf(log_arm, sizeof log_arm, "%s/ode_arm.log", o->out_dir);
    snprintf(log_err, sizeof log_err, "%s/ode_stderr.log", o->out_dir);
    remove(log_err);
    bin_dir(dir, sizeof dir);
    proc_init(ps, O.bus, dir);
    if (proc_spawn(ps, sim_argv, url, log_sim, log_err) < 0 ||
        proc_spawn(ps, arm_argv, url, log_arm, log_err) < 0) {
        fprintf(stderr, "tandem-scenario: cannot start tandem-sim / tandem-arm from %s\n", dir);
        return CHILDREN_NOT_STARTED;
    }
    return 0;
}

static int child_died(proc_set *ps, const tdsd_ode_opts *o)
{
    int k, st;
    for (k = 0; k < ps->n; k++)
        if (ps->alive[k] && proc_poll(ps, ps->pid[k], &st) == 1) {
            fprintf(stderr,
                    "tandem-scenario: a child exited early (status %d); see %s/ode_stderr.log\n",
                    st, o->out_dir);
            return 1;
        }
    return 0;
}

double tdsd_ode_run(const tdsdrun_cfg *c, const tdsdrun_path *p, const double q0_rad[ARM_NJ],
                    const tdsd_ode_opts *o, tdsdrun_metrics *m, tdsdrun_sample_fn on_sample,
                    void *user)
{
    char url[96];
    proc_set ps;
    names_watch names;
    tdsdrun_state st;
    tdsdrun_sample s;
    double q_ref[ARM_NJ], dq_prev[ARM_NJ] = { 0 }, qdd[ARM_NJ], zero[ARM_NJ] = { 0 };
    double t_start = -1.0, result = TDSD_ODE_ERR_RUN;
    const double wall0 = scenario_wall_s();
    int i, failed = 0;

    memset(&O, 0, sizeof O);
    O.pending = O.answered = -1;
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", 33000 + (int)(getpid() % 20000));
    names_watch_init(&names, "tandem-scenario");
    O.bus = run_key_bus();
    O.lcm = lcm_create(url);
    if (!O.lcm) {
        fprintf(stderr, "tandem-scenario: cannot open LCM at %s\n", url);
        return TDSD_ODE_ERR_RUN;
    }
    auth_bus_subscribe(O.bus, O.lcm, "SIM_CLOCK", on_clock, NULL);
    auth_bus_subscribe(O.bus, O.lcm, "ARM1_STATE", on_state, NULL);
    if (start_children(&ps, url, c, q0_rad, o) != 0) {
        proc_kill_all(&ps, 1.0);
        auth_bus_close(O.bus, O.lcm);
        return TDSD_ODE_ERR_RUN;
    }
    memcpy(q_ref, q0_rad, sizeof q_ref);
    tdsdrun_init(&st);
    for (;;) {
        int64_t k;
        double t_sim;
        lcm_handle_timeout(O.lcm, 200);
        bus_names_watch(&names, O.bus, &O.lcm, url); /* a flood of channel names: a new handle */
        if (child_died(&ps, o)) {
            failed = 1;
            break;
        }
        if (scenario_wall_s() - wall0 > 1800.0) {
            fprintf(stderr, "tandem-scenario: wall-time limit reached\n");
            failed = 1;
            break;
        }
        /* answer step k only with the state of step k in hand */
        if (O.pending < 0 || !O.have_state || O.st.step != O.pending)
            continue;
        k = O.pending;
        t_sim = O.st.sim_time_s;
        if (t_sim < o->settle_s) {
            publish_ref(k, q_ref, zero, zero); /* hold q0 while the servo settles */
        } else {
            if (t_start < 0.0)
                t_start = t_sim;
            tdsdrun_step(c, p, &st, O.st.q_rad, &s);
            for (i = 0; i < ARM_NJ; i++) {
                q_ref[i] += s.dq_radps[i] * ODE_DT_S;
                qdd[i] = (s.dq_radps[i] - dq_prev[i]) / ODE_DT_S;
                dq_prev[i] = s.dq_radps[i];
            }
            publish_ref(k, q_ref, s.dq_radps, qdd);
            if (m)
                tdsdrun_metrics_add(m, c->model, &s, O.st.q_rad, O.st.qd_radps);
            if (on_sample)
                on_sample(user, &s, O.st.q_rad);
        }
        ack(k, 0);
        O.answered = k;
        O.pending = -1;
        if (t_start >= 0.0 && (tdsdrun_finished(c, &st) || st.t_s >= o->t_max_s))
            break;
    }
    ack(O.answered >= 0 ? O.answered : 0, 1);
    send_quit();
    proc_kill_all(&ps, 3.0);
    auth_bus_close(O.bus, O.lcm);
    O.lcm = NULL;
    if (!failed)
        result = st.t_path_end_s >= 0.0 ? st.t_path_end_s : o->t_max_s;
    return result;
}
