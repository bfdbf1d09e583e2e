/* tandem-stick: push the stick into an arm's path, or pull it out, in a
 * running tandem-sim (docs/method/carry.md §8). Publishes SIM_CONTROL and
 * sends it again until the simulator's SIM_STATUS shows the stick as asked
 * (a lost message must not leave a stick in the cell), at most --timeout s.
 *
 *   tandem-stick insert --arm N --link L [--length M] [--radius R]
 *   tandem-stick remove
 */
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <lcm/lcm.h>
#include "daemon.h"
#include "options.h"
#include "tandem_sim_control_t.h"
#include "tandem_sim_status_t.h"

#define RESEND_S 0.5        /* a command not shown by then is sent again */
#define STATUS_AFTER_S 0.25 /* a status this long after a send has seen it */

typedef struct stick_options {
    options_bus net; /* --lcm-url, --key-file, --insecure */
    long arm, link;
    double length_m, radius_m;
    double timeout_s;
} stick_options;

/* The simulator's stick as its last SIM_STATUS said, and when it came. */
typedef struct stick_seen {
    int inserted;
    double rx_s; /* monotonic time, < 0 none */
} stick_seen;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const tandem_sim_status_t *m,
                      void *u)
{
    stick_seen *s = u;
    (void)rb;
    (void)ch;
    s->inserted = m->stick_inserted != 0;
    s->rx_s = now_s();
}
AUTH_TYPED_HANDLER(tandem_sim_status_t, raw_on_status, on_status)

/* Sends m until a SIM_STATUS from after a send shows the stick as asked:
 * 0, or 1 when timeout_s passed first (0: sent once, not waited for). */
static int send_until_seen(auth_bus *bus, lcm_t *lcm, const tandem_sim_control_t *m, int want,
                           double timeout_s)
{
    stick_seen seen = { 0, -1.0 };
    const double t0 = now_s();
    double sent = -1.0;
    int tries = 0;
    auth_bus_subscribe(bus, lcm, "SIM_STATUS", raw_on_status, &seen);
    for (;;) {
        const double t = now_s();
        if (sent >= 0.0 && seen.rx_s >= sent + STATUS_AFTER_S && seen.inserted == want)
            return 0;
        if (timeout_s > 0.0 && t - t0 > timeout_s)
            break;
        if (sent < 0.0 || t - sent > RESEND_S) {
            if (AUTH_PUBLISH(tandem_sim_control_t, bus, lcm, "SIM_CONTROL", m) != 0)
                return 1;
            if (tries++ > 0)
                fprintf(stderr, "tandem-stick: not shown by the simulator yet: sent again\n");
            sent = t;
            if (timeout_s <= 0.0)
                return 0;
        }
        lcm_handle_timeout(lcm, 50);
    }
    fprintf(stderr,
            "tandem-stick: the simulator did not show the stick %s within %.1f s (%d sends)\n",
            want ? "in" : "out", timeout_s, tries);
    return 1;
}

static const option_entry stick_table[] = {
    { .name = "arm",
      .type = OPTION_INT,
      OPTION_AT(stick_options, arm),
      .min = 1,
      .max = 2,
      .meta = "N",
      .help = "arm 1 or 2" },
    { .name = "link",
      .type = OPTION_INT,
      OPTION_AT(stick_options, link),
      .min = 1,
      .max = 6,
      .meta = "L",
      .help = "link of that arm" },
    { .name = "length",
      .type = OPTION_DOUBLE,
      OPTION_AT(stick_options, length_m),
      .min = 0.01,
      .max = 2.0,
      .meta = "M",
      .help = "rod length in m",
      .def = "0.6" },
    { .name = "radius",
      .type = OPTION_DOUBLE,
      OPTION_AT(stick_options, radius_m),
      .min = 0.001,
      .max = 0.1,
      .meta = "R",
      .help = "rod radius in m",
      .def = "0.02" },
    { .name = "timeout",
      .type = OPTION_DOUBLE,
      OPTION_AT(stick_options, timeout_s),
      .min = 0.0,
      .max = 600.0,
      .meta = "S",
      .help = "send again until the simulator's SIM_STATUS shows the stick, at most S s "
              "(0: send once, do not wait)",
      .def = "5" },
    OPTION_HELP_ENTRY(0),
    { .name = NULL }
};

int main(int argc, char **argv)
{
    auth_bus bus;
    stick_options o = { { NULL, &bus }, 0, 0, 0.6, 0.02, 5.0 };
    const option_program prog = {
        .name = "tandem-stick",
        .usage =
            "usage: tandem-stick insert --arm 1|2 --link 1..6 [--length M] [--radius R] [--lcm-url URL]\n"
            "                           [--key-file PATH | --insecure]\n"
            "       tandem-stick remove [--lcm-url URL] [--key-file PATH | --insecure]\n"
            "Puts a rod just ahead of the given link of the arm, across its motion, so the\n"
            "link runs into it (docs/method/carry.md §8); 'remove' takes it out. SIM_CONTROL, sent\n"
            "again until the simulator shows it (--timeout).\n\n",
        .epilog =
            "Exit status: 0 shown by the simulator (or sent, --timeout 0), 1 LCM or key error or not\n"
            "shown within --timeout, 2 bad arguments.\n",
        .groups = { { stick_table, &o }, { options_bus_tool, &o.net } },
        .n_groups = 2,
    };
    if (version_requested(argc, argv, "tandem-stick"))
        return 0;
    tandem_sim_control_t m;
    const char *url;
    long arm, link;
    double length, radius;
    int rc, insert;
    lcm_t *lcm;
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        options_print_help(&prog, stdout);
        return 0;
    }
    if (argc < 2 || (strcmp(argv[1], "insert") != 0 && strcmp(argv[1], "remove") != 0)) {
        fprintf(stderr, "tandem-stick: first argument must be 'insert' or 'remove'\n");
        options_print_help(&prog, stderr);
        return 2;
    }
    insert = !strcmp(argv[1], "insert");
    auth_bus_init(&bus);
    rc = options_parse(&prog, argc, argv, 2);
    if (rc < 0)
        return options_exit_status(rc);
    url = o.net.url;
    arm = o.arm;
    link = o.link;
    length = o.length_m;
    radius = o.radius_m;
    if (insert && (arm == 0 || link == 0)) {
        fprintf(stderr, "tandem-stick: insert needs --arm and --link\n");
        return 2;
    }
    if (!insert && (arm || link)) {
        fprintf(stderr, "tandem-stick: remove takes no --arm/--link (there is one stick)\n");
        return 2;
    }
    auth_bus_identity(&bus, AUTH_ROLE_TOOL, 0, 0);
    if (auth_bus_start(&bus, "tandem-stick") != 0)
        return 1;
    lcm = lcm_create(url);
    if (!lcm) {
        fprintf(stderr, "tandem-stick: cannot open LCM at '%s'\n", url ? url : "(default)");
        return 1;
    }
    memset(&m, 0, sizeof m);
    m.utime = daemon_utime_now();
    m.command = insert ? TANDEM_SIM_CONTROL_T_INSERT_STICK : TANDEM_SIM_CONTROL_T_REMOVE_STICK;
    m.target = (int32_t)arm;
    m.link = (int32_t)link;
    m.length_m = insert ? length : 0.0;
    m.radius_m = insert ? radius : 0.0;
    if (send_until_seen(&bus, lcm, &m, insert, o.timeout_s) != 0) {
        lcm_destroy(lcm);
        return 1;
    }
    if (insert)
        printf("stick inserted at arm %ld link %ld (length %.3f m, radius %.3f m)\n", arm, link,
               length, radius);
    else
        printf("stick removed\n");
    lcm_destroy(lcm);
    return 0;
}
