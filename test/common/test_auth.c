/* Unit tests of the secure bus (src/daemons/common/auth*.c): the
 * MAC against libsodium and BLAKE2b's published vectors, the trailer
 * under truncation and garbage, the counter window and replay table, the
 * channel authorisation table and its validator, key files, and the
 * whole receive path of one process on LCM's in-process bus (memq://). */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <sodium.h>
#include "auth.h"
#include "auth_acl.h"
#include "auth_bus.h"
#include "tandem_arm_command_t.h"
#include "tandem_sim_control_t.h"

#define NOW_US 1700000000000000ULL   /* a fixed "local clock" for the table tests */

static const auth_sender ARM1 = { AUTH_ROLE_ARM, 1, 1, 0x01020304u };

static void test_key(auth_key *k, uint8_t seed)
{
    uint8_t b[AUTH_KEY_BYTES];
    int i;
    for (i = 0; i < AUTH_KEY_BYTES; i++)
        b[i] = (uint8_t)(seed + 7 * i);
    auth_key_set(k, b);
}

static void hex(const char *s, uint8_t *out, size_t n)
{
    size_t i;
    for (i = 0; i < n; i++) {
        unsigned v;
        assert_int_equal(sscanf(s + 2 * i, "%2x", &v), 1);
        out[i] = (uint8_t)v;
    }
}

/* libsodium's generichash is keyed BLAKE2b: the first two keyed vectors
 * of the BLAKE2 reference (testvectors/blake2b-kat.txt, key 00..3f). */
static void test_blake2b_reference_vectors(void **state)
{
    uint8_t key[64], out[64], want[64], in = 0;
    int i;
    (void)state;
    for (i = 0; i < 64; i++)
        key[i] = (uint8_t)i;
    hex("10ebb67700b1868efb4417987acf4690ae9d972fb7a590c2f02871799aaa4786"
        "b5e996e8f0f4eb981fc214b005f42d2ff4233499391653df7aefcbc13fc51568", want, 64);
    crypto_generichash(out, 64, NULL, 0, key, 64);
    assert_memory_equal(out, want, 64);
    hex("961f6dd1e4dd30f63901690c512e78e4b45e4742ed197c3c5e45c549fd25f2e4"
        "187b0bc9fe30492b16b0d0bc4ef9b0f34c7003fac09a5ef1532e69430234cebd", want, 64);
    crypto_generichash(out, 64, &in, 1, key, 64);
    assert_memory_equal(out, want, 64);
}

/* auth_mac = BLAKE2b-128 keyed with the key over the documented input,
 * assembled here independently and hashed in one call. */
static void test_mac_is_keyed_blake2b_of_the_documented_input(void **state)
{
    const char *ch = "ARM1_COMMAND";
    uint8_t body[300], head[AUTH_HEAD_BYTES], mac[AUTH_MAC_BYTES], want[AUTH_MAC_BYTES], all[512];
    size_t n = 0;
    auth_key k;
    int i;
    (void)state;
    test_key(&k, 3);
    for (i = 0; i < (int)sizeof body; i++)
        body[i] = (uint8_t)(i * 13);
    for (i = 0; i < AUTH_HEAD_BYTES; i++)
        head[i] = (uint8_t)(200 - i);
    memcpy(all + n, "tandem-auth-v1", 14);
    n += 14;
    all[n++] = (uint8_t)strlen(ch);
    memcpy(all + n, ch, strlen(ch));
    n += strlen(ch);
    memcpy(all + n, body, sizeof body);
    n += sizeof body;
    memcpy(all + n, head, sizeof head);
    n += sizeof head;
    crypto_generichash(want, sizeof want, all, n, k.bytes, AUTH_KEY_BYTES);
    assert_int_equal(auth_mac(&k, ch, body, sizeof body, head, mac), AUTH_OK);
    assert_memory_equal(mac, want, AUTH_MAC_BYTES);
    /* the key id is the first byte of the documented derivation */
    crypto_generichash(want, sizeof want, (const uint8_t *)"tandem-key-id", 13, k.bytes, AUTH_KEY_BYTES);
    assert_int_equal(k.id, want[0]);
}

static size_t signed_message(const auth_key *k, const char *ch, uint8_t *buf, size_t cap, uint64_t counter)
{
    const size_t body = 83;
    size_t i;
    for (i = 0; i < body; i++)
        buf[i] = (uint8_t)(i ^ 0x5a);
    assert_int_equal(auth_sign(k, &ARM1, counter, ch, buf, body, cap), AUTH_OK);
    return body + AUTH_TRAILER_BYTES;
}

static void test_sign_then_verify_gives_back_the_fields(void **state)
{
    uint8_t buf[256];
    auth_keyring ring;
    auth_trailer t;
    size_t n, i;
    (void)state;
    test_key(&ring.key[0], 1);
    ring.n = 1;
    n = signed_message(&ring.key[0], "ARM1_COMMAND", buf, sizeof buf, NOW_US);
    assert_int_equal(auth_verify(&ring, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
    assert_int_equal(t.sender.role, AUTH_ROLE_ARM);
    assert_int_equal(t.sender.first, 1);
    assert_int_equal(t.sender.last, 1);
    assert_int_equal(t.sender.session, ARM1.session);
    assert_true(t.counter == NOW_US);
    assert_int_equal(t.key_id, ring.key[0].id);
    for (i = 0; i < 83; i++)
        assert_int_equal(buf[i], (uint8_t)(i ^ 0x5a));   /* the body is untouched */
    /* too little room for the trailer, or a channel over LCM's limit */
    assert_int_equal(auth_sign(&ring.key[0], &ARM1, 1, "X", buf, 83, 83 + AUTH_TRAILER_BYTES - 1), AUTH_ERR_ARG);
    assert_int_equal(auth_sign(&ring.key[0], &ARM1, 1, "0123456789012345678901234567890123456789012345678901234567890123",
                               buf, 83, sizeof buf), AUTH_ERR_ARG);
}

/* Every single-bit change anywhere, another channel, another key: refused. */
static void test_any_change_is_refused(void **state)
{
    uint8_t buf[256];
    auth_keyring ring, other;
    auth_trailer t;
    size_t n, i;
    int bit;
    (void)state;
    test_key(&ring.key[0], 1);
    ring.n = 1;
    n = signed_message(&ring.key[0], "ARM1_COMMAND", buf, sizeof buf, NOW_US);
    for (i = 0; i < n; i++)
        for (bit = 0; bit < 8; bit++) {
            int rc;
            buf[i] ^= (uint8_t)(1u << bit);
            rc = auth_verify(&ring, "ARM1_COMMAND", buf, n, &t);
            assert_true(rc == AUTH_ERR_MAC || rc == AUTH_ERR_UNSIGNED);
            buf[i] ^= (uint8_t)(1u << bit);
        }
    assert_int_equal(auth_verify(&ring, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
    assert_int_equal(auth_verify(&ring, "ARM2_COMMAND", buf, n, &t), AUTH_ERR_MAC);
    test_key(&other.key[0], 2);
    other.n = 1;
    assert_int_equal(auth_verify(&other, "ARM1_COMMAND", buf, n, &t), AUTH_ERR_MAC);
    other.key[0].id = ring.key[0].id;   /* same id byte, other key */
    assert_int_equal(auth_verify(&other, "ARM1_COMMAND", buf, n, &t), AUTH_ERR_MAC);
    /* while rotating, a ring of the new and the old key takes both */
    other.key[1] = ring.key[0];
    other.n = 2;
    assert_int_equal(auth_verify(&other, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
}

static void test_truncated_and_garbage_buffers(void **state)
{
    uint8_t buf[256], junk[256];
    auth_keyring ring;
    auth_trailer t;
    size_t n, len;
    uint32_t x = 12345;
    int round, i;
    (void)state;
    test_key(&ring.key[0], 1);
    ring.n = 1;
    n = signed_message(&ring.key[0], "SIM_CONTROL", buf, sizeof buf, NOW_US);
    for (len = 0; len < n; len++) {
        uint8_t *copy = malloc(len ? len : 1);   /* exact size: ASan sees any overread */
        memcpy(copy, buf, len);
        assert_int_not_equal(auth_verify(&ring, "SIM_CONTROL", copy, len, &t), AUTH_OK);
        free(copy);
    }
    assert_int_equal(auth_verify(&ring, "SIM_CONTROL", NULL, 0, &t), AUTH_ERR_UNSIGNED);
    for (round = 0; round < 2000; round++) {
        len = (size_t)(x % sizeof junk);
        for (i = 0; i < (int)len; i++) {
            x = x * 1664525u + 1013904223u;
            junk[i] = (uint8_t)(x >> 24);
        }
        if (round % 2 && len >= AUTH_TRAILER_BYTES) {   /* a plausible trailer head */
            junk[len - AUTH_TRAILER_BYTES] = 'T';
            junk[len - AUTH_TRAILER_BYTES + 1] = 'A';
            junk[len - AUTH_TRAILER_BYTES + 2] = AUTH_VERSION;
            junk[len - AUTH_TRAILER_BYTES + 3] = ring.key[0].id;
            junk[len - AUTH_TRAILER_BYTES + 5] = 0;
        }
        assert_int_not_equal(auth_verify(&ring, "SIM_CONTROL", junk, len, &t), AUTH_OK);
    }
}

static void test_sender_ids(void **state)
{
    auth_sender s = ARM1;
    (void)state;
    assert_int_equal(auth_sender_check(&s), AUTH_OK);
    s.role = 0;
    assert_int_equal(auth_sender_check(&s), AUTH_ERR_SENDER);
    s.role = AUTH_ROLE_LAST + 1;
    assert_int_equal(auth_sender_check(&s), AUTH_ERR_SENDER);
    s = ARM1;
    s.first = 3;
    s.last = 2;
    assert_int_equal(auth_sender_check(&s), AUTH_ERR_SENDER);
}

static auth_replay R;   /* large: not on the stack */

static void test_counter_window(void **state)
{
    const uint64_t h = auth_channel_hash("ARM1_COMMAND");
    const uint64_t w = (uint64_t)AUTH_WINDOW_US;
    (void)state;
    auth_replay_init(&R, AUTH_WINDOW_US, 0);
    /* first sight: only a counter within the window of the local clock */
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US - w - 1, NOW_US), AUTH_ERR_REPLAY);
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US + w + 1, NOW_US), AUTH_ERR_REPLAY);
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US - w, NOW_US), AUTH_OK);
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US + w, NOW_US), AUTH_OK);
    /* known stream: still the window, and above its last */
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US + w + 5, NOW_US + 10), AUTH_OK);
    assert_int_equal(auth_replay_check(&R, &ARM1, h, NOW_US + 3 * w, NOW_US + 10), AUTH_ERR_REPLAY);
}

static void test_replay_is_refused_and_changes_nothing(void **state)
{
    const uint64_t h1 = auth_channel_hash("ARM1_COMMAND"), h2 = auth_channel_hash("ARM_EVENTS");
    auth_sender restarted = ARM1;
    uint64_t last = 0, c1, c2;
    (void)state;
    auth_replay_init(&R, AUTH_WINDOW_US, 0);
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US, NOW_US), AUTH_OK);
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US, NOW_US + 5), AUTH_ERR_REPLAY);       /* again */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US - 1000, NOW_US + 5), AUTH_ERR_REPLAY); /* older */
    assert_int_equal(auth_replay_check(&R, &ARM1, h2, NOW_US, NOW_US + 5), AUTH_OK);   /* own stream per channel */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US + 1, NOW_US + 5), AUTH_OK);
    /* a refused counter did not move the stream on */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US + 10 * AUTH_WINDOW_US, NOW_US + 5), AUTH_ERR_REPLAY);
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US + 2, NOW_US + 5), AUTH_OK);
    /* the sender restarted (new session, counter = its clock): taken at once */
    restarted.session++;
    assert_int_equal(auth_replay_check(&R, &restarted, h1, NOW_US + 1000, NOW_US + 1000), AUTH_OK);
    /* a sender's counters always increase, whatever its clock does */
    c1 = auth_next_counter(&last, NOW_US);
    c2 = auth_next_counter(&last, NOW_US);
    assert_true(c2 > c1);
    assert_true(auth_next_counter(&last, NOW_US - 1000) > c2);
    assert_true(auth_next_counter(&last, NOW_US + 99) == NOW_US + 99);
}

/* A receiver that (re)started refuses what was signed before it started
 * (less the slack for other hosts' clocks), even inside the window. */
static void test_nothing_older_than_the_receiver(void **state)
{
    const uint64_t h = auth_channel_hash("ARM2_STATE"), slack = (uint64_t)AUTH_START_SLACK_US;
    auth_sender sim = { AUTH_ROLE_SIM, 0, 0, 9 };
    (void)state;
    auth_replay_init(&R, AUTH_WINDOW_US, NOW_US);
    assert_int_equal(auth_replay_check(&R, &sim, h, NOW_US - slack - 1, NOW_US + 10), AUTH_ERR_REPLAY);
    sim.session++;
    assert_int_equal(auth_replay_check(&R, &sim, h, NOW_US - slack, NOW_US + 10), AUTH_OK);
    sim.session++;
    assert_int_equal(auth_replay_check(&R, &sim, h, NOW_US + 5, NOW_US + 10), AUTH_OK);
}

/* More streams than slots: none refused; a stream pushed out is only as
 * protected as a new one (the window). */
static void test_replay_table_overflow(void **state)
{
    const uint64_t h = auth_channel_hash("TEAM");
    auth_sender s = { AUTH_ROLE_ROVER, 1, 1, 0 };
    uint32_t i;
    (void)state;
    auth_replay_init(&R, AUTH_WINDOW_US, 0);
    for (i = 0; i < 4 * AUTH_REPLAY_SLOTS; i++) {
        s.session = i;
        assert_int_equal(auth_replay_check(&R, &s, h, NOW_US + i, NOW_US + i), AUTH_OK);
    }
    s.session = 4 * AUTH_REPLAY_SLOTS - 1;   /* the newest is remembered */
    assert_int_equal(auth_replay_check(&R, &s, h, NOW_US + 4 * AUTH_REPLAY_SLOTS - 1, NOW_US + 5000), AUTH_ERR_REPLAY);
}

static void test_acl_table_is_valid(void **state)
{
    (void)state;
    assert_int_equal(auth_acl_validate(auth_acl_table, auth_acl_table_n), AUTH_ACL_OK);
}

/* The validator fed a corrupted copy of the table, one fault at a time. */
static void test_acl_validator_catches_corruption(void **state)
{
    auth_acl_rule t[128];
    const int n = auth_acl_table_n;
    (void)state;
    assert_true(n + 1 <= 128);
#define CORRUPT(stmt, want) do { memcpy(t, auth_acl_table, sizeof t[0] * (size_t)n); stmt; \
                                 assert_int_equal(auth_acl_validate(t, n + 1), want); } while (0)
    memcpy(t, auth_acl_table, sizeof t[0] * (size_t)n);
    t[n] = t[0];                                                         /* a duplicate row */
    assert_int_equal(auth_acl_validate(t, n + 1), AUTH_ACL_ERR_OVERLAP);
    CORRUPT((t[n] = t[4], t[n].match = AUTH_ACL_RANGE), AUTH_ACL_ERR_OVERLAP);   /* ARMk_STATE twice */
    CORRUPT((t[n] = t[0], t[n].prefix = "SIM_clock"), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = ""), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].suffix = NULL), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].suffix = "_X"), AUTH_ACL_ERR_MATCH);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].match = 7), AUTH_ACL_ERR_MATCH);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].roles = 0), AUTH_ACL_ERR_ROLES);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].roles = AUTH_ROLE_BIT(AUTH_ROLE_LAST + 1)), AUTH_ACL_ERR_ROLES);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].own = 1), AUTH_ACL_ERR_OWN);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW"), AUTH_ACL_OK);            /* the control: a new channel is fine */
#undef CORRUPT
    assert_int_equal(auth_acl_validate(t, 0), AUTH_ACL_ERR_EMPTY);
    assert_int_equal(auth_acl_validate(NULL, 3), AUTH_ACL_ERR_EMPTY);
}

static int may(int role, int first, int last, const char *channel)
{
    const auth_sender s = { (uint8_t)role, (uint16_t)first, (uint16_t)last, 1 };
    return auth_acl_check(auth_acl_table, auth_acl_table_n, channel, &s) == AUTH_OK;
}

static void test_acl_says_who_publishes_what(void **state)
{
    auth_sender o;
    (void)state;
    assert_true(may(AUTH_ROLE_SIM, 0, 0, "ARM1_STATE"));
    assert_false(may(AUTH_ROLE_TOOL, 0, 0, "ARM1_STATE"));
    assert_true(may(AUTH_ROLE_SIM, 0, 0, "SIM_CLOCK"));
    assert_false(may(AUTH_ROLE_TOOL, 0, 0, "SIM_CLOCK"));
    assert_true(may(AUTH_ROLE_ARM, 1, 1, "ARM1_COMMAND"));
    assert_false(may(AUTH_ROLE_ARM, 2, 2, "ARM1_COMMAND"));
    assert_false(may(AUTH_ROLE_SUPERVISOR, 0, 0, "ARM1_COMMAND"));
    assert_true(may(AUTH_ROLE_SUPERVISOR, 0, 0, "ARM2_ACTION"));
    assert_false(may(AUTH_ROLE_ARM, 2, 2, "ARM2_ACTION"));
    assert_true(may(AUTH_ROLE_SUPERVISOR, 0, 0, "PETRI_MARKING"));
    assert_true(may(AUTH_ROLE_TOOL, 0, 0, "SIM_CONTROL"));
    assert_false(may(AUTH_ROLE_ARM, 1, 1, "SIM_CONTROL"));
    assert_true(may(AUTH_ROLE_ARM, 1, 1, "SIM_ACK"));
    assert_false(may(AUTH_ROLE_SIM, 0, 0, "SIM_ACK"));
    assert_true(may(AUTH_ROLE_ROVER, 1, 3, "ROVER2_COMMAND"));
    assert_false(may(AUTH_ROLE_ROVER, 1, 3, "ROVER4_COMMAND"));
    assert_true(may(AUTH_ROLE_ROVER, 4, 4, "TEAM"));
    assert_false(may(AUTH_ROLE_TOOL, 0, 0, "TEAM"));
    assert_true(may(AUTH_ROLE_ARM, 2, 2, "HEALTH_TANDEM_ARM_2"));
    assert_false(may(AUTH_ROLE_ARM, 1, 1, "HEALTH_TANDEM_ARM_2"));
    assert_true(may(AUTH_ROLE_ROVER, 1, 3, "HEALTH_TANDEM_ROVER_1_3"));
    assert_false(may(AUTH_ROLE_ROVER, 1, 2, "HEALTH_TANDEM_ROVER_1_3"));
    assert_false(may(AUTH_ROLE_SIM, 0, 0, "HEALTH_TANDEM_SUPERVISOR"));
    /* names the table does not hold */
    assert_false(may(AUTH_ROLE_SIM, 0, 0, "ARM1_STATEX"));
    assert_false(may(AUTH_ROLE_SIM, 0, 0, "ARM_STATE"));
    assert_false(may(AUTH_ROLE_SIM, 0, 0, "ARM999999_STATE"));
    assert_false(may(AUTH_ROLE_TOOL, 0, 0, "BENCH_PING"));
    /* the owner a stand-in process signs as */
    assert_int_equal(auth_acl_owner(auth_acl_table, auth_acl_table_n, "ARM2_COMMAND", &o), AUTH_OK);
    assert_int_equal(o.role, AUTH_ROLE_ARM);
    assert_int_equal(o.first, 2);
    assert_int_equal(o.last, 2);
    assert_int_equal(auth_acl_owner(auth_acl_table, auth_acl_table_n, "NOPE", &o), AUTH_ERR_ACL);
}

static void test_key_files(void **state)
{
    char dir[] = "/tmp/test_auth_XXXXXX", path[128], why[256];
    auth_key a, b;
    struct stat st;
    FILE *f;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/sub/bus.key", dir);
    assert_int_equal(auth_key_create(path, why, sizeof why), AUTH_OK);
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0600);
    assert_int_equal((int)st.st_size, AUTH_KEY_BYTES);
    assert_int_equal(auth_key_create(path, why, sizeof why), AUTH_ERR_KEY);   /* never over a key */
    assert_int_equal(auth_key_load(&a, path, why, sizeof why), AUTH_OK);
    assert_int_equal(a.id, auth_key_id(a.bytes));
    chmod(path, 0644);
    assert_int_equal(auth_key_load(&b, path, why, sizeof why), AUTH_ERR_KEY);
    assert_non_null(strstr(why, "chmod 600"));
    chmod(path, 0600);
    f = fopen(path, "ab");
    fputc(0, f);
    fclose(f);
    assert_int_equal(auth_key_load(&b, path, why, sizeof why), AUTH_ERR_KEY);  /* 33 bytes */
    remove(path);
    assert_int_equal(auth_key_load(&b, path, why, sizeof why), AUTH_ERR_KEY);  /* missing */
    snprintf(path, sizeof path, "%s/sub", dir);
    rmdir(path);
    rmdir(dir);
}

/* ---- one process on LCM's in-process bus ---------------------------------------- */

static int got_a, got_b;
static uint8_t captured[512];
static int captured_len;

static void on_a(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_control_t m;
    (void)ch; (void)u;
    /* the handler sees the message without its trailer */
    assert_int_equal(tandem_sim_control_t_decode(rb->data, 0, (int)rb->data_size, &m), (int)rb->data_size);
    tandem_sim_control_t_decode_cleanup(&m);
    got_a++;
}

static void on_b(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb; (void)ch; (void)u;
    got_b++;
}

static void capture(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)ch; (void)u;
    if (rb->data_size <= sizeof captured) {
        memcpy(captured, rb->data, rb->data_size);
        captured_len = (int)rb->data_size;
    }
}

static void test_receive_path_counts_every_refusal(void **state)
{
    char path[600];
    const auth_bus_counts *c = auth_bus_counts_get();
    tandem_sim_control_t m;
    tandem_arm_command_t cmd;
    uint8_t plain[256];
    int n;
    lcm_t *lcm;
    (void)state;
    assert_int_equal(auth_bus_ephemeral_key(path, sizeof path), 0);
    auth_bus_identity(AUTH_ROLE_TOOL, 0, 0);
    assert_int_equal(auth_bus_start("test_auth"), 0);
    assert_int_equal(auth_bus_secure(), 1);
    lcm = lcm_create("memq://");
    assert_non_null(lcm);
    /* two checked subscriptions see one message: checked once, not a replay */
    auth_bus_subscribe(lcm, "SIM_CONTROL", on_a, NULL);
    auth_bus_subscribe(lcm, "SIM_CONTROL", on_b, NULL);
    auth_bus_subscribe(lcm, "ARM1_COMMAND", on_b, NULL);
    lcm_subscribe(lcm, "SIM_CONTROL", capture, NULL);
    memset(&m, 0, sizeof m);
    m.command = TANDEM_SIM_CONTROL_T_QUIT;
    assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, lcm, "SIM_CONTROL", &m), 0);
    lcm_handle(lcm);
    assert_int_equal(got_a, 1);
    assert_int_equal(got_b, 1);
    assert_int_equal(c->accepted, 1);
    assert_int_equal(captured_len, tandem_sim_control_t_encoded_size(&m) + AUTH_TRAILER_BYTES);
    /* the same bytes again: a replay */
    lcm_publish(lcm, "SIM_CONTROL", captured, (unsigned)captured_len);
    lcm_handle(lcm);
    assert_int_equal(c->replayed, 1);
    /* the same bytes on another channel: the MAC covers the channel */
    lcm_publish(lcm, "ARM1_COMMAND", captured, (unsigned)captured_len);
    lcm_handle(lcm);
    assert_int_equal(c->bad_mac, 1);
    /* unsigned */
    n = tandem_sim_control_t_encode(plain, 0, sizeof plain, &m);
    lcm_publish(lcm, "SIM_CONTROL", plain, (unsigned)n);
    lcm_handle(lcm);
    assert_int_equal(c->unsigned_msgs, 1);
    /* signed with the key, by a sender the table does not allow there (a tool
     * is not arm 1) */
    memset(&cmd, 0, sizeof cmd);
    assert_int_equal(AUTH_PUBLISH(tandem_arm_command_t, lcm, "ARM1_COMMAND", &cmd), 0);
    lcm_handle(lcm);
    assert_int_equal(c->unauthorised, 1);
    assert_int_equal(got_a, 1);   /* no handler saw anything refused */
    assert_int_equal(got_b, 1);
    assert_int_equal(auth_bus_rejected_total(), 4);
    lcm_destroy(lcm);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blake2b_reference_vectors),
        cmocka_unit_test(test_mac_is_keyed_blake2b_of_the_documented_input),
        cmocka_unit_test(test_sign_then_verify_gives_back_the_fields),
        cmocka_unit_test(test_any_change_is_refused),
        cmocka_unit_test(test_truncated_and_garbage_buffers),
        cmocka_unit_test(test_sender_ids),
        cmocka_unit_test(test_counter_window),
        cmocka_unit_test(test_replay_is_refused_and_changes_nothing),
        cmocka_unit_test(test_nothing_older_than_the_receiver),
        cmocka_unit_test(test_replay_table_overflow),
        cmocka_unit_test(test_acl_table_is_valid),
        cmocka_unit_test(test_acl_validator_catches_corruption),
        cmocka_unit_test(test_acl_says_who_publishes_what),
        cmocka_unit_test(test_key_files),
        cmocka_unit_test(test_receive_path_counts_every_refusal),
    };
    if (auth_init() != 0)
        return 1;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
