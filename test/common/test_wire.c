/* Unit tests of the raw-byte wire check (src/daemons/common/wire.c) against
 * lcm-gen's own encoder: every message lcm-gen encodes passes and is the
 * type wire_find names; each way a datagram can lie about its layout
 * (a truncated or padded buffer, a negative or too large array length, a
 * string without its NUL, or with one inside, an empty byte array, the
 * wrong type hash) is
 * refused with its named error, before any decoder sees it. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <string.h>
#include "wire.h"
#include "tandem_wire_types.h"
#include "tandem_health_t.h"
#include "tandem_petri_marking_t.h"

#define BUF_BYTES 8192

/* A health message with two channels: strings and variable arrays. */
static int encode_health(uint8_t *buf, char *name, char *status)
{
    static char ch0[] = "ARM1_STATE", ch1[] = "SIM_CLOCK";
    static char *channels[2] = { ch0, ch1 };
    static int64_t received[2] = { 10, 20 }, lost[2] = { 0, 1 }, refused[2] = { 0, 0 };
    tandem_health_t m;
    memset(&m, 0, sizeof m);
    m.name = name;
    m.status = status;
    m.n_channels = 2;
    m.channel = channels;
    m.channel_received = received;
    m.channel_lost = lost;
    m.channel_auth_rejected = refused;
    return tandem_health_t_encode(buf, 0, BUF_BYTES, &m);
}

/* Offset of the 4-byte length of the string holding `text` (found by
 * content: the layout is lcm-gen's, not re-typed here). */
static size_t string_len_at(const uint8_t *buf, int n, const char *text)
{
    const size_t tl = strlen(text);
    size_t i;
    for (i = 4; i + tl <= (size_t)n; i++)
        if (memcmp(buf + i, text, tl) == 0)
            return i - 4;
    fail_msg("string %s not in the encoding", text);
    return 0;
}

static void put_be32(uint8_t *p, int32_t v)
{
    const uint32_t u = (uint32_t)v;
    p[0] = (uint8_t)(u >> 24);
    p[1] = (uint8_t)(u >> 16);
    p[2] = (uint8_t)(u >> 8);
    p[3] = (uint8_t)u;
}

static void test_encoded_messages_pass(void **state)
{
    uint8_t buf[BUF_BYTES];
    char name[] = "tandem-arm-1", status[] = "holding";
    const int n = encode_health(buf, name, status);
    (void)state;
    assert_true(n > 0);
    assert_int_equal(wire_check(&wire_t_tandem_health_t, buf, (size_t)n), WIRE_OK);
    assert_ptr_equal(wire_find(buf, (size_t)n), &wire_t_tandem_health_t);
}

static void test_truncated_or_padded_refused(void **state)
{
    uint8_t buf[BUF_BYTES];
    char name[] = "tandem-arm-1", status[] = "holding";
    const int n = encode_health(buf, name, status);
    int cut;
    (void)state;
    for (cut = 0; cut < n; cut++)
        assert_int_not_equal(wire_check(&wire_t_tandem_health_t, buf, (size_t)cut), WIRE_OK);
    assert_int_not_equal(wire_check(&wire_t_tandem_health_t, buf, (size_t)n + 1), WIRE_OK);
}

static void test_string_nul_only_at_the_end(void **state)
{
    uint8_t buf[BUF_BYTES];
    char name[] = "tandem-arm-1", status[] = "holding";
    const int n = encode_health(buf, name, status);
    const size_t at = string_len_at(buf, n, "holding");
    uint8_t bad[BUF_BYTES];
    (void)state;
    /* a NUL inside: the decoded string would end there and hide the rest */
    memcpy(bad, buf, (size_t)n);
    bad[at + 4 + 3] = 0;
    assert_int_equal(wire_check(&wire_t_tandem_health_t, bad, (size_t)n), WIRE_ERR_STRING);
    /* no NUL at the end */
    memcpy(bad, buf, (size_t)n);
    bad[at + 4 + strlen("holding")] = 'x';
    assert_int_equal(wire_check(&wire_t_tandem_health_t, bad, (size_t)n), WIRE_ERR_STRING);
    /* a length of 0 (lcm-gen always counts the NUL) */
    memcpy(bad, buf, (size_t)n);
    put_be32(bad + at, 0);
    assert_int_equal(wire_check(&wire_t_tandem_health_t, bad, (size_t)n), WIRE_ERR_STRING);
}

static void test_array_lengths_checked(void **state)
{
    uint8_t buf[BUF_BYTES], bad[BUF_BYTES];
    char name[] = "tandem-arm-1", status[] = "holding";
    const int n = encode_health(buf, name, status);
    /* n_channels (int16) sits just before the first channel name's length */
    const size_t at = string_len_at(buf, n, "ARM1_STATE") - 2;
    (void)state;
    assert_int_equal(buf[at], 0);
    assert_int_equal(buf[at + 1], 2);
    memcpy(bad, buf, (size_t)n);
    bad[at] = 0xff; /* -255 channels: lcm-gen's decoder would ask for a huge allocation */
    bad[at + 1] = 0x01;
    assert_int_not_equal(wire_check(&wire_t_tandem_health_t, bad, (size_t)n), WIRE_OK);
    memcpy(bad, buf, (size_t)n);
    bad[at + 1] = 33; /* above the capacity (lcmtypes/capacities: 32) */
    assert_int_not_equal(wire_check(&wire_t_tandem_health_t, bad, (size_t)n), WIRE_OK);
}

/* An empty 1-byte array: lcm-gen would memcpy into a NULL pointer. */
static void test_empty_byte_array_refused(void **state)
{
    uint8_t buf[BUF_BYTES];
    int8_t marking[1] = { 1 }, running[1] = { 0 };
    tandem_petri_marking_t m;
    int n;
    (void)state;
    memset(&m, 0, sizeof m);
    m.n_places = 1;
    m.marking = marking;
    m.n_transitions = 1;
    m.running = running;
    n = tandem_petri_marking_t_encode(buf, 0, BUF_BYTES, &m);
    assert_true(n > 0);
    assert_int_equal(wire_check(&wire_t_tandem_petri_marking_t, buf, (size_t)n), WIRE_OK);
    m.n_transitions = 0;
    n = tandem_petri_marking_t_encode(buf, 0, BUF_BYTES, &m);
    assert_true(n > 0);
    assert_int_equal(wire_check(&wire_t_tandem_petri_marking_t, buf, (size_t)n), WIRE_ERR_LENGTH);
}

static void test_wrong_hash_refused(void **state)
{
    uint8_t buf[BUF_BYTES];
    char name[] = "tandem-arm-1", status[] = "holding";
    const int n = encode_health(buf, name, status);
    (void)state;
    buf[7] ^= 0x40;
    assert_int_not_equal(wire_check(&wire_t_tandem_health_t, buf, (size_t)n), WIRE_OK);
    assert_null(wire_find(buf, (size_t)n));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_encoded_messages_pass),
        cmocka_unit_test(test_truncated_or_padded_refused),
        cmocka_unit_test(test_string_nul_only_at_the_end),
        cmocka_unit_test(test_array_lengths_checked),
        cmocka_unit_test(test_empty_byte_array_refused),
        cmocka_unit_test(test_wrong_hash_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
