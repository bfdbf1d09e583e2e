/* auth: message authentication for the tandem bus (docs/method/lockstep.md §4-5).
 *
 * Keys. A cell (one simulator and its daemons) has a key set made by
 * tandem-keygen from a 32-byte master secret. Every process is one
 * principal (role and instances: the simulator, arm 1, arm 2, the
 * supervisor, a rover or rover host, a tool, the monitors) and holds only
 * the pairwise keys it takes part in:
 *
 *   cell id   = BLAKE2b-128(key = master, "tandem-cell-id")
 *   K(S -> R) = BLAKE2b-256(key = master, "tandem-pair-v2" | cell id | S | R)
 *
 * S and R as 5 bytes (role, first, last instance, big-endian). K(S -> R)
 * differs from K(R -> S) and from every other pair, so a holder of one
 * principal's file can make tags only as that principal; the monitors
 * (tandem-status, the viewer, recorders) hold receive keys only. A
 * process given the master itself (a 32-byte file: the tests, the bench,
 * and bus.key files of earlier versions) derives every pair.
 *
 * Wire. Every message carries a trailer after its LCM encoding: n tags,
 * then the fixed part, so a receiver finds it from the end:
 *
 *   tags      n x 21  receiver (5 bytes: role, first, last) | tag (16)
 *   fixed part, AUTH_FIXED_BYTES:
 *    0      2    magic "TA"
 *    2      1    version (AUTH_VERSION)
 *    3      1    key id (auth_key_id of the master: which key set)
 *    4      1    sender role (AUTH_ROLE_*)
 *    5      1    flags (0; anything else is not this version)
 *    6      2    sender's first instance (arm / robot number, 0 if none)
 *    8      2    sender's last instance (a rover host runs several robots)
 *   10      4    sender session (random per process start)
 *   14      8    counter: microseconds since the Unix epoch, strictly
 *                increasing per sender process
 *   22     16    cell id
 *   38      1    n, the number of tags (at most AUTH_MAX_TAGS)
 *   39      1    0
 *
 * all integers big-endian. The digest
 *   D = BLAKE2b-256("tandem-auth-v2" | channel length (1 byte) | channel |
 *                   LCM encoding | the receivers of the n tags | fixed part)
 * is computed once per message; the tag for receiver R is
 * BLAKE2b-128(key = K(S -> R), D). So a message cannot be altered, moved
 * to another channel or cell, or given another sender, counter or list of
 * receivers; a receiver checks only its own tag. lcm-gen's decoders (C,
 * Java, Python) read only the fields they know and ignore the trailer, so
 * lcm-spy, the viewer and lcm-logger files still decode.
 *
 * Replay: a receiver keeps the last counter per (sender, session,
 * channel) and takes a message only with a larger counter, within
 * AUTH_WINDOW_US of its own clock, and not signed before the receiver
 * itself started (less AUTH_START_SLACK_US for clocks of other hosts): a
 * message captured and sent again later, or to a restarted receiver, is
 * refused, while a restarted sender, whose counter is its clock, is taken
 * at once.
 *
 * Key material lives in sodium_malloc'd memory (locked, guard pages, not
 * in core dumps); key files are opened without following a symlink and
 * must belong to the user and be readable by nobody else.
 *
 * This module is the daemon layer's: it needs libsodium, which the core
 * (src/core/, built for the 68040) never sees. auth_bus.h is the process-wide
 * glue (options, key files, publishing, the receive check).
 */
#ifndef TANDEM_AUTH_H
#define TANDEM_AUTH_H

#include <stddef.h>
#include <stdint.h>
#include <sodium.h>

#define AUTH_VERSION 2
#define AUTH_KEY_BYTES 32
#define AUTH_MAC_BYTES 16
#define AUTH_CELL_BYTES 16
#define AUTH_PEER_BYTES 5 /* role, first, last */
#define AUTH_TAG_ENTRY_BYTES (AUTH_PEER_BYTES + AUTH_MAC_BYTES)
#define AUTH_FIXED_BYTES 40
#define AUTH_HEAD_BYTES AUTH_FIXED_BYTES
#define AUTH_MAX_TAGS 48 /* receivers of one message */
#define AUTH_TRAILER_MIN AUTH_FIXED_BYTES
#define AUTH_TRAILER_MAX (AUTH_FIXED_BYTES + AUTH_MAX_TAGS * AUTH_TAG_ENTRY_BYTES)
#define AUTH_CHANNEL_MAX 63 /* LCM's channel name limit */
#define AUTH_MAX_KEYS 2     /* the current key set and, while rotating, the previous one */
#define AUTH_MAX_PAIRS (2 * AUTH_MAX_TAGS) /* pairwise keys in one key file */
#define AUTH_ROSTER_ROVERS 8 /* rovers a master holder tags for (role files list their own) */
#define AUTH_ROSTER_FIXED 7  /* principals of a roster besides the single rovers (host included) */
#define AUTH_WINDOW_US 60000000LL /* a counter this far from the local clock is refused */
#define AUTH_START_SLACK_US \
    2000000LL                  /* how much older than the receiver a message may be:
                                           the clock difference allowed between hosts */
#define AUTH_REPLAY_SLOTS 1024 /* (sender, channel) streams remembered */
#define AUTH_REPLAY_WAYS 8     /* a stream lives in one set of this many slots */

/* Named results (0 = accepted); distinct values. */
enum {
    AUTH_OK = 0,
    AUTH_ERR_UNSIGNED = -1, /* no trailer, or not this format/version */
    AUTH_ERR_MAC = -2,      /* no tag for this receiver, or it does not verify */
    AUTH_ERR_SENDER = -3,   /* sender of no known role, or no key with it (revoked) */
    AUTH_ERR_REPLAY = -4,   /* counter not above the last, or outside the window */
    AUTH_ERR_ACL = -5,      /* sender not allowed to publish on the channel */
    AUTH_ERR_ARG = -6,      /* bad argument (buffer too small, channel too long) */
    AUTH_ERR_KEY = -7,      /* key file missing, unreadable, wrong size, mode or owner */
    AUTH_ERR_INIT = -8,     /* auth_init: libsodium does not start */
    AUTH_ERR_CELL = -9,     /* the message belongs to another cell (key set) */
    AUTH_ERR_TYPE = -10,    /* before any MAC: not a tandem type, or over its size */
    AUTH_ERR_CHANNEL = -11  /* before any MAC: a channel the table does not name */
};
/* A name for an AUTH_* result. */
const char *auth_strerror(int rc);

/* Who publishes: the roles of auth_acl.c's table. */
enum {
    AUTH_ROLE_SIM = 1,        /* tandem-sim */
    AUTH_ROLE_ARM = 2,        /* tandem-arm, instance = arm */
    AUTH_ROLE_SUPERVISOR = 3, /* tandem-supervisor */
    AUTH_ROLE_ROVER = 4,      /* tandem-rover, instances = the robots it hosts */
    AUTH_ROLE_TOOL = 5,       /* tandem-scenario, tandem-stick, tests holding the key */
    AUTH_ROLE_MONITOR = 6,    /* tandem-status, viewer, recorders: receive keys only */
    AUTH_ROLE_LAST = AUTH_ROLE_MONITOR
};
#define AUTH_ROLE_BIT(r) (1u << (r))
/* A principal's name as key files and reports spell it: sim, arm1,
 * supervisor, tool, monitor, rover3, and rover1-3 for a host of three. */
void auth_principal_name(int role, int first, int last, char *out, size_t cap);
#define AUTH_ROLES_ALL                                                      \
    (AUTH_ROLE_BIT(AUTH_ROLE_SIM) | AUTH_ROLE_BIT(AUTH_ROLE_ARM) |          \
     AUTH_ROLE_BIT(AUTH_ROLE_SUPERVISOR) | AUTH_ROLE_BIT(AUTH_ROLE_ROVER) | \
     AUTH_ROLE_BIT(AUTH_ROLE_TOOL) | AUTH_ROLE_BIT(AUTH_ROLE_MONITOR))

/* A principal: role and the instances it covers. */
typedef struct auth_peer {
    uint8_t role;
    uint16_t first, last;
} auth_peer;

/* The rover principals of a cell: rovers 1..rovers, hosted by `hosts`
 * processes (tandem-rover --id A-B; 1: the host of them all), each a run
 * of whole units of `unit` robots (a team), as even as the units allow
 * (auth_fleet_host). A role file made for this roster is one the cell's
 * other role files also list, so every host can talk to every process. */
typedef struct auth_fleet {
    int rovers, hosts, unit;
} auth_fleet;
#define AUTH_FLEET_HOSTS_MAX 32 /* hosts of one roster (each a principal, tagged) */

typedef struct auth_sender {
    uint8_t role;
    uint16_t first, last; /* instances covered, first <= last */
    uint32_t session;
} auth_sender;

/* One pairwise key of a key file. */
enum { AUTH_DIR_SEND = 'S', AUTH_DIR_RECV = 'R' };
typedef struct auth_pair {
    auth_peer peer;
    uint8_t dir; /* AUTH_DIR_SEND: holder -> peer; RECV: peer -> holder */
    uint8_t key[AUTH_KEY_BYTES];
    /* BLAKE2b-128 already keyed with key: a tag then costs one compression,
     * not two (the key block is done once, at load) */
    crypto_generichash_state keyed;
} auth_pair;

/* What one key file gives a process (always in sodium_malloc'd memory). */
typedef struct auth_keyset {
    uint8_t id; /* auth_key_id of the master */
    uint8_t cell[AUTH_CELL_BYTES];
    auth_peer holder;
    int is_master; /* 1: master below, every pair derivable */
    uint8_t master[AUTH_KEY_BYTES];
    auth_fleet fleet; /* a master holder's roster: rovers 1..fleet.rovers */
    int n;
    auth_pair pair[AUTH_MAX_PAIRS];
} auth_keyset;

typedef struct auth_keyring {
    auth_keyset *set[AUTH_MAX_KEYS]; /* set[0] signs; every set verifies */
    int n;
} auth_keyring;

typedef struct auth_trailer {
    uint8_t key_id;
    auth_sender sender;
    uint64_t counter;
    uint8_t cell[AUTH_CELL_BYTES];
    int n_tags;
    size_t len; /* bytes of the whole trailer */
} auth_trailer;

/* 0 once libsodium is ready (idempotent), AUTH_ERR_INIT if it cannot start. */
int auth_init(void);
/* The key set's id byte: the first byte of BLAKE2b("tandem-key-id") keyed with the master. */
uint8_t auth_key_id(const uint8_t master[AUTH_KEY_BYTES]);
void auth_cell_id(const uint8_t master[AUTH_KEY_BYTES], uint8_t cell[AUTH_CELL_BYTES]);
void auth_pair_key(const uint8_t master[AUTH_KEY_BYTES], const uint8_t cell[AUTH_CELL_BYTES],
                   const auth_peer *from, const auth_peer *to, uint8_t key[AUTH_KEY_BYTES]);
int auth_peer_equal(const auth_peer *a, const auth_peer *b);

/* A key set in locked memory: auth_keyset_free releases (and wipes) it. */
auth_keyset *auth_keyset_new(void);
void auth_keyset_free(auth_keyset *k);
/* A master holder's set (holder = who it is, rovers = its roster). */
void auth_keyset_master(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES],
                        const auth_peer *holder, int rovers);
/* The roster of a cell with `rovers` robots: sim, arms 1-2, supervisor,
 * tool, monitor, for two or more the host of them all (rover 1-rovers),
 * then single rovers 1, 2, ... as far as cap allows; returns how many
 * (<= cap). */
int auth_roster(int rovers, auth_peer *out, int cap);
/* The same with the fleet's hosts: each host's range (rovers 1..N if one)
 * in place of the host of them all. */
int auth_roster_fleet(const auth_fleet *f, auth_peer *out, int cap);
/* Host h's robots (0 <= h < hosts): *first..*last; 0, or -1 when there is
 * no such host (h out of range, fewer units than hosts, no robots). */
int auth_fleet_host(const auth_fleet *f, int h, int *first, int *last);
/* f with its fields brought into range: rovers 0..AUTH_ACL_NUMBER_MAX,
 * hosts 1..AUTH_FLEET_HOSTS_MAX and no more than the units, unit >= 1. */
auth_fleet auth_fleet_clamped(int rovers, int hosts, int unit);
/* The role file of `holder` in the cell of master with the given roster:
 * a send key to every other principal but the monitor (monitors only
 * receive), a receive key from every other one. */
void auth_keyset_role(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES], const auth_peer *holder,
                      const auth_peer *roster, int n);
/* Reads a key file: a 32-byte master, or a role file (auth_keyset_write).
 * Opened with O_NOFOLLOW; a regular file of this user that nobody else
 * may read or write (mode 0600 or stricter). On failure AUTH_ERR_KEY with
 * the reason in why. holder: who a master holder is. */
int auth_keyset_load(auth_keyset *k, const char *path, const auth_peer *holder, char *why,
                     size_t why_cap);
/* Writes k as a role file, mode 0600, never over an existing file. */
int auth_keyset_write(const auth_keyset *k, const char *path, char *why, size_t why_cap);
/* Creates a new master file (32 random bytes), mode 0600, never over an
 * existing file (O_EXCL); its directory is created 0700 if missing.
 * AUTH_ERR_KEY with the reason in why on failure. */
int auth_key_create(const char *path, char *why, size_t why_cap);
/* Reads exactly 32 bytes of a master file (checks as auth_keyset_load). */
int auth_master_load(uint8_t master[AUTH_KEY_BYTES], const char *path, char *why, size_t why_cap);

/* Appends the trailer to buf[0, body_len) (cap bytes available) with one
 * tag for each receiver of the set whose role bit is in readers and which
 * `wants` (NULL: all) accepts; AUTH_OK or AUTH_ERR_ARG. *out_len: the
 * signed message's length. */
typedef int (*auth_wants_fn)(const auth_peer *receiver, const char *channel);
int auth_sign(const auth_keyset *k, const auth_sender *s, uint64_t counter, const char *channel,
              unsigned readers, auth_wants_fn wants, uint8_t *buf, size_t body_len, size_t cap,
              size_t *out_len);
/* The receivers auth_sign would tag (at most AUTH_MAX_TAGS into out): a
 * sender that publishes often on a channel keeps them (auth_bus does). */
int auth_receivers(const auth_keyset *k, const char *channel, unsigned readers, auth_wants_fn wants,
                   auth_peer out[AUTH_MAX_TAGS]);
/* auth_sign with the receivers given: a tag for each of to[0, n). */
int auth_sign_to(const auth_keyset *k, const auth_sender *s, uint64_t counter, const char *channel,
                 const auth_peer *to, int n, uint8_t *buf, size_t body_len, size_t cap,
                 size_t *out_len);
/* Reads the trailer at the end of buf[0, len): AUTH_OK or AUTH_ERR_UNSIGNED. */
int auth_parse(const uint8_t *buf, size_t len, auth_trailer *t);
/* auth_parse, then the tag for receiver me with the ring's key of the
 * message's cell: AUTH_OK, AUTH_ERR_UNSIGNED, AUTH_ERR_CELL, AUTH_ERR_SENDER
 * (no key with that sender) or AUTH_ERR_MAC. On AUTH_OK the body is
 * buf[0, len - t->len). */
int auth_verify(const auth_keyring *ring, const auth_peer *me, const char *channel,
                const uint8_t *buf, size_t len, auth_trailer *t);
/* AUTH_OK if the sender id names a known role and a valid instance range. */
int auth_sender_check(const auth_sender *s);

/* The last counter of every (sender, session, channel) stream seen. */
typedef struct auth_stream {
    auth_sender sender;
    uint64_t channel_hash;
    uint64_t last_counter;
    uint64_t last_seen_us; /* for eviction: the stream quiet longest goes */
    int used;
} auth_stream;

typedef struct auth_replay {
    auth_stream slot[AUTH_REPLAY_SLOTS];
    int64_t window_us;
    uint64_t oldest_us; /* the receiver's start less AUTH_START_SLACK_US */
} auth_replay;

/* A receiver started at start_us (its wall clock, microseconds). */
void auth_replay_init(auth_replay *r, int64_t window_us, uint64_t start_us);
uint64_t auth_channel_hash(const char *channel);
/* Accepts (AUTH_OK, and remembers the counter) a counter within window of
 * now_us, not older than the receiver, and larger than the last one of its
 * stream; AUTH_ERR_REPLAY otherwise (the table is left as it was). */
int auth_replay_check(auth_replay *r, const auth_sender *s, uint64_t channel_hash, uint64_t counter,
                      uint64_t now_us);
/* The next counter of a sender: now_us, or one more than the last if the
 * clock has not moved on (or went back). */
uint64_t auth_next_counter(uint64_t *last, uint64_t now_us);

#endif
