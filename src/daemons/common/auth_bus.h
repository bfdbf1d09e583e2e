/* auth_bus: the process side of the secure bus (docs/method/lockstep.md §4-5; auth.h has the
 * wire format). A bus is one sender: it signs everything it publishes
 * with the deployment key and checks everything it receives before any
 * handler sees it. Its state is an auth_bus the program holds (a daemon:
 * daemon.bus; a tool: a variable of main) and passes to every function
 * here; nothing of it is global.
 *
 *   Key: --key-file PATH, else $TANDEM_KEY_FILE, else the default key
 *   file (auth_bus_default_key_path: ${XDG_CONFIG_HOME:-$HOME/.config}/
 *   tandem/bus.key, made by tandem-keygen) if it exists; otherwise the
 *   program refuses to start and names both options. The file is this
 *   process's role file (tandem-keygen --cell), or a cell master, which
 *   can sign as anyone (auth.h).
 *   $TANDEM_INSECURE=1 stands for --insecure (how tandem-scenario passes
 *   it to its children).
 *   --key-file may be given twice while rotating keys: the first signs,
 *   both verify. --insecure signs and checks nothing (and says so on
 *   stderr and in every health message).
 *
 *   Publish: AUTH_PUBLISH(type, bus, lcm, channel, &msg) instead of
 *   type_publish(lcm, channel, &msg): encodes, appends the trailer,
 *   lcm_publish.
 *
 *   Receive: auth_bus_accept (rx.c calls it for every daemon
 *   subscription; tools use auth_bus_subscribe) first checks, before any
 *   MAC, the size, the channel (in the table) and the type (its
 *   fingerprint, and at most the type's longest encoding plus a trailer);
 *   then the cell, this receiver's tag, sender, channel authorisation and
 *   counter; counts a refusal by kind, and hands on the message without
 *   its trailer.
 */
#ifndef TANDEM_AUTH_BUS_H
#define TANDEM_AUTH_BUS_H

#include <stddef.h>
#include <stdint.h>
#include <lcm/lcm.h>
#include "auth.h"

#define AUTH_BUS_KEY_ENV "TANDEM_KEY_FILE"
#define AUTH_BUS_INSECURE_ENV "TANDEM_INSECURE" /* "1": as --insecure (for child processes) */

/* Failures (0 = ok), distinct values; the ones marked (said) have printed
 * why on stderr. auth_bus_strerror names them. */
#define AUTH_BUS_OK 0
#define AUTH_BUS_ERR_OPTION (-101) /* --key-file empty, or a third one (said) */
#define AUTH_BUS_ERR_NO_HOME \
    (-102) /* no $XDG_CONFIG_HOME or $HOME, or the path does
                                          not fit the buffer */
#define AUTH_BUS_ERR_START \
    (-103) /* auth_bus_start: channel table unsound, --insecure
                                          with --key-file, libsodium, no identity (said) */
#define AUTH_BUS_ERR_KEY \
    (-104)                              /* no key file, one that does not load (said), or
                                          no temporary key made (auth_bus_ephemeral_key) */
#define AUTH_BUS_ERR_ARG (-105)         /* body_len < 0 (a failed encode), no buffer */
#define AUTH_BUS_ERR_MEMORY (-106)      /* the transmit buffer cannot grow */
#define AUTH_BUS_ERR_NOT_STARTED (-107) /* publishing before auth_bus_start (said) */
#define AUTH_BUS_ERR_SIGN (-108)        /* auth_sign refused the message */
#define AUTH_BUS_ERR_SEND (-109)        /* lcm_publish did not send it */
const char *auth_bus_strerror(int rc);

/* Receive bounds (docs/method/lockstep.md §5): a subscription queues at
 * most this many messages (LCM drops the rest of a flood; a real sender's
 * messages are few per cycle), and a datagram longer than this is never
 * a tandem message. */
#define AUTH_BUS_QUEUE_CAPACITY 256
#define AUTH_BUS_MAX_DATAGRAM 65536

/* Options every program that talks on the bus takes. */
enum { OPT_KEY_FILE = 1200, OPT_INSECURE };
/* (the options table, src/daemons/common/options.c, maps --key-file and
 * --insecure onto auth_bus_option) */

/* Refusals counted by kind (HEALTH_* auth_* fields). */
typedef struct auth_bus_counts {
    int64_t accepted;
    int64_t unsigned_msgs;  /* AUTH_ERR_UNSIGNED */
    int64_t bad_mac;        /* AUTH_ERR_MAC */
    int64_t unknown_sender; /* AUTH_ERR_SENDER */
    int64_t replayed;       /* AUTH_ERR_REPLAY */
    int64_t unauthorised;   /* AUTH_ERR_ACL */
    int64_t other_cell;     /* AUTH_ERR_CELL */
    int64_t precheck;       /* AUTH_ERR_TYPE / AUTH_ERR_CHANNEL: refused before any MAC */
    /* AUTH_ERR_REPLAY of a copy a renewal made (auth_bus_move): refused
     * like a replay, counted apart and in no refusal total, since it is
     * no attack. Between the new handle's subscription and the old one's
     * close both sockets receive, so what arrived then comes twice. Taken
     * for such a copy: within AUTH_BUS_RENEW_OVERLAP_US after the renewal,
     * signed no earlier than that before it. */
    int64_t renewal_copies;
} auth_bus_counts;

#define AUTH_BUS_RENEW_OVERLAP_US 2000000LL /* generous: sanitizers on a loaded host */

#define AUTH_BUS_MAX_SUBS 64

typedef struct auth_bus auth_bus;
/* A checked subscription: what it is (handler, user, channel, queue
 * capacity) and where it is (lcm, sub), so that a renewed handle takes it
 * over (auth_bus_move). used = 0: a free slot. */
typedef struct bus_sub {
    auth_bus *bus;
    lcm_msg_handler_t handler;
    void *user;
    char channel[AUTH_CHANNEL_MAX + 1];
    int capacity;
    lcm_t *lcm;
    lcm_subscription_t *sub;
    int used;
} bus_sub;

/* The last verdict, so a message several subscriptions of this process
 * match is checked (and counted) once: a second check would see its own
 * counter again and call it a replay. A delivery is the same when LCM
 * hands over the same buffer with the same receive time, size, channel
 * and MAC; a copy sent again by someone else arrives in a buffer of its
 * own, received later. */
typedef struct last_verdict {
    const void *data;
    int64_t recv_utime;
    uint32_t size;
    uint64_t channel_hash;
    uint8_t mac[AUTH_MAC_BYTES]; /* delivery_mark */
    size_t trailer;              /* its trailer's length when accepted */
    auth_sender sender;          /* who signed it (when accepted) */
    int rc;
    int valid;
} last_verdict;

/* Who a channel's messages are signed as and tagged for: worked out from
 * the channel table once per channel, not per message (a 1 kHz loop
 * publishes the same few channels all the time). */
#define AUTH_BUS_ROUTES 64
typedef struct tx_route {
    uint64_t channel_hash;
    char channel[AUTH_CHANNEL_MAX + 1];
    auth_sender sender;
    int n;
    auth_peer to[AUTH_MAX_TAGS];
} tx_route;

/* One bus: who it is, its keys, the replay window, what it has
 * counted, its publish buffer and routes. The program holds it (a daemon
 * in its `daemon`, a tool in main) and passes it to every function below;
 * its fields are auth_bus.c's alone. All zero (auth_bus_init) before the
 * options; it stays where it is while subscriptions made on it last (LCM
 * holds a pointer into it). */
struct auth_bus {
    const char *key_file[AUTH_MAX_KEYS];
    int n_key_files;
    int insecure;
    int have_identity, as_owner;
    auth_fleet fleet; /* the roster's rovers and hosts; rovers 0: AUTH_ROSTER_ROVERS */
    auth_sender me;
    auth_peer me_peer;
    auth_keyring ring;
    int started, secure;
    uint64_t last_counter;
    uint64_t renewed_us; /* wall clock of the last auth_bus_move, 0: none */
    auth_replay replay;
    auth_bus_counts counts;
    /* the last message refused as not allowed on its channel: a key
     * holder speaking out of turn is a fault or a bug, so its exit
     * report names it (auth_bus_report_unauthorised) */
    char unauthorised_channel[AUTH_CHANNEL_MAX + 1];
    auth_sender unauthorised_sender;
    last_verdict last;
    uint8_t *tx;
    int tx_cap;
    bus_sub subs[AUTH_BUS_MAX_SUBS];
    int n_subs;
    char prog[64];
    tx_route routes[AUTH_BUS_ROUTES];
    int n_routes; /* 0 after anything a route depends on changed */
};

/* All zero: no key, no identity, not started. */
void auth_bus_init(auth_bus *bus);

/* Handles OPT_KEY_FILE / OPT_INSECURE: 1 handled, 0 not ours,
 * AUTH_BUS_ERR_OPTION. */
int auth_bus_option(auth_bus *bus, const char *prog, int opt, const char *arg);
/* Who this process is (before auth_bus_start): the principal whose key
 * file it holds (a master holder may be anyone). */
void auth_bus_identity(auth_bus *bus, int role, int first, int last);
/* The cell's roster as a holder of the master sees it: rovers 1..rovers
 * and the host of them all (auth_roster); AUTH_ROSTER_ROVERS unless set.
 * A master holder tags for these, and the role files it makes for its
 * children (auth_child.h) list them; set it before the first child starts. */
void auth_bus_roster(auth_bus *bus, int rovers);
/* The same with the rovers hosted by f->hosts processes, each a run of
 * whole teams of f->unit robots (auth_fleet_host): the ranges a launcher
 * gives its tandem-rover --id A-B hosts. */
void auth_bus_roster_fleet(auth_bus *bus, const auth_fleet *f);
/* In a handler: 1 when the message being handled may speak for instance
 * k (a rover id in a batch or a team message), that is when its signer's
 * instances cover k, or when the bus is not secure. 0: a rover host
 * speaking for another host's robot (a holder of the master signing as a
 * channel's owner speaks as rover 1: sender_for). */
int auth_bus_sender_covers(const auth_bus *bus, long k);
/* The roster (auth_bus_roster_fleet; the default's rovers filled in). */
auth_fleet auth_bus_fleet(const auth_bus *bus);
/* A process standing in for several publishers (integration tests, the
 * round-trip bench) signs each message as its channel's owner
 * (auth_acl_owner) -- what only a holder of the cell's master can do
 * (a role file holds no other principal's keys). 0: as its own identity
 * again. */
void auth_bus_sign_as_owner(auth_bus *bus, int on);
/* Loads the key(s) the options and environment name and prints the
 * --insecure warning; 0, or AUTH_BUS_ERR_START / _KEY after printing why
 * (then exit 1). */
int auth_bus_start(auth_bus *bus, const char *prog);
/* 1 when messages are signed and checked, 0 with --insecure. */
int auth_bus_secure(const auth_bus *bus);
/* After auth_bus_start: the key journals authenticate their records with
 * (journal.h), derived from the signing key (keyed BLAKE2b of a "tandem
 * journal" context): 1, or 0 with --insecure (out untouched). */
int auth_bus_journal_key(const auth_bus *bus, uint8_t out[32]);
/* ${XDG_CONFIG_HOME:-$HOME/.config}/tandem/bus.key; AUTH_BUS_ERR_NO_HOME. */
int auth_bus_default_key_path(char *out, size_t cap);
/* Creates a key for this run alone in a fresh 0700 temporary directory
 * (both removed at exit) and exports it as $TANDEM_KEY_FILE, so child
 * processes use it too (tandem-scenario, the integration tests); a bus
 * then loads it at auth_bus_start. The process's, not a bus's.
 * 0, or AUTH_BUS_ERR_KEY. */
int auth_bus_ephemeral_key(char *path, size_t cap);

/* The transmit buffer AUTH_PUBLISH encodes into; reserve: 0, or
 * AUTH_BUS_ERR_ARG / AUTH_BUS_ERR_MEMORY. */
int auth_bus_tx_reserve(auth_bus *bus, int body_len);
uint8_t *auth_bus_tx(const auth_bus *bus);
int auth_bus_tx_cap(const auth_bus *bus);
/* Signs the body_len bytes in auth_bus_tx() for channel and publishes
 * them: what lcm_publish returns (0 sent, -1 not), or AUTH_BUS_ERR_ARG
 * (body_len < 0: a failed encode), AUTH_BUS_ERR_NOT_STARTED or
 * AUTH_BUS_ERR_SIGN. */
int auth_bus_publish_tx(auth_bus *bus, lcm_t *lcm, const char *channel, int body_len);
/* Copies buf into the transmit buffer, signs, publishes (raw bytes, e.g.
 * the malformed messages of the fault tests). */
int auth_bus_publish_raw(auth_bus *bus, lcm_t *lcm, const char *channel, const void *buf, int len);
/* AUTH_PUBLISH(type, bus, lcm, channel, &msg): msg encoded into bus's
 * transmit buffer (AUTH_BUS_ENCODE: its length, or AUTH_BUS_ERR_ARG), signed,
 * published. bus is evaluated more than once. */
#define AUTH_BUS_ENCODE(type, bus, msg)                                    \
    (auth_bus_tx_reserve((bus), type##_encoded_size(msg)) == 0             \
         ? type##_encode(auth_bus_tx(bus), 0, auth_bus_tx_cap(bus), (msg)) \
         : AUTH_BUS_ERR_ARG)
#define AUTH_PUBLISH(type, bus, lcm, channel, msg) \
    auth_bus_publish_tx((bus), (lcm), (channel), AUTH_BUS_ENCODE(type, bus, msg))

/* The receive check: AUTH_OK with *body = rb without the trailer, or the
 * refusal (counted). With --insecure every message passes (a trailer, if
 * any, stripped). */
int auth_bus_accept(auth_bus *bus, const lcm_recv_buf_t *rb, const char *channel,
                    lcm_recv_buf_t *body);
/* lcm_subscribe through auth_bus_accept and wire_check (for tools), with
 * a queue of AUTH_BUS_QUEUE_CAPACITY messages. The bus keeps what was
 * subscribed on it (its subs), so that a renewed handle takes it over
 * (auth_bus_move, bus_names_watch in daemon.h): a tool does not keep the
 * returned lcm_subscription_t past a renewal, it ends its subscriptions
 * with auth_bus_unsubscribe_user or auth_bus_close. */
lcm_subscription_t *auth_bus_subscribe(auth_bus *bus, lcm_t *lcm, const char *channel,
                                       lcm_msg_handler_t handler, void *user);
/* The same with a queue of capacity messages (0: LCM's unbounded). */
lcm_subscription_t *auth_bus_subscribe_queue(auth_bus *bus, lcm_t *lcm, const char *channel,
                                             lcm_msg_handler_t handler, void *user, int capacity);
/* Ends every checked subscription of bus on lcm handed user; how many. */
int auth_bus_unsubscribe_user(auth_bus *bus, lcm_t *lcm, const void *user);
/* A renewed handle is being subscribed: from now on, for
 * AUTH_BUS_RENEW_OVERLAP_US, a replay refusal of a message signed about
 * now is a copy both handles received (auth_bus_counts.renewal_copies).
 * auth_bus_move calls it; a receive path with subscriptions of its own
 * (rx.c) calls it as it moves them. */
void auth_bus_renewing(auth_bus *bus);
/* Every checked subscription of bus on old made again on fresh (a renewed
 * handle); how many. */
int auth_bus_move(auth_bus *bus, lcm_t *old, lcm_t *fresh);
/* lcm_destroy, and the checked subscriptions of bus on lcm forgotten. */
void auth_bus_close(auth_bus *bus, lcm_t *lcm);
/* Gives back the bus's publish buffer (the next publish makes it again):
 * for a bus that is done, before it goes out of scope. */
void auth_bus_free(auth_bus *bus);
const auth_bus_counts *auth_bus_counts_get(const auth_bus *bus);
int64_t auth_bus_rejected_total(const auth_bus *bus);
/* Writes to out, if bus refused any message as not allowed on its
 * channel, how many and the last one's channel and signer (for a
 * daemon's exit report); "" if none. */
void auth_bus_report_unauthorised(const auth_bus *bus, char *out, size_t cap);

struct _tandem_health_t;
/* The auth_* fields of a health message. */
void auth_bus_fill_health(const auth_bus *bus, struct _tandem_health_t *h);
/* A health message's refusals by kind, in the order unsigned, bad MAC,
 * unknown sender, replayed, not allowed, other cell, refused before the MAC
 * (for readers: tandem-status, the tests); returns their sum. */
#define AUTH_BUS_KINDS 7
int64_t auth_bus_health_refusals(const struct _tandem_health_t *h, int64_t kinds[AUTH_BUS_KINDS]);

/* A raw handler that decodes `type` and calls typed(rb, ch, &msg, user):
 * for a typed handler on auth_bus_subscribe. */
#define AUTH_TYPED_HANDLER(type, name, typed)                                 \
    static void name(const lcm_recv_buf_t *rb_, const char *ch_, void *user_) \
    {                                                                         \
        type m_;                                                              \
        if (type##_decode(rb_->data, 0, (int)rb_->data_size, &m_) < 0)        \
            return;                                                           \
        typed(rb_, ch_, &m_, user_);                                          \
        type##_decode_cleanup(&m_);                                           \
    }

#endif
