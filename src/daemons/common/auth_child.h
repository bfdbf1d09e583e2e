/* auth_child: the role file of a child process (docs/security.md).
 *
 * A parent that holds its cell's master (tandem-scenario, the integration
 * tests: a key made for the run, $TANDEM_KEY_FILE) must not hand the
 * master on: a child holding it could sign as any principal. Before each
 * child starts, auth_child_key writes the role file of the principal its
 * command line names into a 0700 directory of the parent's, and the child
 * is given that file in $TANDEM_KEY_FILE:
 *
 *   tandem-sim          the simulator
 *   tandem-arm --arm K  arm K (1 without --arm)
 *   tandem-supervisor   the supervisor
 *   tandem-rover --id K rover K; --id A-B the host of rovers A..B
 *   tandem-status       a monitor (receive keys only)
 *   tandem-scenario     the master as it is (a launcher: it makes its
 *                       own children's role files)
 *   anything else       a tool
 *
 * The roster is the parent's bus's (auth_bus_roster; auth_child_keys.parent): rovers 1..N and the host
 * of all N; a rover host of another range is in no role file and is
 * refused (AUTH_CHILD_ERR_PRINCIPAL). With --insecure, or a key file that
 * is itself a role file, the child inherits the environment as it is.
 */
#ifndef TANDEM_AUTH_CHILD_H
#define TANDEM_AUTH_CHILD_H

#include <stddef.h>
#include "auth.h"

/* Results (distinct values); auth_child_strerror names them. */
#define AUTH_CHILD_INHERIT 1      /* no role file made: the child keeps the environment */
#define AUTH_CHILD_OK 0           /* a role file made: *path */
#define AUTH_CHILD_ERR_DIR (-201) /* the 0700 directory cannot be made */
#define AUTH_CHILD_ERR_KEY (-202) /* the master does not load, or the file cannot be written */
#define AUTH_CHILD_ERR_PRINCIPAL (-203) /* the command line names a principal outside the roster */
#define AUTH_CHILD_ERR_ARG (-204)       /* no argv[0], or the path does not fit */
const char *auth_child_strerror(int rc);

struct auth_bus;
typedef struct auth_child_keys {
    char dir[512];                 /* the role files' directory; "" until the first is made */
    int files;                     /* role files written (their names are numbered) */
    const struct auth_bus *parent; /* the parent's bus: its roster (NULL: the
                                        default roster, AUTH_ROSTER_ROVERS) */
} auth_child_keys;

/* parent: the bus whose roster the role files list (NULL: the default). */
void auth_child_keys_init(auth_child_keys *c, const struct auth_bus *parent);
/* The principal a command line names (the table above). */
void auth_child_principal(const char *const argv[], auth_peer *who);
/* Writes the role file for argv's principal from the master in
 * $TANDEM_KEY_FILE: AUTH_CHILD_OK and its path, AUTH_CHILD_INHERIT, or an
 * error (said on stderr). */
int auth_child_key(auth_child_keys *c, const char *const argv[], char *path, size_t cap);
/* Removes the role files and their directory. */
void auth_child_keys_remove(auth_child_keys *c);

#endif
