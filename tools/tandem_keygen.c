/* tandem-keygen: makes the key set of a cell (docs/method/lockstep.md §4-5;
 * src/daemons/common/auth.h): a master secret (32 random bytes from libsodium,
 * mode 0600, by default ${XDG_CONFIG_HOME:-~/.config}/tandem/bus.key) and,
 * with --cell DIR, one role file per principal holding only the pairwise
 * keys that principal takes part in (sim, arm1, arm2, supervisor, tool,
 * monitor, rover1..N, and rover1-N for one process hosting the whole
 * team: tandem-rover --id 1-N). tools/tandem-run and tandem-scenario make a fresh
 * set per run.
 *
 *   tandem-keygen [PATH]                 a new master; an existing file is kept
 *   tandem-keygen --rotate [PATH]        a new master; the old one moves to PATH.prev
 *   tandem-keygen --show [PATH]          key id and cell id of a key file
 *   tandem-keygen --cell DIR [--rovers N] [--revoke NAME] [PATH]
 *                                        role files DIR/<name>.key from the master
 *                                        PATH (made if missing); --revoke leaves
 *                                        NAME out of every file (its keys stop working)
 *   tandem-keygen --cell DIR --rovers N --hosts H [--robots-per-team K] [PATH]
 *                                        a fleet on H hosts of whole teams of K:
 *                                        roverA-B.key for each (auth_fleet_host)
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#include <sodium.h>
#include "auth.h"
#include "auth_acl.h"
#include "auth_bus.h"
#include "options.h"
#include "version.h"

#define PROG "tandem-keygen"

typedef struct keygen_options {
    int rotate, show;
    int rovers;
    int hosts, per_team; /* --hosts, --robots-per-team: the fleet's hosts (auth_fleet) */
    const char *cell;    /* --cell DIR */
    const char *revoke;  /* --revoke NAME */
    const char *path;    /* the one PATH argument, NULL: the default */
} keygen_options;

static const option_entry keygen_table[] = {
    { .name = "rotate",
      .type = OPTION_FLAG,
      OPTION_AT(keygen_options, rotate),
      .help =
          "make a new key; the old one is kept as PATH.prev: restart the daemons with --key-file PATH "
          "--key-file PATH.prev while some still sign with the old key, then with --key-file PATH alone" },
    { .name = "show",
      .type = OPTION_FLAG,
      OPTION_AT(keygen_options, show),
      .help = "print the key id byte of PATH (which key signed a message)" },
    { .name = "cell",
      .type = OPTION_STRING,
      OPTION_AT(keygen_options, cell),
      .min = 1,
      .meta = "DIR",
      .help =
          "write the role files of a cell into DIR (0700): DIR/sim.key, arm1.key, arm2.key, supervisor.key, "
          "tool.key, monitor.key, rover1.key ... and rover1-N.key (a process hosting the whole team)" },
    { .name = "rovers",
      .type = OPTION_INT,
      OPTION_AT(keygen_options, rovers),
      .min = 0,
      .max = AUTH_ACL_NUMBER_MAX,
      .meta = "N",
      .help = "with --cell: rovers in the cell (default 8; at most 41 without --hosts)" },
    { .name = "hosts",
      .type = OPTION_INT,
      OPTION_AT(keygen_options, hosts),
      .min = 1,
      .max = AUTH_FLEET_HOSTS_MAX,
      .meta = "H",
      .help =
          "with --cell: the rovers hosted by H processes of whole teams, roverA-B.key each (the "
          "ranges tandem-scenario formation --hosts H gives them); --rovers may then be up to "
          "65535, single rovers' files as far as a message's tags go" },
    { .name = "robots-per-team",
      .type = OPTION_INT,
      OPTION_AT(keygen_options, per_team),
      .min = 1,
      .max = 65535,
      .meta = "K",
      .help = "with --hosts: a team's robots, the unit a host's range is made of" },
    { .name = "revoke",
      .type = OPTION_STRING,
      OPTION_AT(keygen_options, revoke),
      .min = 1,
      .meta = "NAME",
      .help =
          "with --cell: leave principal NAME (e.g. rover2) out of every role file; restart the others with "
          "their new files and NAME is refused" },
    OPTION_HELP_ENTRY('h'),
    OPTION_VERSION_ENTRY,
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

static void print_cell(const auth_keyset *k)
{
    int i;
    printf("key id 0x%02x, cell ", k->id);
    for (i = 0; i < AUTH_CELL_BYTES; i++)
        printf("%02x", k->cell[i]);
}

static int show(const char *path)
{
    const auth_peer anyone = { AUTH_ROLE_TOOL, 0, 0 };
    auth_keyset *k;
    char why[1200];
    if (auth_init() != 0 || !(k = auth_keyset_new())) {
        fprintf(stderr, PROG ": libsodium does not start\n");
        return 1;
    }
    if (auth_keyset_load(k, path, &anyone, why, sizeof why) != AUTH_OK) {
        fprintf(stderr, PROG ": %s\n", why);
        auth_keyset_free(k);
        return 1;
    }
    printf("%s: %s, ", path, k->is_master ? "master" : "role file");
    print_cell(k);
    if (!k->is_master)
        printf(", holder role %d instances %d-%d, %d pairwise keys", k->holder.role,
               k->holder.first, k->holder.last, k->n);
    printf("\n");
    auth_keyset_free(k);
    return 0;
}

/* The file name of a principal: sim, arm1, supervisor, tool, monitor,
 * rover3, and rover1-3 for the host of a whole team of three. */
static void peer_name(const auth_peer *p, char *out, size_t cap)
{
    auth_principal_name(p->role, p->first, p->last, out, cap);
}

/* Writes DIR/<name>.key for every principal of the roster but the revoked one. */
static int write_cell(const char *dir, const uint8_t *master, const auth_fleet *fleet,
                      const char *revoke)
{
    auth_peer roster[AUTH_MAX_TAGS], kept[AUTH_MAX_TAGS];
    auth_keyset *k = auth_keyset_new();
    char name[32], path[1200], tmp[1300], why[1400];
    int i, n, m = 0, rc = 0;
    if (!k)
        return 1;
    n = auth_roster_fleet(fleet, roster, AUTH_MAX_TAGS);
    for (i = 0; i < n; i++) {
        peer_name(&roster[i], name, sizeof name);
        if (!revoke || strcmp(revoke, name) != 0)
            kept[m++] = roster[i];
    }
    if (revoke && m == n)
        fprintf(stderr, PROG ": --revoke %s: no such principal in the cell\n", revoke), rc = 1;
    for (i = 0; i < m && rc == 0; i++) {
        peer_name(&kept[i], name, sizeof name);
        snprintf(path, sizeof path, "%s/%s.key", dir, name);
        snprintf(tmp, sizeof tmp, "%s/.%s.key.new", dir, name);
        auth_keyset_role(k, master, &kept[i], kept, m);
        remove(tmp);
        /* written beside, then renamed over: a reader sees the old or the new file */
        if (auth_keyset_write(k, tmp, why, sizeof why) != AUTH_OK || rename(tmp, path) != 0) {
            fprintf(stderr, PROG ": %s\n", why);
            rc = 1;
        }
    }
    if (revoke && rc == 0) {
        snprintf(path, sizeof path, "%s/%s.key", dir, revoke);
        remove(path);
        printf("revoked %s: restart the other daemons with their new files in %s\n", revoke, dir);
    }
    auth_keyset_free(k);
    return rc;
}

static int make_cell(const keygen_options *o)
{
    const auth_fleet fleet = auth_fleet_clamped(o->rovers, o->hosts, o->per_team);
    uint8_t *master;
    char why[1200];
    int rc;
    if (mkdir(o->cell, 0700) != 0 && access(o->cell, F_OK) != 0) {
        perror(PROG ": --cell");
        return 1;
    }
    if (access(o->path, F_OK) != 0 && auth_key_create(o->path, why, sizeof why) != AUTH_OK) {
        fprintf(stderr, PROG ": %s\n", why);
        return 1;
    }
    if (auth_init() != 0 || !(master = sodium_malloc(AUTH_KEY_BYTES)))
        return 1;
    rc = auth_master_load(master, o->path, why, sizeof why);
    if (rc != AUTH_OK)
        fprintf(stderr, PROG ": %s\n", why);
    else
        rc = write_cell(o->cell, master, &fleet, o->revoke);
    sodium_free(master);
    if (rc == 0 && !o->revoke)
        printf("cell key set in %s (master %s): give each daemon --key-file %s/<name>.key\n",
               o->cell, o->path, o->cell);
    return rc == 0 ? 0 : 1;
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
    keygen_options o = { 0, 0, AUTH_ROSTER_ROVERS, 1, 1, NULL, NULL, NULL };
    const option_program prog = {
        .name = PROG,
        .usage = usage,
        .epilog =
            "\nWithout an option it makes a new key; an existing file is left alone (exit 1).\n"
            "Exit status: 0 done, 1 key error, 2 bad arguments.\n",
        .groups = { { keygen_table, &o } },
        .n_groups = 1,
        .other = path_word,
        .other_user = &o, /* exact option names, as before */
    };
    int rc;
    if (version_requested(argc, argv, PROG))
        return 0;
    auth_bus_default_key_path(def, sizeof def);
    snprintf(usage, sizeof usage,
             "usage: tandem-keygen [--rotate | --show | --cell DIR [--rovers N] [--hosts H "
             "[--robots-per-team K]] [--revoke NAME]] [PATH]\n"
             "Makes the master key of a tandem cell: 32 random bytes (libsodium), mode 0600;\n"
             "with --cell, the role files of the cell's daemons and tools from it.\n"
             "PATH defaults to %s.\n\n",
             def);
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
    if (o.rovers < 0 || (o.hosts <= 1 && o.rovers > AUTH_MAX_TAGS - AUTH_ROSTER_FIXED) ||
        (o.revoke && !o.cell)) {
        fprintf(stderr, PROG ": --rovers 0..%d (more with --hosts); --revoke needs --cell\n",
                AUTH_MAX_TAGS - AUTH_ROSTER_FIXED);
        return OPTIONS_EXIT_BAD_ARGS;
    }
    if (o.cell)
        return make_cell(&o);
    return o.show ? show(o.path) : make(o.path, o.rotate);
}
