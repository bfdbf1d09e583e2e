/* tandem-stick: push the stick into an arm's path, or pull it out, in a
 * running tandem-sim (SPEC.md §2.6). Publishes one SIM_CONTROL message.
 *
 *   tandem-stick insert --arm N --link L [--length M] [--radius R]
 *   tandem-stick remove
 */
#include <stdio.h>
#include <string.h>
#include <lcm/lcm.h>
#include "daemon.h"
#include "tandem_sim_control_t.h"

static void usage(FILE *f)
{
    fprintf(f, "usage: tandem-stick insert --arm 1|2 --link 1..6 [--length M] [--radius R] [--lcm-url URL]\n"
               "                           [--key-file PATH | --insecure]\n"
               "       tandem-stick remove [--lcm-url URL] [--key-file PATH | --insecure]\n"
               "Puts a rod just ahead of the given link of the arm, across its motion, so the\n"
               "link runs into it (SPEC 2.6); 'remove' takes it out. One SIM_CONTROL message.\n\n"
               "  --arm N         arm 1 or 2\n"
               "  --link L        link 1..6 of that arm\n"
               "  --length M      rod length in m (0.01-2, default 0.6)\n"
               "  --radius R      rod radius in m (0.001-0.1, default 0.02)\n"
               "  --lcm-url URL   LCM provider (default $LCM_DEFAULT_URL or " DAEMON_DEFAULT_LCM_URL ")\n"
               AUTH_BUS_HELP
               "  --help          this text\n"
               "Exit status: 0 sent, 1 LCM or key error, 2 bad arguments.\n");
}

int main(int argc, char **argv)
{
    static const struct option opts[] = {
        { "arm", required_argument, 0, 'a' },
        { "link", required_argument, 0, 'l' },
        { "length", required_argument, 0, 'L' },
        { "radius", required_argument, 0, 'r' },
        { "lcm-url", required_argument, 0, 'u' },
        { "help", no_argument, 0, 'h' },
        AUTH_BUS_OPTIONS,
        { 0, 0, 0, 0 }
    };
    if (version_requested(argc, argv, "tandem-stick"))
        return 0;
    tandem_sim_control_t m;
    const char *url = NULL;
    long arm = 0, link = 0;
    double length = 0.6, radius = 0.02;
    int c, insert;
    lcm_t *lcm;
    if (argc >= 2 && (!strcmp(argv[1], "--help") || !strcmp(argv[1], "-h"))) {
        usage(stdout);
        return 0;
    }
    if (argc < 2 || (strcmp(argv[1], "insert") && strcmp(argv[1], "remove"))) {
        fprintf(stderr, "tandem-stick: first argument must be 'insert' or 'remove'\n");
        usage(stderr);
        return 2;
    }
    insert = !strcmp(argv[1], "insert");
    optind = 2;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        switch (c) {
        case 'a': if (parse_int_opt("tandem-stick", "--arm", optarg, 1, 2, &arm) < 0) return 2; break;
        case 'l': if (parse_int_opt("tandem-stick", "--link", optarg, 1, 6, &link) < 0) return 2; break;
        case 'L': if (parse_double_opt("tandem-stick", "--length", optarg, 0.01, 2.0, &length) < 0) return 2; break;
        case 'r': if (parse_double_opt("tandem-stick", "--radius", optarg, 0.001, 0.1, &radius) < 0) return 2; break;
        case 'u': url = optarg; break;
        case 'h': usage(stdout); return 0;
        default:
            if (auth_bus_option("tandem-stick", c, optarg) > 0) break;
            usage(stderr);
            return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "tandem-stick: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
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
