/* auth_child: role files for child processes (see auth_child.h). */
#include "auth_child.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "auth_bus.h"

void auth_child_keys_init(auth_child_keys *c, const auth_bus *parent)
{
    memset(c, 0, sizeof *c);
    c->parent = parent;
}

static auth_fleet roster_fleet(const auth_child_keys *c)
{
    return c->parent ? auth_bus_fleet(c->parent) : auth_fleet_clamped(AUTH_ROSTER_ROVERS, 1, 1);
}

/* The value of option --name in argv (--name V or --name=V), or NULL. */
static const char *option_value(const char *const argv[], const char *name)
{
    const size_t n = strlen(name);
    int i;
    for (i = 1; argv[i]; i++) {
        if (strncmp(argv[i], "--", 2) != 0 || strncmp(argv[i] + 2, name, n) != 0)
            continue;
        if (argv[i][2 + n] == '=')
            return argv[i] + 3 + n;
        if (argv[i][2 + n] == '\0')
            return argv[i + 1];
    }
    return NULL;
}

static void set_peer(auth_peer *p, int role, long first, long last)
{
    p->role = (uint8_t)role;
    p->first = (uint16_t)(first < 0 || first > 65535 ? 0 : first);
    p->last = (uint16_t)(last < 0 || last > 65535 ? 0 : last);
}

void auth_child_principal(const char *const argv[], auth_peer *who)
{
    const char *slash = strrchr(argv[0], '/'), *prog = slash ? slash + 1 : argv[0], *v;
    set_peer(who, AUTH_ROLE_TOOL, 0, 0);
    if (strcmp(prog, "tandem-sim") == 0) {
        set_peer(who, AUTH_ROLE_SIM, 0, 0);
    } else if (strcmp(prog, "tandem-arm") == 0) {
        v = option_value(argv, "arm");
        set_peer(who, AUTH_ROLE_ARM, v ? strtol(v, NULL, 10) : 1, v ? strtol(v, NULL, 10) : 1);
    } else if (strcmp(prog, "tandem-supervisor") == 0) {
        set_peer(who, AUTH_ROLE_SUPERVISOR, 0, 0);
    } else if (strcmp(prog, "tandem-rover") == 0) {
        char *end = NULL;
        long a = 0, b;
        v = option_value(argv, "id");
        if (v)
            a = strtol(v, &end, 10);
        b = end && *end == '-' ? strtol(end + 1, NULL, 10) : a;
        set_peer(who, AUTH_ROLE_ROVER, a, b);
    } else if (strcmp(prog, "tandem-status") == 0) {
        set_peer(who, AUTH_ROLE_MONITOR, 0, 0);
    }
}

/* 1 when the child's command line chooses its key itself, or the child
 * is tandem-scenario: a launcher that makes its own children's role files
 * from the master (a trust its parent already gives it). */
static int keyed_by_argv(const char *const argv[])
{
    const char *slash = strrchr(argv[0], '/');
    int i;
    if (strcmp(slash ? slash + 1 : argv[0], "tandem-scenario") == 0)
        return 1;
    for (i = 1; argv[i]; i++)
        if (strcmp(argv[i], "--insecure") == 0 || strncmp(argv[i], "--key-file", 10) == 0)
            return 1;
    return 0;
}

static int in_roster(const auth_peer *who, const auth_peer *roster, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (auth_peer_equal(who, &roster[i]))
            return 1;
    return 0;
}

static int make_dir(auth_child_keys *c)
{
    const char *tmp = getenv("TMPDIR");
    if (c->dir[0])
        return AUTH_CHILD_OK;
    snprintf(c->dir, sizeof c->dir, "%s/tandem-roles-XXXXXX", tmp && tmp[0] == '/' ? tmp : "/tmp");
    if (!mkdtemp(c->dir)) { /* mkdtemp makes it 0700 */
        perror("tandem: role file directory");
        c->dir[0] = '\0';
        return AUTH_CHILD_ERR_DIR;
    }
    return AUTH_CHILD_OK;
}

/* The role file of who from the master set m, written to path. */
static int write_role(const auth_keyset *m, const auth_peer *who, const auth_peer *roster, int n,
                      const char *path)
{
    auth_keyset *k = auth_keyset_new();
    char why[700];
    int rc = AUTH_CHILD_ERR_KEY;
    if (!k)
        return rc;
    auth_keyset_role(k, m->master, who, roster, n);
    unlink(path); /* a restarted child gets a fresh file */
    if (auth_keyset_write(k, path, why, sizeof why) == AUTH_OK)
        rc = AUTH_CHILD_OK;
    else
        fprintf(stderr, "tandem: role file %s\n", why);
    auth_keyset_free(k);
    return rc;
}

int auth_child_key(auth_child_keys *c, const char *const argv[], char *path, size_t cap)
{
    const char *env = getenv(AUTH_BUS_KEY_ENV), *ins = getenv(AUTH_BUS_INSECURE_ENV);
    auth_peer who, roster[AUTH_MAX_TAGS];
    const auth_peer tool = { AUTH_ROLE_TOOL, 0, 0 };
    auth_keyset *m;
    auth_fleet fleet;
    char why[700];
    int n, rc;
    if (!argv || !argv[0])
        return AUTH_CHILD_ERR_ARG;
    if (keyed_by_argv(argv) || !env || !env[0] || (ins && strcmp(ins, "1") == 0))
        return AUTH_CHILD_INHERIT;
    if (!(m = auth_keyset_new()))
        return AUTH_CHILD_ERR_KEY;
    rc = auth_keyset_load(m, env, &tool, why, sizeof why);
    if (rc != AUTH_OK || !m->is_master) { /* a role file is handed on as it is */
        auth_keyset_free(m);
        return rc == AUTH_OK ? AUTH_CHILD_INHERIT : AUTH_CHILD_ERR_KEY;
    }
    auth_child_principal(argv, &who);
    fleet = roster_fleet(c);
    n = auth_roster_fleet(&fleet, roster, AUTH_MAX_TAGS);
    if (!in_roster(&who, roster, n)) {
        fprintf(stderr,
                "tandem: %s: principal %d %d-%d is in no role file of this cell (rovers 1-%d on "
                "%d host(s) of whole teams of %d, and single rovers 1..%d: AUTH_MAX_TAGS)\n",
                argv[0], who.role, who.first, who.last, fleet.rovers, fleet.hosts, fleet.unit,
                fleet.rovers < AUTH_MAX_TAGS - AUTH_ROSTER_FIXED
                    ? fleet.rovers
                    : AUTH_MAX_TAGS - AUTH_ROSTER_FIXED);
        auth_keyset_free(m);
        return AUTH_CHILD_ERR_PRINCIPAL;
    }
    rc = make_dir(c);
    if (rc == AUTH_CHILD_OK) {
        const int len = snprintf(path, cap, "%s/role%d.key", c->dir, c->files++);
        rc = len > 0 && (size_t)len < cap ? write_role(m, &who, roster, n, path)
                                          : AUTH_CHILD_ERR_ARG;
    }
    auth_keyset_free(m);
    return rc;
}

void auth_child_keys_remove(auth_child_keys *c)
{
    char path[600];
    int i;
    if (!c->dir[0])
        return;
    for (i = 0; i < c->files; i++) {
        snprintf(path, sizeof path, "%s/role%d.key", c->dir, i);
        unlink(path);
    }
    rmdir(c->dir);
    c->dir[0] = '\0';
    c->files = 0;
}
