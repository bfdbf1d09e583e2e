/* version: prints the build's version (git describe at build time). The
 * string comes from build/gen/tandem_version.h, which the Makefile rewrites
 * only when git describe changes, so a commit does not rebuild everything. */
#include <stdio.h>
#include <string.h>
#include "version.h"
#include "tandem_version.h"

const char *tandem_version(void)
{
    return TANDEM_VERSION;
}

void daemon_print_version(const char *prog)
{
    printf("%s (tandem) %s\n", prog, TANDEM_VERSION);
}

int version_requested(int argc, char **argv, const char *prog)
{
    int i;
    for (i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--"))
            break;
        if (!strcmp(argv[i], "--version")) {
            daemon_print_version(prog);
            return 1;
        }
    }
    return 0;
}
