/* Integration: keys per role (docs/security.md). The simulator and both
 * arm controllers run with their own role files (proc_spawn hands each
 * one only its principal's keys).
 *
 * 1. A process holding only rover 1's role file, signing correctly as
 *    rover 1, sends an arm 1 action row (ARM1_ACTION), a brake and a
 *    torque for arm 1 (ARM1_COMMAND) and a QUIT (SIM_CONTROL); it also
 *    signs rows claiming to be the supervisor. Arm 1 does not move, the
 *    simulator does not stop, and the receivers count the refusals: the
 *    channel table's (not allowed) for what rover 1 signed as itself, a
 *    bad MAC for the claim (rover 1 holds no key of the supervisor's).
 * 2. A row signed by the supervisor of a second cell (another key set) is
 *    relayed byte for byte: arm 1 refuses it as another cell's.
 * 3. Then a row from this cell's supervisor moves arm 1: the arm did not
 *    stand still for want of listening.
 * Without the channel table's check or the cell id in the MAC, 1 or 2
 * moves the arm and the counts do not match.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <time.h>
#include <unistd.h>
#include <sodium.h>
#include "harness.h"
#include "auth.h"
#include "auth_child.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_health_t.h"
#include "tandem_sim_control_t.h"

#define ATTACKS 20 /* each kind of message, 30 ms apart */
#define ATTACK_GAP_NS 30000000L
#define MOVE_RAD 0.5   /* what the forged rows ask of joint 1 */
#define STILL_RAD 0.02 /* arm 1 stood still: joint 1 moved less */

typedef struct arm_view {
    double q[6];
    int seen;
    int events[16]; /* ARM_EVENTS of arm 1 by kind, rows of ours (900..999) only */
} arm_view;

static uint64_t now_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (uint64_t)tv.tv_sec * 1000000u + (uint64_t)tv.tv_usec;
}

static void pause_ns(long ns)
{
    struct timespec ts = { 0, ns };
    nanosleep(&ts, NULL);
}

/* ARM1_STATE as the simulator sends it (the test reads it, unchecked). */
static void on_arm1(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_view *v = u;
    tandem_arm_state_t s;
    (void)ch;
    if (tandem_arm_state_t_decode(rb->data, 0, (int)rb->data_size, &s) < 0)
        return;
    memcpy(v->q, s.q_rad, sizeof v->q);
    v->seen++;
    tandem_arm_state_t_decode_cleanup(&s);
}

/* ARM_EVENTS about rows of this test: what arm 1 made of them. */
static void on_event(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    arm_view *v = u;
    tandem_action_event_t e;
    (void)ch;
    if (tandem_action_event_t_decode(rb->data, 0, (int)rb->data_size, &e) < 0)
        return;
    if (e.arm == 1 && e.action_id >= 900 && e.action_id <= 999 && e.event >= 0 && e.event < 16) {
        v->events[e.event]++;
        if (e.event == TANDEM_ACTION_EVENT_T_REJECTED)
            printf("arm 1 rejected row %d: %s\n", (int)e.action_id, e.detail);
    }
    tandem_action_event_t_decode_cleanup(&e);
}

/* A one-segment joint move of arm 1 to q, encoded into buf; its length. */
static int encode_row(uint8_t *buf, int cap, int action_id, const double q[6])
{
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    memset(&row, 0, sizeof row);
    memset(&seg, 0, sizeof seg);
    seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
    seg.orientation_quat[0] = 1.0;
    memcpy(seg.q_rad, q, sizeof seg.q_rad);
    row.action_id = action_id;
    row.arm = 1;
    row.n_segments = 1;
    row.segments = &seg;
    return tandem_action_row_t_encode(buf, 0, cap, &row);
}

/* Signs buf[0, len) with set k as sender `as` and publishes it as it is. */
static void publish_signed_as(lcm_t *l, const auth_keyset *k, const auth_sender *as, const char *ch,
                              uint8_t *buf, int len, int cap)
{
    size_t out = 0;
    uint64_t last = 0;
    if (auth_sign(k, as, auth_next_counter(&last, now_us()), ch, AUTH_ROLES_ALL, NULL, buf,
                  (size_t)len, (size_t)cap, &out) == AUTH_OK)
        lcm_publish(l, ch, buf, (unsigned)out);
}

/* ---- the process with rover 1's role file ------------------------------------------ */

static void rover_round(auth_bus *bus, lcm_t *l, const auth_keyset *k, int i, const double q[6])
{
    const auth_sender sup = { AUTH_ROLE_SUPERVISOR, 0, 0, 7u };
    tandem_arm_command_t cmd;
    tandem_sim_control_t c;
    uint8_t buf[4096];
    int n;
    /* as itself: a well-signed message of a principal that may not send it */
    n = encode_row(buf, (int)sizeof buf - AUTH_TRAILER_MAX, 900 + i, q);
    auth_bus_publish_raw(bus, l, "ARM1_ACTION", buf, n);
    memset(&cmd, 0, sizeof cmd);
    cmd.arm = 1;
    cmd.mode = i % 2 ? TANDEM_ARM_COMMAND_T_MODE_BRAKE : TANDEM_ARM_COMMAND_T_MODE_TORQUE;
    cmd.tau_Nm[0] = 40.0;
    AUTH_PUBLISH(tandem_arm_command_t, bus, l, "ARM1_COMMAND", &cmd);
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_QUIT;
    AUTH_PUBLISH(tandem_sim_control_t, bus, l, "SIM_CONTROL", &c);
    /* as the supervisor: it holds none of the supervisor's keys */
    n = encode_row(buf, (int)sizeof buf - AUTH_TRAILER_MAX, 950 + i, q);
    publish_signed_as(l, k, &sup, "ARM1_ACTION", buf, n, (int)sizeof buf);
}

/* it_roles --as-rover1 --key-file=PATH URL Q0..Q5: the attacker. */
static int as_rover1(int argc, char **argv)
{
    const auth_peer me = { AUTH_ROLE_ROVER, 1, 1 };
    const char *key = argv[2] + strlen("--key-file=");
    auth_bus bus;
    auth_keyset *k;
    double q[6];
    char why[700];
    lcm_t *l;
    int i;
    if (argc < 10)
        return 2;
    for (i = 0; i < 6; i++)
        q[i] = atof(argv[4 + i]);
    unsetenv(AUTH_BUS_KEY_ENV); /* nothing but the role file */
    auth_bus_init(&bus);
    if (auth_bus_option(&bus, "it_roles", OPT_KEY_FILE, key) != 1)
        return 3;
    auth_bus_identity(&bus, AUTH_ROLE_ROVER, 1, 1);
    if (auth_bus_start(&bus, "it_roles rover 1") != 0 || !(k = auth_keyset_new()) ||
        auth_keyset_load(k, key, &me, why, sizeof why) != AUTH_OK || k->is_master ||
        !(l = lcm_create(argv[3])))
        return 4;
    for (i = 0; i < ATTACKS; i++) {
        rover_round(&bus, l, k, i, q);
        pause_ns(ATTACK_GAP_NS);
    }
    auth_keyset_free(k);
    lcm_destroy(l);
    return 0;
}

/* ---- the test ------------------------------------------------------------------------ */

static void pump_until_state(harness *h, arm_view *v)
{
    int i;
    for (i = 0; i < 100 && v->seen < 100; i++)
        harness_pump(h, 50);
    assert_true(v->seen >= 100);
}

static harness_health health_after(harness *h, const char *name, int ms)
{
    harness_pump(h, ms);
    return harness_health_of(h, name);
}

/* The role file of rover 1 in this test's cell: what tandem-keygen --cell
 * writes as rover1.key. */
static void rover1_key(auth_child_keys *keys, char *path, size_t cap)
{
    const char *const argv[] = { "tandem-rover", "--id", "1", NULL };
    assert_int_equal(auth_child_key(keys, argv, path, cap), AUTH_CHILD_OK);
}

static void run_rover1(harness *h, const char *key, const double q[6])
{
    char key_opt[700], qs[6][32];
    const char *argv[] = { "it_roles", "--as-rover1", key_opt, h->url, qs[0], qs[1],
                           qs[2],      qs[3],         qs[4],   qs[5],  NULL };
    pid_t p;
    int i, st = -1;
    snprintf(key_opt, sizeof key_opt, "--key-file=%s", key);
    for (i = 0; i < 6; i++)
        snprintf(qs[i], sizeof qs[i], "%.17g", q[i]);
    p = harness_spawn(h, argv);
    assert_true(p > 0);
    for (i = 0; i < 200 && proc_poll(&h->procs, p, &st) == 0; i++)
        harness_pump(h, 50);
    assert_int_equal(st, 0);
}

/* ATTACKS rows for arm 1 signed by the supervisor of another cell. */
static void relay_other_cell(harness *h, const double q[6])
{
    const auth_peer sup_peer = { AUTH_ROLE_SUPERVISOR, 0, 0 };
    const auth_sender sup = { AUTH_ROLE_SUPERVISOR, 0, 0, 11u };
    uint8_t master[AUTH_KEY_BYTES], buf[4096];
    auth_keyset *other = auth_keyset_new();
    int i, n;
    assert_non_null(other);
    randombytes_buf(master, sizeof master);
    auth_keyset_master(other, master, &sup_peer, AUTH_ROSTER_ROVERS);
    sodium_memzero(master, sizeof master);
    for (i = 0; i < ATTACKS; i++) {
        n = encode_row(buf, (int)sizeof buf - AUTH_TRAILER_MAX, 980 + i, q);
        publish_signed_as(h->lcm, other, &sup, "ARM1_ACTION", buf, n, (int)sizeof buf);
        harness_pump(h, 30);
    }
    auth_keyset_free(other);
}

static void test_rover_key_commands_no_arm(void **state)
{
    harness h;
    arm_view v;
    auth_child_keys keys;
    const char *sim[] = { "tandem-sim", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", NULL };
    harness_health a0, a1, a2, s0, s1;
    double q0[6], target[6];
    char key[600];
    pid_t p_sim;
    int i;
    (void)state;
    memset(&v, 0, sizeof v);
    assert_int_equal(harness_open(&h, 51), 0);
    auth_child_keys_init(&keys, &h.bus);
    harness_watch_health(&h);
    lcm_subscribe(h.lcm, "ARM1_STATE", on_arm1, &v);
    lcm_subscribe(h.lcm, "ARM_EVENTS", on_event, &v);
    p_sim = harness_spawn(&h, sim);
    assert_true(p_sim > 0);
    harness_pump(&h, 300);
    assert_true(harness_spawn(&h, arm1) > 0);
    assert_true(harness_spawn(&h, arm2) > 0);
    pump_until_state(&h, &v);
    harness_pump(&h, 1500);
    memcpy(q0, v.q, sizeof q0);
    memcpy(target, q0, sizeof target);
    target[0] += MOVE_RAD;
    a0 = health_after(&h, "tandem-arm-1", 1200);
    s0 = harness_health_of(&h, "tandem-sim");
    harness_print_refused(&a0);
    harness_print_refused(&s0);
    assert_int_equal(harness_refused(&a0), 0);
    assert_int_equal(harness_refused(&s0), 0);

    /* 1: rover 1's key */
    rover1_key(&keys, key, sizeof key);
    run_rover1(&h, key, target);
    a1 = health_after(&h, "tandem-arm-1", 2500);
    s1 = harness_health_of(&h, "tandem-sim");
    harness_print_refused(&a1);
    harness_print_refused(&s1);
    printf("arm 1 joint 1: %.4f rad before, %.4f after rover 1's rows\n", q0[0], v.q[0]);
    assert_true(fabs(v.q[0] - q0[0]) < STILL_RAD);
    assert_int_equal(v.events[TANDEM_ACTION_EVENT_T_STARTED], 0);
    assert_int_equal(proc_poll(&h.procs, p_sim, NULL), 0); /* the QUITs were not obeyed */
    assert_in_range(a1.refused[4] - a0.refused[4], ATTACKS - ATTACKS / 10,
                    ATTACKS); /* rows as rover 1 */
    assert_in_range(a1.refused[1] - a0.refused[1], ATTACKS - ATTACKS / 10,
                    ATTACKS); /* rows "as the supervisor" */
    assert_in_range(s1.refused[4] - s0.refused[4], 2 * (ATTACKS - ATTACKS / 10),
                    2 * ATTACKS); /* commands, QUITs */

    /* 2: a row of another cell */
    relay_other_cell(&h, target);
    a2 = health_after(&h, "tandem-arm-1", 2500);
    harness_print_refused(&a2);
    printf("arm 1 joint 1: %.4f rad after the other cell's rows\n", v.q[0]);
    assert_true(fabs(v.q[0] - q0[0]) < STILL_RAD);
    assert_in_range(a2.refused[5] - a1.refused[5], ATTACKS - ATTACKS / 10, ATTACKS);
    assert_int_equal(a2.refused[4] - a1.refused[4], 0);

    /* 3: this cell's supervisor (the test signs as each channel's owner) */
    harness_send_joint_row(&h, 1, 999, target);
    for (i = 0; i < 100 && !v.events[TANDEM_ACTION_EVENT_T_DONE]; i++)
        harness_pump(&h, 100);
    a2 = harness_health_of(&h, "tandem-arm-1");
    harness_print_refused(&a2);
    assert_int_equal(v.events[TANDEM_ACTION_EVENT_T_STARTED], 1);
    printf("arm 1 joint 1: %.4f rad after this cell's supervisor's row (asked %.4f)\n", v.q[0],
           target[0]);
    assert_true(fabs(v.q[0] - q0[0]) > MOVE_RAD / 2);
    auth_child_keys_remove(&keys);
    harness_close(&h);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_rover_key_commands_no_arm),
    };
    if (argc >= 2 && strcmp(argv[1], "--as-rover1") == 0)
        return as_rover1(argc, argv);
    harness_private_net();
    return cmocka_run_group_tests(tests, NULL, NULL);
}
