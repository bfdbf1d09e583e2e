/* Integration: bad rover messages over a real udpm bus are counted and
 * change nothing. tandem-sim (two Pioneers, real time) gets malformed and
 * out-of-range commands on both the per-robot and the batched channel,
 * while robot 2 is driven by valid batched commands: robot 2 must move
 * (the test could fail) and robot 1 must not. tandem-rover (robots 1-2,
 * no simulator) gets malformed sensor frames and team messages and must
 * count them. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "harness.h"
#include "tandem_health_t.h"
#include "tandem_rover_command_t.h"
#include "tandem_rover_truth_t.h"
#include "tandem_rovers_command_t.h"
#include "tandem_teams_msg_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_sim_status_t.h"
#include "tandem_team_msg_t.h"

static const char junk[] = "definitely not an LCM message";

typedef struct watch {
    long long sim_rejected, rover_rejected;
    int have_truth;
    double first[2][2], last[2][2]; /* robot 1, 2: x, y of O */
} watch;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *m,
                      void *u)
{
    (void)rb;
    (void)ch;
    ((watch *)u)->sim_rejected = m->msgs_rejected;
}

static void on_health(const lcm_recv_buf_t *rb, const char *ch, const tandem_health_t *m, void *u)
{
    (void)rb;
    (void)ch;
    ((watch *)u)->rover_rejected = m->msgs_rejected;
}

static void on_truth(const lcm_recv_buf_t *rb, const char *ch, const tandem_rover_truth_t *m,
                     void *u)
{
    watch *w = u;
    int i;
    (void)rb;
    (void)ch;
    if (m->n != 2)
        return;
    for (i = 0; i < 2; i++) {
        if (!w->have_truth) {
            w->first[i][0] = m->x_m[i];
            w->first[i][1] = m->y_m[i];
        }
        w->last[i][0] = m->x_m[i];
        w->last[i][1] = m->y_m[i];
    }
    w->have_truth = 1;
}

/* A batch commanding robot `robot` at 0.3 m/s, signed by rover host
 * first..last's role (a role file's principal, not the owner a holder of
 * the master signs as). */
static void drive_as(harness *h, int64_t seq, int robot, int first, int last)
{
    tandem_rover_command_t c;
    tandem_rovers_command_t b;
    memset(&c, 0, sizeof c);
    c.robot = robot;
    c.v_mps = 0.3;
    memset(&b, 0, sizeof b);
    b.seq = seq;
    b.n = 1;
    b.cmd = &c;
    auth_bus_sign_as_owner(&h->bus, 0);
    auth_bus_identity(&h->bus, AUTH_ROLE_ROVER, first, last);
    AUTH_PUBLISH(tandem_rovers_command_t, &h->bus, h->lcm, "ROVERS_COMMAND", &b);
    auth_bus_sign_as_owner(&h->bus, 1);
}

/* 7 rejections: junk x2, NaN, wrong channel, and a batch of three bad ones */
static void bad_commands(harness *h)
{
    tandem_rover_command_t c, three[3];
    tandem_rovers_command_t b;
    auth_bus_publish_raw(&h->bus, h->lcm, "ROVER1_COMMAND", junk, (int)sizeof junk);
    auth_bus_publish_raw(&h->bus, h->lcm, "ROVERS_COMMAND", junk, (int)sizeof junk);
    memset(&c, 0, sizeof c);
    c.robot = 1;
    c.v_mps = NAN;
    AUTH_PUBLISH(tandem_rover_command_t, &h->bus, h->lcm, "ROVER1_COMMAND", &c);
    c.v_mps = 0.5;
    c.robot = 2; /* robot 2's command on robot 1's channel */
    AUTH_PUBLISH(tandem_rover_command_t, &h->bus, h->lcm, "ROVER1_COMMAND", &c);
    memset(three, 0, sizeof three);
    three[0].robot = 1;
    three[0].w_radps = INFINITY;
    three[1].robot = 99;
    three[1].v_mps = 0.2; /* no such robot */
    three[2].robot = 1;
    three[2].v_mps = 40.0; /* not physically sane */
    memset(&b, 0, sizeof b);
    b.n = 3;
    b.cmd = three;
    AUTH_PUBLISH(tandem_rovers_command_t, &h->bus, h->lcm, "ROVERS_COMMAND", &b);
}

/* 7 rejections at the rover: junk batch, NaN encoder, NaN sonar, bad
 * team, junk team batch, a team batch's NaN element (its valid mate
 * element beside it is taken), a valid element signed by another robot's principal */
static void bad_frames(harness *h)
{
    tandem_rover_sensors_t s;
    tandem_sonar_scan_t sc;
    tandem_rovers_sensors_t b;
    tandem_team_msg_t t, tt[2];
    tandem_teams_msg_t tb;
    double ang[8] = { 0 }, rng[8] = { 1, 1, 1, 1, 1, 1, 1, 1 };
    auth_bus_publish_raw(&h->bus, h->lcm, "ROVERS_SENSORS", junk, (int)sizeof junk);
    memset(&s, 0, sizeof s);
    memset(&sc, 0, sizeof sc);
    s.robot = sc.robot = 1;
    s.step = sc.step = 100000;
    s.wheel_left_rad = NAN;
    sc.n = 8;
    sc.angle_rad = ang;
    sc.range_m = rng;
    rng[3] = NAN;
    b.seq = 0;
    b.utime = 0;
    b.step = 100000;
    b.n = 1;
    b.sensors = &s;
    b.sonar = &sc;
    AUTH_PUBLISH(tandem_rovers_sensors_t, &h->bus, h->lcm, "ROVERS_SENSORS", &b);
    memset(&t, 0, sizeof t);
    t.robot = 3;
    t.x_m = NAN;
    t.formation_scale = 1.0;
    AUTH_PUBLISH(tandem_team_msg_t, &h->bus, h->lcm, "TEAM", &t);
    auth_bus_publish_raw(&h->bus, h->lcm, "TEAMS", junk, (int)sizeof junk);
    memset(tt, 0, sizeof tt);
    tt[0].robot = 1;
    tt[0].step = 100000;
    tt[0].formation_scale = 1.0;
    tt[1] = tt[0];
    tt[1].robot = 2;
    tt[1].y_m = NAN;
    memset(&tb, 0, sizeof tb);
    tb.step = 100000;
    tb.n = 2;
    tb.team = tt;
    AUTH_PUBLISH(tandem_teams_msg_t, &h->bus, h->lcm, "TEAMS", &tb);
    /* robot 1's valid team message signed as robot 2 alone: not
     * its robot to speak for (auth_bus_sender_covers) */
    tb.n = 1;
    tt[0].step = 100001;
    auth_bus_sign_as_owner(&h->bus, 0);
    auth_bus_identity(&h->bus, AUTH_ROLE_ROVER, 2, 2);
    AUTH_PUBLISH(tandem_teams_msg_t, &h->bus, h->lcm, "TEAMS", &tb);
    auth_bus_sign_as_owner(&h->bus, 1);
}

static void test_bad_commands_counted_robot_stays(void **state)
{
    harness h;
    watch w;
    const char *sim[] = { "tandem-sim", "--no-arms", "--rovers", "2", "--world",
                          "open",       "--steps",   "4000",     NULL };
    tandem_sim_status_t_subscription_t *s1;
    tandem_rover_truth_t_subscription_t *s3;
    pid_t ps;
    int i;
    double moved[2];
    (void)state;
    memset(&w, 0, sizeof w);
    assert_int_equal(harness_open(&h, 41), 0);
    s1 = tandem_sim_status_t_subscribe(h.lcm, "SIM_STATUS", on_status, &w);
    s3 = tandem_rover_truth_t_subscribe(h.lcm, "ROVER_TRUTH", on_truth, &w);
    ps = harness_spawn(&h, sim);
    assert_true(ps > 0);
    /* start-up: up to 10 s (a loaded machine took more than 2) */
    for (i = 0; i < 500 && !w.have_truth; i++)
        harness_pump(&h, 20);
    assert_true(w.have_truth);
    harness_pump(&h, 500); /* let the robots settle on their wheels */
    w.have_truth = 0;
    harness_pump(&h, 100);
    assert_true(w.have_truth);
    if (!getenv("NOBAD"))
        bad_commands(&h);
    for (i = 0; i < 25; i++) { /* 2.5 s of valid commands for robot 2 */
        drive_as(&h, i, 2, 2, 2);
        /* robot 1 by robot 2's host: refused (auth_bus_sender_covers),
         * counted, robot 1 stays */
        if (!getenv("NOBAD"))
            drive_as(&h, 1000 + i, 1, 2, 2);
        harness_pump(&h, 100);
    }
    harness_pump(&h, 1200); /* the next status */
    for (i = 0; i < 2; i++)
        moved[i] = hypot(w.last[i][0] - w.first[i][0], w.last[i][1] - w.first[i][1]);
    printf("sim rejected %lld; robot 1 moved %.4f m, robot 2 (valid batched commands) %.3f m\n",
           w.sim_rejected, moved[0], moved[1]);
    assert_true(w.sim_rejected >= 7 + 25);
    assert_true(moved[0] < 0.005);
    assert_true(moved[1] > 0.2);
    tandem_sim_status_t_unsubscribe(h.lcm, s1);
    tandem_rover_truth_t_unsubscribe(h.lcm, s3);
    harness_close(&h);
}

/* The rover daemon alone: no simulator clock, so it never commands; it
 * still validates and counts what arrives. */
static void test_bad_frames_counted_by_rover(void **state)
{
    harness h;
    watch w;
    const char *rover[] = { "tandem-rover", "--id", "1-2", "--robots", "2", NULL };
    tandem_health_t_subscription_t *s2;
    pid_t pr;
    (void)state;
    memset(&w, 0, sizeof w);
    w.rover_rejected = -1;
    assert_int_equal(harness_open(&h, 42), 0);
    auth_bus_roster(&h.bus, 2); /* the host of rovers 1-2 is a principal of this cell */
    s2 = tandem_health_t_subscribe(h.lcm, "HEALTH_TANDEM_ROVER_1_2", on_health, &w);
    pr = harness_spawn(&h, rover);
    assert_true(pr > 0);
    harness_pump(&h, 500);
    bad_frames(&h);
    harness_pump(&h, 2200); /* at least one health message after */
    printf("rover rejected %lld\n", w.rover_rejected);
    assert_true(w.rover_rejected >= 7);
    tandem_health_t_unsubscribe(h.lcm, s2);
    harness_close(&h);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bad_commands_counted_robot_stays),
        cmocka_unit_test(test_bad_frames_counted_by_rover),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
