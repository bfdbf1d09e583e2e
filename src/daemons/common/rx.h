/* rx: the receive path every daemon subscription goes through
 * (daemon_subscribe). Before a handler sees a message it is
 *   0. authenticated (auth_bus_accept: trailer, MAC, sender, channel
 *      authorisation, counter); a refused message is counted per channel
 *      and by kind and touches nothing else, not even the drop hash; the
 *      handler gets the message without its trailer;
 *   1. dropped on purpose with probability --drop-rate (fault injection,
 *      deterministic for --drop-seed: a hash of the seed, the channel, the
 *      message's seq and how many copies of the channel arrived);
 *   2. checked on its raw bytes (wire.h): a malformed message is counted
 *      as received + rejected and never reaches lcm-gen's decoder;
 *   3. counted per channel, with sequence gaps (messages lost on the way)
 *      found from the leading seq field, per sender.
 * The counts go into the HEALTH_<NAME> message (rx_fill_health).
 */
#ifndef TANDEM_RX_H
#define TANDEM_RX_H

#include <stdint.h>
#include <lcm/lcm.h>

#define RX_MAX_CHANNELS 32 /* per process; more are summed in "(other)" */
#define RX_MAX_SUBS 64
#define RX_STREAMS 8 /* senders told apart per channel */
#define RX_CHANNEL_NAME 48

typedef struct rx_channel {
    char name[RX_CHANNEL_NAME];
    int64_t received;      /* passed the wire check */
    int64_t rejected;      /* failed it */
    int64_t lost;          /* sequence gaps */
    int64_t dropped;       /* dropped on purpose (--drop-rate) */
    int64_t auth_rejected; /* refused by auth_bus_accept */
    int64_t copies;        /* every arrival, for the drop hash */
    int64_t last_seq[RX_STREAMS];
    int n_streams;
} rx_channel;

struct daemon;
struct _tandem_health_t;

typedef struct rx_sub {
    struct daemon *d;
    lcm_msg_handler_t handler;
    void *user;
    char channel[RX_CHANNEL_NAME];
    lcm_t *lcm; /* the handle it is subscribed on, and how */
    lcm_subscription_t *sub;
} rx_sub;

/* The receive path's state: one per daemon (daemon.rx), so nothing of it
 * is shared between daemons of one process (the unit tests run several). */
typedef struct rx_state {
    rx_channel chans[RX_MAX_CHANNELS];
    int n_chans;
    rx_sub subs[RX_MAX_SUBS];
    int n_subs;
    double drop_p; /* --drop-rate */
    uint64_t drop_seed;
    int64_t deferred; /* drains that hit their budget (daemon_drain) */
    /* the most CPU time one drain took, this thread's alone (a loaded
     * machine's preemption is not in it): what receive work costs a
     * cycle, whatever the flood (health rx_cpu_max_us) */
    int64_t drain_cpu_max_ns;
    /* the health message's arrays point here (rx_fill_health) */
    const char *health_names[RX_MAX_CHANNELS];
    int64_t health_received[RX_MAX_CHANNELS], health_lost[RX_MAX_CHANNELS];
    int64_t health_auth_rejected[RX_MAX_CHANNELS];
} rx_state;

void rx_init(rx_state *rx);
/* Fault injection: drop received messages with probability p (0 = off). */
void rx_set_drop(rx_state *rx, double p, uint64_t seed);
/* lcm_subscribe through the receive path of d (daemon_subscribe calls
 * this). The same handler, user and channel again on the same handle
 * (a model re-created after a simulator reset) is the subscription
 * already made, not a second one. The subscription lives as long as
 * the daemon: a renewed handle (daemon_renew_lcm) takes it over, so
 * nobody keeps the lcm_subscription_t. */
lcm_subscription_t *rx_subscribe(struct daemon *d, const char *channel, lcm_msg_handler_t handler,
                                 void *user);
/* Every subscription of rx made on old again on fresh, each with a queue
 * of capacity messages (a new handle: daemon_renew_lcm, lcm_renew). The
 * number moved. */
int rx_move_subscriptions(rx_state *rx, lcm_t *old, lcm_t *fresh, int capacity);
/* The same in two halves, for a handle made beside the control thread
 * (renew.h). rx_stage, on any thread: subscribes s's channel (copied by
 * the caller) on fresh with s's trampoline and a queue of capacity;
 * nothing of s is read. rx_commit_subscriptions, on the control thread:
 * every subscription of rx on old moves to fresh, taking staged[i] for
 * subs[i] (i < n_staged, non-NULL) and subscribing the rest now. */
lcm_subscription_t *rx_stage(lcm_t *fresh, const char *channel, rx_sub *s, int capacity);
int rx_commit_subscriptions(rx_state *rx, lcm_t *old, lcm_t *fresh,
                            lcm_subscription_t *const *staged, int n_staged, int capacity);
/* Adds per-channel counts, gaps, the loss rate and the deferred drains to
 * a health message; the strings and arrays point into rx. */
void rx_fill_health(rx_state *rx, struct _tandem_health_t *h);
/* Totals over every channel. */
int64_t rx_lost_total(const rx_state *rx);
int64_t rx_dropped_total(const rx_state *rx);

/* Sequence-gap bookkeeping of one channel (exposed for the unit test):
 * returns how many messages were missing before this seq. Several senders
 * may share a channel (ARM_EVENTS, TEAM, SIM_ACK): the message extends the
 * stream whose last seq is the closest below it; a seq no stream can take
 * (behind all of them, or a jump of more than RX_GAP_WINDOW) starts a new
 * stream (a restarted or new sender) and counts no loss. */
#define RX_GAP_WINDOW 1000
int64_t rx_seq_gap(rx_channel *c, int64_t seq);

#endif
