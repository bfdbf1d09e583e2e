/* tandem-keygen: makes the bus key every tandem program signs and checks
 * its messages with (docs/method/lockstep.md §4-5; daemons/common/auth.h). 32 random bytes
 * from libsodium in a file only its owner may read (0600), by default
 * ${XDG_CONFIG_HOME:-~/.config}/tandem/bus.key, which `make run` also
 * creates on first use.
 *
 *   tandem-keygen [PATH]           a new key; an existing file is kept
 *   tandem-keygen --rotate [PATH]  a new key; the old one moves to PATH.prev
 *   tandem-keygen --show [PATH]    the key id byte of a key file
 */
#include <stdio.h>
#include <string.h>
#include "auth.h"
#include "auth_bus.h"
#include "version.h"

#define PROG "tandem-keygen"

static void usage(FILE *f)
{
    char def[1024] = "~/.config/tandem/bus.key";
    auth_bus_default_key_path(def, sizeof def);
    fprintf(f, "usage: tandem-keygen [--rotate | --show] [PATH]\n"
               "Makes the tandem bus key: 32 random bytes (libsodium), mode 0600.\n"
               "PATH defaults to %s.\n\n"
               "  (no option)  make a new key; an existing file is left alone (exit 1)\n"
               "  --rotate     make a new key; the old one is kept as PATH.prev: restart the\n"
               "               daemons with --key-file PATH --key-file PATH.prev while some\n"
               "               still sign with the old key, then with --key-file PATH alone\n"
               "  --show       print the key id byte of PATH (which key signed a message)\n"
               "  --help, --version\n"
               "Exit status: 0 done, 1 key error, 2 bad arguments.\n", def);
}

static int show(const char *path)
{
    auth_key k;
    char why[1200];
    if (auth_init() != 0 || auth_key_load(&k, path, why, sizeof why) != AUTH_OK) {
        fprintf(stderr, PROG ": %s\n", why);
        return 1;
    }
    printf("%s: key id 0x%02x\n", path, k.id);
    return 0;
}

static int make(const char *path, int rotate)
{
    char why[1200], next[1100], prev[1100];
    if (!rotate) {
        if (auth_key_create(path, why, sizeof why) != AUTH_OK) {
            fprintf(stderr, PROG ": %s\n", why);
            return 1;
        }
        printf("new bus key: %s\n", path);
        return show(path);
    }
    snprintf(next, sizeof next, "%s.new", path);
    snprintf(prev, sizeof prev, "%s.prev", path);
    if (auth_key_create(next, why, sizeof why) != AUTH_OK) {
        fprintf(stderr, PROG ": %s\n", why);
        return 1;
    }
    if (rename(path, prev) != 0 || rename(next, path) != 0) {
        perror(PROG ": rename");
        remove(next);
        return 1;
    }
    printf("new bus key: %s (the previous one is %s)\n", path, prev);
    return show(path);
}

int main(int argc, char **argv)
{
    char def[1024];
    const char *path = NULL;
    int i, rotate = 0, show_only = 0;
    if (version_requested(argc, argv, PROG))
        return 0;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--help") || !strcmp(argv[i], "-h")) {
            usage(stdout);
            return 0;
        } else if (!strcmp(argv[i], "--rotate")) {
            rotate = 1;
        } else if (!strcmp(argv[i], "--show")) {
            show_only = 1;
        } else if (argv[i][0] != '-' && !path) {
            path = argv[i];
        } else {
            usage(stderr);
            return 2;
        }
    }
    if (rotate && show_only) {
        usage(stderr);
        return 2;
    }
    if (!path) {
        if (auth_bus_default_key_path(def, sizeof def) != 0) {
            fprintf(stderr, PROG ": no HOME: give the key's PATH\n");
            return 2;
        }
        path = def;
    }
    return show_only ? show(path) : make(path, rotate);
}
