/* auth: message authentication for the tandem bus (docs/method/lockstep.md §4-5).
 *
 * Every message carries a fixed-size trailer after its LCM encoding:
 *
 *   offset size  field
 *    0      2    magic "TA"
 *    2      1    version (AUTH_VERSION)
 *    3      1    key id (auth_key_id: which deployment key signed it)
 *    4      1    sender role (AUTH_ROLE_*)
 *    5      1    flags (0; anything else is not this version)
 *    6      2    sender's first instance (arm / robot number, 0 if none)
 *    8      2    sender's last instance (a rover host runs several robots)
 *   10      4    sender session (random per process start)
 *   14      8    counter: microseconds since the Unix epoch, strictly
 *                increasing per sender process
 *   22     16    MAC
 *
 * all integers big-endian. The MAC is keyed BLAKE2b with a 16-byte output
 * (libsodium's crypto_generichash) over
 *   "tandem-auth-v1" | channel length (1 byte) | channel | LCM encoding |
 *   trailer bytes 0-21
 * so a message cannot be altered, moved to another channel, or given
 * another sender or counter. lcm-gen's decoders (C, Java, Python) read
 * only the fields they know and ignore the trailer, so lcm-spy, the
 * viewer and lcm-logger files still decode.
 *
 * Replay: a receiver keeps the last counter per (sender, session,
 * channel) and takes a message only with a larger counter, within
 * AUTH_WINDOW_US of its own clock, and not signed before the receiver
 * itself started (less AUTH_START_SLACK_US for clocks of other hosts): a
 * message captured and sent again later, or to a restarted receiver, is
 * refused, while a restarted sender, whose counter is its clock, is taken
 * at once.
 *
 * This module is the daemon layer's: it needs libsodium, which the core
 * (src/core/, built for the 68040) never sees. auth_bus.h is the process-wide
 * glue (options, key files, publishing, the receive check).
 */
#ifndef TANDEM_AUTH_H
#define TANDEM_AUTH_H

#include <stddef.h>
#include <stdint.h>

#define AUTH_VERSION        1
#define AUTH_KEY_BYTES      32
#define AUTH_MAC_BYTES      16
#define AUTH_HEAD_BYTES     22          /* trailer bytes covered by the MAC */
#define AUTH_TRAILER_BYTES  (AUTH_HEAD_BYTES + AUTH_MAC_BYTES)
#define AUTH_CHANNEL_MAX    63          /* LCM's channel name limit */
#define AUTH_MAX_KEYS       2           /* the current key and, while rotating, the previous one */
#define AUTH_WINDOW_US      60000000LL  /* a counter this far from the local clock is refused */
#define AUTH_START_SLACK_US 2000000LL   /* how much older than the receiver a message may be:
                                           the clock difference allowed between hosts */
#define AUTH_REPLAY_SLOTS   1024        /* (sender, channel) streams remembered */
#define AUTH_REPLAY_WAYS    8           /* a stream lives in one set of this many slots */

/* Named results (0 = accepted). */
enum {
    AUTH_OK = 0,
    AUTH_ERR_UNSIGNED = -1,     /* no trailer, or not this format/version */
    AUTH_ERR_MAC = -2,          /* unknown key id, or the MAC does not verify */
    AUTH_ERR_SENDER = -3,       /* MAC fine, sender id of no known role */
    AUTH_ERR_REPLAY = -4,       /* counter not above the last, or outside the window */
    AUTH_ERR_ACL = -5,          /* sender not allowed to publish on the channel */
    AUTH_ERR_ARG = -6,          /* bad argument (buffer too small, channel too long) */
    AUTH_ERR_KEY = -7           /* key file missing, unreadable, wrong size or mode */
};
#define AUTH_ERR_INIT (-1)      /* auth_init: libsodium does not start */

/* Who publishes: the roles of auth_acl.c's table. */
enum {
    AUTH_ROLE_SIM = 1,          /* tandem-sim */
    AUTH_ROLE_ARM = 2,          /* tandem-arm, instance = arm */
    AUTH_ROLE_SUPERVISOR = 3,   /* tandem-supervisor */
    AUTH_ROLE_ROVER = 4,        /* tandem-rover, instances = the robots it hosts */
    AUTH_ROLE_TOOL = 5,         /* tandem-scenario, tandem-stick, tests holding the key */
    AUTH_ROLE_LAST = AUTH_ROLE_TOOL
};
#define AUTH_ROLE_BIT(r) (1u << (r))
#define AUTH_ROLES_ALL   (AUTH_ROLE_BIT(AUTH_ROLE_SIM) | AUTH_ROLE_BIT(AUTH_ROLE_ARM) | \
                          AUTH_ROLE_BIT(AUTH_ROLE_SUPERVISOR) | AUTH_ROLE_BIT(AUTH_ROLE_ROVER) | \
                          AUTH_ROLE_BIT(AUTH_ROLE_TOOL))

typedef struct auth_sender {
    uint8_t  role;
    uint16_t first, last;       /* instances covered, first <= last */
    uint32_t session;
} auth_sender;

typedef struct auth_key {
    uint8_t bytes[AUTH_KEY_BYTES];
    uint8_t id;                 /* auth_key_id(bytes) */
} auth_key;

typedef struct auth_keyring {
    auth_key key[AUTH_MAX_KEYS];   /* key[0] signs; every key verifies */
    int      n;
} auth_keyring;

typedef struct auth_trailer {
    uint8_t     key_id;
    auth_sender sender;
    uint64_t    counter;
    uint8_t     mac[AUTH_MAC_BYTES];
} auth_trailer;

/* 0 once libsodium is ready (idempotent), AUTH_ERR_INIT if it cannot start. */
int  auth_init(void);
/* Fills k from AUTH_KEY_BYTES bytes (and its id). */
void auth_key_set(auth_key *k, const uint8_t bytes[AUTH_KEY_BYTES]);
/* The key's id byte: the first byte of BLAKE2b("tandem-key-id") keyed with it. */
uint8_t auth_key_id(const uint8_t bytes[AUTH_KEY_BYTES]);
/* Reads a key file: exactly AUTH_KEY_BYTES bytes, a regular file nobody
 * but its owner may read or write (mode 0600 or stricter). On failure
 * returns AUTH_ERR_KEY with the reason in why. */
int  auth_key_load(auth_key *k, const char *path, char *why, size_t why_cap);
/* Creates a new key file from libsodium's random bytes, mode 0600, never
 * over an existing file (O_EXCL); its directory is created 0700 if
 * missing. AUTH_ERR_KEY with the reason in why on failure. */
int  auth_key_create(const char *path, char *why, size_t why_cap);

/* The 16-byte MAC of a message body on a channel with trailer head `head`. */
int  auth_mac(const auth_key *k, const char *channel, const uint8_t *body, size_t body_len,
              const uint8_t head[AUTH_HEAD_BYTES], uint8_t mac[AUTH_MAC_BYTES]);
/* Appends the trailer to buf[0, body_len) (cap bytes available); AUTH_OK
 * or AUTH_ERR_ARG. The signed message is body_len + AUTH_TRAILER_BYTES long. */
int  auth_sign(const auth_key *k, const auth_sender *s, uint64_t counter, const char *channel,
               uint8_t *buf, size_t body_len, size_t cap);
/* Reads the trailer at the end of buf[0, len): AUTH_OK or AUTH_ERR_UNSIGNED. */
int  auth_parse(const uint8_t *buf, size_t len, auth_trailer *t);
/* auth_parse, then the MAC with the ring's key of that id: AUTH_OK,
 * AUTH_ERR_UNSIGNED or AUTH_ERR_MAC. On AUTH_OK the body is
 * buf[0, len - AUTH_TRAILER_BYTES). */
int  auth_verify(const auth_keyring *ring, const char *channel, const uint8_t *buf, size_t len,
                 auth_trailer *t);
/* AUTH_OK if the sender id names a known role and a valid instance range. */
int  auth_sender_check(const auth_sender *s);

/* The last counter of every (sender, session, channel) stream seen. */
typedef struct auth_stream {
    auth_sender sender;
    uint64_t    channel_hash;
    uint64_t    last_counter;
    uint64_t    last_seen_us;   /* for eviction: the stream quiet longest goes */
    int         used;
} auth_stream;

typedef struct auth_replay {
    auth_stream slot[AUTH_REPLAY_SLOTS];
    int64_t     window_us;
    uint64_t    oldest_us;     /* the receiver's start less AUTH_START_SLACK_US */
} auth_replay;

/* A receiver started at start_us (its wall clock, microseconds). */
void     auth_replay_init(auth_replay *r, int64_t window_us, uint64_t start_us);
uint64_t auth_channel_hash(const char *channel);
/* Accepts (AUTH_OK, and remembers the counter) a counter within window of
 * now_us, not older than the receiver, and larger than the last one of its
 * stream; AUTH_ERR_REPLAY otherwise (the table is left as it was). */
int      auth_replay_check(auth_replay *r, const auth_sender *s, uint64_t channel_hash,
                           uint64_t counter, uint64_t now_us);
/* The next counter of a sender: now_us, or one more than the last if the
 * clock has not moved on (or went back). */
uint64_t auth_next_counter(uint64_t *last, uint64_t now_us);

#endif
