/* Integration: the secure bus (docs/method/lockstep.md §4-5).
 *
 * 1. An attacker without the key changes nothing. A short carry and a
 *    short formation scenario run twice on two buses, once alone and once
 *    while a process without the key publishes SIM_CONTROL QUIT /
 *    KILL_ROBOT / stick moves, ARMk_COMMAND (torques, gripper open),
 *    ARMk_ACTION rows, SIM_ACK (a new participant, an arm leaving), a
 *    SIM_CLOCK far ahead, ARM_EVENTS, TEAM and rover commands, each
 *    unsigned, with a made-up trailer, and with garbage. When permitted
 *    (root) the attacker sits in a network namespace of its own, joined
 *    to the bus's by a veth pair like another machine on the LAN, runs as
 *    `nobody` with ttl=1 and cannot read the key file; otherwise it is a
 *    separate keyless process on the same host. Both runs must give the
 *    same results bit for bit (summary.json but the wall time, blocks.csv,
 *    transitions.csv, truth.csv, and the simulator's state hash every 100
 *    steps), the daemons must refuse nothing in the quiet run and every
 *    daemon must count refusals in the attacked one.
 * 2. Replays: valid signed messages captured from a running system are
 *    published again: every daemon counts each one it would have taken as
 *    a replay, and none reaches validation; a restarted arm controller
 *    refuses those signed before it started. A key holder signing as the
 *    wrong role is refused by the channel table.
 */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "harness.h"
#include "auth.h"
#include "daemon.h"
#include "tandem_action_event_t.h"
#include "tandem_action_row_t.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_clock_ack_t.h"
#include "tandem_health_t.h"
#include "tandem_rover_command_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"
#include "tandem_team_msg_t.h"

/* unshare(2) and setgroups(2) are not declared under _POSIX_C_SOURCE
 * (and _GNU_SOURCE would clash with the daemon shell's `daemon` type). */
#ifdef __linux__
extern int unshare(int flags);
extern int setgroups(size_t size, const gid_t *list);
#define IT_CLONE_NEWNET 0x40000000
#endif

#define N_BUS 2 /* 0: carry, 1: formation */
#define MAX_HASHES 4096
#define NOBODY 65534
/* One round of forgeries (48 messages per bus) every 20 ms: an attack, not
 * a flood. A flood is a denial of service that authentication does not
 * stop: the simulator's socket loses real commands, and a lost command is
 * held over (README, Known limitations), so the run is no longer the
 * deterministic one. */
#define ATTACK_ROUND_NS 20000000L
/* The runs' buses: deep socket buffers, as tandem-scenario formation's own */
#define BUS_OPTIONS "&recv_buf_size=4194304"

/* ---- what the test sees on each bus ------------------------------------------- */

/* The simulator's state hash every 100 steps (SIM_STATUS). */
typedef struct bus_view {
    int64_t hash_step[MAX_HASHES], hash[MAX_HASHES];
    int n_hash;
} bus_view;

static bus_view V[N_BUS];
static int bus_ids[N_BUS] = { 0, 1 };
static int netns; /* 1: the attacker has a network namespace of its own */

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *s,
                      void *u)
{
    bus_view *v = &V[*(int *)u];
    (void)rb;
    (void)ch;
    if (s->step % 100 != 0 || v->n_hash == MAX_HASHES ||
        (v->n_hash > 0 && v->hash_step[v->n_hash - 1] >= s->step))
        return;
    v->hash_step[v->n_hash] = s->step;
    v->hash[v->n_hash++] = s->state_hash;
}

AUTH_TYPED_HANDLER(tandem_sim_status_t, raw_on_status, on_status)

static void watch(harness *h, int bus)
{
    harness_watch_health(h);
    auth_bus_subscribe(&h->bus, h->lcm, "SIM_STATUS", raw_on_status, &bus_ids[bus]);
}

static void pump_all(harness *h, int n, int ms)
{
    int i;
    for (i = 0; i < n; i++)
        harness_pump(&h[i], ms);
}

/* ---- the attacker ------------------------------------------------------------------ */

static uint32_t rng = 2463534242u;
static uint32_t next_rand(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 17;
    rng ^= rng << 5;
    return rng;
}

static uint64_t now_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (uint64_t)tv.tv_sec * 1000000u + (uint64_t)tv.tv_usec;
}

/* Publishes an encoded message three ways: as it is, with a trailer of
 * the right format but a made-up MAC (the attacker cannot compute one),
 * and with garbage where the trailer goes. */
static void publish_forged(lcm_t *l, const char *ch, uint8_t *buf, int n)
{
    uint8_t *t = buf + n;
    uint64_t c = now_us();
    int i;
    if (n < 0)
        return;
    lcm_publish(l, ch, buf, (unsigned)n);
    t[0] = 'T';
    t[1] = 'A';
    t[2] = AUTH_VERSION;
    t[3] = (uint8_t)next_rand();
    t[4] = (uint8_t)(1 + next_rand() % AUTH_ROLE_LAST);
    t[5] = 0;
    t[6] = t[8] = 0;
    t[7] = t[9] = 1;
    for (i = 10; i < 14; i++)
        t[i] = (uint8_t)next_rand();
    for (i = 14; i < 22; i++)
        t[i] = (uint8_t)(c >> (8 * (21 - i)));
    for (i = 22; i < 38; i++) /* a cell id */
        t[i] = (uint8_t)next_rand();
    t[38] = t[39] = 0; /* no tag for anyone */
    lcm_publish(l, ch, buf, (unsigned)(n + AUTH_FIXED_BYTES));
    for (i = 0; i < AUTH_FIXED_BYTES; i++)
        t[i] = (uint8_t)next_rand();
    lcm_publish(l, ch, buf, (unsigned)(n + AUTH_FIXED_BYTES));
}

static uint8_t fbuf[4096];
#define FORGE(type, l, ch, msg)     \
    publish_forged((l), (ch), fbuf, \
                   type##_encode(fbuf, 0, (int)sizeof fbuf - AUTH_TRAILER_MAX, (msg)))

static void forge_control(lcm_t *l, int cmd, int target, int link)
{
    tandem_sim_control_t c;
    memset(&c, 0, sizeof c);
    c.command = (int8_t)cmd;
    c.target = target;
    c.link = link;
    c.length_m = 0.6;
    c.radius_m = 0.05;
    FORGE(tandem_sim_control_t, l, "SIM_CONTROL", &c);
}

static void forge_arms(lcm_t *l, int64_t step)
{
    tandem_arm_command_t c;
    tandem_action_row_t row;
    tandem_action_segment_t seg;
    tandem_action_event_t e;
    char ch[24];
    int a, j;
    for (a = 1; a <= 2; a++) {
        memset(&c, 0, sizeof c);
        c.arm = (int8_t)a;
        c.step = step;
        c.mode = TANDEM_ARM_COMMAND_T_MODE_TORQUE;
        c.gripper = TANDEM_ARM_COMMAND_T_GRIP_OPEN;
        for (j = 0; j < 6; j++)
            c.tau_Nm[j] = 40.0;
        snprintf(ch, sizeof ch, "ARM%d_COMMAND", a);
        FORGE(tandem_arm_command_t, l, ch, &c);
        memset(&row, 0, sizeof row);
        memset(&seg, 0, sizeof seg);
        seg.kind = TANDEM_ACTION_SEGMENT_T_MOVE_JOINT;
        seg.orientation_quat[0] = 1.0;
        seg.q_rad[0] = 1.0;
        row.action_id = 9000 + a;
        row.arm = (int8_t)a;
        row.n_segments = 1;
        row.segments = &seg;
        snprintf(ch, sizeof ch, "ARM%d_ACTION", a);
        FORGE(tandem_action_row_t, l, ch, &row);
        memset(&e, 0, sizeof e);
        e.arm = (int8_t)a;
        e.event = TANDEM_ACTION_EVENT_T_DONE;
        e.transition = 1;
        e.detail = "";
        FORGE(tandem_action_event_t, l, "ARM_EVENTS", &e);
    }
}

static void forge_lockstep(lcm_t *l)
{
    tandem_clock_ack_t a;
    tandem_sim_clock_t c;
    memset(&a, 0, sizeof a);
    a.name = "intruder";
    a.period_steps = 1;
    FORGE(tandem_clock_ack_t, l, "SIM_ACK", &a); /* would stall the lockstep */
    a.name = "tandem-arm-1";
    a.leaving = 1;
    FORGE(tandem_clock_ack_t, l, "SIM_ACK", &a); /* would drop arm 1 from it */
    a.name = "tandem-rover-1";
    FORGE(tandem_clock_ack_t, l, "SIM_ACK", &a);
    memset(&c, 0, sizeof c);
    c.step = 5000000;
    c.sim_time_s = 5000.0;
    c.mode = TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP;
    FORGE(tandem_sim_clock_t, l, "SIM_CLOCK", &c);
}

static void forge_rovers(lcm_t *l)
{
    tandem_team_msg_t t;
    tandem_rover_command_t c;
    memset(&t, 0, sizeof t);
    t.robot = 2;
    t.x_m = 3.0;
    t.formation_scale = 1.0;
    t.announce = TANDEM_TEAM_MSG_T_ANNOUNCE_LEAVE;
    t.announce_seq = (int32_t)(next_rand() % 1000);
    FORGE(tandem_team_msg_t, l, "TEAM", &t);
    memset(&c, 0, sizeof c);
    c.robot = 1;
    c.v_mps = 1.0;
    c.w_radps = 2.0;
    FORGE(tandem_rover_command_t, l, "ROVER1_COMMAND", &c);
}

/* The attacker's whole life: it cannot read the key, so it sends what it
 * can until it is killed. */
static int attack(int argc, char **argv)
{
    lcm_t *l[4];
    int n = 0, i, fd;
    int64_t round = 0;
    fd = open(argv[2], O_RDONLY);
    printf("attacker (uid %d): the key file %s\n", (int)getuid(),
           fd < 0 ? strerror(errno) : "IS READABLE (running without privileges to drop)");
    fflush(stdout);
    if (fd >= 0)
        close(fd); /* not used either way */
    for (i = 3; i < argc && n < 4; i++)
        if ((l[n] = lcm_create(argv[i])) != NULL)
            n++;
    printf("attacker: forging on %d of %d buses\n", n, argc - 3);
    fflush(stdout);
    if (n == 0)
        return 1;
    for (;;) {
        struct timespec ts = { 0, ATTACK_ROUND_NS };
        for (i = 0; i < n; i++) {
            forge_control(l[i], TANDEM_SIM_CONTROL_T_QUIT, 0, 0);
            forge_control(l[i], TANDEM_SIM_CONTROL_T_KILL_ROBOT, 2, 0);
            forge_control(l[i],
                          round % 2 ? TANDEM_SIM_CONTROL_T_INSERT_STICK
                                    : TANDEM_SIM_CONTROL_T_REMOVE_STICK,
                          2, 2);
            forge_control(l[i], TANDEM_SIM_CONTROL_T_PAUSE, 0, 0);
            forge_arms(l[i], round * 4);
            forge_lockstep(l[i]);
            forge_rovers(l[i]);
        }
        round++;
        nanosleep(&ts, NULL);
    }
}

/* ttl=0 -> ttl=1: the attacker's datagrams must cross the veth "wire". */
static void attacker_url(const char *url, char *out, size_t cap)
{
    const char *p = strstr(url, "ttl=0");
    if (p)
        snprintf(out, cap, "%.*sttl=1%s", (int)(p - url), url, p + 5);
    else
        snprintf(out, cap, "%s", url);
}

/* Starts the attacker: in its own namespace (netns) joined by the veth
 * pair, as nobody, or as a plain child. It re-executes this program, so
 * it holds nothing of ours in memory. */
static pid_t start_attacker(char (*bus_url)[160], int n, const char *key)
{
    char urls[N_BUS][192];
    int ready[2], go[2], i;
    char c = 0;
    pid_t pid;
    for (i = 0; i < n; i++)
        attacker_url(bus_url[i], urls[i], sizeof urls[i]);
    if (pipe(ready) != 0 || pipe(go) != 0)
        return -1;
    pid = fork();
    if (pid == 0) {
        /* opened while still root: nobody may not be allowed to walk the
         * path to this program (a checkout under a 0700 directory) */
        const int exe = open("/proc/self/exe", O_RDONLY);
        char *const args[] = {
            "it_secure", "--attack", (char *)key, urls[0], n > 1 ? urls[1] : NULL, NULL
        };
        extern char **environ;
        if (netns) {
            if (unshare(IT_CLONE_NEWNET) != 0)
                _exit(126);
            if (write(ready[1], &c, 1) != 1 || read(go[0], &c, 1) != 1)
                _exit(126);
            if (harness_sh(
                    "ip link set lo up && ip addr add 10.213.0.2/24 dev ta0 && ip link set ta0 up && "
                    "ip route add 224.0.0.0/4 dev ta0") != 0)
                _exit(126);
        }
        if (geteuid() == 0 &&
            (setgroups(0, NULL) != 0 || setgid(NOBODY) != 0 || setuid(NOBODY) != 0))
            _exit(126);
        if (exe < 0)
            _exit(127);
        fexecve(exe, args, environ);
        _exit(127);
    }
    harness_track_child(pid);
    if (pid > 0 && netns) {
        if (read(ready[0], &c, 1) != 1 || harness_sh("ip link set ta0 netns %d", (int)pid) != 0 ||
            write(go[1], &c, 1) != 1) {
            kill(pid, SIGKILL);
            waitpid(pid, NULL, 0);
            pid = -1;
        }
    }
    close(ready[0]);
    close(ready[1]);
    close(go[0]);
    close(go[1]);
    return pid;
}

/* The attacker's end of the wire comes back before it dies (its
 * namespace, and the veth pair with it, would go away otherwise). */
static void stop_attacker(pid_t pid)
{
    if (netns &&
        harness_sh("nsenter -t %d -n ip link set ta0 netns %d", (int)pid, (int)getpid()) != 0)
        fprintf(stderr, "it_secure: could not take the veth end back\n");
    kill(pid, SIGKILL);
    waitpid(pid, NULL, 0);
}

/* The bus's namespace: its multicast goes over the veth end tb0, so the
 * daemons' sockets join the group there (their own datagrams, ttl=0,
 * still loop back to them and never leave). */
static int bus_namespace(void)
{
#ifdef __linux__
    if (geteuid() != 0 || getenv("TANDEM_SHARED_NET") ||
        /* NOLINTNEXTLINE(cert-env33-c): asks the shell whether nsenter is installed */
        system("command -v nsenter >/dev/null") != 0 || unshare(IT_CLONE_NEWNET) != 0)
        return -1;
    if (harness_sh(
            "ip link set lo up && ip link add tb0 type veth peer name ta0 && ip addr add 10.213.0.1/24 dev tb0 && "
            "ip link set tb0 up && ip route add 224.0.0.0/4 dev tb0") != 0) {
        fprintf(stderr, "it_secure: cannot set up the veth pair\n");
        return -1;
    }
    return 0;
#else
    return -1;
#endif
}

/* ---- one pair of runs ------------------------------------------------------------- */

typedef struct run_out {
    char url[N_BUS][160];
    char dir[N_BUS][256];
    int status[N_BUS];
    bus_view view[N_BUS];
    harness health[N_BUS]; /* the daemons' last health of the run */
} run_out;

static void run_pair(harness *h, const char *tag, int attacked, run_out *o)
{
    const char *key = getenv(AUTH_BUS_KEY_ENV);
    char base[200];
    pid_t p[N_BUS], att = -1;
    int i, left, k;
    snprintf(base, sizeof base, "/tmp/it_secure_%d/%s", (int)getpid(), tag);
    for (i = 0; i < N_BUS; i++) {
        snprintf(o->url[i], sizeof o->url[i], "%s" BUS_OPTIONS, h[i].url);
        snprintf(o->dir[i], sizeof o->dir[i], "%s/%s", base, i == 0 ? "carry" : "formation");
        memset(&V[i], 0, sizeof V[i]);
        h[i].n_health = 0;
    }
    {
        const char *carry[] = {
            "tandem-scenario", "carry",   "--workpieces", "1", "--block", "1:3:1:1", "--no-serial",
            "--lcm-url",       o->url[0], "--key-file",   key, "--out",   o->dir[0], NULL
        };
        const char *formation[] = { "tandem-scenario", "formation", "--world",    "obstacles",
                                    "--robots",        "3",         "--seed",     "2",
                                    "--procs",         "separate",  "--max-time", "20",
                                    "--lcm-url",       o->url[1],   "--key-file", key,
                                    "--out",           o->dir[1],   NULL };
        if (attacked && !getenv("IT_SECURE_DEBUG_NO_ATTACK")) {
            att = start_attacker(o->url, N_BUS, key);
            assert_true(att > 0);
            pump_all(h, N_BUS, 300); /* it is sending before the runs start */
        }
        p[0] = harness_spawn(&h[0], carry);
        p[1] = harness_spawn(&h[1], formation);
    }
    assert_true(p[0] > 0 && p[1] > 0);
    o->status[0] = o->status[1] = -1;
    for (k = 0, left = N_BUS; left > 0 && k < 60000;
         k++) { /* at most ~20 min under the sanitizers */
        pump_all(h, N_BUS, 10);
        for (i = 0, left = 0; i < N_BUS; i++)
            if (o->status[i] < 0 && proc_poll(&h[i].procs, p[i], &o->status[i]) != 1)
                left++;
    }
    pump_all(h, N_BUS, 300); /* the daemons' last health */
    if (att > 0)
        stop_attacker(att);
    memcpy(o->view, V, sizeof V);
    memcpy(o->health, h, sizeof o->health);
    printf("%s: carry exit %d, formation exit %d; state hashes seen %d, %d\n", tag, o->status[0],
           o->status[1], V[0].n_hash, V[1].n_hash);
}

/* ---- comparisons ------------------------------------------------------------------ */

/* The lines of dir/file holding what: a daemon's exit report of whom it
 * refused, for a quiet run that refused anything. */
static void print_lines_with(const char *dir, const char *file, const char *what)
{
    char path[512], line[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    f = fopen(path, "r");
    if (!f)
        return;
    while (fgets(line, sizeof line, f))
        if (strstr(line, what))
            printf("  %s: %s", file, line);
    fclose(f);
}

/* The file with lines holding `skip` (NULL: none) left out. */
static char *slurp(const char *dir, const char *file, const char *skip, long *len)
{
    char path[512], line[8192];
    char *out = NULL;
    size_t n = 0, cap = 0;
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    f = fopen(path, "r");
    if (!f)
        return NULL;
    while (fgets(line, sizeof line, f)) {
        const size_t l = strlen(line);
        if (skip && strstr(line, skip))
            continue;
        if (n + l + 1 > cap) {
            char *grown = realloc(out, 2 * (n + l + 1));
            if (!grown) { /* the comparison fails on NULL; the file read so far is not leaked */
                free(out);
                fclose(f);
                return NULL;
            }
            out = grown;
            cap = 2 * (n + l + 1);
        }
        memcpy(out + n, line, l);
        n += l;
    }
    fclose(f);
    if (!out)
        out = calloc(1, 1);
    out[n] = '\0';
    *len = (long)n;
    return out;
}

static void assert_same_file(const run_out *a, const run_out *b, int bus, const char *file,
                             const char *skip)
{
    long la = -1, lb = -2;
    char *fa = slurp(a->dir[bus], file, skip, &la), *fb = slurp(b->dir[bus], file, skip, &lb);
    printf("  %-9s %-16s %7ld bytes quiet, %7ld attacked: %s\n", bus == 0 ? "carry" : "formation",
           file, la, lb,
           fa && fb && la == lb && memcmp(fa, fb, (size_t)la) == 0 ? "identical" : "DIFFERENT");
    assert_non_null(fa);
    assert_non_null(fb);
    assert_true(la > 20);
    assert_int_equal(la, lb);
    assert_memory_equal(fa, fb, (size_t)la);
    free(fa);
    free(fb);
}

static void assert_same_hashes(const bus_view *a, const bus_view *b, const char *what)
{
    int i = 0, j = 0, common = 0, differ = 0;
    while (i < a->n_hash && j < b->n_hash) {
        if (a->hash_step[i] < b->hash_step[j]) {
            i++;
        } else if (a->hash_step[i] > b->hash_step[j]) {
            j++;
        } else {
            if (a->hash[i] != b->hash[j] && differ++ < 5)
                printf("  %s: state hash differs at step %lld\n", what, (long long)a->hash_step[i]);
            common++;
            i++;
            j++;
        }
    }
    printf("  %-9s state hash equal at %d of the %d steps seen in both runs\n", what,
           common - differ, common);
    assert_true(common >= 50);
    assert_int_equal(differ, 0);
}

static harness_health expect_daemon(harness *h, const char *name)
{
    const harness_health d = harness_health_of(h, name);
    if (d.pid == 0) {
        printf("  no health from %s\n", name);
        fail();
    }
    return d;
}

static void test_attacker_without_key_changes_nothing(void **state)
{
    static const char *const carry_daemons[] = { "tandem-sim", "tandem-arm-1", "tandem-arm-2",
                                                 "tandem-supervisor" };
    static const char *const team_daemons[] = { "tandem-sim", "tandem-rover-1", "tandem-rover-2",
                                                "tandem-rover-3" };
    static run_out quiet, attacked;
    harness h[N_BUS];
    int i, b;
    (void)state;
    for (i = 0; i < N_BUS; i++) {
        assert_int_equal(harness_open(&h[i], 11 + i), 0);
        watch(&h[i], i);
    }
    run_pair(h, "quiet", 0, &quiet);
    run_pair(h, "attacked", 1, &attacked);
    for (i = 0; i < N_BUS; i++)
        harness_close(&h[i]);
    assert_int_equal(quiet.status[0], 0); /* the carry met its criteria */
    assert_int_equal(attacked.status[0], quiet.status[0]);
    assert_int_equal(attacked.status[1], quiet.status[1]);
    for (b = 0; b < N_BUS; b++)
        for (i = 0; i < quiet.health[b].n_health; i++)
            if (harness_refused(&quiet.health[b].health[i]) > 0) {
                printf("quiet run, refused (must be none):\n");
                harness_print_refused(&quiet.health[b].health[i]);
                print_lines_with(quiet.dir[b], "children.log", "not allowed");
            }
    for (b = 0; b < N_BUS; b++)
        for (i = 0; i < attacked.health[b].n_health; i++)
            harness_print_refused(&attacked.health[b].health[i]);
    assert_same_hashes(&quiet.view[0], &attacked.view[0], "carry");
    assert_same_hashes(&quiet.view[1], &attacked.view[1], "formation");
    assert_same_file(&quiet, &attacked, 1, "summary.json", "wall_time");
    assert_same_file(&quiet, &attacked, 1, "truth.csv", NULL);
    assert_same_file(&quiet, &attacked, 0, "summary.json", "wall_time");
    assert_same_file(&quiet, &attacked, 0, "blocks.csv", NULL);
    assert_same_file(&quiet, &attacked, 0, "transitions.csv", NULL);
    for (b = 0; b < N_BUS; b++)
        for (i = 0; i < 4; i++) {
            const char *name = b == 0 ? carry_daemons[i] : team_daemons[i];
            const harness_health q = expect_daemon(&quiet.health[b], name);
            const harness_health a = expect_daemon(&attacked.health[b], name);
            assert_int_equal(q.auth_on, 1);
            assert_int_equal(harness_refused(&q), 0); /* nothing legitimate was refused */
            assert_int_equal(a.auth_on, 1);
            assert_true(harness_refused(&a) > 0);             /* every daemon saw the attacker */
            assert_int_equal(a.refused[3] + a.refused[4], 0); /* it cannot replay or sign */
        }
}

/* ---- replays ------------------------------------------------------------------------ */

#define MAX_CAPTURE 4000

typedef struct captured {
    char ch[32];
    uint8_t *data;
    int len;
} captured;

static captured CAP[MAX_CAPTURE];
static int n_cap, capturing;

static void capture(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)u;
    if (!capturing || n_cap == MAX_CAPTURE || strlen(ch) >= sizeof CAP[0].ch)
        return;
    snprintf(CAP[n_cap].ch, sizeof CAP[0].ch, "%s", ch);
    CAP[n_cap].data = malloc(rb->data_size);
    memcpy(CAP[n_cap].data, rb->data, rb->data_size);
    CAP[n_cap].len = (int)rb->data_size;
    n_cap++;
}

/* Publishes the captured messages of the channels in `only` (NULL: all)
 * again, paced so the receivers' sockets keep up; how many went out per
 * receiving daemon comes back in the counts. */
static void replay(harness *h, const char *const *only, int n_only)
{
    int i, k, sent = 0;
    for (i = 0; i < n_cap; i++) {
        int take = only == NULL;
        for (k = 0; k < n_only && !take; k++)
            take = strcmp(CAP[i].ch, only[k]) == 0;
        if (!take)
            continue;
        lcm_publish(h->lcm, CAP[i].ch, CAP[i].data, (unsigned)CAP[i].len);
        /* 2,500 a second: a receiver keeps at most 256 per subscription
         * (DAEMON_QUEUE_CAPACITY) and handles them for a quarter of its
         * period each cycle; on a loaded machine a faster replay is a flood */
        if (++sent % 5 == 0)
            harness_pump(h, 2);
    }
}

static int count_captured(const char *const *chs, int n)
{
    int i, k, c = 0;
    for (i = 0; i < n_cap; i++)
        for (k = 0; k < n; k++)
            c += strcmp(CAP[i].ch, chs[k]) == 0;
    return c;
}

/* The last health of `name` after listening for `seconds` more (daemons
 * publish health once a second). */
static harness_health latest_health(harness *h, const char *name, double seconds)
{
    harness_pump(h, (int)(seconds * 1000.0));
    return harness_health_of(h, name);
}

static void test_replayed_messages_are_refused(void **state)
{
    static const char *const sim_in[] = { "ARM1_COMMAND", "ARM2_COMMAND", "SIM_ACK",
                                          "SIM_CONTROL" };
    static const char *const arm2_in[] = { "ARM2_STATE", "SIM_CLOCK", "ARM_EVENTS", "ARM2_ACTION" };
    harness h;
    const char *sim[] = { "tandem-sim", NULL };
    const char *arm1[] = { "tandem-arm", "--arm", "1", NULL };
    const char *arm2[] = { "tandem-arm", "--arm", "2", NULL };
    harness_health s0, a0, s1, a1, fresh0, fresh1;
    tandem_sim_control_t c;
    tandem_arm_command_t cmd;
    int n_sim, n_arm2, i;
    pid_t p_arm2;
    (void)state;
    memset(V, 0, sizeof V);
    assert_int_equal(harness_open(&h, 13), 0);
    strncat(h.url, BUS_OPTIONS, sizeof h.url - strlen(h.url) - 1); /* the daemons' sockets */
    watch(&h, 0);
    lcm_subscribe(h.lcm, "(ARM[12]_STATE|ARM[12]_COMMAND|SIM_CLOCK|ARM_EVENTS|SIM_CONTROL)",
                  capture, NULL);
    assert_true(harness_spawn(&h, sim) > 0);
    harness_pump(&h, 300);
    assert_true(harness_spawn(&h, arm1) > 0);
    p_arm2 = harness_spawn(&h, arm2);
    assert_true(p_arm2 > 0);
    harness_pump(&h, 1500);
    /* capture a signed tool command too: it is obeyed the first time */
    capturing = 1;
    memset(&c, 0, sizeof c);
    c.command = TANDEM_SIM_CONTROL_T_REMOVE_STICK;
    AUTH_PUBLISH(tandem_sim_control_t, &h.bus, h.lcm, "SIM_CONTROL", &c);
    for (i = 0; i < 100 && (count_captured(sim_in, 4) < 200 || count_captured(arm2_in, 4) < 200);
         i++)
        harness_pump(&h, 50); /* a loaded machine runs the simulator slower than real time */
    capturing = 0;
    s0 = latest_health(&h, "tandem-sim", 1.2);
    a0 = latest_health(&h, "tandem-arm-2", 0.0);
    n_sim = count_captured(sim_in, 4);
    n_arm2 = count_captured(arm2_in, 4);
    printf(
        "captured %d messages (%d for the simulator, %d for arm 2); refused so far: sim %lld, arm 2 %lld\n",
        n_cap, n_sim, n_arm2, (long long)harness_refused(&s0), (long long)harness_refused(&a0));
    assert_true(n_sim >= 200 && n_arm2 >= 200);
    assert_int_equal(harness_refused(&s0), 0);
    assert_int_equal(harness_refused(&a0), 0);
    replay(&h, NULL, 0);
    s1 = latest_health(&h, "tandem-sim", 2.5);
    a1 = latest_health(&h, "tandem-arm-2", 0.0);
    harness_print_refused(&s1);
    harness_print_refused(&a1);
    /* each replayed message on a channel it reads: a replay, never validated
     * (a loaded machine may lose a few datagrams on the way: at most 2 %) */
    assert_in_range(s1.refused[3] - s0.refused[3], n_sim - n_sim / 50, n_sim);
    assert_in_range(a1.refused[3] - a0.refused[3], n_arm2 - n_arm2 / 50, n_arm2);
    assert_int_equal(harness_refused(&s1) - harness_refused(&s0), s1.refused[3] - s0.refused[3]);

    /* arm 2 restarts: what was signed before it started is still refused */
    kill(p_arm2, SIGTERM);
    harness_pump(&h, 500);
    p_arm2 = harness_spawn(&h, arm2);
    assert_true(p_arm2 > 0);
    for (i = 0; i < 100; i++) { /* its first health: it listens */
        fresh0 = latest_health(&h, "tandem-arm-2", 0.1);
        if (fresh0.pid == (int)p_arm2)
            break;
    }
    assert_int_equal(fresh0.pid, (int)p_arm2);
    replay(&h, arm2_in, 4);
    fresh1 = latest_health(&h, "tandem-arm-2", 2.5);
    harness_print_refused(&fresh1);
    assert_in_range(fresh1.refused[3] - fresh0.refused[3], n_arm2 - n_arm2 / 50, n_arm2);

    /* a key holder signing as the wrong role: refused by the channel table */
    auth_bus_identity(&h.bus, AUTH_ROLE_TOOL, 0, 0);
    auth_bus_sign_as_owner(&h.bus, 0);
    memset(&cmd, 0, sizeof cmd);
    cmd.arm = 1;
    cmd.mode = TANDEM_ARM_COMMAND_T_MODE_TORQUE;
    cmd.tau_Nm[0] = 40.0;
    AUTH_PUBLISH(tandem_arm_command_t, &h.bus, h.lcm, "ARM1_COMMAND", &cmd);
    AUTH_PUBLISH(tandem_arm_command_t, &h.bus, h.lcm, "ARM2_COMMAND", &cmd);
    auth_bus_sign_as_owner(&h.bus, 1);
    s0 = s1;
    s1 = latest_health(&h, "tandem-sim", 2.5);
    harness_print_refused(&s1);
    assert_int_equal(s1.refused[4] - s0.refused[4], 2);
    harness_close(&h);
    for (i = 0; i < n_cap; i++)
        free(CAP[i].data);
}

int main(int argc, char **argv)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_attacker_without_key_changes_nothing),
        cmocka_unit_test(test_replayed_messages_are_refused),
    };
    if (argc >= 4 && strcmp(argv[1], "--attack") == 0)
        return attack(argc, argv);
    netns = bus_namespace() == 0;
    if (netns)
        printf(
            "it_secure: the attacker gets a network namespace of its own, joined by a veth pair, as nobody\n");
    else
        printf(
            "it_secure: no network namespaces here (needs root): the attacker is a keyless process on this "
            "host, on the same private ports\n");
    fflush(stdout);
    return cmocka_run_group_tests(tests, NULL, NULL);
}
