/* sweep_worlds: what tandem-scenario sweep adds for sweeps over worlds
 * (--world-seeds): the runs' directories (DIR/world-W) and the list of
 * failing worlds with the command that flies each again from its file.
 */
#ifndef TANDEM_SWEEP_WORLDS_H
#define TANDEM_SWEEP_WORLDS_H

#include <stddef.h>
#include <sys/types.h>

#define SWEEP_MAX_KEYS 24
#define SWEEP_VAL 48

typedef struct sweep_run {
    long seed; /* the noise seed, or the world seed in a sweep over worlds */
    pid_t pid;
    int status; /* exit status, or SWEEP_NOT_RUN */
    int done;
    char val[SWEEP_MAX_KEYS][SWEEP_VAL];
} sweep_run;

/* DIR/seed-S, or DIR/world-W when over worlds. */
void sweep_run_dir(char *buf, size_t cap, const char *out, int worlds, long seed);

/* pass[k] as run i (from 0) gives it: --robots, --formation and
 * --world-kind may be lists (--robots 3,4,6,8 or --robots=3,4,6,8), and
 * run i takes item i mod n of each; lists of co-prime lengths (4 sizes,
 * 3 formations) so give every pair in turn, each once in 12 runs. Other
 * words as they are; an item goes to buf. */
const char *sweep_in_turn(const char *const *pass, int k, int i, char *buf, size_t cap);

/* DIR/failing_worlds.txt: for every run that did not exit 0, its world
 * file and the command that flies it again (the sweep's options for the
 * scenario with the generator's replaced by --world-file); a line on
 * stdout says how many. */
void sweep_list_failing(const char *out, const sweep_run *run, int n_run, long noise_seed,
                        const char *const *pass, int n_pass);

#endif
