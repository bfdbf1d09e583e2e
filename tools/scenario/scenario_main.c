/* tandem-scenario NAME [options] --out DIR: dispatch to one scenario. */
#include <stdio.h>
#include <string.h>
#include "daemon.h"
#include "run_key.h"
#include "scenario.h"
#include "version.h"

/* Each tools/scenario/scenario_<name>.c defines `const scenario_def
 * scenario_<name>`; the Makefile lists them in SCENARIO_LIST. */
extern const scenario_def scenario_carry, scenario_singularity, scenario_liquid, scenario_formation,
    scenario_sweep;

static const scenario_def *const all[] = { SCENARIO_LIST };

static void usage(FILE *f)
{
    size_t i;
    fprintf(f, "usage: tandem-scenario NAME [options] --out DIR\n"
               "Runs an experiment (lockstep, deterministic for a seed) and writes\n"
               "DIR/summary.json, CSV time series and PNG plots.\n\nscenarios:\n");
    for (i = 0; i < sizeof all / sizeof all[0]; i++)
        fprintf(f, "  %-13s %s\n", all[i]->name, all[i]->summary);
    fprintf(f, "\n'tandem-scenario NAME --help' lists a scenario's options.\n" RUN_KEY_HELP);
}

int main(int argc, char **argv)
{
    size_t i;
    names_watch_env(argv); /* G_SLICE for the bound on LCM's names (daemon.h) */
    if (version_requested(argc, argv, "tandem-scenario"))
        return 0;
    if (argc < 2 || !strcmp(argv[1], "--help") || !strcmp(argv[1], "-h")) {
        usage(argc < 2 ? stderr : stdout);
        return argc < 2 ? 2 : 0;
    }
    for (i = 0; i < sizeof all / sizeof all[0]; i++)
        if (strcmp(argv[1], all[i]->name) == 0) {
            if (run_key_setup(&argc, argv) != 0)
                return 1;
            return all[i]->run(argc - 1, argv + 1);
        }
    fprintf(stderr, "tandem-scenario: unknown scenario '%s'\n", argv[1]);
    usage(stderr);
    return 2;
}
