/* tandem-stick: push the stick into an arm's path, or pull it out, in a
 * running tandem-sim (docs/method/carry.md §8). Publishes one SIM_CONTROL message.
 *
 *   tandem-stick insert --arm N --link L [--length M] [--radius R]
 *   tandem-stick remove
 */
#include <stdio.h>
#include <string.h>
#include <lcm/lcm.h>
#include "daemon.h"
#include "options.h"
#include "tandem_sim_control_t.h"

typedef struct stick_options {
    const char *url;
    long   arm, link;
    double length_m, radius_m;
} stick_options;

static const option_entry stick_table[] = {
    { .name = "arm", .type = OPTION_INT, OPTION_AT(stick_options, arm), .min = 1, .max = 2, .meta = "N",
      .help = "arm 1 or 2" },
    { .name = "link", .type = OPTION_INT, OPTION_AT(stick_options, link), .min = 1, .max = 6, .meta = "L",
      .help = "link of that arm" },
    { .name = "length", .type = OPTION_DOUBLE, OPTION_AT(stick_options, length_m), .min = 0.01, .max = 2.0,
      .meta = "M", .help = "rod length in m", .def = "0.6" },
    { .name = "radius", .type = OPTION_DOUBLE, OPTION_AT(stick_options, radius_m), .min = 0.001, .max = 0.1,
      .meta = "R", .help = "rod radius in m", .def = "0.02" },
    { .name = "help", .type = OPTION_HELP, .help = "this text" },
    { .name = NULL }
};

int main(int argc, char **argv)
{
    stick_options o = { NULL, 0, 0, 0.6, 0.02 };
    const option_program prog = {
        .name = "tandem-stick",
        .usage = "usage: tandem-stick insert --arm 1|2 --link 1..6 [--length M] [--radius R] [--lcm-url URL]\n"
                 "                           [--key-file PATH | --insecure]\n"
                 "       tandem-stick remove [--lcm-url URL] [--key-file PATH | --insecure]\n"
                 "Puts a rod just ahead of the given link of the arm, across its motion, so the\n"
                 "link runs into it (docs/method/carry.md §8); 'remove' takes it out. One SIM_CONTROL message.\n\n",
        .epilog = "Exit status: 0 sent, 1 LCM or key error, 2 bad arguments.\n",
        .groups = { { stick_table, &o }, { options_bus_tool, &o.url } }, .n_groups = 2,
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
    if (argc < 2 || (strcmp(argv[1], "insert") && strcmp(argv[1], "remove"))) {
        fprintf(stderr, "tandem-stick: first argument must be 'insert' or 'remove'\n");
        options_print_help(&prog, stderr);
        return 2;
    }
    insert = !strcmp(argv[1], "insert");
    rc = options_parse(&prog, argc, argv, 2);
    if (rc < 0)
        return options_exit_status(rc);
    url = o.url;
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
    auth_bus_identity(AUTH_ROLE_TOOL, 0, 0);
    if (auth_bus_start("tandem-stick") != 0)
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
    if (AUTH_PUBLISH(tandem_sim_control_t, lcm, "SIM_CONTROL", &m) != 0) {
        fprintf(stderr, "tandem-stick: publish failed\n");
        lcm_destroy(lcm);
        return 1;
    }
    if (insert)
        printf("stick inserted at arm %ld link %ld (length %.3f m, radius %.3f m)\n", arm, link, length, radius);
    else
        printf("stick removed\n");
    lcm_destroy(lcm);
    return 0;
}
