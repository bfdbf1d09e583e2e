/* auth_bus: the process side of the secure bus (docs/method/lockstep.md §4-5; auth.h has the
 * wire format). One process = one sender: it signs everything it
 * publishes with the deployment key and checks everything it receives
 * before any handler sees it.
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
 *   Publish: AUTH_PUBLISH(type, lcm, channel, &msg) instead of
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
#define AUTH_BUS_INSECURE_ENV "TANDEM_INSECURE"   /* "1": as --insecure (for child processes) */

/* Failures (0 = ok), distinct values; the ones marked (said) have printed
 * why on stderr. auth_bus_strerror names them. */
#define AUTH_BUS_OK 0
#define AUTH_BUS_ERR_OPTION (-101)     /* --key-file empty, or a third one (said) */
#define AUTH_BUS_ERR_NO_HOME (-102)    /* no $XDG_CONFIG_HOME or $HOME, or the path does
                                          not fit the buffer */
#define AUTH_BUS_ERR_START (-103)      /* auth_bus_start: channel table unsound, --insecure
                                          with --key-file, libsodium, no identity (said) */
#define AUTH_BUS_ERR_KEY (-104)        /* no key file, one that does not load (said), or
                                          no temporary key made (auth_bus_ephemeral_key) */
#define AUTH_BUS_ERR_ARG (-105)        /* body_len < 0 (a failed encode), no buffer */
#define AUTH_BUS_ERR_MEMORY (-106)     /* the transmit buffer cannot grow */
#define AUTH_BUS_ERR_NOT_STARTED (-107) /* publishing before auth_bus_start (said) */
#define AUTH_BUS_ERR_SIGN (-108)       /* auth_sign refused the message */
#define AUTH_BUS_ERR_SEND (-109)       /* lcm_publish did not send it */
const char *auth_bus_strerror(int rc);

/* Receive bounds (docs/method/lockstep.md §5): a subscription queues at
 * most this many messages (LCM drops the rest of a flood; a real sender's
 * messages are few per cycle), and a datagram longer than this is never
 * a tandem message. */
#define AUTH_BUS_QUEUE_CAPACITY 256
#define AUTH_BUS_MAX_DATAGRAM   65536

/* Options every program that talks on the bus takes. */
enum { OPT_KEY_FILE = 1200, OPT_INSECURE };
/* (the options table, src/daemons/common/options.c, maps --key-file and
 * --insecure onto auth_bus_option) */

/* Refusals counted by kind (HEALTH_* auth_* fields). */
typedef struct auth_bus_counts {
    int64_t accepted;
    int64_t unsigned_msgs;     /* AUTH_ERR_UNSIGNED */
    int64_t bad_mac;           /* AUTH_ERR_MAC */
    int64_t unknown_sender;    /* AUTH_ERR_SENDER */
    int64_t replayed;          /* AUTH_ERR_REPLAY */
    int64_t unauthorised;      /* AUTH_ERR_ACL */
    int64_t other_cell;        /* AUTH_ERR_CELL */
    int64_t precheck;          /* AUTH_ERR_TYPE / AUTH_ERR_CHANNEL: refused before any MAC */
} auth_bus_counts;

/* Handles OPT_KEY_FILE / OPT_INSECURE: 1 handled, 0 not ours,
 * AUTH_BUS_ERR_OPTION. */
int  auth_bus_option(const char *prog, int opt, const char *arg);
/* Who this process is (before auth_bus_start): the principal whose key
 * file it holds (a master holder may be anyone). */
void auth_bus_identity(int role, int first, int last);
/* The cell's roster as a holder of the master sees it: rovers 1..rovers
 * and the host of them all (auth_roster); AUTH_ROSTER_ROVERS unless set.
 * A master holder tags for these, and the role files it makes for its
 * children (auth_child.h) list them; set it before the first child starts. */
void auth_bus_roster(int rovers);
int  auth_bus_roster_rovers(void);
/* A process standing in for several publishers (integration tests, the
 * round-trip bench) signs each message as its channel's owner
 * (auth_acl_owner) -- what only a holder of the cell's master can do
 * (a role file holds no other principal's keys). 0: as its own identity
 * again. */
void auth_bus_sign_as_owner(int on);
/* Loads the key(s) the options and environment name and prints the
 * --insecure warning; 0, or AUTH_BUS_ERR_START / _KEY after printing why
 * (then exit 1). */
int  auth_bus_start(const char *prog);
/* 1 when messages are signed and checked, 0 with --insecure. */
int  auth_bus_secure(void);
/* After auth_bus_start: the key journals authenticate their records with
 * (journal.h), derived from the signing key (keyed BLAKE2b of a "tandem
 * journal" context): 1, or 0 with --insecure (out untouched). */
int  auth_bus_journal_key(uint8_t out[32]);
/* ${XDG_CONFIG_HOME:-$HOME/.config}/tandem/bus.key; AUTH_BUS_ERR_NO_HOME. */
int  auth_bus_default_key_path(char *out, size_t cap);
/* Creates a key for this run alone in a fresh 0700 temporary directory
 * (both removed at exit) and exports it as $TANDEM_KEY_FILE, so child
 * processes use it too (tandem-scenario, the integration tests).
 * 0, or AUTH_BUS_ERR_KEY. */
int  auth_bus_ephemeral_key(char *path, size_t cap);

/* The transmit buffer AUTH_PUBLISH encodes into; reserve: 0, or
 * AUTH_BUS_ERR_ARG / AUTH_BUS_ERR_MEMORY. */
int      auth_bus_tx_reserve(int body_len);
uint8_t *auth_bus_tx(void);
int      auth_bus_tx_cap(void);
/* Signs the body_len bytes in auth_bus_tx() for channel and publishes
 * them: what lcm_publish returns (0 sent, -1 not), or AUTH_BUS_ERR_ARG
 * (body_len < 0: a failed encode), AUTH_BUS_ERR_NOT_STARTED or
 * AUTH_BUS_ERR_SIGN. */
int  auth_bus_publish_tx(lcm_t *lcm, const char *channel, int body_len);
/* Copies buf into the transmit buffer, signs, publishes (raw bytes, e.g.
 * the malformed messages of the fault tests). */
int  auth_bus_publish_raw(lcm_t *lcm, const char *channel, const void *buf, int len);
#define AUTH_PUBLISH(type, lcm, channel, msg) \
    auth_bus_publish_tx((lcm), (channel), \
                        auth_bus_tx_reserve(type##_encoded_size(msg)) == 0 ? \
                        type##_encode(auth_bus_tx(), 0, auth_bus_tx_cap(), (msg)) : AUTH_BUS_ERR_ARG)

/* The receive check: AUTH_OK with *body = rb without the trailer, or the
 * refusal (counted). With --insecure every message passes (a trailer, if
 * any, stripped). */
int  auth_bus_accept(const lcm_recv_buf_t *rb, const char *channel, lcm_recv_buf_t *body);
/* lcm_subscribe through auth_bus_accept and wire_check (for tools), with
 * a queue of AUTH_BUS_QUEUE_CAPACITY messages. The process keeps what
 * it subscribed to, so that a renewed handle takes it over (auth_bus_move,
 * bus_names_watch in daemon.h): a tool does not keep the returned
 * lcm_subscription_t past a renewal, it ends its subscriptions with
 * auth_bus_unsubscribe_user or auth_bus_close. */
lcm_subscription_t *auth_bus_subscribe(lcm_t *lcm, const char *channel, lcm_msg_handler_t handler, void *user);
/* The same with a queue of capacity messages (0: LCM's unbounded). */
lcm_subscription_t *auth_bus_subscribe_queue(lcm_t *lcm, const char *channel,
                                             lcm_msg_handler_t handler, void *user, int capacity);
/* Ends every checked subscription on lcm handed user; how many. */
int  auth_bus_unsubscribe_user(lcm_t *lcm, const void *user);
/* Every checked subscription on old made again on fresh (a renewed
 * handle); how many. */
int  auth_bus_move(lcm_t *old, lcm_t *fresh);
/* lcm_destroy, and the checked subscriptions on lcm forgotten. */
void auth_bus_close(lcm_t *lcm);
const auth_bus_counts *auth_bus_counts_get(void);
int64_t auth_bus_rejected_total(void);

struct _tandem_health_t;
/* The auth_* fields of a health message. */
void auth_bus_fill_health(struct _tandem_health_t *h);
/* A health message's refusals by kind, in the order unsigned, bad MAC,
 * unknown sender, replayed, not allowed, other cell, refused before the MAC
 * (for readers: tandem-status, the tests); returns their sum. */
#define AUTH_BUS_KINDS 7
int64_t auth_bus_health_refusals(const struct _tandem_health_t *h, int64_t kinds[AUTH_BUS_KINDS]);

/* A raw handler that decodes `type` and calls typed(rb, ch, &msg, user):
 * for a typed handler on auth_bus_subscribe. */
#define AUTH_TYPED_HANDLER(type, name, typed) \
    static void name(const lcm_recv_buf_t *rb_, const char *ch_, void *user_) \
    { \
        type m_; \
        if (type##_decode(rb_->data, 0, (int)rb_->data_size, &m_) < 0) \
            return; \
        typed(rb_, ch_, &m_, user_); \
        type##_decode_cleanup(&m_); \
    }

#endif
