/* bench_roundtrip: state -> controller -> command over the real LCM bus,
 * beside a bare LCM ping-pong of the same message sizes, in the same run;
 * and what authentication (src/daemons/common/auth*.h) costs, per-role keys
 * (a tag per reader) beside an Ed25519 signature of the same message.
 *
 *   tandem path: this process publishes ARM1_STATE + SIM_CLOCK (what the
 *     simulator sends each step) to a real `tandem-arm --lockstep`, which
 *     decodes, validates, runs computed torque (RNE) and publishes
 *     ARM1_COMMAND; we time until that command arrives. Twice: to an arm
 *     run with --insecure on one bus, and to an arm checking and signing
 *     with a bus key on another (this process then signs its messages and
 *     checks the command, as the simulator does).
 *   bare path: a forked echo process receives the same two payload sizes
 *     (state, clock) and answers the second with one of the command's size.
 * The three kinds of exchange alternate, each first in turn, so all see
 * the same load; the N exchanges of each kind come in REPS blocks, and the
 * ratio authenticated / bare is taken in each block (p50 over p50) and
 * reported as the median over the blocks with its range: a burst of load
 * from another job moves one block's ratio, not the figure. Prints p50 /
 * p99 / max in microseconds over all N exchanges, and first the cost of
 * signing and of checking one message of each size.
 *   bench_roundtrip [N [BIN_DIR]]
 *   bench_roundtrip roundtrip N [BIN_DIR [REPS]]   only the round trips
 *   bench_roundtrip auth N   only the signing and checking, N messages of
 *                            each size (for instruction counts: callgrind)
 *   bench_roundtrip ed25519 N  only Ed25519 sign + verify, N of each size
 */
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "auth_acl.h"
#include "auth_child.h"
#include "daemon.h"
#include <sodium.h>
#include "loopstats.h"
#include "rtloop.h"
#include "tandem_arm_command_t.h"
#include "tandem_arm_state_t.h"
#include "tandem_sim_clock_t.h"

static volatile int got;

static void on_any(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    got = 1;
}

static void on_echo(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    static char reply[256];
    (void)ch;
    int size;
    memcpy(&size, rb->data, sizeof size);
    if (size <= 0 || size > (int)sizeof reply)
        return;
    lcm_publish((lcm_t *)u, "BENCH_PONG", reply, (unsigned)size);
}

static int wait_reply(lcm_t *l)
{
    int guard;
    for (guard = 0; guard < 1000 && !got; guard++)
        if (lcm_handle_timeout(l, 100) < 0)
            return -1;
    return got ? 0 : -1;
}

/* Bare path: the same two messages the simulator sends (a state-sized and
 * a clock-sized payload); the echo answers the second with a command-sized
 * payload. The first int of each payload is the reply size (0: none). */
static int bare_exchange(lcm_t *l, int state_size, int clock_size, int cmd_size, loopstats *s)
{
    char buf[512];
    const int none = 0;
    int64_t t0;
    memset(buf, 0, sizeof buf);
    got = 0;
    t0 = rtloop_now_ns();
    memcpy(buf, &none, sizeof none);
    lcm_publish(l, "BENCH_PING", buf, (unsigned)state_size);
    memcpy(buf, &cmd_size, sizeof cmd_size);
    lcm_publish(l, "BENCH_PING", buf, (unsigned)clock_size);
    if (wait_reply(l) != 0)
        return -1;
    if (s)
        loopstats_add(s, (double)(rtloop_now_ns() - t0) * 1e-3);
    return 0;
}

/* Encodes and publishes without authentication (to the --insecure arm). */
#define PUBLISH_PLAIN(type, l, ch, msg)                             \
    do {                                                            \
        uint8_t b_[512];                                            \
        const int n_ = type##_encode(b_, 0, (int)sizeof b_, (msg)); \
        if (n_ > 0)                                                 \
            lcm_publish((l), (ch), b_, (unsigned)n_);               \
    } while (0)

/* tandem path: ARM1_STATE + SIM_CLOCK to tandem-arm, wait for ARM1_COMMAND. */
static int tandem_exchange(auth_bus *bus, lcm_t *l, int signed_msgs, tandem_arm_state_t *st,
                           tandem_sim_clock_t *clk, int i, loopstats *s)
{
    int64_t t0;
    st->step = i;
    st->sim_time_s = i * 1e-3;
    clk->step = i;
    clk->sim_time_s = st->sim_time_s;
    got = 0;
    t0 = rtloop_now_ns();
    if (signed_msgs) {
        AUTH_PUBLISH(tandem_arm_state_t, bus, l, "ARM1_STATE", st);
        AUTH_PUBLISH(tandem_sim_clock_t, bus, l, "SIM_CLOCK", clk);
    } else {
        PUBLISH_PLAIN(tandem_arm_state_t, l, "ARM1_STATE", st);
        PUBLISH_PLAIN(tandem_sim_clock_t, l, "SIM_CLOCK", clk);
    }
    if (wait_reply(l) != 0)
        return -1;
    if (s)
        loopstats_add(s, (double)(rtloop_now_ns() - t0) * 1e-3);
    return 0;
}

static void print_row(const char *name, const loopstats *s)
{
    printf("  %-34s p50 %7.1f us   p99 %7.1f us   max %8.1f us   (n=%lld)\n", name,
           loopstats_percentile(s, 0.50), loopstats_percentile(s, 0.99), s->max_us,
           (long long)s->count);
}

static void print_ratio(const char *name, const loopstats *a, const loopstats *b, const char *note)
{
    if (a->count > 0 && b->count > 0)
        printf("  %-34s p50 %.2fx   p99 %.2fx%s\n", name,
               loopstats_percentile(a, 0.5) / loopstats_percentile(b, 0.5),
               loopstats_percentile(a, 0.99) / loopstats_percentile(b, 0.99), note);
}

#define BENCH_REPS_MAX 64

/* A block's samples added to the run's. */
static void stats_merge(loopstats *into, const loopstats *from)
{
    int i;
    if (from->count == 0)
        return;
    for (i = 0; i < LOOPSTATS_BINS; i++)
        into->hist[i] += from->hist[i];
    if (into->count == 0 || from->min_us < into->min_us)
        into->min_us = from->min_us;
    if (from->max_us > into->max_us)
        into->max_us = from->max_us;
    into->count += from->count;
    into->sum_us += from->sum_us;
}

static int cmp_double(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of n > 0 values (sorts v). */
static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof v[0], cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

/* The median over the blocks of a / b at p50, with the blocks' range. */
static void print_block_ratio(const char *name, double *r, int n, const char *note)
{
    double lo, hi;
    if (n <= 0)
        return;
    qsort(r, (size_t)n, sizeof r[0], cmp_double);
    lo = r[0];
    hi = r[n - 1];
    printf("  %-34s p50 %.2fx median of %d blocks (blocks %.2f-%.2fx)%s\n", name, median(r, n), n,
           lo, hi, note);
}

static double wall_s(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (double)tv.tv_sec + 1e-6 * (double)tv.tv_usec;
}

/* Who reads a channel: the channel table's readers (as auth_bus tags them). */
static int bench_wants(const auth_peer *r, const char *channel)
{
    return auth_acl_readers(auth_acl_table, auth_acl_table_n, channel) == 0 ||
           auth_acl_reader_wanted(auth_acl_table, auth_acl_table_n, channel, r);
}

/* The role file of p in the cell of master m, as tandem-keygen --cell writes it. */
static auth_keyset *role_set(const uint8_t m[AUTH_KEY_BYTES], const auth_peer *p)
{
    auth_peer roster[AUTH_MAX_TAGS];
    const int n = auth_roster(3, roster, AUTH_MAX_TAGS);
    auth_keyset *k = auth_keyset_new();
    if (k)
        auth_keyset_role(k, m, p, roster, n);
    return k;
}

/* Microseconds per auth_sign (the sender's role file: one tag per reader)
 * and per check at one receiver (its role file: auth_verify, the channel
 * table, the replay table) of a body_len-byte message; beside them an
 * Ed25519 signature (crypto_sign) of the same body: one signature every
 * receiver checks with the sender's public key. */
static void time_sign_verify(const char *channel, const auth_peer *reader, int body_len, int reps,
                             int ed_reps)
{
    static uint8_t buf[2048], ed_sig[crypto_sign_BYTES], ed_pk[crypto_sign_PUBLICKEYBYTES],
        ed_sk[crypto_sign_SECRETKEYBYTES];
    static auth_replay replay;
    uint8_t m[AUTH_KEY_BYTES];
    auth_keyset *ks, *kr;
    auth_keyring ring;
    auth_sender s;
    auth_trailer t;
    auth_peer sp, to[AUTH_MAX_TAGS];
    int n_to;
    size_t len = 0;
    double t0, sign_us, check_us, ed_sign_us, ed_verify_us;
    int i, bad = 0;
    memset(m, 7, sizeof m);
    memset(buf, 0x5a, (size_t)body_len);
    auth_acl_owner(auth_acl_table, auth_acl_table_n, channel, &s);
    if (s.role != AUTH_ROLE_ARM && s.role != AUTH_ROLE_ROVER)
        s.first = s.last = 0;
    s.session = 1;
    sp.role = s.role;
    sp.first = s.first;
    sp.last = s.last;
    ks = role_set(m, &sp);
    kr = role_set(m, reader);
    if (!ks || !kr)
        return;
    ring.set[0] = kr;
    ring.n = 1;
    auth_replay_init(&replay, AUTH_WINDOW_US, 0);
    /* the receivers once per channel, as auth_bus keeps them */
    n_to = auth_receivers(ks, channel, AUTH_ROLES_ALL, bench_wants, to);
    t0 = wall_s();
    for (i = 0; i < reps; i++)
        auth_sign_to(ks, &s, 1000000000000000ULL + (uint64_t)i, channel, to, n_to, buf,
                     (size_t)body_len, sizeof buf, &len);
    sign_us = (wall_s() - t0) * 1e6 / reps;
    t0 = wall_s();
    for (i = 0; i < reps; i++) {
        /* the same message each time: the check's work without re-signing */
        bad += auth_verify(&ring, reader, channel, buf, len, &t) != AUTH_OK;
        bad += auth_acl_check(auth_acl_table, auth_acl_table_n, channel, &t.sender) != AUTH_OK;
        auth_replay_check(&replay, &t.sender, auth_channel_hash(channel), t.counter + (uint64_t)i,
                          t.counter + (uint64_t)i);
    }
    check_us = (wall_s() - t0) * 1e6 / reps;
    crypto_sign_keypair(ed_pk, ed_sk);
    t0 = wall_s();
    for (i = 0; i < ed_reps; i++)
        crypto_sign_detached(ed_sig, NULL, buf, (unsigned long long)body_len, ed_sk);
    ed_sign_us = ed_reps > 0 ? (wall_s() - t0) * 1e6 / ed_reps : 0.0;
    t0 = wall_s();
    for (i = 0; i < ed_reps; i++)
        bad += crypto_sign_verify_detached(ed_sig, buf, (unsigned long long)body_len, ed_pk) != 0;
    ed_verify_us = ed_reps > 0 ? (wall_s() - t0) * 1e6 / ed_reps : 0.0;
    printf("  %-13s %4d B + %3d B trailer (%d tags): sign %.2f us, check %.2f us | Ed25519 + 64 B: "
           "sign %.1f us, verify %.1f us%s\n",
           channel, body_len, (int)t.len, t.n_tags, sign_us, check_us, ed_sign_us, ed_verify_us,
           bad ? "  (CHECK FAILED)" : "");
    auth_keyset_free(ks);
    auth_keyset_free(kr);
}

static pid_t start_arm(const char *path, const char *url, int insecure, auth_child_keys *keys)
{
    const char *const argv[] = { "tandem-arm", "--arm", "1", NULL };
    char key[600];
    const int keyed = insecure ? AUTH_CHILD_INHERIT : auth_child_key(keys, argv, key, sizeof key);
    const pid_t pid = keyed < 0 ? -1 : fork();
    if (pid == 0) {
        setenv("LCM_DEFAULT_URL", url, 1);
        /* as tandem-run starts its daemons (daemon.h) */
        setenv(DAEMON_GLIB_SLICE_ENV, DAEMON_GLIB_SLICE_VALUE, 1);
        if (keyed == AUTH_CHILD_OK)
            setenv(AUTH_BUS_KEY_ENV, key, 1); /* arm 1's role file, as tandem-run gives it */
        if (insecure)
            execl(path, "tandem-arm", "--arm", "1", "--lockstep", "--insecure", (char *)NULL);
        else
            execl(path, "tandem-arm", "--arm", "1", "--lockstep", (char *)NULL);
        perror("exec tandem-arm");
        _exit(127);
    }
    return pid;
}

/* ARM1_STATE, ARM1_COMMAND and SIM_CLOCK as the simulator and an arm send
 * them, each checked by its main reader. */
static void time_auth(int reps, int ed_reps, int state_size, int cmd_size, int clock_size)
{
    const auth_peer arm1 = { AUTH_ROLE_ARM, 1, 1 }, sim = { AUTH_ROLE_SIM, 0, 0 };
    printf(
        "authentication, per-role keys (keyed BLAKE2b-128 tag per reader, libsodium), cell of 3 rovers,\n"
        "%d messages each (Ed25519: %d), one core:\n",
        reps, ed_reps);
    time_sign_verify("ARM1_STATE", &arm1, state_size, reps, ed_reps);
    time_sign_verify("ARM1_COMMAND", &sim, cmd_size, reps, ed_reps);
    time_sign_verify("SIM_CLOCK", &arm1, clock_size, reps, ed_reps);
}

int main(int argc, char **argv)
{
    const int ed_only = argc > 2 && strcmp(argv[1], "ed25519") == 0;
    const int auth_only = ed_only || (argc > 2 && strcmp(argv[1], "auth") == 0);
    const int rt_only = argc > 2 && strcmp(argv[1], "roundtrip") == 0;
    const int a0 = rt_only ? 2 : 1; /* N [BIN_DIR [REPS]] from here */
    const int n = auth_only ? atoi(argv[2]) : argc > a0 ? atoi(argv[a0]) : 10000;
    const char *bin = !auth_only && argc > a0 + 1 ? argv[a0 + 1] : "build/bin";
    const int reps_arg = rt_only && argc > a0 + 2 ? atoi(argv[a0 + 2]) : 10;
    const int reps = reps_arg < 1 ? 1 : reps_arg > BENCH_REPS_MAX ? BENCH_REPS_MAX : reps_arg;
    static loopstats blk[3];
    double r_auth_bare[BENCH_REPS_MAX], r_auth_ins[BENCH_REPS_MAX], r_ins_bare[BENCH_REPS_MAX];
    int n_blocks = 0, per_block;
    char url_ins[96], url_sec[96], path[512], key[600], sim_key[600];
    lcm_t *l_ins, *l_sec;
    pid_t echo_pid, arm_ins, arm_sec;
    tandem_arm_state_t st;
    tandem_sim_clock_t clk;
    tandem_arm_command_t cmd0;
    loopstats bare, plain, authed;
    auth_child_keys keys;
    static auth_bus bus; /* this process's (the simulator's) side of the bus */
    int i, state_size, cmd_size, clock_size;
    snprintf(url_ins, sizeof url_ins, "udpm://239.255.76.67:%d?ttl=0",
             40000 + (int)(getpid() % 10000));
    snprintf(url_sec, sizeof url_sec, "udpm://239.255.76.67:%d?ttl=0",
             50000 + (int)(getpid() % 10000));
    auth_child_keys_init(&keys, &bus);
    if (auth_bus_ephemeral_key(key, sizeof key) != 0)
        return 1;
    /* a cell of three rovers; this process is its simulator and holds the
     * simulator's role file, as tandem-sim does under tandem-run */
    auth_bus_roster(&bus, 3);
    {
        const char *const sim_argv[] = { "tandem-sim", NULL };
        if (auth_child_key(&keys, sim_argv, sim_key, sizeof sim_key) != AUTH_CHILD_OK ||
            auth_bus_option(&bus, "bench_roundtrip", OPT_KEY_FILE, sim_key) != 1)
            return 1;
    }
    auth_bus_identity(&bus, AUTH_ROLE_SIM, 0, 0);
    if (auth_bus_start(&bus, "bench_roundtrip") != 0)
        return 1;
    memset(&st, 0, sizeof st);
    st.arm = 1;
    st.q_rad[1] = 0.6;
    st.q_rad[2] = 2.9;
    st.q_rad[4] = -0.4;
    state_size = tandem_arm_state_t_encoded_size(&st);
    memset(&cmd0, 0, sizeof cmd0);
    cmd_size = tandem_arm_command_t_encoded_size(&cmd0);
    memset(&clk, 0, sizeof clk);
    clk.mode = TANDEM_SIM_CLOCK_T_MODE_LOCKSTEP;
    clock_size = tandem_sim_clock_t_encoded_size(&clk);

    if (!rt_only)
        time_auth(ed_only     ? 0
                  : auth_only ? n
                              : 100000,
                  ed_only     ? n
                  : auth_only ? 0
                              : 10000,
                  state_size, cmd_size, clock_size);
    if (auth_only)
        return 0;

    echo_pid = fork();
    if (echo_pid == 0) {
        lcm_t *e = lcm_create(url_ins);
        lcm_subscribe(e, "BENCH_PING", on_echo, e);
        for (;;)
            lcm_handle(e);
    }
    snprintf(path, sizeof path, "%s/tandem-arm", bin);
    arm_ins = start_arm(path, url_ins, 1, &keys);
    arm_sec = start_arm(path, url_sec, 0, &keys);
    l_ins = lcm_create(url_ins);
    l_sec = lcm_create(url_sec);
    lcm_subscribe(l_ins, "BENCH_PONG", on_any, NULL);
    lcm_subscribe(l_ins, "ARM1_COMMAND", on_any, NULL);
    auth_bus_subscribe(&bus, l_sec, "ARM1_COMMAND", on_any,
                       NULL); /* checked, as the simulator does */
    {
        struct timespec ts = { 0, 300000000L };
        nanosleep(&ts, NULL);
    }
    loopstats_reset(&bare);
    loopstats_reset(&plain);
    loopstats_reset(&authed);
    per_block = n / reps > 0 ? n / reps : 1;
    printf(
        "round trip over LCM, %d exchanges of each kind in %d blocks, state %d B, command %d B (+ a trailer of a\n"
        "tag per reader when authenticated; the arm holds its role file)\n",
        per_block * reps, reps, state_size, cmd_size);

    /* Exchanges alternate bare / insecure / authenticated, each kind first
     * in turn, so all see the same machine load and none always follows
     * the same one; the first 100 of each warm up and are not counted. */
    for (i = 0; i < per_block * reps + 100; i++) {
        const int k = i - 100;
        int j, bad = 0;
        if (k >= 0 && k % per_block == 0) {
            loopstats_reset(&blk[0]);
            loopstats_reset(&blk[1]);
            loopstats_reset(&blk[2]);
        }
        for (j = 0; j < 3 && !bad; j++) {
            switch ((i + j) % 3) {
            case 0:
                bad = bare_exchange(l_ins, state_size, clock_size, cmd_size,
                                    k >= 0 ? &blk[0] : NULL) != 0;
                if (bad)
                    fprintf(stderr, "bench: no echo\n");
                break;
            case 1:
                bad = tandem_exchange(&bus, l_ins, 0, &st, &clk, i, k >= 0 ? &blk[1] : NULL) != 0;
                if (bad)
                    fprintf(stderr, "bench: no command from tandem-arm --insecure\n");
                break;
            default:
                bad = tandem_exchange(&bus, l_sec, 1, &st, &clk, i, k >= 0 ? &blk[2] : NULL) != 0;
                if (bad)
                    fprintf(stderr, "bench: no command from tandem-arm (authenticated)\n");
                break;
            }
        }
        if (bad)
            break;
        if (k >= 0 && k % per_block == per_block - 1) {
            const double b = loopstats_percentile(&blk[0], 0.5),
                         p = loopstats_percentile(&blk[1], 0.5),
                         a = loopstats_percentile(&blk[2], 0.5);
            stats_merge(&bare, &blk[0]);
            stats_merge(&plain, &blk[1]);
            stats_merge(&authed, &blk[2]);
            if (b > 0.0 && p > 0.0) {
                r_auth_bare[n_blocks] = a / b;
                r_auth_ins[n_blocks] = a / p;
                r_ins_bare[n_blocks] = p / b;
                n_blocks++;
            }
        }
    }
    print_row("bare LCM ping-pong", &bare);
    print_row("tandem-arm, --insecure", &plain);
    print_row("tandem-arm, authenticated", &authed);
    print_ratio("insecure / bare, all:", &plain, &bare, "");
    print_ratio("authenticated / bare, all:", &authed, &bare, "");
    print_block_ratio("insecure / bare:", r_ins_bare, n_blocks, "");
    print_block_ratio("authenticated / bare:", r_auth_bare, n_blocks, "   (target: <= 1.20x)");
    print_block_ratio("authenticated / insecure:", r_auth_ins, n_blocks, "");
    kill(echo_pid, SIGKILL);
    kill(arm_ins, SIGTERM);
    kill(arm_sec, SIGTERM);
    waitpid(echo_pid, NULL, 0);
    waitpid(arm_ins, NULL, 0);
    waitpid(arm_sec, NULL, 0);
    lcm_destroy(l_ins);
    lcm_destroy(l_sec);
    auth_child_keys_remove(&keys);
    return 0;
}
