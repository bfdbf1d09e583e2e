/* Unit tests of the secure bus (src/daemons/common/auth*.c): the
 * key derivation against libsodium and BLAKE2b's published vectors, what
 * a role file can and cannot sign, the trailer
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
#include "auth_child.h"
#include "daemon.h"
#include "tandem_arm_command_t.h"
#include "tandem_sim_control_t.h"

#define NOW_US 1700000000000000ULL /* a fixed "local clock" for the table tests */

static const auth_sender ARM1 = { AUTH_ROLE_ARM, 1, 1, 0x01020304u };

static const auth_peer P_ARM1 = { AUTH_ROLE_ARM, 1, 1 }, P_ARM2 = { AUTH_ROLE_ARM, 2, 2 },
                       P_SIM = { AUTH_ROLE_SIM, 0, 0 }, P_SUP = { AUTH_ROLE_SUPERVISOR, 0, 0 },
                       P_ROVER1 = { AUTH_ROLE_ROVER, 1, 1 }, P_MON = { AUTH_ROLE_MONITOR, 0, 0 };

static void test_master(uint8_t m[AUTH_KEY_BYTES], uint8_t seed)
{
    int i;
    for (i = 0; i < AUTH_KEY_BYTES; i++)
        m[i] = (uint8_t)(seed + 7 * i);
}

/* The role file of who in the cell of master seed (default roster). */
static auth_keyset *role_set(uint8_t seed, const auth_peer *who)
{
    uint8_t m[AUTH_KEY_BYTES];
    auth_peer roster[AUTH_MAX_TAGS];
    auth_keyset *k = auth_keyset_new();
    const int n = auth_roster(AUTH_ROSTER_ROVERS, roster, AUTH_MAX_TAGS);
    assert_non_null(k);
    test_master(m, seed);
    auth_keyset_role(k, m, who, roster, n);
    return k;
}

static void ring_of(auth_keyring *r, auth_keyset *a, auth_keyset *b)
{
    r->set[0] = a;
    r->set[1] = b;
    r->n = b ? 2 : 1;
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
        "b5e996e8f0f4eb981fc214b005f42d2ff4233499391653df7aefcbc13fc51568",
        want, 64);
    crypto_generichash(out, 64, NULL, 0, key, 64);
    assert_memory_equal(out, want, 64);
    hex("961f6dd1e4dd30f63901690c512e78e4b45e4742ed197c3c5e45c549fd25f2e4"
        "187b0bc9fe30492b16b0d0bc4ef9b0f34c7003fac09a5ef1532e69430234cebd",
        want, 64);
    crypto_generichash(out, 64, &in, 1, key, 64);
    assert_memory_equal(out, want, 64);
}

/* The pairwise key and cell id are keyed BLAKE2b of the documented inputs. */
static void test_kdf_is_keyed_blake2b_of_the_documented_input(void **state)
{
    uint8_t m[AUTH_KEY_BYTES], cell[AUTH_CELL_BYTES], want[32], key[32], in[64];
    size_t n = 0;
    (void)state;
    test_master(m, 3);
    auth_cell_id(m, cell);
    crypto_generichash(want, AUTH_CELL_BYTES, (const uint8_t *)"tandem-cell-id", 14, m,
                       AUTH_KEY_BYTES);
    assert_memory_equal(cell, want, AUTH_CELL_BYTES);
    /* NOLINTNEXTLINE(bugprone-not-null-terminated-result): bytes of a key derivation input, not a string */
    memcpy(in, "tandem-pair-v2", 14);
    n = 14;
    memcpy(in + n, cell, AUTH_CELL_BYTES);
    n += AUTH_CELL_BYTES;
    /* NOLINTNEXTLINE(bugprone-not-null-terminated-result): bytes of a key derivation input, not a string */
    memcpy(in + n,
           "\x03\x00\x00\x00\x00"
           "\x02\x00\x01\x00\x01",
           10); /* supervisor -> arm 1 */
    n += 10;
    crypto_generichash(want, 32, in, n, m, AUTH_KEY_BYTES);
    auth_pair_key(m, cell, &P_SUP, &P_ARM1, key);
    assert_memory_equal(key, want, 32);
    auth_pair_key(m, cell, &P_ARM1, &P_SUP, key); /* the other direction differs */
    assert_memory_not_equal(key, want, 32);
    crypto_generichash(want, 16, (const uint8_t *)"tandem-key-id", 13, m, AUTH_KEY_BYTES);
    assert_int_equal(auth_key_id(m), want[0]);
}

static size_t signed_message(const auth_keyset *k, const auth_sender *s, const char *ch,
                             uint8_t *buf, size_t cap, uint64_t counter)
{
    const size_t body = 83;
    size_t i, len = 0;
    for (i = 0; i < body; i++)
        buf[i] = (uint8_t)(i ^ 0x5a);
    assert_int_equal(auth_sign(k, s, counter, ch, AUTH_ROLES_ALL, NULL, buf, body, cap, &len),
                     AUTH_OK);
    return len;
}

static void test_sign_then_verify_gives_back_the_fields(void **state)
{
    uint8_t buf[2048];
    auth_keyset *a1 = role_set(1, &P_ARM1), *sim = role_set(1, &P_SIM);
    auth_keyring ring;
    auth_trailer t;
    size_t n, i, len;
    (void)state;
    ring_of(&ring, sim, NULL);
    n = signed_message(a1, &ARM1, "ARM1_COMMAND", buf, sizeof buf, NOW_US);
    assert_int_equal(auth_verify(&ring, &P_SIM, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
    assert_int_equal(t.sender.role, AUTH_ROLE_ARM);
    assert_int_equal(t.sender.first, 1);
    assert_int_equal(t.sender.last, 1);
    assert_int_equal(t.sender.session, ARM1.session);
    assert_true(t.counter == NOW_US);
    assert_int_equal(t.key_id, sim->id);
    assert_int_equal(n - t.len, 83);
    for (i = 0; i < 83; i++)
        assert_int_equal(buf[i], (uint8_t)(i ^ 0x5a)); /* the body is untouched */
    /* too little room for the trailer, or a channel over LCM's limit */
    assert_int_equal(
        auth_sign(a1, &ARM1, 1, "X", AUTH_ROLES_ALL, NULL, buf, 83, 83 + AUTH_FIXED_BYTES, &len),
        AUTH_ERR_ARG);
    assert_int_equal(auth_sign(a1, &ARM1, 1,
                               "0123456789012345678901234567890123456789012345678901234567890123",
                               AUTH_ROLES_ALL, NULL, buf, 83, sizeof buf, &len),
                     AUTH_ERR_ARG);
    auth_keyset_free(a1);
    auth_keyset_free(sim);
}

/* Every single-bit change anywhere, another channel, another cell: refused. */
static void test_any_change_is_refused(void **state)
{
    uint8_t buf[2048];
    auth_keyset *a1 = role_set(1, &P_ARM1), *sim = role_set(1, &P_SIM),
                *other = role_set(2, &P_SIM);
    auth_keyring ring;
    auth_trailer t;
    size_t n, i;
    int bit;
    (void)state;
    ring_of(&ring, sim, NULL);
    n = signed_message(a1, &ARM1, "ARM1_COMMAND", buf, sizeof buf, NOW_US);
    for (i = 0; i < n; i += (i < 83 || i > n - 60) ? 1 : 7)
        for (bit = 0; bit < 8; bit++) {
            int rc;
            buf[i] ^= (uint8_t)(1u << bit);
            rc = auth_verify(&ring, &P_SIM, "ARM1_COMMAND", buf, n, &t);
            /* only another receiver's tag is not this receiver's business */
            if (rc == AUTH_OK) {
                const size_t e = (i - 83) % AUTH_TAG_ENTRY_BYTES;
                assert_true(i >= 83 && i < n - AUTH_FIXED_BYTES && e >= AUTH_PEER_BYTES &&
                            buf[i - e] != AUTH_ROLE_SIM);
            }
            buf[i] ^= (uint8_t)(1u << bit);
        }
    assert_int_equal(auth_verify(&ring, &P_SIM, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
    assert_int_equal(auth_verify(&ring, &P_SIM, "ARM2_COMMAND", buf, n, &t), AUTH_ERR_MAC);
    ring_of(&ring, other, NULL); /* another cell */
    assert_int_equal(auth_verify(&ring, &P_SIM, "ARM1_COMMAND", buf, n, &t), AUTH_ERR_CELL);
    /* while rotating, a ring of the new and the old key set takes both */
    ring_of(&ring, other, sim);
    assert_int_equal(auth_verify(&ring, &P_SIM, "ARM1_COMMAND", buf, n, &t), AUTH_OK);
    auth_keyset_free(a1);
    auth_keyset_free(sim);
    auth_keyset_free(other);
}

/* What rover 1's file can do: sign as rover 1; nothing as anyone else. */
static void test_a_role_file_signs_only_as_its_role(void **state)
{
    uint8_t buf[2048];
    const auth_sender as_sup = { AUTH_ROLE_SUPERVISOR, 0, 0, 5 },
                      as_rover1 = { AUTH_ROLE_ROVER, 1, 1, 5 };
    auth_keyset *rv = role_set(1, &P_ROVER1), *a1 = role_set(1, &P_ARM1),
                *a2 = role_set(1, &P_ARM2), *mon = role_set(1, &P_MON), *sup = role_set(1, &P_SUP);
    auth_keyring r1, r2, rm;
    auth_trailer t;
    size_t n;
    (void)state;
    ring_of(&r1, a1, NULL);
    ring_of(&r2, a2, NULL);
    ring_of(&rm, mon, NULL);
    /* rover 1 claims to be the supervisor: no key of the supervisor's pairs */
    n = signed_message(rv, &as_sup, "ARM1_ACTION", buf, sizeof buf, NOW_US);
    assert_int_not_equal(auth_verify(&r1, &P_ARM1, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    /* as itself it is taken (the channel table then refuses it on ARM1_ACTION) */
    n = signed_message(rv, &as_rover1, "ARM1_ACTION", buf, sizeof buf, NOW_US);
    assert_int_equal(auth_verify(&r1, &P_ARM1, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    /* arm 2 cannot speak as the supervisor to arm 1 */
    n = signed_message(a2, &as_sup, "ARM1_ACTION", buf, sizeof buf, NOW_US);
    assert_int_not_equal(auth_verify(&r1, &P_ARM1, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    /* the supervisor's real row: arm 1 and the monitor verify it */
    n = signed_message(sup, &as_sup, "ARM1_ACTION", buf, sizeof buf, NOW_US);
    assert_int_equal(auth_verify(&r1, &P_ARM1, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    assert_int_equal(auth_verify(&rm, &P_MON, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    /* a monitor holds no send key: what it signs nobody takes */
    n = signed_message(mon, &as_sup, "ARM1_ACTION", buf, sizeof buf, NOW_US);
    assert_int_not_equal(auth_verify(&r1, &P_ARM1, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    assert_int_not_equal(auth_verify(&r2, &P_ARM2, "ARM1_ACTION", buf, n, &t), AUTH_OK);
    auth_keyset_free(rv);
    auth_keyset_free(a1);
    auth_keyset_free(a2);
    auth_keyset_free(mon);
    auth_keyset_free(sup);
}

static void test_truncated_and_garbage_buffers(void **state)
{
    uint8_t buf[2048], junk[512];
    auth_keyset *a1 = role_set(1, &P_ARM1), *sim = role_set(1, &P_SIM);
    auth_keyring ring;
    auth_trailer t;
    size_t n, len;
    uint32_t x = 12345;
    int round, i;
    (void)state;
    ring_of(&ring, sim, NULL);
    n = signed_message(a1, &ARM1, "SIM_CONTROL", buf, sizeof buf, NOW_US);
    for (len = 0; len < n; len++) {
        uint8_t *copy = malloc(len ? len : 1); /* exact size: ASan sees any overread */
        memcpy(copy, buf, len);
        assert_int_not_equal(auth_verify(&ring, &P_SIM, "SIM_CONTROL", copy, len, &t), AUTH_OK);
        free(copy);
    }
    assert_int_equal(auth_verify(&ring, &P_SIM, "SIM_CONTROL", NULL, 0, &t), AUTH_ERR_UNSIGNED);
    for (round = 0; round < 2000; round++) {
        len = (size_t)(x % sizeof junk);
        for (i = 0; i < (int)len; i++) {
            x = x * 1664525u + 1013904223u;
            junk[i] = (uint8_t)(x >> 24);
        }
        if (round % 2 && len >= AUTH_FIXED_BYTES) { /* a plausible fixed part */
            uint8_t *f = junk + len - AUTH_FIXED_BYTES;
            f[0] = 'T';
            f[1] = 'A';
            f[2] = AUTH_VERSION;
            f[5] = 0;
            f[39] = 0;
            f[38] = (uint8_t)(f[38] % (AUTH_MAX_TAGS + 1));
            if (round % 4 == 1)
                memcpy(f + 22, sim->cell, AUTH_CELL_BYTES);
        }
        assert_int_not_equal(auth_verify(&ring, &P_SIM, "SIM_CONTROL", junk, len, &t), AUTH_OK);
    }
    auth_keyset_free(a1);
    auth_keyset_free(sim);
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

static auth_replay R; /* large: not on the stack */

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
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US, NOW_US + 5),
                     AUTH_ERR_REPLAY); /* again */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US - 1000, NOW_US + 5),
                     AUTH_ERR_REPLAY); /* older */
    assert_int_equal(auth_replay_check(&R, &ARM1, h2, NOW_US, NOW_US + 5),
                     AUTH_OK); /* own stream per channel */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US + 1, NOW_US + 5), AUTH_OK);
    /* a refused counter did not move the stream on */
    assert_int_equal(auth_replay_check(&R, &ARM1, h1, NOW_US + 10 * AUTH_WINDOW_US, NOW_US + 5),
                     AUTH_ERR_REPLAY);
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
    assert_int_equal(auth_replay_check(&R, &sim, h, NOW_US - slack - 1, NOW_US + 10),
                     AUTH_ERR_REPLAY);
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
    s.session = 4 * AUTH_REPLAY_SLOTS - 1; /* the newest is remembered */
    assert_int_equal(
        auth_replay_check(&R, &s, h, NOW_US + 4 * AUTH_REPLAY_SLOTS - 1, NOW_US + 5000),
        AUTH_ERR_REPLAY);
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
#define CORRUPT(stmt, want)                                  \
    do {                                                     \
        memcpy(t, auth_acl_table, sizeof t[0] * (size_t)n);  \
        stmt;                                                \
        assert_int_equal(auth_acl_validate(t, n + 1), want); \
    } while (0)
    memcpy(t, auth_acl_table, sizeof t[0] * (size_t)n);
    t[n] = t[0]; /* a duplicate row */
    assert_int_equal(auth_acl_validate(t, n + 1), AUTH_ACL_ERR_OVERLAP);
    CORRUPT((t[n] = t[4], t[n].match = AUTH_ACL_RANGE),
            AUTH_ACL_ERR_OVERLAP); /* ARMk_STATE twice */
    CORRUPT((t[n] = t[0], t[n].prefix = "SIM_clock"), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = ""), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].suffix = NULL), AUTH_ACL_ERR_NAME);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].suffix = "_X"), AUTH_ACL_ERR_MATCH);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].match = 7), AUTH_ACL_ERR_MATCH);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].roles = 0), AUTH_ACL_ERR_ROLES);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].roles = AUTH_ROLE_BIT(AUTH_ROLE_LAST + 1)),
            AUTH_ACL_ERR_ROLES);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW", t[n].own = 1), AUTH_ACL_ERR_OWN);
    CORRUPT((t[n] = t[0], t[n].prefix = "NEW"),
            AUTH_ACL_OK); /* the control: a new channel is fine */
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
    char dir[] = "/tmp/test_auth_XXXXXX", path[128], link[160], why[256];
    auth_keyset *a = auth_keyset_new(), *b = auth_keyset_new(), *r = role_set(4, &P_ARM2);
    struct stat st;
    int i;
    FILE *f;
    (void)state;
    assert_non_null(mkdtemp(dir));
    snprintf(path, sizeof path, "%s/sub/bus.key", dir);
    assert_int_equal(auth_key_create(path, why, sizeof why), AUTH_OK);
    assert_int_equal(stat(path, &st), 0);
    assert_int_equal(st.st_mode & 0777, 0600);
    assert_int_equal((int)st.st_size, AUTH_KEY_BYTES);
    assert_int_equal(auth_key_create(path, why, sizeof why), AUTH_ERR_KEY); /* never over a key */
    assert_int_equal(auth_keyset_load(a, path, &P_ARM1, why, sizeof why), AUTH_OK);
    assert_true(a->is_master);
    chmod(path, 0644);
    assert_int_equal(auth_keyset_load(b, path, &P_ARM1, why, sizeof why), AUTH_ERR_KEY);
    assert_non_null(strstr(why, "chmod 600"));
    chmod(path, 0600);
    /* a symbolic link is not followed */
    snprintf(link, sizeof link, "%s/link.key", dir);
    assert_int_equal(symlink(path, link), 0);
    assert_int_equal(auth_keyset_load(b, link, &P_ARM1, why, sizeof why), AUTH_ERR_KEY);
    assert_non_null(strstr(why, "symbolic link"));
    remove(link);
    f = fopen(path, "ab");
    fputc(0, f);
    fclose(f);
    assert_int_equal(auth_keyset_load(b, path, &P_ARM1, why, sizeof why),
                     AUTH_ERR_KEY); /* 33 bytes */
    remove(path);
    assert_int_equal(auth_keyset_load(b, path, &P_ARM1, why, sizeof why),
                     AUTH_ERR_KEY); /* missing */
    /* a role file goes round and holds only its own pairs */
    assert_int_equal(auth_keyset_write(r, path, why, sizeof why), AUTH_OK);
    assert_int_equal(auth_keyset_load(b, path, &P_ARM1, why, sizeof why), AUTH_OK);
    assert_false(b->is_master);
    assert_true(auth_peer_equal(&b->holder, &P_ARM2));
    assert_int_equal(b->n, r->n);
    for (i = 0; i < r->n; i++) {
        assert_true(auth_peer_equal(&b->pair[i].peer, &r->pair[i].peer));
        assert_int_equal(b->pair[i].dir, r->pair[i].dir);
        assert_memory_equal(b->pair[i].key, r->pair[i].key, AUTH_KEY_BYTES);
    }
    remove(path);
    snprintf(path, sizeof path, "%s/sub", dir);
    rmdir(path);
    rmdir(dir);
    auth_keyset_free(a);
    auth_keyset_free(b);
    auth_keyset_free(r);
}

/* ---- one process on LCM's in-process bus ---------------------------------------- */

static int got_a, got_b;
static uint8_t captured[2048];
static int captured_len;

static void on_a(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sim_control_t m;
    (void)ch;
    (void)u;
    /* the handler sees the message without its trailer */
    assert_int_equal(tandem_sim_control_t_decode(rb->data, 0, (int)rb->data_size, &m),
                     (int)rb->data_size);
    tandem_sim_control_t_decode_cleanup(&m);
    got_a++;
}

static void on_b(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)rb;
    (void)ch;
    (void)u;
    got_b++;
}

static void capture(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)ch;
    (void)u;
    if (rb->data_size <= sizeof captured) {
        memcpy(captured, rb->data, rb->data_size);
        captured_len = (int)rb->data_size;
    }
}

static void test_receive_path_counts_every_refusal(void **state)
{
    char path[600];
    auth_bus bus;
    const auth_bus_counts *c;
    tandem_sim_control_t m;
    tandem_arm_command_t cmd;
    uint8_t plain[256];
    int n;
    lcm_t *lcm;
    (void)state;
    auth_bus_init(&bus);
    c = auth_bus_counts_get(&bus);
    assert_int_equal(auth_bus_ephemeral_key(path, sizeof path), 0);
    auth_bus_identity(&bus, AUTH_ROLE_TOOL, 0, 0);
    assert_int_equal(auth_bus_start(&bus, "test_auth"), 0);
    assert_int_equal(auth_bus_secure(&bus), 1);
    lcm = lcm_create("memq://");
    assert_non_null(lcm);
    /* two checked subscriptions see one message: checked once, not a replay */
    auth_bus_subscribe(&bus, lcm, "SIM_CONTROL", on_a, NULL);
    auth_bus_subscribe(&bus, lcm, "SIM_CONTROL", on_b, NULL);
    auth_bus_subscribe(&bus, lcm, "ARM1_COMMAND", on_b, NULL);
    lcm_subscribe(lcm, "SIM_CONTROL", capture, NULL);
    memset(&m, 0, sizeof m);
    m.command = TANDEM_SIM_CONTROL_T_QUIT;
    assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, &bus, lcm, "SIM_CONTROL", &m), 0);
    lcm_handle(lcm);
    assert_int_equal(got_a, 1);
    assert_int_equal(got_b, 1);
    assert_int_equal(c->accepted, 1);
    assert_true(captured_len > tandem_sim_control_t_encoded_size(&m) + AUTH_FIXED_BYTES);
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
    assert_int_equal(AUTH_PUBLISH(tandem_arm_command_t, &bus, lcm, "ARM1_COMMAND", &cmd), 0);
    lcm_handle(lcm);
    assert_int_equal(c->unauthorised, 1);
    assert_int_equal(got_a, 1); /* no handler saw anything refused */
    assert_int_equal(got_b, 1);
    assert_int_equal(auth_bus_rejected_total(&bus), 4);
    lcm_destroy(lcm);
    auth_bus_free(&bus);
}

static int move_checked(void *subs, lcm_t *old, lcm_t *fresh)
{
    return auth_bus_move(subs, old, fresh);
}

/* A tool's checked subscriptions on a renewed handle (lcm_renew, as
 * bus_names_watch does under a flood of channel names): a message the old
 * handle still held is handed on, the new handle is subscribed as the old
 * one was, and a subscription ends by its user after the renewal (the
 * lcm_subscription_t the tool was given at first is gone). Runs after
 * test_receive_path_counts_every_refusal (its ephemeral key in the
 * environment). */
static void test_checked_subscriptions_move(void **state)
{
    static int user_a, user_b;
    auth_bus bus;
    tandem_sim_control_t m;
    lcm_t *lcm, *old;
    int a0, b0;
    (void)state;
    auth_bus_init(&bus);
    auth_bus_identity(&bus, AUTH_ROLE_TOOL, 0, 0);
    assert_int_equal(auth_bus_start(&bus, "test_auth"), 0);
    assert_int_equal(auth_bus_secure(&bus), 1);
    lcm = lcm_create("memq://");
    assert_non_null(lcm);
    assert_non_null(auth_bus_subscribe(&bus, lcm, "SIM_CONTROL", on_a, &user_a));
    assert_non_null(auth_bus_subscribe_queue(&bus, lcm, "ARM1_COMMAND", on_b, &user_b, 8));
    memset(&m, 0, sizeof m);
    m.command = TANDEM_SIM_CONTROL_T_QUIT;
    a0 = got_a;
    b0 = got_b;
    /* queued on the old handle, not handled yet */
    assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, &bus, lcm, "SIM_CONTROL", &m), 0);
    old = lcm;
    assert_int_equal(lcm_renew(&lcm, "memq://", move_checked, &bus, 1000000000LL), DAEMON_OK);
    assert_true(lcm != old);
    assert_int_equal(got_a, a0 + 1); /* the old handle's last message, handed on */
    assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, &bus, lcm, "SIM_CONTROL", &m), 0);
    assert_true(lcm_handle_timeout(lcm, 1000) > 0);
    assert_int_equal(got_a, a0 + 2);
    /* a datagram both handles received while they overlapped comes twice:
     * the copy is refused, counted as a renewal's copy and not as a replay
     * (nor in the refusal total) */
    {
        const auth_bus_counts *c = auth_bus_counts_get(&bus);
        const int64_t replayed = c->replayed, refused = auth_bus_rejected_total(&bus);
        lcm_subscription_t *cap = lcm_subscribe(lcm, "SIM_CONTROL", capture, NULL);
        assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, &bus, lcm, "SIM_CONTROL", &m), 0);
        assert_true(lcm_handle_timeout(lcm, 1000) > 0);
        lcm_unsubscribe(lcm, cap);
        assert_int_equal(got_a, a0 + 3);
        lcm_publish(lcm, "SIM_CONTROL", captured, (unsigned)captured_len);
        assert_true(lcm_handle_timeout(lcm, 1000) > 0);
        assert_int_equal(got_a, a0 + 3);
        assert_int_equal(c->renewal_copies, 1);
        assert_int_equal(c->replayed, replayed);
        assert_int_equal(auth_bus_rejected_total(&bus), refused);
    }
    /* ended by its user: no more */
    assert_int_equal(auth_bus_unsubscribe_user(&bus, lcm, &user_a), 1);
    assert_int_equal(AUTH_PUBLISH(tandem_sim_control_t, &bus, lcm, "SIM_CONTROL", &m), 0);
    assert_int_equal(lcm_handle_timeout(lcm, 50), 0);
    assert_int_equal(got_a, a0 + 3);
    assert_int_equal(got_b, b0);
    /* a handle that cannot open: nothing changes */
    old = lcm;
    assert_int_equal(lcm_renew(&lcm, "nosuchprovider://", move_checked, &bus, 1000000LL),
                     DAEMON_ERR_LCM);
    assert_true(lcm == old);
    auth_bus_close(&bus, lcm);
    auth_bus_free(&bus);
}

/* A child's command line names its principal: what its role file is made for. */
/* A fleet's hosts (auth_fleet_host): for fleets of every size, team size
 * and host count, the ranges are consecutive, cover 1..N once, start and
 * end on team boundaries (the last at N), every host has at least one
 * team and no two differ by more than one; the roster lists each range of
 * more than one robot once, before the single rovers. */
static void test_fleet_hosts_partition_the_teams(void **state)
{
    static const int rovers[] = { 1, 2, 3, 12, 30, 300, 1000, 9999, 10000 };
    static const int units[] = { 1, 3, 10 };
    size_t a, b;
    (void)state;
    for (a = 0; a < sizeof rovers / sizeof rovers[0]; a++)
        for (b = 0; b < sizeof units / sizeof units[0]; b++) {
            int hosts;
            for (hosts = 1; hosts <= AUTH_FLEET_HOSTS_MAX + 2; hosts++) {
                const auth_fleet f = auth_fleet_clamped(rovers[a], hosts, units[b]);
                const int n_units = (rovers[a] + f.unit - 1) / f.unit;
                int h, first, last, next = 1, least = 1 << 30, most = 0;
                assert_true(f.hosts >= 1 && f.hosts <= hosts && f.hosts <= n_units);
                for (h = 0; auth_fleet_host(&f, h, &first, &last) == 0; h++) {
                    const int teams = (last - first) / f.unit + 1;
                    assert_int_equal(first, next);
                    assert_true(last >= first);
                    assert_int_equal((first - 1) % f.unit, 0);
                    assert_true(last == rovers[a] || last % f.unit == 0);
                    least = teams < least ? teams : least;
                    most = teams > most ? teams : most;
                    next = last + 1;
                }
                assert_int_equal(h, f.hosts);
                assert_int_equal(next, rovers[a] + 1);
                assert_true(most - least <= 1);
            }
        }
    {
        const auth_fleet f = auth_fleet_clamped(10000, 4, 10);
        auth_peer roster[AUTH_MAX_TAGS];
        const int n = auth_roster_fleet(&f, roster, AUTH_MAX_TAGS);
        assert_int_equal(n, AUTH_MAX_TAGS);
        assert_int_equal(roster[6].first, 1);
        assert_int_equal(roster[6].last, 2500);
        assert_int_equal(roster[9].first, 7501);
        assert_int_equal(roster[9].last, 10000);
        assert_int_equal(roster[10].first, 1); /* then the single rovers */
        assert_int_equal(roster[10].last, 1);
    }
}

/* Names as key files spell them; a host of several rovers gives its range. */
static void test_principal_names(void **state)
{
    char n[32];
    (void)state;
    auth_principal_name(AUTH_ROLE_ROVER, 1, 3, n, sizeof n);
    assert_string_equal(n, "rover1-3");
    auth_principal_name(AUTH_ROLE_ROVER, 7, 7, n, sizeof n);
    assert_string_equal(n, "rover7");
    auth_principal_name(AUTH_ROLE_ARM, 2, 2, n, sizeof n);
    assert_string_equal(n, "arm2");
    auth_principal_name(AUTH_ROLE_SUPERVISOR, 0, 0, n, sizeof n);
    assert_string_equal(n, "supervisor");
    auth_principal_name(AUTH_ROLE_LAST + 1, 0, 0, n, sizeof n);
    assert_string_equal(n, "?");
}

static void test_child_principal(void **state)
{
    const char *const sim[] = { "tandem-sim", "--rovers", "3", NULL };
    const char *const arm2[] = { "tandem-arm", "--lockstep", "--arm", "2", NULL };
    const char *const arm_eq[] = { "tandem-arm", "--arm=1", NULL };
    const char *const rover[] = { "tandem-rover", "--id", "3", "--robots", "3", NULL };
    const char *const host[] = { "tandem-rover", "--id", "1-4", NULL };
    const char *const status[] = { "tandem-status", NULL };
    const char *const other[] = { "it_roles", "--as-rover1", NULL };
    auth_peer p;
    (void)state;
    auth_child_principal(sim, &p);
    assert_true(p.role == AUTH_ROLE_SIM && p.first == 0 && p.last == 0);
    auth_child_principal(arm2, &p);
    assert_true(p.role == AUTH_ROLE_ARM && p.first == 2 && p.last == 2);
    auth_child_principal(arm_eq, &p);
    assert_true(p.role == AUTH_ROLE_ARM && p.first == 1 && p.last == 1);
    auth_child_principal(rover, &p);
    assert_true(p.role == AUTH_ROLE_ROVER && p.first == 3 && p.last == 3);
    auth_child_principal(host, &p);
    assert_true(p.role == AUTH_ROLE_ROVER && p.first == 1 && p.last == 4);
    auth_child_principal(status, &p);
    assert_true(p.role == AUTH_ROLE_MONITOR);
    auth_child_principal(other, &p);
    assert_true(p.role == AUTH_ROLE_TOOL);
    assert_string_equal(auth_child_strerror(AUTH_CHILD_ERR_PRINCIPAL),
                        "the child's principal is not in the cell's roster");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_blake2b_reference_vectors),
        cmocka_unit_test(test_kdf_is_keyed_blake2b_of_the_documented_input),
        cmocka_unit_test(test_a_role_file_signs_only_as_its_role),
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
        cmocka_unit_test(test_checked_subscriptions_move),
        cmocka_unit_test(test_child_principal),
        cmocka_unit_test(test_principal_names),
        cmocka_unit_test(test_fleet_hosts_partition_the_teams),
    };
    if (auth_init() != 0)
        return 1;
    return cmocka_run_group_tests(tests, NULL, NULL);
}
