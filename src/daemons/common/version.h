/* version: the build's version string (git describe at build time, from the
 * generated tandem_version.h) and the one way every program prints it. */
#ifndef TANDEM_VERSION_H
#define TANDEM_VERSION_H

/* "tandem <git describe>" */
const char *tandem_version(void);
/* Prints "PROG (tandem) VERSION" on stdout, the form help2man reads. */
void daemon_print_version(const char *prog);
/* 1 if argv holds --version (after printing it), else 0: for programs that
 * have no options table (options_parse handles --version itself). */
int version_requested(int argc, char **argv, const char *prog);

#endif
