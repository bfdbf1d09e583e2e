/* tandem-flood: floods an LCM bus the way an attacker on the LAN could, to
 * measure what it costs the daemons (docs/security.md, "Flooding"). It
 * holds no key: nothing it sends can be taken, so what it measures is the
 * cost of refusing.
 *
 *   junk     LCM datagrams (the LCM framing, so they reach the channel
 *            lookup and, on a subscribed channel, the handler) with random
 *            bytes, at --rate per second
 *   forge    messages of --size bytes that look like tandem messages: a
 *            tandem type's fingerprint, random bytes, and a trailer of the
 *            right form (magic, version, a sender, tags of random bytes),
 *            one datagram each (the LCM fragment form above 1400 bytes),
 *            as fast as the socket takes them (or at --rate)
 *   raw      datagrams without the LCM framing (dropped by LCM at once)
 *
 * on one channel (--channel) or on a new random name each time
 * (--random-channels). It writes to the bus's multicast group and port
 * directly (not through lcm_publish), with the URL's ttl.
 */
#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>
#include "auth.h"
#include "daemon.h"
#include "options.h"
#include "tandem_action_row_t.h"

#define PROG "tandem-flood"
#define FLOOD_MAX_DATAGRAM 65000    /* one UDP datagram, headers included, under 64 KiB */
#define LCM_SHORT_MAX 1400          /* LCM sends longer messages in the fragment form */
#define LCM_MAGIC_SHORT 0x4c433032u /* "LC02" */
#define LCM_MAGIC_LONG 0x4c433033u  /* "LC03" */
#define BATCH_NS 1000000LL          /* the rate is kept per millisecond */

/* Results (distinct values). */
#define FLOOD_OK 0
#define FLOOD_ERR_URL (-1)    /* not udpm://ADDR:PORT[?ttl=N] */
#define FLOOD_ERR_SOCKET (-2) /* the socket cannot be made */
#define FLOOD_ERR_OPTION (-3) /* a bad combination of options */

enum { KIND_JUNK, KIND_FORGE, KIND_RAW };
static const char *const kind_names[] = { "junk", "forge", "raw", NULL };

typedef struct flood_options {
    const char *url;
    int kind;
    double rate; /* datagrams per second, 0: as fast as possible */
    int size;    /* payload bytes */
    double duration_s;
    const char *channel;
    int random_channels;
} flood_options;

typedef struct flood {
    flood_options o;
    int fd;
    struct sockaddr_in to;
    uint64_t rng;
    uint32_t seq;
    int64_t sent, failed, bytes;
    uint8_t pkt[FLOOD_MAX_DATAGRAM];
    uint8_t msg[FLOOD_MAX_DATAGRAM];
} flood;

static volatile sig_atomic_t stop;
static void on_signal(int sig)
{
    (void)sig;
    stop = 1;
}

static const option_entry flood_table[] = {
    { .name = "lcm-url",
      .type = OPTION_STRING,
      OPTION_AT(flood_options, url),
      .meta = "URL",
      .help = "the bus",
      .def = "$LCM_DEFAULT_URL or " DAEMON_DEFAULT_LCM_URL },
    { .name = "kind",
      .type = OPTION_CHOICE,
      OPTION_AT(flood_options, kind),
      .choices = kind_names,
      .meta = "K",
      .help = "junk (LCM framing, random bytes) | forge (tandem-looking messages with a trailer) | "
              "raw (no LCM framing)",
      .def = "junk" },
    { .name = "rate",
      .type = OPTION_DOUBLE,
      OPTION_AT(flood_options, rate),
      .min = 0.0,
      .max = 1e7,
      .meta = "N",
      .help = "datagrams per second (0: as fast as the socket takes them)",
      .def = "50000" },
    { .name = "size",
      .type = OPTION_INT,
      OPTION_AT(flood_options, size),
      .min = 16,
      .max = 60000,
      .meta = "BYTES",
      .help = "message bytes (junk, raw, forge)",
      .def = "100" },
    { .name = "duration",
      .type = OPTION_DOUBLE,
      OPTION_AT(flood_options, duration_s),
      .min = 0.0,
      .max = 86400.0,
      .meta = "S",
      .help = "stop after S seconds (0: until Ctrl-C)",
      .def = "10" },
    { .name = "channel",
      .type = OPTION_STRING,
      OPTION_AT(flood_options, channel),
      .min = 1,
      .max = AUTH_CHANNEL_MAX,
      .meta = "NAME",
      .help = "the channel",
      .def = "ARM1_ACTION" },
    { .name = "random-channels",
      .type = OPTION_FLAG,
      OPTION_AT(flood_options, random_channels),
      .help =
          "a new random channel name for every datagram (what LCM remembers of each name it sees)" },
    OPTION_HELP_ENTRY('h'),
    OPTION_VERSION_ENTRY,
    { .name = NULL }
};

static uint64_t next_rand(flood *f)
{
    f->rng ^= f->rng << 13;
    f->rng ^= f->rng >> 7;
    f->rng ^= f->rng << 17;
    return f->rng;
}

static void random_bytes(flood *f, uint8_t *p, size_t n)
{
    size_t i;
    for (i = 0; i + 8 <= n; i += 8) {
        const uint64_t r = next_rand(f);
        memcpy(p + i, &r, 8);
    }
    for (; i < n; i++)
        p[i] = (uint8_t)(next_rand(f) >> 24);
}

static int64_t now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000LL + ts.tv_nsec;
}

static void put32(uint8_t *p, uint32_t v)
{
    p[0] = (uint8_t)(v >> 24);
    p[1] = (uint8_t)(v >> 16);
    p[2] = (uint8_t)(v >> 8);
    p[3] = (uint8_t)v;
}

/* udpm://ADDR:PORT[?...ttl=N...] into the destination and the ttl. */
static int parse_url(const char *url, struct sockaddr_in *to, int *ttl)
{
    char addr[64];
    const char *p = strncmp(url, "udpm://", 7) == 0 ? url + 7 : NULL, *colon, *t;
    size_t n;
    if (!p || !(colon = strchr(p, ':')) || (n = (size_t)(colon - p)) >= sizeof addr)
        return FLOOD_ERR_URL;
    memcpy(addr, p, n);
    addr[n] = '\0';
    memset(to, 0, sizeof *to);
    to->sin_family = AF_INET;
    to->sin_port = htons((uint16_t)atoi(colon + 1));
    if (inet_pton(AF_INET, addr, &to->sin_addr) != 1 || to->sin_port == 0)
        return FLOOD_ERR_URL;
    t = strstr(colon, "ttl=");
    *ttl = t ? atoi(t + 4) : 0;
    return FLOOD_OK;
}

static int open_socket(flood *f)
{
    int ttl = 0, loop = 1;
    const char *url = f->o.url ? f->o.url : getenv("LCM_DEFAULT_URL");
    if (!url || !url[0])
        url = DAEMON_DEFAULT_LCM_URL;
    if (parse_url(url, &f->to, &ttl) != FLOOD_OK) {
        fprintf(stderr, PROG ": --lcm-url: '%s' is not udpm://ADDR:PORT[?ttl=N]\n", url);
        return FLOOD_ERR_URL;
    }
    if ((f->fd = socket(AF_INET, SOCK_DGRAM, 0)) < 0) {
        perror(PROG ": socket");
        return FLOOD_ERR_SOCKET;
    }
    /* ttl 0 keeps it on this host, as the bus's own sockets do */
    setsockopt(f->fd, IPPROTO_IP, IP_MULTICAST_TTL, &(unsigned char){ (unsigned char)ttl }, 1);
    setsockopt(f->fd, IPPROTO_IP, IP_MULTICAST_LOOP, &(unsigned char){ (unsigned char)loop }, 1);
    return FLOOD_OK;
}

/* A channel name: the option's, or random capitals and digits. */
static void channel_of(flood *f, char *out, size_t cap)
{
    size_t i, n;
    if (!f->o.random_channels) {
        snprintf(out, cap, "%s", f->o.channel);
        return;
    }
    n = 12 + next_rand(f) % 20;
    for (i = 0; i < n && i + 1 < cap; i++)
        out[i] = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_"[next_rand(f) % 37];
    out[i] = '\0';
}

/* A tandem-looking message of `size` bytes in f->msg: a real type's
 * encoding (its fingerprint first), random bytes, a trailer of the right
 * form whose tags cannot verify. */
static int forged_message(flood *f)
{
    tandem_action_row_t row;
    uint8_t *t;
    int n_tags = 6, trailer, head;
    memset(&row, 0, sizeof row);
    head = tandem_action_row_t_encode(f->msg, 0, (int)sizeof f->msg, &row);
    trailer = AUTH_FIXED_BYTES + n_tags * AUTH_TAG_ENTRY_BYTES;
    if (f->o.size < head + trailer)
        return head > 0 ? head : 0;
    /* the whole body once; then only its first bytes and the tags change,
     * so the rate is the socket's, not the random generator's */
    random_bytes(f, f->msg + head, (size_t)(f->sent == 0 ? f->o.size - head : 64));
    random_bytes(f, f->msg + f->o.size - trailer, (size_t)(trailer - AUTH_FIXED_BYTES));
    t = f->msg + f->o.size - AUTH_FIXED_BYTES;
    t[0] = 'T';
    t[1] = 'A';
    t[2] = AUTH_VERSION;
    t[4] = AUTH_ROLE_SUPERVISOR;
    t[5] = 0;
    t[38] = (uint8_t)n_tags;
    t[39] = 0;
    return f->o.size;
}

/* The datagram of one message: LCM's short form, or its fragment form (one
 * fragment) above LCM_SHORT_MAX. Its length. */
static int frame(flood *f, const char *channel, const uint8_t *msg, int len)
{
    const int ch = (int)strlen(channel) + 1;
    uint8_t *p = f->pkt;
    int head;
    if (ch + len < LCM_SHORT_MAX) {
        put32(p, LCM_MAGIC_SHORT);
        put32(p + 4, f->seq++);
        head = 8;
    } else {
        put32(p, LCM_MAGIC_LONG);
        put32(p + 4, f->seq++);
        put32(p + 8, (uint32_t)len); /* message size */
        put32(p + 12, 0);            /* fragment offset */
        p[16] = p[17] = 0;           /* fragment 0 */
        p[18] = 0;
        p[19] = 1; /* of 1 */
        head = 20;
    }
    if (head + ch + len > FLOOD_MAX_DATAGRAM)
        len = FLOOD_MAX_DATAGRAM - head - ch;
    memcpy(p + head, channel, (size_t)ch);
    memcpy(p + head + ch, msg, (size_t)len);
    return head + ch + len;
}

static void send_one(flood *f)
{
    char channel[AUTH_CHANNEL_MAX + 1];
    int n;
    if (f->o.kind == KIND_RAW) {
        n = f->o.size;
        random_bytes(f, f->pkt, (size_t)n);
    } else {
        channel_of(f, channel, sizeof channel);
        if (f->o.kind == KIND_FORGE) {
            n = forged_message(f);
        } else {
            n = f->o.size;
            random_bytes(f, f->msg, (size_t)n);
        }
        n = frame(f, channel, f->msg, n);
    }
    if (sendto(f->fd, f->pkt, (size_t)n, 0, (const struct sockaddr *)&f->to, sizeof f->to) == n) {
        f->sent++;
        f->bytes += n;
    } else {
        f->failed++;
    }
}

static void run(flood *f)
{
    const int64_t t0 = now_ns(),
                  end = f->o.duration_s > 0.0 ? t0 + (int64_t)(f->o.duration_s * 1e9) : INT64_MAX;
    int64_t now = t0, due = 0;
    while (!stop && now < end) {
        if (f->o.rate <= 0.0) {
            send_one(f);
        } else {
            /* the datagrams due by now; then sleep out the millisecond */
            due = (int64_t)((double)(now - t0) * 1e-9 * f->o.rate) + 1;
            while (f->sent + f->failed < due && !stop)
                send_one(f);
            {
                struct timespec ts = { 0, (long)(BATCH_NS - (now_ns() - now) % BATCH_NS) };
                nanosleep(&ts, NULL);
            }
        }
        now = now_ns();
    }
    {
        const double s = (double)(now_ns() - t0) * 1e-9;
        printf(PROG ": %s: %lld datagrams (%.0f/s, %.1f MB/s), %lld not sent, in %.1f s\n",
               kind_names[f->o.kind], (long long)f->sent, (double)f->sent / s,
               (double)f->bytes / s * 1e-6, (long long)f->failed, s);
    }
}

int main(int argc, char **argv)
{
    static flood f;
    const option_program prog = {
        .name = PROG,
        .usage =
            "usage: tandem-flood [--kind junk|forge|raw] [--rate N] [--size BYTES] [--duration S]\n"
            "                    [--channel NAME | --random-channels] [--lcm-url URL]\n"
            "Floods the bus without any key, to measure what refusing costs the daemons\n"
            "(docs/security.md). junk: LCM datagrams of random bytes; forge: messages that\n"
            "look like tandem's (a type's fingerprint, a trailer of the right form) of\n"
            "--size bytes; raw: datagrams without LCM's framing.\n\n",
        .groups = { { flood_table, &f.o } },
        .n_groups = 1,
    };
    int rc;
    f.o.kind = KIND_JUNK;
    f.o.rate = 50000.0;
    f.o.size = 100;
    f.o.duration_s = 10.0;
    f.o.channel = "ARM1_ACTION";
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    if (open_socket(&f) != FLOOD_OK)
        return 1;
    f.rng = (uint64_t)now_ns() | 1u;
    signal(SIGINT, on_signal);
    signal(SIGTERM, on_signal);
    run(&f);
    close(f.fd);
    return 0;
}
