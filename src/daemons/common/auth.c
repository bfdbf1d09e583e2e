/* auth: trailer, keyed BLAKE2b MAC, key files and replay table (see auth.h). */
#include "auth.h"
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <sodium.h>

static const char domain[] = "tandem-auth-v1";
static const char key_id_domain[] = "tandem-key-id";

int auth_init(void)
{
    return sodium_init() < 0 ? AUTH_ERR_INIT : AUTH_OK;
}

static void put_be(uint8_t *p, uint64_t v, int n)
{
    int i;
    for (i = n - 1; i >= 0; i--) {
        p[i] = (uint8_t)(v & 0xffu);
        v >>= 8;
    }
}

static uint64_t get_be(const uint8_t *p, int n)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < n; i++)
        v = (v << 8) | p[i];
    return v;
}

uint8_t auth_key_id(const uint8_t bytes[AUTH_KEY_BYTES])
{
    uint8_t out[16];
    crypto_generichash(out, sizeof out, (const unsigned char *)key_id_domain, sizeof key_id_domain - 1,
                       bytes, AUTH_KEY_BYTES);
    return out[0];
}

void auth_key_set(auth_key *k, const uint8_t bytes[AUTH_KEY_BYTES])
{
    memcpy(k->bytes, bytes, AUTH_KEY_BYTES);
    k->id = auth_key_id(bytes);
}

static int key_error(char *why, size_t cap, const char *path, const char *what)
{
    snprintf(why, cap, "%s: %s", path, what);
    return AUTH_ERR_KEY;
}

int auth_key_load(auth_key *k, const char *path, char *why, size_t why_cap)
{
    uint8_t buf[AUTH_KEY_BYTES + 1];
    struct stat st;
    ssize_t n;
    int fd = open(path, O_RDONLY);
    if (fd < 0)
        return key_error(why, why_cap, path, strerror(errno));
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return key_error(why, why_cap, path, "not a regular file");
    }
    if ((st.st_mode & 077) != 0) {
        close(fd);
        return key_error(why, why_cap, path, "readable or writable by others (chmod 600 it)");
    }
    n = read(fd, buf, sizeof buf);
    close(fd);
    if (n != AUTH_KEY_BYTES) {
        sodium_memzero(buf, sizeof buf);
        return key_error(why, why_cap, path, "not a tandem key (must be exactly 32 bytes)");
    }
    auth_key_set(k, buf);
    sodium_memzero(buf, sizeof buf);
    return AUTH_OK;
}

/* make_parent_dirs: the path is too long, or mkdir failed (errno says why) */
#define MKDIR_FAILED (-1)

/* mkdir -p of path's directory, new components 0700. */
static int make_parent_dirs(const char *path)
{
    char dir[1024];
    size_t i;
    if (snprintf(dir, sizeof dir, "%s", path) >= (int)sizeof dir)
        return MKDIR_FAILED;
    for (i = 1; dir[i]; i++) {
        if (dir[i] != '/')
            continue;
        dir[i] = '\0';
        if (mkdir(dir, 0700) != 0 && errno != EEXIST)
            return MKDIR_FAILED;
        dir[i] = '/';
    }
    return 0;
}

int auth_key_create(const char *path, char *why, size_t why_cap)
{
    uint8_t key[AUTH_KEY_BYTES];
    int fd, ok;
    if (auth_init() != 0)
        return key_error(why, why_cap, path, "libsodium does not start");
    if (make_parent_dirs(path) != 0)
        return key_error(why, why_cap, path, "cannot create its directory");
    fd = open(path, O_WRONLY | O_CREAT | O_EXCL, 0600);
    if (fd < 0)
        return key_error(why, why_cap, path, strerror(errno));
    randombytes_buf(key, sizeof key);
    ok = fchmod(fd, 0600) == 0 && write(fd, key, sizeof key) == (ssize_t)sizeof key && fsync(fd) == 0;
    sodium_memzero(key, sizeof key);
    if (close(fd) != 0 || !ok) {
        unlink(path);
        return key_error(why, why_cap, path, "cannot write the key");
    }
    return AUTH_OK;
}

int auth_mac(const auth_key *k, const char *channel, const uint8_t *body, size_t body_len,
             const uint8_t head[AUTH_HEAD_BYTES], uint8_t mac[AUTH_MAC_BYTES])
{
    crypto_generichash_state st;
    const size_t ch_len = strlen(channel);
    const uint8_t ch_len_byte = (uint8_t)ch_len;
    if (ch_len > AUTH_CHANNEL_MAX)
        return AUTH_ERR_ARG;
    crypto_generichash_init(&st, k->bytes, AUTH_KEY_BYTES, AUTH_MAC_BYTES);
    crypto_generichash_update(&st, (const unsigned char *)domain, sizeof domain - 1);
    crypto_generichash_update(&st, &ch_len_byte, 1);
    crypto_generichash_update(&st, (const unsigned char *)channel, ch_len);
    crypto_generichash_update(&st, body, body_len);
    crypto_generichash_update(&st, head, AUTH_HEAD_BYTES);
    crypto_generichash_final(&st, mac, AUTH_MAC_BYTES);
    return AUTH_OK;
}

static void write_head(uint8_t *h, uint8_t key_id, const auth_sender *s, uint64_t counter)
{
    h[0] = 'T';
    h[1] = 'A';
    h[2] = AUTH_VERSION;
    h[3] = key_id;
    h[4] = s->role;
    h[5] = 0;
    put_be(h + 6, s->first, 2);
    put_be(h + 8, s->last, 2);
    put_be(h + 10, s->session, 4);
    put_be(h + 14, counter, 8);
}

int auth_sign(const auth_key *k, const auth_sender *s, uint64_t counter, const char *channel,
              uint8_t *buf, size_t body_len, size_t cap)
{
    uint8_t *t = buf + body_len;
    if (!buf || cap < body_len || cap - body_len < AUTH_TRAILER_BYTES || strlen(channel) > AUTH_CHANNEL_MAX)
        return AUTH_ERR_ARG;
    write_head(t, k->id, s, counter);
    return auth_mac(k, channel, buf, body_len, t, t + AUTH_HEAD_BYTES);
}

int auth_parse(const uint8_t *buf, size_t len, auth_trailer *out)
{
    const uint8_t *t;
    if (!buf || len < AUTH_TRAILER_BYTES)
        return AUTH_ERR_UNSIGNED;
    t = buf + len - AUTH_TRAILER_BYTES;
    if (t[0] != 'T' || t[1] != 'A' || t[2] != AUTH_VERSION || t[5] != 0)
        return AUTH_ERR_UNSIGNED;
    out->key_id = t[3];
    out->sender.role = t[4];
    out->sender.first = (uint16_t)get_be(t + 6, 2);
    out->sender.last = (uint16_t)get_be(t + 8, 2);
    out->sender.session = (uint32_t)get_be(t + 10, 4);
    out->counter = get_be(t + 14, 8);
    memcpy(out->mac, t + AUTH_HEAD_BYTES, AUTH_MAC_BYTES);
    return AUTH_OK;
}

int auth_verify(const auth_keyring *ring, const char *channel, const uint8_t *buf, size_t len,
                auth_trailer *t)
{
    int i, rc = auth_parse(buf, len, t);
    if (rc != AUTH_OK)
        return rc;
    if (strlen(channel) > AUTH_CHANNEL_MAX)
        return AUTH_ERR_MAC;
    for (i = 0; i < ring->n; i++) {
        uint8_t mac[AUTH_MAC_BYTES];
        const size_t body = len - AUTH_TRAILER_BYTES;
        if (ring->key[i].id != t->key_id)
            continue;
        auth_mac(&ring->key[i], channel, buf, body, buf + body, mac);
        if (crypto_verify_16(mac, t->mac) == 0)
            return AUTH_OK;
    }
    return AUTH_ERR_MAC;
}

int auth_sender_check(const auth_sender *s)
{
    if (s->role < AUTH_ROLE_SIM || s->role > AUTH_ROLE_LAST || s->first > s->last)
        return AUTH_ERR_SENDER;
    return AUTH_OK;
}

/* ---- replay ------------------------------------------------------------------ */

void auth_replay_init(auth_replay *r, int64_t window_us, uint64_t start_us)
{
    memset(r, 0, sizeof *r);
    r->window_us = window_us;
    r->oldest_us = start_us > (uint64_t)AUTH_START_SLACK_US ? start_us - (uint64_t)AUTH_START_SLACK_US : 0;
}

uint64_t auth_channel_hash(const char *channel)
{
    uint64_t h = 1469598103934665603ULL;
    for (; *channel; channel++)
        h = (h ^ (unsigned char)*channel) * 1099511628211ULL;
    return h;
}

static int same_sender(const auth_sender *a, const auth_sender *b)
{
    return a->role == b->role && a->first == b->first && a->last == b->last && a->session == b->session;
}

static size_t set_of(const auth_sender *s, uint64_t channel_hash)
{
    uint64_t h = channel_hash ^ ((uint64_t)s->role << 56) ^ ((uint64_t)s->first << 40) ^
                 ((uint64_t)s->last << 24) ^ s->session;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdULL;
    h ^= h >> 33;
    return (size_t)(h % (AUTH_REPLAY_SLOTS / AUTH_REPLAY_WAYS)) * AUTH_REPLAY_WAYS;
}

static int within_window(uint64_t counter, uint64_t now_us, int64_t window_us)
{
    const uint64_t w = (uint64_t)window_us;
    return counter <= now_us + w && counter + w >= now_us;
}

int auth_replay_check(auth_replay *r, const auth_sender *s, uint64_t channel_hash,
                      uint64_t counter, uint64_t now_us)
{
    const size_t base = set_of(s, channel_hash);
    auth_stream *victim = &r->slot[base];
    size_t i;
    /* LCM has no history: nothing sent before we started is news */
    if (!within_window(counter, now_us, r->window_us) || counter < r->oldest_us)
        return AUTH_ERR_REPLAY;
    for (i = base; i < base + AUTH_REPLAY_WAYS; i++) {
        auth_stream *e = &r->slot[i];
        if (e->used && e->channel_hash == channel_hash && same_sender(&e->sender, s)) {
            if (counter <= e->last_counter)
                return AUTH_ERR_REPLAY;
            e->last_counter = counter;
            e->last_seen_us = now_us;
            return AUTH_OK;
        }
        if (victim->used && (!e->used || e->last_seen_us < victim->last_seen_us))
            victim = e;
    }
    /* first sight (or forgotten): the window alone decides */
    victim->used = 1;
    victim->sender = *s;
    victim->channel_hash = channel_hash;
    victim->last_counter = counter;
    victim->last_seen_us = now_us;
    return AUTH_OK;
}

uint64_t auth_next_counter(uint64_t *last, uint64_t now_us)
{
    *last = now_us > *last ? now_us : *last + 1;
    return *last;
}
