/* rx: checked, counted, optionally lossy receive path (see rx.h). */
#include "rx.h"
#include <stdio.h>
#include <string.h>
#include "auth_bus.h"
#include "daemon.h"
#include "wire.h"
#include "tandem_health_t.h"

void rx_init(rx_state *rx)
{
    memset(rx, 0, sizeof *rx);
}

void rx_set_drop(rx_state *rx, double p, uint64_t seed)
{
    rx->drop_p = p;
    rx->drop_seed = seed;
}

static rx_channel *channel_known(rx_state *rx, const char *name)
{
    int i;
    for (i = 0; i < rx->n_chans; i++)
        if (strncmp(rx->chans[i].name, name, RX_CHANNEL_NAME - 1) == 0)
            return &rx->chans[i];
    return NULL;
}

static rx_channel *channel_of(rx_state *rx, const char *name)
{
    rx_channel *c = channel_known(rx, name);
    if (c)
        return c;
    if (rx->n_chans < RX_MAX_CHANNELS - 1) {
        snprintf(rx->chans[rx->n_chans].name, RX_CHANNEL_NAME, "%s", name);
        return &rx->chans[rx->n_chans++];
    }
    /* the table is full: the last slot sums the rest */
    if (rx->n_chans == RX_MAX_CHANNELS - 1)
        snprintf(rx->chans[rx->n_chans++].name, RX_CHANNEL_NAME, "(other)");
    return &rx->chans[RX_MAX_CHANNELS - 1];
}

int64_t rx_seq_gap(rx_channel *c, int64_t seq)
{
    int i, best = -1;
    int64_t gap;
    for (i = 0; i < c->n_streams; i++) {
        const int64_t dd = seq - c->last_seq[i];
        if (dd >= 1 && dd <= RX_GAP_WINDOW && (best < 0 || dd < seq - c->last_seq[best]))
            best = i;
    }
    if (best < 0) {
        /* a duplicate of a seq some stream already has is no new stream */
        for (i = 0; i < c->n_streams; i++)
            if (c->last_seq[i] == seq)
                return 0;
        if (c->n_streams < RX_STREAMS)
            best = c->n_streams++;
        else
            best = (int)(c->copies % RX_STREAMS); /* replace one, round robin */
        c->last_seq[best] = seq;
        return 0;
    }
    gap = seq - c->last_seq[best] - 1;
    c->last_seq[best] = seq;
    return gap;
}

static uint64_t mix64(uint64_t x)
{
    x += 0x9e3779b97f4a7c15ULL;
    x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
    x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
    return x ^ (x >> 31);
}

static int drop_this(const rx_state *rx, const rx_channel *c, int64_t seq)
{
    uint64_t h = 1469598103934665603ULL;
    const char *p;
    if (rx->drop_p <= 0.0)
        return 0;
    for (p = c->name; *p; p++)
        h = (h ^ (unsigned char)*p) * 1099511628211ULL;
    h = mix64(h ^ mix64(rx->drop_seed) ^ mix64((uint64_t)seq * 31u + (uint64_t)c->copies));
    return (double)(h >> 11) * (1.0 / 9007199254740992.0) < rx->drop_p;
}

static void trampoline(const lcm_recv_buf_t *rb_in, const char *ch, void *u)
{
    rx_sub *s = u;
    rx_state *rx = &s->d->rx;
    lcm_recv_buf_t body;
    const lcm_recv_buf_t *rb = &body;
    rx_channel *c;
    const wire_type *t;
    int64_t seq;
    int rc;
    rc = auth_bus_accept(&s->d->bus, rb_in, ch, &body);
    if (rc != AUTH_OK) {
        /* a forged channel name must not take a slot of the table */
        c = channel_known(rx, ch);
        if (rc ==
            AUTH_ERR_TYPE) { /* not a tandem type or too long: malformed, refused before any MAC */
            s->d->msgs.received++;
            s->d->msgs.rejected++;
            if (c)
                c->rejected++;
        } else if (c) {
            c->auth_rejected++;
        }
        return;
    }
    c = channel_of(rx, ch);
    t = wire_find(rb->data, rb->data_size);
    seq = wire_seq(rb->data, rb->data_size);
    c->copies++;
    if (drop_this(rx, c, seq)) {
        c->dropped++;
        return;
    }
    if (!t || wire_check(t, rb->data, rb->data_size) != WIRE_OK) {
        s->d->msgs.received++;
        s->d->msgs.rejected++;
        c->rejected++;
        return;
    }
    c->received++;
    c->lost += rx_seq_gap(c, seq);
    s->handler(rb, ch, s->user);
}

lcm_subscription_t *rx_subscribe(daemon *d, const char *channel, lcm_msg_handler_t handler,
                                 void *user)
{
    rx_state *rx = &d->rx;
    rx_sub *s = NULL;
    int i;
    /* a model re-created after a simulator reset subscribes again: the
     * same subscription */
    for (i = 0; i < rx->n_subs && !s; i++)
        if (rx->subs[i].handler == handler && rx->subs[i].user == user && rx->subs[i].d == d &&
            strncmp(rx->subs[i].channel, channel, RX_CHANNEL_NAME - 1) == 0)
            s = &rx->subs[i];
    if (s && s->sub && s->lcm == d->lcm)
        return s->sub;
    if (!s) {
        if (rx->n_subs >= RX_MAX_SUBS) {
            fprintf(stderr, "%s: more than %d subscriptions\n", d->name, RX_MAX_SUBS);
            return NULL;
        }
        s = &rx->subs[rx->n_subs++];
    }
    s->d = d;
    s->handler = handler;
    s->user = user;
    snprintf(s->channel, sizeof s->channel, "%s", channel);
    /* a plain channel gets its row now, so refusals before its first
     * accepted message are counted on it too */
    if (strspn(channel, "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") == strlen(channel))
        channel_of(rx, channel);
    s->lcm = d->lcm;
    s->sub = lcm_subscribe(d->lcm, channel, trampoline, s);
    return s->sub;
}

lcm_subscription_t *rx_stage(lcm_t *fresh, const char *channel, rx_sub *s, int capacity)
{
    /* s is only handed to LCM here: the trampoline reads it when the
     * control thread handles fresh, after rx_commit_subscriptions */
    lcm_subscription_t *sub = lcm_subscribe(fresh, channel, trampoline, s);
    if (sub)
        lcm_subscription_set_queue_capacity(sub, capacity);
    return sub;
}

int rx_commit_subscriptions(rx_state *rx, lcm_t *old, lcm_t *fresh,
                            lcm_subscription_t *const *staged, int n_staged, int capacity)
{
    int i, n = 0;
    for (i = 0; i < rx->n_subs; i++) {
        rx_sub *s = &rx->subs[i];
        if (s->lcm != old || !s->sub)
            continue;
        if (n == 0)
            auth_bus_renewing(&s->d->bus); /* what both handles get is a copy */
        s->lcm = fresh;
        /* one made since the snapshot was staged: subscribed now */
        s->sub = i < n_staged && staged[i] ? staged[i] : rx_stage(fresh, s->channel, s, capacity);
        if (s->sub)
            n++;
    }
    return n;
}

int rx_move_subscriptions(rx_state *rx, lcm_t *old, lcm_t *fresh, int capacity)
{
    return rx_commit_subscriptions(rx, old, fresh, NULL, 0, capacity);
}

int64_t rx_lost_total(const rx_state *rx)
{
    int64_t n = 0;
    int i;
    for (i = 0; i < rx->n_chans; i++)
        n += rx->chans[i].lost;
    return n;
}

int64_t rx_dropped_total(const rx_state *rx)
{
    int64_t n = 0;
    int i;
    for (i = 0; i < rx->n_chans; i++)
        n += rx->chans[i].dropped;
    return n;
}

void rx_fill_health(rx_state *rx, tandem_health_t *h)
{
    int64_t rec = 0;
    int i;
    for (i = 0; i < rx->n_chans; i++) {
        rx->health_names[i] = rx->chans[i].name;
        rx->health_received[i] = rx->chans[i].received;
        rx->health_lost[i] = rx->chans[i].lost;
        rx->health_auth_rejected[i] = rx->chans[i].auth_rejected;
        rec += rx->chans[i].received;
    }
    h->n_channels = (int16_t)rx->n_chans;
    h->channel = (char **)rx->health_names;
    h->channel_received = rx->health_received;
    h->channel_lost = rx->health_lost;
    h->channel_auth_rejected = rx->health_auth_rejected;
    h->msgs_lost = rx_lost_total(rx);
    h->msgs_dropped = rx_dropped_total(rx);
    h->rx_deferred = rx->deferred;
    h->rx_cpu_max_us = 1e-3 * (double)rx->drain_cpu_max_ns;
    h->loss_rate = rec + h->msgs_lost > 0 ? (double)h->msgs_lost / (double)(rec + h->msgs_lost)
                                          : 0.0;
}
