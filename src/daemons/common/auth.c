/* auth: pairwise keys, key files, trailer, tags and replay table (see auth.h). */
#include "auth.h"
#include "auth_acl.h"
#include <errno.h>
#include <fcntl.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <sodium.h>

static const char domain[] = "tandem-auth-v2";
static const char key_id_domain[] = "tandem-key-id";
static const char cell_domain[] = "tandem-cell-id";
static const char pair_domain[] = "tandem-pair-v2";
static const uint8_t role_file_magic[4] = { 'T', 'K', 'S', '2' };

#define ROLE_FILE_HEAD (4 + 1 + AUTH_PEER_BYTES + AUTH_CELL_BYTES + 2)
#define ROLE_FILE_PAIR (1 + AUTH_PEER_BYTES + AUTH_KEY_BYTES)
#define ROLE_FILE_MAX (ROLE_FILE_HEAD + AUTH_MAX_PAIRS * ROLE_FILE_PAIR)

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

static void put_peer(uint8_t *p, const auth_peer *a)
{
    p[0] = a->role;
    put_be(p + 1, a->first, 2);
    put_be(p + 3, a->last, 2);
}

static void get_peer(const uint8_t *p, auth_peer *a)
{
    a->role = p[0];
    a->first = (uint16_t)get_be(p + 1, 2);
    a->last = (uint16_t)get_be(p + 3, 2);
}

int auth_peer_equal(const auth_peer *a, const auth_peer *b)
{
    return a->role == b->role && a->first == b->first && a->last == b->last;
}

uint8_t auth_key_id(const uint8_t master[AUTH_KEY_BYTES])
{
    uint8_t out[16];
    crypto_generichash(out, sizeof out, (const unsigned char *)key_id_domain,
                       sizeof key_id_domain - 1, master, AUTH_KEY_BYTES);
    return out[0];
}

void auth_cell_id(const uint8_t master[AUTH_KEY_BYTES], uint8_t cell[AUTH_CELL_BYTES])
{
    crypto_generichash(cell, AUTH_CELL_BYTES, (const unsigned char *)cell_domain,
                       sizeof cell_domain - 1, master, AUTH_KEY_BYTES);
}

void auth_pair_key(const uint8_t master[AUTH_KEY_BYTES], const uint8_t cell[AUTH_CELL_BYTES],
                   const auth_peer *from, const auth_peer *to, uint8_t key[AUTH_KEY_BYTES])
{
    uint8_t in[sizeof pair_domain - 1 + AUTH_CELL_BYTES + 2 * AUTH_PEER_BYTES];
    size_t n = sizeof pair_domain - 1;
    memcpy(in, pair_domain, n);
    memcpy(in + n, cell, AUTH_CELL_BYTES);
    n += AUTH_CELL_BYTES;
    put_peer(in + n, from);
    put_peer(in + n + AUTH_PEER_BYTES, to);
    crypto_generichash(key, AUTH_KEY_BYTES, in, sizeof in, master, AUTH_KEY_BYTES);
}

/* ---- key sets ------------------------------------------------------------------ */

auth_keyset *auth_keyset_new(void)
{
    /* sodium_malloc: guard pages, mlock'd, MADV_DONTDUMP; allocated at
     * start-up, never inside a control cycle. sodium_malloc aborts the
     * process unless libsodium was initialised: a caller that never ran
     * auth_init (a bench, a tool spawning daemons) gets NULL instead */
    auth_keyset *k = sodium_init() < 0 ? NULL : sodium_malloc(sizeof *k);
    if (k)
        memset(k, 0, sizeof *k);
    return k;
}

void auth_keyset_free(auth_keyset *k)
{
    sodium_free(k); /* wipes before unlocking */
}

auth_fleet auth_fleet_clamped(int rovers, int hosts, int unit)
{
    auth_fleet f;
    int units;
    f.rovers = rovers < 0 ? 0 : rovers > AUTH_ACL_NUMBER_MAX ? AUTH_ACL_NUMBER_MAX : rovers;
    f.unit = unit < 1 ? 1 : unit > f.rovers && f.rovers > 0 ? f.rovers : unit;
    units = (f.rovers + f.unit - 1) / f.unit;
    f.hosts = hosts < 1 ? 1 : hosts > AUTH_FLEET_HOSTS_MAX ? AUTH_FLEET_HOSTS_MAX : hosts;
    if (units >= 1 && f.hosts > units)
        f.hosts = units;
    return f;
}

int auth_fleet_host(const auth_fleet *f, int h, int *first, int *last)
{
    const auth_fleet c = auth_fleet_clamped(f->rovers, f->hosts, f->unit);
    const long units = (c.rovers + c.unit - 1) / c.unit;
    long lo, hi;
    if (c.rovers < 1 || h < 0 || h >= c.hosts)
        return -1;
    /* units [h U / H, (h+1) U / H): every host at least one unit, sizes
     * differing by at most one unit */
    lo = (long)h * units / c.hosts;
    hi = (long)(h + 1) * units / c.hosts;
    *first = (int)(lo * c.unit + 1);
    *last = (int)(hi * c.unit < c.rovers ? hi * c.unit : c.rovers);
    return 0;
}

int auth_roster_fleet(const auth_fleet *f, auth_peer *out, int cap)
{
    static const auth_peer fixed[] = {
        { AUTH_ROLE_SIM, 0, 0 },        { AUTH_ROLE_ARM, 1, 1 },  { AUTH_ROLE_ARM, 2, 2 },
        { AUTH_ROLE_SUPERVISOR, 0, 0 }, { AUTH_ROLE_TOOL, 0, 0 }, { AUTH_ROLE_MONITOR, 0, 0 },
    };
    const auth_fleet c = auth_fleet_clamped(f->rovers, f->hosts, f->unit);
    int i, n = 0, a, b;
    for (i = 0; i < (int)(sizeof fixed / sizeof fixed[0]) && n < cap; i++)
        out[n++] = fixed[i];
    /* the processes hosting the robots (tandem-rover --id A-B; one for the
     * whole team with the formation scenario's --procs single) are
     * principals of their own, listed before the single rovers, so that
     * they have their keys however many robots there are (the single
     * rovers fill what a message's tags leave) */
    for (i = 0; i < c.hosts && n < cap; i++) {
        if (auth_fleet_host(&c, i, &a, &b) != 0 || b <= a)
            continue; /* one robot: the single rover below */
        out[n].role = AUTH_ROLE_ROVER;
        out[n].first = (uint16_t)a;
        out[n].last = (uint16_t)b;
        n++;
    }
    for (i = 1; i <= c.rovers && n < cap; i++) {
        out[n].role = AUTH_ROLE_ROVER;
        out[n].first = out[n].last = (uint16_t)i;
        n++;
    }
    return n;
}

int auth_roster(int rovers, auth_peer *out, int cap)
{
    const auth_fleet f = auth_fleet_clamped(rovers, 1, 1);
    return auth_roster_fleet(&f, out, cap);
}

static void set_head(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES], const auth_peer *holder)
{
    k->id = auth_key_id(master);
    auth_cell_id(master, k->cell);
    k->holder = *holder;
    k->n = 0;
}

static void add_pair(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES], const auth_peer *peer,
                     uint8_t dir)
{
    auth_pair *p;
    if (k->n >= AUTH_MAX_PAIRS)
        return;
    p = &k->pair[k->n++];
    p->peer = *peer;
    p->dir = dir;
    if (dir == AUTH_DIR_SEND)
        auth_pair_key(master, k->cell, &k->holder, peer, p->key);
    else
        auth_pair_key(master, k->cell, peer, &k->holder, p->key);
    crypto_generichash_init(&p->keyed, p->key, AUTH_KEY_BYTES, AUTH_MAC_BYTES);
}

void auth_keyset_role(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES], const auth_peer *holder,
                      const auth_peer *roster, int n)
{
    const int monitor = holder->role == AUTH_ROLE_MONITOR;
    int i;
    set_head(k, master, holder);
    k->is_master = 0;
    k->fleet = auth_fleet_clamped(0, 1, 1);
    for (i = 0; i < n; i++) {
        const int self = auth_peer_equal(&roster[i], holder);
        /* a monitor is told everything and may tell nobody anything;
         * a sender also tags for itself (a process reads what it sends) */
        if (!self && roster[i].role != AUTH_ROLE_MONITOR)
            add_pair(k, master, &roster[i], AUTH_DIR_RECV);
        if (!monitor)
            add_pair(k, master, &roster[i], AUTH_DIR_SEND);
    }
}

void auth_keyset_master(auth_keyset *k, const uint8_t master[AUTH_KEY_BYTES],
                        const auth_peer *holder, int rovers)
{
    auth_peer roster[AUTH_MAX_TAGS];
    const int n = auth_roster(rovers, roster, AUTH_MAX_TAGS);
    auth_keyset_role(k, master, holder, roster, n); /* the usual pairs, precomputed */
    k->is_master = 1;
    k->fleet = auth_fleet_clamped(rovers, 1, 1);
    memcpy(k->master, master, AUTH_KEY_BYTES);
}

static int key_error(char *why, size_t cap, const char *path, const char *what)
{
    snprintf(why, cap, "%s: %s", path, what);
    return AUTH_ERR_KEY;
}

/* Opens a key file for reading: no symlink, a regular file of ours that
 * nobody else may read or write; its size in *size. fd or -1 (why said). */
static int open_key_file(const char *path, off_t *size, char *why, size_t why_cap)
{
    struct stat st;
    int fd = open(path, O_RDONLY | O_NOFOLLOW | O_NOCTTY);
    if (fd < 0) {
        key_error(why, why_cap, path,
                  errno == ELOOP ? "is a symbolic link (refused)" : strerror(errno));
        return -1;
    }
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        key_error(why, why_cap, path, "not a regular file");
    } else if (st.st_uid != geteuid()) {
        key_error(why, why_cap, path, "belongs to another user (refused)");
    } else if ((st.st_mode & 077) != 0) {
        key_error(why, why_cap, path, "readable or writable by others (chmod 600 it)");
    } else {
        *size = st.st_size;
        return fd;
    }
    close(fd);
    return -1;
}

static int read_all(int fd, uint8_t *buf, size_t cap)
{
    size_t got = 0;
    while (got < cap) {
        const ssize_t n = read(fd, buf + got, cap - got);
        if (n < 0 && errno == EINTR)
            continue;
        if (n <= 0)
            break;
        got += (size_t)n;
    }
    return (int)got;
}

static int parse_role_file(auth_keyset *k, const uint8_t *b, int n)
{
    int i, pairs;
    if (n < ROLE_FILE_HEAD || memcmp(b, role_file_magic, 4) != 0)
        return AUTH_ERR_KEY;
    k->id = b[4];
    get_peer(b + 5, &k->holder);
    memcpy(k->cell, b + 5 + AUTH_PEER_BYTES, AUTH_CELL_BYTES);
    pairs = (int)get_be(b + ROLE_FILE_HEAD - 2, 2);
    if (pairs > AUTH_MAX_PAIRS || n != ROLE_FILE_HEAD + pairs * ROLE_FILE_PAIR)
        return AUTH_ERR_KEY;
    for (i = 0; i < pairs; i++) {
        const uint8_t *p = b + ROLE_FILE_HEAD + i * ROLE_FILE_PAIR;
        if (p[0] != AUTH_DIR_SEND && p[0] != AUTH_DIR_RECV)
            return AUTH_ERR_KEY;
        k->pair[i].dir = p[0];
        get_peer(p + 1, &k->pair[i].peer);
        memcpy(k->pair[i].key, p + 1 + AUTH_PEER_BYTES, AUTH_KEY_BYTES);
        crypto_generichash_init(&k->pair[i].keyed, k->pair[i].key, AUTH_KEY_BYTES, AUTH_MAC_BYTES);
    }
    k->n = pairs;
    k->is_master = 0;
    return AUTH_OK;
}

int auth_keyset_load(auth_keyset *k, const char *path, const auth_peer *holder, char *why,
                     size_t why_cap)
{
    uint8_t *buf = sodium_malloc(ROLE_FILE_MAX + 1);
    off_t size = 0;
    int n, rc = AUTH_ERR_KEY, fd;
    if (!buf)
        return key_error(why, why_cap, path, "no locked memory for the key");
    fd = open_key_file(path, &size, why, why_cap);
    if (fd >= 0) {
        n = size <= ROLE_FILE_MAX ? read_all(fd, buf, ROLE_FILE_MAX + 1) : -1;
        close(fd);
        if (n == AUTH_KEY_BYTES) {
            auth_keyset_master(k, buf, holder, AUTH_ROSTER_ROVERS);
            rc = AUTH_OK;
        } else if (n > 0 && parse_role_file(k, buf, n) == AUTH_OK) {
            rc = AUTH_OK;
        } else {
            key_error(why, why_cap, path,
                      "not a tandem key (a 32-byte master or a tandem-keygen role file)");
        }
    }
    sodium_free(buf);
    return rc;
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

/* Writes len bytes to a new 0600 file (never over one, never through a symlink). */
static int write_new_file(const char *path, const uint8_t *b, size_t len, char *why, size_t why_cap)
{
    int fd, ok;
    if (make_parent_dirs(path) != 0)
        return key_error(why, why_cap, path, "cannot create its directory");
    fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW, 0600);
    if (fd < 0)
        return key_error(why, why_cap, path, strerror(errno));
    ok = fchmod(fd, 0600) == 0 && write(fd, b, len) == (ssize_t)len && fsync(fd) == 0;
    if (close(fd) != 0 || !ok) {
        unlink(path);
        return key_error(why, why_cap, path, "cannot write the key");
    }
    return AUTH_OK;
}

int auth_key_create(const char *path, char *why, size_t why_cap)
{
    uint8_t *key;
    int rc;
    if (auth_init() != 0)
        return key_error(why, why_cap, path, "libsodium does not start");
    key = sodium_malloc(AUTH_KEY_BYTES);
    if (!key)
        return key_error(why, why_cap, path, "no locked memory for the key");
    randombytes_buf(key, AUTH_KEY_BYTES);
    rc = write_new_file(path, key, AUTH_KEY_BYTES, why, why_cap);
    sodium_free(key);
    return rc;
}

int auth_master_load(uint8_t master[AUTH_KEY_BYTES], const char *path, char *why, size_t why_cap)
{
    off_t size = 0;
    int n, fd = open_key_file(path, &size, why, why_cap);
    if (fd < 0)
        return AUTH_ERR_KEY;
    n = size == AUTH_KEY_BYTES ? read_all(fd, master, AUTH_KEY_BYTES) : -1;
    close(fd);
    if (n != AUTH_KEY_BYTES)
        return key_error(why, why_cap, path, "not a master key (must be exactly 32 bytes)");
    return AUTH_OK;
}

int auth_keyset_write(const auth_keyset *k, const char *path, char *why, size_t why_cap)
{
    uint8_t *b = sodium_malloc(ROLE_FILE_MAX);
    size_t n = ROLE_FILE_HEAD;
    int i, rc;
    if (!b)
        return key_error(why, why_cap, path, "no locked memory for the key");
    memcpy(b, role_file_magic, 4);
    b[4] = k->id;
    put_peer(b + 5, &k->holder);
    memcpy(b + 5 + AUTH_PEER_BYTES, k->cell, AUTH_CELL_BYTES);
    put_be(b + ROLE_FILE_HEAD - 2, (uint64_t)k->n, 2);
    for (i = 0; i < k->n; i++, n += ROLE_FILE_PAIR) {
        b[n] = k->pair[i].dir;
        put_peer(b + n + 1, &k->pair[i].peer);
        memcpy(b + n + 1 + AUTH_PEER_BYTES, k->pair[i].key, AUTH_KEY_BYTES);
    }
    rc = write_new_file(path, b, n, why, why_cap);
    sodium_free(b);
    return rc;
}

/* ---- trailer and tags ---------------------------------------------------------- */

/* The tag hash of pair (from -> to), keyed: the set's own, or for a
 * master a key derived now. */
static int pair_mac(const auth_keyset *k, const auth_peer *from, const auth_peer *to,
                    crypto_generichash_state *st)
{
    const int send = auth_peer_equal(from, &k->holder), recv = auth_peer_equal(to, &k->holder);
    uint8_t key[AUTH_KEY_BYTES];
    int i;
    for (i = 0; i < k->n && (send || recv); i++) {
        const auth_pair *p = &k->pair[i];
        if ((send && p->dir == AUTH_DIR_SEND && auth_peer_equal(&p->peer, to)) ||
            (recv && p->dir == AUTH_DIR_RECV && auth_peer_equal(&p->peer, from))) {
            *st = p->keyed;
            return AUTH_OK;
        }
    }
    if (!k->is_master)
        return AUTH_ERR_SENDER;
    auth_pair_key(k->master, k->cell, from, to, key);
    crypto_generichash_init(st, key, AUTH_KEY_BYTES, AUTH_MAC_BYTES);
    sodium_memzero(key, sizeof key);
    return AUTH_OK;
}

static void write_fixed(uint8_t *h, const auth_keyset *k, const auth_sender *s, uint64_t counter,
                        int n_tags)
{
    h[0] = 'T';
    h[1] = 'A';
    h[2] = AUTH_VERSION;
    h[3] = k->id;
    h[4] = s->role;
    h[5] = 0;
    put_be(h + 6, s->first, 2);
    put_be(h + 8, s->last, 2);
    put_be(h + 10, s->session, 4);
    put_be(h + 14, counter, 8);
    memcpy(h + 22, k->cell, AUTH_CELL_BYTES);
    h[38] = (uint8_t)n_tags;
    h[39] = 0;
}

/* D over channel, body, the receivers of the tag list and the fixed part. */
static void digest(const char *channel, const uint8_t *body, size_t body_len, const uint8_t *tags,
                   int n_tags, const uint8_t *fixed, uint8_t d[32])
{
    crypto_generichash_state st;
    const size_t ch_len = strlen(channel);
    const uint8_t ch_len_byte = (uint8_t)ch_len;
    int i;
    crypto_generichash_init(&st, NULL, 0, 32);
    crypto_generichash_update(&st, (const unsigned char *)domain, sizeof domain - 1);
    crypto_generichash_update(&st, &ch_len_byte, 1);
    crypto_generichash_update(&st, (const unsigned char *)channel, ch_len);
    crypto_generichash_update(&st, body, body_len);
    for (i = 0; i < n_tags; i++)
        crypto_generichash_update(&st, tags + (size_t)i * AUTH_TAG_ENTRY_BYTES, AUTH_PEER_BYTES);
    crypto_generichash_update(&st, fixed, AUTH_FIXED_BYTES);
    crypto_generichash_final(&st, d, 32);
}

/* BLAKE2b-128(key, d) from the keyed state st (used up). */
static void tag_of(crypto_generichash_state *st, const uint8_t d[32], uint8_t tag[AUTH_MAC_BYTES])
{
    crypto_generichash_update(st, d, 32);
    crypto_generichash_final(st, tag, AUTH_MAC_BYTES);
}

/* The receivers of a message: the set's send peers (a master's roster). */
int auth_receivers(const auth_keyset *k, const char *channel, unsigned readers, auth_wants_fn wants,
                   auth_peer out[AUTH_MAX_TAGS])
{
    auth_peer roster[AUTH_MAX_TAGS];
    int i, n = 0, n_all;
    if (k->is_master) {
        n_all = auth_roster_fleet(&k->fleet, roster, AUTH_MAX_TAGS);
    } else {
        for (i = n_all = 0; i < k->n; i++)
            if (k->pair[i].dir == AUTH_DIR_SEND && n_all < AUTH_MAX_TAGS)
                roster[n_all++] = k->pair[i].peer;
    }
    for (i = 0; i < n_all; i++) {
        const auth_peer *r = &roster[i];
        if (r->role > AUTH_ROLE_LAST || !(readers & AUTH_ROLE_BIT(r->role)))
            continue;
        if (wants && !wants(r, channel))
            continue;
        out[n++] = *r;
    }
    return n;
}

int auth_sign(const auth_keyset *k, const auth_sender *s, uint64_t counter, const char *channel,
              unsigned readers, auth_wants_fn wants, uint8_t *buf, size_t body_len, size_t cap,
              size_t *out_len)
{
    auth_peer to[AUTH_MAX_TAGS];
    if (!k || strlen(channel) > AUTH_CHANNEL_MAX)
        return AUTH_ERR_ARG;
    return auth_sign_to(k, s, counter, channel, to, auth_receivers(k, channel, readers, wants, to),
                        buf, body_len, cap, out_len);
}

int auth_sign_to(const auth_keyset *k, const auth_sender *s, uint64_t counter, const char *channel,
                 const auth_peer *to, int n, uint8_t *buf, size_t body_len, size_t cap,
                 size_t *out_len)
{
    const auth_peer from = { s->role, s->first, s->last };
    crypto_generichash_state st;
    uint8_t d[32], *tags, *fixed;
    int i;
    if (!buf || !k || strlen(channel) > AUTH_CHANNEL_MAX || cap < body_len || n < 0 ||
        n > AUTH_MAX_TAGS)
        return AUTH_ERR_ARG;
    if (cap - body_len < AUTH_FIXED_BYTES + (size_t)n * AUTH_TAG_ENTRY_BYTES)
        return AUTH_ERR_ARG;
    tags = buf + body_len;
    fixed = tags + (size_t)n * AUTH_TAG_ENTRY_BYTES;
    for (i = 0; i < n; i++)
        put_peer(tags + (size_t)i * AUTH_TAG_ENTRY_BYTES, &to[i]);
    write_fixed(fixed, k, s, counter, n);
    digest(channel, buf, body_len, tags, n, fixed, d);
    for (i = 0; i < n; i++) {
        uint8_t *e = tags + (size_t)i * AUTH_TAG_ENTRY_BYTES;
        if (pair_mac(k, &from, &to[i], &st) != AUTH_OK)
            memset(e + AUTH_PEER_BYTES, 0,
                   AUTH_MAC_BYTES); /* no key with it: a tag that cannot verify */
        else
            tag_of(&st, d, e + AUTH_PEER_BYTES);
    }
    sodium_memzero(&st, sizeof st);
    *out_len = (size_t)(fixed - buf) + AUTH_FIXED_BYTES;
    return AUTH_OK;
}

int auth_parse(const uint8_t *buf, size_t len, auth_trailer *out)
{
    const uint8_t *t;
    size_t need;
    if (!buf || len < AUTH_FIXED_BYTES)
        return AUTH_ERR_UNSIGNED;
    t = buf + len - AUTH_FIXED_BYTES;
    if (t[0] != 'T' || t[1] != 'A' || t[2] != AUTH_VERSION || t[5] != 0 || t[39] != 0 ||
        t[38] > AUTH_MAX_TAGS)
        return AUTH_ERR_UNSIGNED;
    need = AUTH_FIXED_BYTES + (size_t)t[38] * AUTH_TAG_ENTRY_BYTES;
    if (len < need)
        return AUTH_ERR_UNSIGNED;
    out->key_id = t[3];
    out->sender.role = t[4];
    out->sender.first = (uint16_t)get_be(t + 6, 2);
    out->sender.last = (uint16_t)get_be(t + 8, 2);
    out->sender.session = (uint32_t)get_be(t + 10, 4);
    out->counter = get_be(t + 14, 8);
    memcpy(out->cell, t + 22, AUTH_CELL_BYTES);
    out->n_tags = t[38];
    out->len = need;
    return AUTH_OK;
}

static const auth_keyset *set_of_cell(const auth_keyring *ring, const uint8_t cell[AUTH_CELL_BYTES])
{
    int i;
    for (i = 0; i < ring->n; i++)
        if (ring->set[i] && sodium_memcmp(ring->set[i]->cell, cell, AUTH_CELL_BYTES) == 0)
            return ring->set[i];
    return NULL;
}

int auth_verify(const auth_keyring *ring, const auth_peer *me, const char *channel,
                const uint8_t *buf, size_t len, auth_trailer *t)
{
    const auth_keyset *k;
    const uint8_t *tags, *mine = NULL;
    crypto_generichash_state st;
    uint8_t d[32], want[AUTH_MAC_BYTES];
    auth_peer from, r;
    int i, rc = auth_parse(buf, len, t);
    if (rc != AUTH_OK)
        return rc;
    if (strlen(channel) > AUTH_CHANNEL_MAX)
        return AUTH_ERR_MAC;
    if (!(k = set_of_cell(ring, t->cell)))
        return AUTH_ERR_CELL;
    tags = buf + len - t->len;
    for (i = 0; i < t->n_tags && !mine; i++) {
        get_peer(tags + (size_t)i * AUTH_TAG_ENTRY_BYTES, &r);
        if (auth_peer_equal(&r, me))
            mine = tags + (size_t)i * AUTH_TAG_ENTRY_BYTES + AUTH_PEER_BYTES;
    }
    if (!mine)
        return AUTH_ERR_MAC;
    from.role = t->sender.role;
    from.first = t->sender.first;
    from.last = t->sender.last;
    if (pair_mac(k, &from, me, &st) != AUTH_OK)
        return AUTH_ERR_SENDER;
    digest(channel, buf, len - t->len, tags, t->n_tags, buf + len - AUTH_FIXED_BYTES, d);
    tag_of(&st, d, want);
    sodium_memzero(&st, sizeof st);
    return crypto_verify_16(want, mine) == 0 ? AUTH_OK : AUTH_ERR_MAC;
}

int auth_sender_check(const auth_sender *s)
{
    /* a monitor holds no send key: nothing it signs is any receiver's */
    if (s->role < AUTH_ROLE_SIM || s->role > AUTH_ROLE_TOOL || s->first > s->last)
        return AUTH_ERR_SENDER;
    return AUTH_OK;
}

/* ---- replay ------------------------------------------------------------------ */

void auth_replay_init(auth_replay *r, int64_t window_us, uint64_t start_us)
{
    memset(r, 0, sizeof *r);
    r->window_us = window_us;
    r->oldest_us = start_us > (uint64_t)AUTH_START_SLACK_US
                       ? start_us - (uint64_t)AUTH_START_SLACK_US
                       : 0;
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
    return a->role == b->role && a->first == b->first && a->last == b->last &&
           a->session == b->session;
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

int auth_replay_check(auth_replay *r, const auth_sender *s, uint64_t channel_hash, uint64_t counter,
                      uint64_t now_us)
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

void auth_principal_name(int role, int first, int last, char *out, size_t cap)
{
    static const char *const names[] = {
        "?", "sim", "arm", "supervisor", "rover", "tool", "monitor"
    };
    const char *n = role >= 0 && role <= AUTH_ROLE_LAST ? names[role] : "?";
    if (role == AUTH_ROLE_ROVER && first != last)
        snprintf(out, cap, "%s%d-%d", n, first, last);
    else if (role == AUTH_ROLE_ARM || role == AUTH_ROLE_ROVER)
        snprintf(out, cap, "%s%d", n, first);
    else
        snprintf(out, cap, "%s", n);
}
