/* sweep_worlds: run directories and the failing worlds of a sweep over
 * worlds (see sweep_worlds.h; docs/formation.md, "Generated worlds").
 */
#include "sweep_worlds.h"

#include <stdio.h>
#include <string.h>
#include <unistd.h>
#include "scenario.h"

void sweep_run_dir(char *buf, size_t cap, const char *out, int worlds, long seed)
{
    snprintf(buf, cap, "%s/%s-%ld", out, worlds ? "world" : "seed", seed);
}

/* The generator's options (and their values) are not passed on: the world
 * is the file now. */
static int generator_option(const char *word)
{
    return !strcmp(word, "--world") || !strcmp(word, "--world-kind") ||
           !strcmp(word, "--world-size");
}

/* The options a sweep may give as lists, one item per run in turn. */
static const char *const in_turn_options[] = { "--robots", "--formation", "--world-kind", NULL };

/* The list's item i mod n into buf. */
static const char *item_in_turn(const char *list, int i, char *buf, size_t cap)
{
    int n = 1, k;
    const char *p, *e;
    size_t len;
    for (p = list; *p; p++)
        n += *p == ',';
    for (p = list, k = i % n; k > 0; k--)
        p = strchr(p, ',') + 1;
    e = strchr(p, ',');
    len = e ? (size_t)(e - p) : strlen(p);
    snprintf(buf, cap, "%.*s", (int)len, p);
    return buf;
}

const char *sweep_in_turn(const char *const *pass, int k, int i, char *buf, size_t cap)
{
    int o;
    for (o = 0; in_turn_options[o]; o++) {
        const size_t len = strlen(in_turn_options[o]);
        if (k > 0 && !strcmp(pass[k - 1], in_turn_options[o]) && strchr(pass[k], ','))
            return item_in_turn(pass[k], i, buf, cap);
        if (!strncmp(pass[k], in_turn_options[o], len) && pass[k][len] == '=' &&
            strchr(pass[k], ',')) {
            char item[64];
            item_in_turn(pass[k] + len + 1, i, item, sizeof item);
            snprintf(buf, cap, "%s=%s", in_turn_options[o], item);
            return buf;
        }
    }
    return pass[k];
}

void sweep_list_failing(const char *out, const sweep_run *run, int n_run, long noise_seed,
                        const char *const *pass, int n_pass)
{
    FILE *f = scenario_fopen(out, "failing_worlds.txt");
    char dir[1024], yaml[1100];
    int i, k, failing = 0;
    if (!f)
        return;
    fprintf(f, "# worlds whose run did not exit 0; each flies again with the command below it\n");
    for (i = 0; i < n_run; i++) {
        if (!run[i].done || run[i].status == 0)
            continue;
        failing++;
        sweep_run_dir(dir, sizeof dir, out, 1, run[i].seed);
        snprintf(yaml, sizeof yaml, "%s/world.yaml", dir);
        fprintf(f, "# world %ld: exit %d%s\ntandem-scenario formation --world-file %s --seed %ld",
                run[i].seed, run[i].status,
                access(yaml, R_OK) == 0 ? "" : " (no world was written)", yaml, noise_seed);
        for (k = 0; k < n_pass; k++) {
            char item[256];
            if (generator_option(pass[k])) {
                k++;
                continue;
            }
            fprintf(f, " %s", sweep_in_turn(pass, k, i, item, sizeof item));
        }
        fprintf(f, " --out %s/again\n", dir);
    }
    fclose(f);
    printf("failing worlds: %d (each with its command in %s/failing_worlds.txt)\n", failing, out);
}
