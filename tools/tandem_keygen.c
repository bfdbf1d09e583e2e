/* tandem-keygen: makes the bus key every tandem program signs and checks
 * its messages with (docs/method/lockstep.md §4-5; src/daemons/common/auth.h). 32 random bytes
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
#include "options.h"
#include "version.h"

#define PROG "tandem-keygen"

typedef struct keygen_options {
    int rotate, show;
    const char *path;     /* the one PATH argument, NULL: the default */
} keygen_options;

static const option_entry keygen_table[] = {
    { .name = "rotate", .type = OPTION_FLAG, OPTION_AT(keygen_options, rotate),
      .help = "make a new key; the old one is kept as PATH.prev: restart the daemons with --key-file PATH "
              "--key-file PATH.prev while some still sign with the old key, then with --key-file PATH alone" },
    { .name = "show", .type = OPTION_FLAG, OPTION_AT(keygen_options, show),
      .help = "print the key id byte of PATH (which key signed a message)" },
    { .name = "help", .letter = 'h', .type = OPTION_HELP, .help = "this text" },
    { .name = "version", .type = OPTION_VERSION, .help = "program version" },
    { .name = NULL }
};

/* A word that is not an option: the PATH, once. */
static int path_word(void *user, const char *word)
{
    keygen_options *o = user;
    if (word[0] == '-')
        fprintf(stderr, PROG ": unknown option '%s' (" PROG " --help lists them)\n", word);
    else if (o->path)
        fprintf(stderr, PROG ": one PATH only ('%s', then '%s')\n", o->path, word);
    else {
        o->path = word;
        return 0;
    }
    return OPTIONS_ERR_VALUE;
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
    char def[1024] = "~/.config/tandem/bus.key", usage[1400];
    keygen_options o = { 0, 0, NULL };
    const option_program prog = {
        .name = PROG, .usage = usage,
        .epilog = "\nWithout an option it makes a new key; an existing file is left alone (exit 1).\n"
                  "Exit status: 0 done, 1 key error, 2 bad arguments.\n",
        .groups = { { keygen_table, &o } }, .n_groups = 1,
        .other = path_word, .other_user = &o,   /* exact option names, as before */
    };
    int rc;
    if (version_requested(argc, argv, PROG))
        return 0;
    auth_bus_default_key_path(def, sizeof def);
    snprintf(usage, sizeof usage,
             "usage: tandem-keygen [--rotate | --show] [PATH]\n"
             "Makes the tandem bus key: 32 random bytes (libsodium), mode 0600.\n"
             "PATH defaults to %s.\n\n", def);
    if ((rc = options_parse(&prog, argc, argv, 1)) < 0)
        return options_exit_status(rc);
    if (o.rotate && o.show) {
        fprintf(stderr, PROG ": --rotate and --show exclude each other\n");
        return OPTIONS_EXIT_BAD_ARGS;
    }
    if (!o.path) {
        if (auth_bus_default_key_path(def, sizeof def) != 0) {
            fprintf(stderr, PROG ": no HOME: give the key's PATH\n");
            return 2;
        }
        o.path = def;
    }
    return o.show ? show(o.path) : make(o.path, o.rotate);
}
