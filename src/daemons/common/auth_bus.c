/* auth_bus: signing, checking and key handling of one process (see auth_bus.h). */
#include "auth_bus.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/time.h>
#include <unistd.h>
#include <sodium.h>
#include "auth_acl.h"
#include "shell_status.h"
#include "wire.h"
#include "tandem_health_t.h"

void auth_bus_init(auth_bus *bus)
{
    memset(bus, 0, sizeof *bus);
}

static uint64_t wall_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (uint64_t)tv.tv_sec * 1000000u + (uint64_t)tv.tv_usec;
}

int auth_bus_option(auth_bus *bus, const char *prog, int opt, const char *arg)
{
    switch (opt) {
    case OPT_KEY_FILE:
        if (!arg[0] || bus->n_key_files >= AUTH_MAX_KEYS) {
            fprintf(stderr, "%s: --key-file: %s\n", prog,
                    arg[0] ? "at most two (the key and the previous one)" : "empty path");
            return AUTH_BUS_ERR_OPTION;
        }
        bus->key_file[bus->n_key_files++] = arg;
        return 1;
    case OPT_INSECURE: bus->insecure = 1; return 1;
    default: return 0;
    }
}

void auth_bus_identity(auth_bus *bus, int role, int first, int last)
{
    bus->me.role = (uint8_t)role;
    bus->me.first = (uint16_t)first;
    bus->me.last = (uint16_t)last;
    bus->me_peer.role = bus->me.role;
    bus->me_peer.first = bus->me.first;
    bus->me_peer.last = bus->me.last;
    bus->have_identity = 1;
    bus->n_routes = 0;
}

void auth_bus_roster(auth_bus *bus, int rovers)
{
    const auth_fleet f = auth_fleet_clamped(rovers, 1, 1);
    auth_bus_roster_fleet(bus, &f);
}

void auth_bus_roster_fleet(auth_bus *bus, const auth_fleet *f)
{
    int i;
    /* the hosts cover every robot; the single rovers are as many as a
     * message's tags hold (auth_roster_fleet) */
    bus->fleet = auth_fleet_clamped(f->rovers, f->hosts, f->unit);
    bus->n_routes = 0;
    for (i = 0; i < bus->ring.n; i++) /* a master holder tags for the new roster at once */
        if (bus->ring.set[i] && bus->ring.set[i]->is_master)
            bus->ring.set[i]->fleet = auth_bus_fleet(bus);
}

int auth_bus_sender_covers(const auth_bus *bus, long k)
{
    const auth_sender *s = &bus->last.sender;
    if (!bus->secure || !bus->last.valid || bus->last.rc != AUTH_OK)
        return !bus->secure;
    return k >= s->first && k <= s->last;
}

auth_fleet auth_bus_fleet(const auth_bus *bus)
{
    return bus->fleet.rovers > 0 ? bus->fleet : auth_fleet_clamped(AUTH_ROSTER_ROVERS, 1, 1);
}

void auth_bus_sign_as_owner(auth_bus *bus, int on)
{
    bus->as_owner = on != 0;
    bus->n_routes = 0;
}

int auth_bus_secure(const auth_bus *bus)
{
    return bus->secure;
}

/* The journal key: BLAKE2b over every pairwise key the signing set holds
 * (or the master), under a context naming the use. Only the holder of the
 * whole role file (or the master) has them all: a peer that shares one
 * pair with this process cannot forge its journal. Stable across restarts
 * of the same role. */
int auth_bus_journal_key(const auth_bus *bus, uint8_t out[32])
{
    static const char ctx[] = "tandem journal key v2";
    const auth_keyset *ks;
    crypto_generichash_state h;
    int i;
    if (!bus->secure || bus->ring.n < 1 || !(ks = bus->ring.set[0]))
        return 0;
    crypto_generichash_init(&h, NULL, 0, 32);
    crypto_generichash_update(&h, (const unsigned char *)ctx, sizeof ctx - 1);
    crypto_generichash_update(&h, ks->cell, AUTH_CELL_BYTES);
    if (ks->is_master)
        crypto_generichash_update(&h, ks->master, AUTH_KEY_BYTES);
    for (i = 0; !ks->is_master && i < ks->n; i++)
        crypto_generichash_update(&h, ks->pair[i].key, AUTH_KEY_BYTES);
    crypto_generichash_final(&h, out, 32);
    return 1;
}

int auth_bus_default_key_path(char *out, size_t cap)
{
    const char *xdg = getenv("XDG_CONFIG_HOME"), *home = getenv("HOME");
    int n;
    if (xdg && xdg[0] == '/')
        n = snprintf(out, cap, "%s/tandem/bus.key", xdg);
    else if (home && home[0])
        n = snprintf(out, cap, "%s/.config/tandem/bus.key", home);
    else
        return AUTH_BUS_ERR_NO_HOME;
    return n > 0 && (size_t)n < cap ? AUTH_BUS_OK : AUTH_BUS_ERR_NO_HOME;
}

static void warn_insecure(const auth_bus *bus)
{
    fprintf(stderr,
            "%s: WARNING: --insecure: bus messages are NOT authenticated. Nothing this process\n"
            "%s: WARNING: sends is signed and nothing it receives is checked: anyone who can\n"
            "%s: WARNING: reach the bus can command it. Its health messages say auth_on = 0.\n",
            bus->prog, bus->prog, bus->prog);
}

/* The key files to load: the options, else $TANDEM_KEY_FILE, else the
 * default file if it exists. 0, or AUTH_BUS_ERR_KEY when there is none. */
static int key_files(const auth_bus *bus, const char *files[AUTH_MAX_KEYS], int *n, char *def,
                     size_t cap)
{
    const char *env = getenv(AUTH_BUS_KEY_ENV);
    int i;
    *n = bus->n_key_files;
    for (i = 0; i < bus->n_key_files; i++)
        files[i] = bus->key_file[i];
    if (*n > 0)
        return 0;
    if (env && env[0]) {
        files[(*n)++] = env;
        return 0;
    }
    if (auth_bus_default_key_path(def, cap) == 0 && access(def, F_OK) == 0) {
        files[(*n)++] = def;
        return 0;
    }
    return AUTH_BUS_ERR_KEY;
}

static int load_keys(auth_bus *bus)
{
    const char *files[AUTH_MAX_KEYS];
    char def[1024] = "", why[1200];
    int i, n;
    if (key_files(bus, files, &n, def, sizeof def) != 0) {
        fprintf(stderr,
                "%s: no bus key. Give --key-file PATH (`make run` creates %s on first use,\n"
                "%s: `tandem-keygen` makes one), or --insecure to run without authentication.\n",
                bus->prog, def[0] ? def : "~/.config/tandem/bus.key", bus->prog);
        return AUTH_BUS_ERR_KEY;
    }
    for (i = 0; i < n; i++) {
        /* locked memory, allocated once at start-up; a repeated start (a
         * run repeated in one process) reuses it */
        if (!bus->ring.set[i] && !(bus->ring.set[i] = auth_keyset_new())) {
            fprintf(stderr, "%s: no locked memory for the bus key\n", bus->prog);
            return AUTH_BUS_ERR_KEY;
        }
        if (auth_keyset_load(bus->ring.set[i], files[i], &bus->me_peer, why, sizeof why) !=
            AUTH_OK) {
            fprintf(stderr, "%s: bus key %s\n", bus->prog, why);
            return AUTH_BUS_ERR_KEY;
        }
        if (bus->ring.set[i]->is_master)
            bus->ring.set[i]->fleet = auth_bus_fleet(bus);
        if (!bus->ring.set[i]->is_master &&
            !auth_peer_equal(&bus->ring.set[i]->holder, &bus->me_peer)) {
            fprintf(stderr,
                    "%s: bus key %s is the key file of another role (%d %d-%d; this is %d %d-%d)\n",
                    bus->prog, files[i], bus->ring.set[i]->holder.role,
                    bus->ring.set[i]->holder.first, bus->ring.set[i]->holder.last,
                    bus->me_peer.role, bus->me_peer.first, bus->me_peer.last);
            return AUTH_BUS_ERR_KEY;
        }
    }
    bus->ring.n = n;
    return 0;
}

/* $TANDEM_INSECURE=1 without any key option or $TANDEM_KEY_FILE. */
static int insecure_from_env(const auth_bus *bus)
{
    const char *ins = getenv(AUTH_BUS_INSECURE_ENV), *key = getenv(AUTH_BUS_KEY_ENV);
    return bus->n_key_files == 0 && !(key && key[0]) && ins && strcmp(ins, "1") == 0;
}

int auth_bus_start(auth_bus *bus, const char *prog)
{
    int rc;
    snprintf(bus->prog, sizeof bus->prog, "%s", prog);
    /* a channel table that lets two rules claim one channel, or names none,
     * would grant or refuse by accident: no process starts on one */
    if ((rc = auth_acl_validate(auth_acl_table, auth_acl_table_n)) != AUTH_ACL_OK) {
        fprintf(stderr,
                "%s: the channel table (auth_acl_table) is unsound: auth_acl_validate: %s\n", prog,
                auth_acl_strerror(rc));
        return AUTH_BUS_ERR_START;
    }
    if (insecure_from_env(bus))
        bus->insecure = 1;
    if (bus->insecure && bus->n_key_files > 0) {
        fprintf(stderr, "%s: --insecure and --key-file exclude each other\n", prog);
        return AUTH_BUS_ERR_START;
    }
    bus->started = 1;
    if (bus->insecure) {
        bus->secure = 0;
        warn_insecure(bus);
        return 0;
    }
    if (auth_init() != 0) {
        fprintf(stderr, "%s: libsodium does not start\n", prog);
        return AUTH_BUS_ERR_START;
    }
    if (!bus->have_identity && !bus->as_owner) {
        fprintf(stderr, "%s: no bus identity set (auth_bus_identity)\n", prog);
        return AUTH_BUS_ERR_START;
    }
    if (!bus->have_identity)
        auth_bus_identity(bus, AUTH_ROLE_TOOL, 0, 0); /* a stand-in receives as a tool */
    bus->n_routes = 0;
    if (load_keys(bus) != 0)
        return AUTH_BUS_ERR_KEY;
    bus->me.session = randombytes_random();
    auth_replay_init(&bus->replay, AUTH_WINDOW_US, wall_us());
    bus->secure = 1;
    return 0;
}

/* ---- ephemeral key ------------------------------------------------------------- */

/* The temporary key of auth_bus_ephemeral_key: a resource of the process,
 * not of a bus, removed at its exit by an atexit handler, which gets no
 * context (tools/lint-state.allow). */
static struct ephemeral_key {
    char dir[512], file[600];
    pid_t owner;
} ephemeral;

static void remove_ephemeral(void)
{
    if (getpid() != ephemeral.owner)
        return; /* a forked child that did not exec must not take the key away */
    unlink(ephemeral.file);
    rmdir(ephemeral.dir);
}

int auth_bus_ephemeral_key(char *path, size_t cap)
{
    const char *tmp = getenv("TMPDIR");
    char why[700];
    snprintf(ephemeral.dir, sizeof ephemeral.dir, "%s/tandem-key-XXXXXX",
             tmp && tmp[0] == '/' ? tmp : "/tmp");
    if (!mkdtemp(ephemeral.dir))
        return AUTH_BUS_ERR_KEY;
    snprintf(ephemeral.file, sizeof ephemeral.file, "%s/bus.key", ephemeral.dir);
    if (auth_key_create(ephemeral.file, why, sizeof why) != AUTH_OK) {
        fprintf(stderr, "tandem: %s\n", why);
        rmdir(ephemeral.dir);
        return AUTH_BUS_ERR_KEY;
    }
    ephemeral.owner = getpid();
    atexit(remove_ephemeral);
    setenv(AUTH_BUS_KEY_ENV, ephemeral.file, 1);
    snprintf(path, cap, "%s", ephemeral.file);
    return 0;
}

/* ---- publishing ---------------------------------------------------------------- */

int auth_bus_tx_reserve(auth_bus *bus, int body_len)
{
    const int need = body_len + AUTH_TRAILER_MAX;
    if (body_len < 0)
        return AUTH_BUS_ERR_ARG;
    if (need > bus->tx_cap) {
        uint8_t *p = realloc(bus->tx, (size_t)need);
        if (!p)
            return AUTH_BUS_ERR_MEMORY;
        bus->tx = p;
        bus->tx_cap = need;
    }
    return 0;
}

uint8_t *auth_bus_tx(const auth_bus *bus)
{
    return bus->tx;
}

int auth_bus_tx_cap(const auth_bus *bus)
{
    return bus->tx_cap - AUTH_TRAILER_MAX;
}

static int sender_for(const auth_bus *bus, const char *channel, auth_sender *s)
{
    *s = bus->me;
    if (bus->as_owner && auth_acl_owner(auth_acl_table, auth_acl_table_n, channel, s) != AUTH_OK) {
        s->role = AUTH_ROLE_TOOL;
        s->first = s->last = 0;
    }
    /* as a principal every role file knows: the simulator, supervisor
     * and tools have no instances (ARM1_ACTION's owner is the supervisor,
     * not "supervisor 1"); a channel of no one arm or rover (ARM_EVENTS,
     * TEAM, ROVERS_COMMAND) is spoken as instance 1 */
    if (bus->as_owner && s->role != AUTH_ROLE_ARM && s->role != AUTH_ROLE_ROVER)
        s->first = s->last = 0;
    else if (bus->as_owner && s->first == 0)
        s->first = s->last = 1;
    s->session = bus->me.session;
    return 0;
}

/* A receiver gets a tag when the channel table says it reads the channel;
 * a channel the table does not name (a bench's ping) goes to everyone. */
static int wants(const auth_peer *r, const char *channel)
{
    return auth_acl_readers(auth_acl_table, auth_acl_table_n, channel) == 0 ||
           auth_acl_reader_wanted(auth_acl_table, auth_acl_table_n, channel, r);
}

/* The route of channel: from the cache, or worked out (and kept while
 * there is room). */
static const tx_route *route_of(auth_bus *bus, const char *channel, tx_route *scratch)
{
    const uint64_t h = auth_channel_hash(channel);
    tx_route *r;
    int i;
    for (i = 0; i < bus->n_routes; i++)
        if (bus->routes[i].channel_hash == h && strcmp(bus->routes[i].channel, channel) == 0)
            return &bus->routes[i];
    r = bus->n_routes < AUTH_BUS_ROUTES ? &bus->routes[bus->n_routes++] : scratch;
    r->channel_hash = h;
    snprintf(r->channel, sizeof r->channel, "%s", channel);
    sender_for(bus, channel, &r->sender);
    r->n = auth_receivers(bus->ring.set[0], channel, AUTH_ROLES_ALL, wants, r->to);
    return r;
}

int auth_bus_publish_tx(auth_bus *bus, lcm_t *lcm, const char *channel, int body_len)
{
    tx_route scratch;
    const tx_route *r;
    size_t len;
    if (body_len < 0 || !bus->tx)
        return AUTH_BUS_ERR_ARG;
    if (!bus->started) {
        fprintf(stderr, "tandem: publishing on %s before auth_bus_start: not sent\n", channel);
        return AUTH_BUS_ERR_NOT_STARTED;
    }
    if (!bus->secure)
        return lcm_publish(lcm, channel, bus->tx, (unsigned)body_len);
    if (strlen(channel) > AUTH_CHANNEL_MAX)
        return AUTH_BUS_ERR_SIGN;
    r = route_of(bus, channel, &scratch);
    if (auth_sign_to(bus->ring.set[0], &r->sender, auth_next_counter(&bus->last_counter, wall_us()),
                     channel, r->to, r->n, bus->tx, (size_t)body_len, (size_t)bus->tx_cap,
                     &len) != AUTH_OK)
        return AUTH_BUS_ERR_SIGN;
    return lcm_publish(lcm, channel, bus->tx, (unsigned)len);
}

int auth_bus_publish_raw(auth_bus *bus, lcm_t *lcm, const char *channel, const void *buf, int len)
{
    const int rc = auth_bus_tx_reserve(bus, len);
    if (rc != AUTH_BUS_OK)
        return rc;
    memcpy(bus->tx, buf, (size_t)len);
    return auth_bus_publish_tx(bus, lcm, channel, len);
}

/* ---- receiving ----------------------------------------------------------------- */

static void count(auth_bus *bus, int rc)
{
    switch (rc) {
    case AUTH_OK: bus->counts.accepted++; break;
    case AUTH_ERR_MAC: bus->counts.bad_mac++; break;
    case AUTH_ERR_SENDER: bus->counts.unknown_sender++; break;
    case AUTH_ERR_REPLAY: bus->counts.replayed++; break;
    case AUTH_ERR_ACL: bus->counts.unauthorised++; break;
    case AUTH_ERR_CELL: bus->counts.other_cell++; break;
    case AUTH_ERR_TYPE:
        break; /* malformed, not forged: rx counts it as rejected, as the wire check would */
    case AUTH_ERR_CHANNEL: bus->counts.precheck++; break;
    default: bus->counts.unsigned_msgs++; break;
    }
}

/* A replay refusal of a message that a renewal's two handles both
 * delivered (auth_bus_counts.renewal_copies). */
static int renewal_copy(const auth_bus *bus, int rc, const auth_trailer *t)
{
    const uint64_t now = (uint64_t)wall_us();
    return rc == AUTH_ERR_REPLAY && bus->renewed_us != 0 &&
           now <= bus->renewed_us + (uint64_t)AUTH_BUS_RENEW_OVERLAP_US &&
           t->counter + (uint64_t)AUTH_BUS_RENEW_OVERLAP_US >= bus->renewed_us;
}

static int same_delivery(const auth_bus *bus, const lcm_recv_buf_t *rb, uint64_t ch_hash,
                         const uint8_t *mac)
{
    return bus->last.valid && bus->last.data == rb->data &&
           bus->last.recv_utime == rb->recv_utime && bus->last.size == rb->data_size &&
           bus->last.channel_hash == ch_hash && memcmp(bus->last.mac, mac, AUTH_MAC_BYTES) == 0;
}

/* Before any MAC, so that junk costs a table look-up, not a hash of up to
 * 64 kB: a channel of the table, a known type, no longer than that type's
 * longest encoding plus the longest trailer. */
static int precheck(const uint8_t *data, uint32_t size, const char *channel)
{
    const wire_type *w;
    if (size > AUTH_BUS_MAX_DATAGRAM || size < 8 + AUTH_TRAILER_MIN)
        return AUTH_ERR_TYPE;
    if (!auth_acl_find(auth_acl_table, auth_acl_table_n, channel, &(long){ 0 }, &(long){ 0 }))
        return AUTH_ERR_CHANNEL;
    w = wire_find(data, size);
    if (!w || size > wire_max_size(w) + AUTH_TRAILER_MAX)
        return AUTH_ERR_TYPE;
    return AUTH_OK;
}

/* The first 16 bytes of the trailer (for same_delivery): any bytes that
 * differ between two datagrams of one sender. */
static void delivery_mark(const uint8_t *data, uint32_t size, uint8_t mark[AUTH_MAC_BYTES])
{
    memset(mark, 0, AUTH_MAC_BYTES);
    if (size >= AUTH_FIXED_BYTES)
        memcpy(mark, data + size - AUTH_FIXED_BYTES + 6,
               AUTH_MAC_BYTES); /* instances, session, counter */
}

static int check(auth_bus *bus, const uint8_t *data, uint32_t size, const char *channel,
                 uint64_t ch_hash, auth_trailer *t)
{
    int rc = precheck(data, size, channel);
    if (rc != AUTH_OK)
        return rc;
    rc = auth_verify(&bus->ring, &bus->me_peer, channel, data, size, t);
    if (rc == AUTH_OK)
        rc = auth_sender_check(&t->sender);
    if (rc == AUTH_OK)
        rc = auth_acl_check(auth_acl_table, auth_acl_table_n, channel, &t->sender);
    if (rc == AUTH_OK)
        rc = auth_replay_check(&bus->replay, &t->sender, ch_hash, t->counter, wall_us());
    return rc;
}

int auth_bus_accept(auth_bus *bus, const lcm_recv_buf_t *rb, const char *channel,
                    lcm_recv_buf_t *body)
{
    const uint8_t *data = rb->data;
    const uint64_t ch_hash = auth_channel_hash(channel);
    uint8_t mark[AUTH_MAC_BYTES];
    auth_trailer t;
    int rc;
    memset(&t, 0, sizeof t);
    *body = *rb;
    if (!bus->started)
        return AUTH_ERR_KEY; /* fail closed */
    if (!bus->secure) {
        if (auth_parse(data, rb->data_size, &t) == AUTH_OK)
            body->data_size -= (uint32_t)t.len;
        return AUTH_OK;
    }
    delivery_mark(data, rb->data_size, mark);
    if (same_delivery(bus, rb, ch_hash, mark)) {
        rc = bus->last.rc;
    } else {
        rc = check(bus, data, rb->data_size, channel, ch_hash, &t);
        if (renewal_copy(bus, rc, &t))
            bus->counts.renewal_copies++;
        else
            count(bus, rc);
        if (rc == AUTH_ERR_ACL) {
            snprintf(bus->unauthorised_channel, sizeof bus->unauthorised_channel, "%s", channel);
            bus->unauthorised_sender = t.sender;
        }
        bus->last.valid = 1;
        bus->last.data = rb->data;
        bus->last.recv_utime = rb->recv_utime;
        bus->last.size = rb->data_size;
        bus->last.channel_hash = ch_hash;
        memcpy(bus->last.mac, mark, AUTH_MAC_BYTES);
        bus->last.rc = rc;
        bus->last.trailer = t.len;
        bus->last.sender = t.sender;
    }
    if (rc == AUTH_OK)
        body->data_size -= (uint32_t)bus->last.trailer;
    return rc;
}

static void sub_trampoline(const lcm_recv_buf_t *rb, const char *channel, void *u)
{
    const bus_sub *s = u;
    lcm_recv_buf_t body;
    const wire_type *w;
    if (auth_bus_accept(s->bus, rb, channel, &body) != AUTH_OK)
        return;
    w = wire_find(body.data, body.data_size);
    if (!w || wire_check(w, body.data, body.data_size) != WIRE_OK)
        return;
    s->handler(&body, channel, s->user);
}

lcm_subscription_t *auth_bus_subscribe_queue(auth_bus *bus, lcm_t *lcm, const char *channel,
                                             lcm_msg_handler_t handler, void *user, int capacity)
{
    bus_sub *s = NULL, *free_slot = NULL;
    int i;
    /* a run repeated in one process subscribes again: its slot */
    for (i = 0; i < bus->n_subs && !s; i++) {
        bus_sub *e = &bus->subs[i];
        if (!e->used) {
            if (!free_slot)
                free_slot = e;
        } else if (e->handler == handler && e->user == user &&
                   strncmp(e->channel, channel, AUTH_CHANNEL_MAX) == 0) {
            s = e;
        }
    }
    if (!s)
        s = free_slot;
    if (!s) {
        if (bus->n_subs >= AUTH_BUS_MAX_SUBS) {
            fprintf(stderr, "tandem: more than %d checked subscriptions\n", AUTH_BUS_MAX_SUBS);
            return NULL;
        }
        s = &bus->subs[bus->n_subs++];
    }
    s->bus = bus;
    s->handler = handler;
    s->user = user;
    snprintf(s->channel, sizeof s->channel, "%s", channel);
    s->capacity = capacity;
    s->lcm = lcm;
    s->used = 1;
    s->sub = lcm_subscribe(lcm, channel, sub_trampoline, s);
    if (s->sub)
        lcm_subscription_set_queue_capacity(s->sub, capacity);
    return s->sub;
}

lcm_subscription_t *auth_bus_subscribe(auth_bus *bus, lcm_t *lcm, const char *channel,
                                       lcm_msg_handler_t handler, void *user)
{
    return auth_bus_subscribe_queue(bus, lcm, channel, handler, user, AUTH_BUS_QUEUE_CAPACITY);
}

int auth_bus_unsubscribe_user(auth_bus *bus, lcm_t *lcm, const void *user)
{
    int i, n = 0;
    for (i = 0; i < bus->n_subs; i++) {
        bus_sub *e = &bus->subs[i];
        if (!e->used || e->lcm != lcm || e->user != user)
            continue;
        if (e->sub)
            lcm_unsubscribe(lcm, e->sub);
        memset(e, 0, sizeof *e);
        n++;
    }
    return n;
}

void auth_bus_renewing(auth_bus *bus)
{
    bus->renewed_us = (uint64_t)wall_us();
}

int auth_bus_move(auth_bus *bus, lcm_t *old, lcm_t *fresh)
{
    int i, n = 0;
    auth_bus_renewing(bus);
    for (i = 0; i < bus->n_subs; i++) {
        bus_sub *e = &bus->subs[i];
        if (!e->used || e->lcm != old || !e->sub)
            continue;
        e->lcm = fresh;
        e->sub = lcm_subscribe(fresh, e->channel, sub_trampoline, e);
        if (e->sub) {
            lcm_subscription_set_queue_capacity(e->sub, e->capacity);
            n++;
        }
    }
    return n;
}

void auth_bus_close(auth_bus *bus, lcm_t *lcm)
{
    int i;
    if (!lcm)
        return;
    for (i = 0; i < bus->n_subs; i++)
        if (bus->subs[i].used && bus->subs[i].lcm == lcm)
            memset(&bus->subs[i], 0, sizeof bus->subs[i]);
    lcm_destroy(lcm);
}

void auth_bus_free(auth_bus *bus)
{
    free(bus->tx);
    bus->tx = NULL;
    bus->tx_cap = 0;
}

const auth_bus_counts *auth_bus_counts_get(const auth_bus *bus)
{
    return &bus->counts;
}

int64_t auth_bus_rejected_total(const auth_bus *bus)
{
    return bus->counts.unsigned_msgs + bus->counts.bad_mac + bus->counts.unknown_sender +
           bus->counts.replayed + bus->counts.unauthorised + bus->counts.other_cell +
           bus->counts.precheck;
}

void auth_bus_report_unauthorised(const auth_bus *bus, char *out, size_t cap)
{
    char who[32];
    const auth_sender *s = &bus->unauthorised_sender;
    if (cap > 0)
        out[0] = '\0';
    if (bus->counts.unauthorised == 0)
        return;
    auth_principal_name(s->role, s->first, s->last, who, sizeof who);
    snprintf(out, cap,
             "%lld messages refused as not allowed on their channel, the last on %s signed by %s",
             (long long)bus->counts.unauthorised, bus->unauthorised_channel, who);
}

int64_t auth_bus_health_refusals(const tandem_health_t *h, int64_t kinds[AUTH_BUS_KINDS])
{
    kinds[0] = h->auth_unsigned;
    kinds[1] = h->auth_bad_mac;
    kinds[2] = h->auth_unknown_sender;
    kinds[3] = h->auth_replayed;
    kinds[4] = h->auth_unauthorised;
    kinds[5] = h->auth_other_cell;
    kinds[6] = h->auth_precheck;
    return kinds[0] + kinds[1] + kinds[2] + kinds[3] + kinds[4] + kinds[5] + kinds[6];
}

void auth_bus_fill_health(const auth_bus *bus, tandem_health_t *h)
{
    h->auth_on = (int8_t)bus->secure;
    h->auth_unsigned = bus->counts.unsigned_msgs;
    h->auth_bad_mac = bus->counts.bad_mac;
    h->auth_unknown_sender = bus->counts.unknown_sender;
    h->auth_replayed = bus->counts.replayed;
    h->auth_unauthorised = bus->counts.unauthorised;
    h->auth_other_cell = bus->counts.other_cell;
    h->auth_precheck = bus->counts.precheck;
    h->msgs_duplicate += bus->counts.renewal_copies; /* copies, refused, of messages taken */
}
