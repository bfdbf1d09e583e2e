/* run_key: bus key of a scenario run (see run_key.h). */
#include "run_key.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "auth_bus.h"

#define PROG "tandem-scenario"

/* tandem-scenario's one bus (run_key_bus) */
static auth_bus scenario_bus;

auth_bus *run_key_bus(void)
{
    return &scenario_bus;
}

/* 1 and the option's value if argv[i] is --key-file PATH or --key-file=PATH
 * (*used: how many words it took); 2 for --insecure; 0 otherwise. */
static int key_option(int argc, char **argv, int i, const char **value, int *used)
{
    const char *a = argv[i];
    *used = 1;
    if (strcmp(a, "--insecure") == 0)
        return 2;
    if (strncmp(a, "--key-file=", 11) == 0) {
        *value = a + 11;
        return 1;
    }
    if (strcmp(a, "--key-file") == 0) {
        *value = i + 1 < argc ? argv[i + 1] : "";
        *used = i + 1 < argc ? 2 : 1;
        return 1;
    }
    return 0;
}

/* Takes the key options out of argv; RUN_KEY_ERR_OPTION on a bad one. */
static int strip_options(int *argc, char **argv)
{
    int i = 1, j, keys = 0;
    while (i < *argc) {
        const char *value = NULL;
        int used;
        const int kind = key_option(*argc, argv, i, &value, &used);
        if (kind == 0) {
            i++;
            continue;
        }
        if (auth_bus_option(&scenario_bus, PROG, kind == 1 ? OPT_KEY_FILE : OPT_INSECURE, value) <
            0)
            return RUN_KEY_ERR_OPTION;
        if (kind == 1 && keys++ == 0) {
            setenv(AUTH_BUS_KEY_ENV, value, 1); /* the children sign with the first key */
            unsetenv(AUTH_BUS_INSECURE_ENV);
        } else if (kind == 2) {
            setenv(AUTH_BUS_INSECURE_ENV, "1", 1);
            unsetenv(AUTH_BUS_KEY_ENV);
        }
        for (j = i; j + used <= *argc; j++)
            argv[j] = argv[j + used];
        *argc -= used;
    }
    return 0;
}

int run_key_setup(int *argc, char **argv)
{
    char path[700];
    const char *env_key, *env_insecure;
    if (strip_options(argc, argv) != 0)
        return RUN_KEY_ERR_OPTION;
    env_key = getenv(AUTH_BUS_KEY_ENV);
    env_insecure = getenv(AUTH_BUS_INSECURE_ENV);
    if (!(env_key && env_key[0]) && !(env_insecure && strcmp(env_insecure, "1") == 0)) {
        if (auth_bus_ephemeral_key(path, sizeof path) != 0) {
            fprintf(stderr, PROG ": cannot make a key for this run\n");
            return RUN_KEY_ERR_KEY;
        }
    }
    auth_bus_identity(&scenario_bus, AUTH_ROLE_TOOL, 0, 0);
    return auth_bus_start(&scenario_bus, PROG);
}
