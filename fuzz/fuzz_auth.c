/* fuzz_auth: libFuzzer target for the secure bus's receive check, v2
 * (src/daemons/common/auth.c, auth_acl.c: a tag per receiver under pairwise
 * keys, the cell id in every digest), the code every tandem message meets
 * before any decoder (built by tools/fuzz.sh as fuzz_auth).
 *
 * The receiver is a tool holding a fixed cell master (it derives every
 * pairwise key, so any sender of the roster can be signed as and checked).
 * Input: byte 0 picks the mode, byte 1 the channel name's length (mod 64),
 * then the channel name's bytes, then the datagram.
 *  - mode even: the datagram as received: auth_verify (trailer parse from
 *    the end, the cell, this receiver's tag among up to 48, the pairwise
 *    key of the claimed sender). A tag must never verify without having
 *    been computed here: a datagram that does aborts.
 *  - mode odd: the datagram's last AUTH_FIXED_BYTES bytes give a sender
 *    (role, first, last instance, session: bytes 0-8) and a counter (bytes
 *    9-16), the rest is the body; it is signed with the tags of every
 *    roster principal and must then verify, parse back to the same sender,
 *    counter and key id, pass the sender, channel table and replay checks
 *    as auth_bus_accept chains them at most once (the same counter a
 *    second time is a replay), and must no longer verify with one bit
 *    flipped in the body or in the fixed part of the trailer (identities,
 *    checked by abort).
 * The sanitizers catch overflows and undefined behaviour in the parsing.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "auth.h"
#include "auth_acl.h"

#define FUZZ_MAX_BODY 65536
#define FUZZ_NOW_US 1800000000000000ULL /* a fixed wall clock: deterministic runs */

typedef struct fuzz_ctx {
    auth_keyring ring;
    auth_replay replay;
} fuzz_ctx;

static const auth_peer fuzz_me = { AUTH_ROLE_TOOL, 0, 0 }; /* the receiver */

static fuzz_ctx *ctx(void)
{
    static fuzz_ctx c;
    static int ready;
    if (!ready) {
        uint8_t k[AUTH_KEY_BYTES];
        int i;
        if (auth_init() != 0)
            abort();
        for (i = 0; i < AUTH_KEY_BYTES; i++)
            k[i] = (uint8_t)(i * 37 + 11);
        if (!(c.ring.set[0] = auth_keyset_new()))
            abort();
        auth_keyset_master(c.ring.set[0], k, &fuzz_me, AUTH_ROSTER_ROVERS);
        c.ring.n = 1;
        auth_replay_init(&c.replay, AUTH_WINDOW_US, FUZZ_NOW_US - 10000000ULL);
        ready = 1;
    }
    return &c;
}

static uint64_t be(const uint8_t *p, int n)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < n; i++)
        v = (v << 8) | p[i];
    return v;
}

/* The chain after the MAC, as auth_bus_accept runs it. */
static int admit(fuzz_ctx *c, const char *channel, const auth_trailer *t)
{
    int rc = auth_sender_check(&t->sender);
    if (rc == AUTH_OK)
        rc = auth_acl_check(auth_acl_table, auth_acl_table_n, channel, &t->sender);
    if (rc == AUTH_OK)
        rc = auth_replay_check(&c->replay, &t->sender, auth_channel_hash(channel), t->counter,
                               FUZZ_NOW_US);
    return rc;
}

static void as_received(fuzz_ctx *c, const char *channel, const uint8_t *d, size_t n)
{
    auth_trailer t;
    if (auth_verify(&c->ring, &fuzz_me, channel, d, n, &t) == AUTH_OK)
        abort(); /* a MAC nobody here computed verified */
}

static void signed_here(fuzz_ctx *c, const char *channel, const uint8_t *d, size_t n)
{
    static uint8_t buf[FUZZ_MAX_BODY + AUTH_TRAILER_MAX];
    size_t len, flip;
    auth_sender s;
    auth_trailer t;
    uint64_t counter;
    size_t body;
    int rc;
    if (n < AUTH_HEAD_BYTES || n - AUTH_HEAD_BYTES > FUZZ_MAX_BODY)
        return;
    body = n - AUTH_HEAD_BYTES;
    s.role = d[body];
    s.first = (uint16_t)be(d + body + 1, 2);
    s.last = (uint16_t)be(d + body + 3, 2);
    s.session = (uint32_t)be(d + body + 5, 4);
    counter = be(d + body + 9, 8);
    memcpy(buf, d, body);
    if (auth_sign(c->ring.set[0], &s, counter, channel, AUTH_ROLES_ALL, NULL, buf, body, sizeof buf,
                  &len) != AUTH_OK)
        return;
    if (auth_verify(&c->ring, &fuzz_me, channel, buf, len, &t) != AUTH_OK)
        abort(); /* signed and refused */
    if (t.sender.role != s.role || t.sender.first != s.first || t.sender.last != s.last ||
        t.sender.session != s.session || t.counter != counter || t.key_id != c->ring.set[0]->id)
        abort(); /* the trailer does not read back what was written */
    rc = admit(c, channel, &t);
    if (rc == AUTH_OK && admit(c, channel, &t) != AUTH_ERR_REPLAY)
        abort();                             /* the same counter taken twice */
    flip = d[0] % (body + AUTH_FIXED_BYTES); /* a byte of the body or of the fixed part */
    buf[flip < body ? flip : len - AUTH_FIXED_BYTES + (flip - body)] ^= 0x01;
    if (auth_verify(&c->ring, &fuzz_me, channel, buf, len, &t) == AUTH_OK)
        abort(); /* a flipped bit of the body or trailer head still verifies */
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    fuzz_ctx *c = ctx();
    char channel[64];
    size_t len;
    if (size < 2)
        return 0;
    len = data[1] % 64u;
    if (size < 2 + len)
        return 0;
    memcpy(channel, data + 2, len);
    channel[len] = '\0'; /* an embedded NUL shortens it, as in a C string */
    if (data[0] & 1)
        signed_here(c, channel, data + 2 + len, size - 2 - len);
    else
        as_received(c, channel, data + 2 + len, size - 2 - len);
    return 0;
}
