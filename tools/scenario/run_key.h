/* run_key: the bus key of a tandem-scenario run (docs/method/lockstep.md §4-5). The options
 * --key-file PATH and --insecure are taken out of the command line before
 * the scenario parses it. Without them the run uses $TANDEM_KEY_FILE if
 * set, else a key made for this run alone (a 0600 file in a fresh
 * temporary directory, removed at exit). When that key is the cell's
 * master, each child the run starts gets only the role file of the
 * principal its command line names (auth_child.h: proc_spawn and the
 * formation run's spawn make it), in $TANDEM_KEY_FILE; a role file or
 * --insecure is handed on as it is ($TANDEM_KEY_FILE, $TANDEM_INSECURE). */
#ifndef TANDEM_RUN_KEY_H
#define TANDEM_RUN_KEY_H

#include "auth_bus.h"

#define RUN_KEY_HELP                                                                \
    "\nbus authentication (every scenario):\n"                                      \
    "  --key-file PATH   sign and check with this key (default $TANDEM_KEY_FILE,\n" \
    "                    else a key made for this run alone)\n"                     \
    "  --insecure        no authentication for this run and its daemons\n"

/* Removes the options from argv (updating *argc), sets up the key for this
 * process (a tool: it sends SIM_CONTROL, SIM_ACK, joint references) and
 * its children. 0, or RUN_KEY_ERR_OPTION, RUN_KEY_ERR_KEY or
 * auth_bus_start's AUTH_BUS_ERR_* after printing why. */
#define RUN_KEY_ERR_OPTION (-301) /* a --key-file auth_bus_option refuses */
#define RUN_KEY_ERR_KEY (-302)    /* no key made for this run */
int run_key_setup(int *argc, char **argv);
/* The bus of this tandem-scenario process (the program holds it here, as
 * a daemon holds its own in its `daemon`): run_key_setup starts it; each
 * scenario takes it at its set-up and passes it on (the carry run in
 * carry_state.bus, the formation run in fm_bus.auth, the TDSD run in its
 * state). */
auth_bus *run_key_bus(void);

#endif
