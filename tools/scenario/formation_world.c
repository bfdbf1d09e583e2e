/* formation_world: the world of a formation run when it comes from a file
 * (docs/formation.md, "Worlds from files"): kept in the output directory
 * as world.yaml + world.pgm (start and goal as flown, after --start and
 * --goal), and that copy is what the simulator and the rovers read, so
 * the run can be flown again from its directory alone; with --world
 * random the world is generated first (worldgen.h) and kept the same way.
 * A picture of it beside them: world.svg.
 */
#include "formation_scen.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "worldgen.h"

const char *const fm_world_names[] = {
    "open", "obstacles", "corridor", "deadzone", "random", NULL
};
const int fm_world_values[] = { ROVER_WORLD_OPEN, ROVER_WORLD_OBSTACLES, ROVER_WORLD_CORRIDOR,
                                ROVER_WORLD_DEADZONE, FM_WORLD_RANDOM };
const char *const fm_world_kinds[] = { "clutter", "traps", "corridor", "mixed", NULL };

static int parse_size(const char *v, double *w, double *h)
{
    char *end;
    *w = strtod(v, &end);
    if (end == v || *end != 'x')
        return 0;
    *h = strtod(end + 1, &end);
    return *end == '\0' && *w > 0.0 && *h > 0.0 && *w < 1e6 && *h < 1e6;
}

int fm_random_world(fm_cfg *cfg)
{
    char why[WORLD_FILE_WHY_MAX];
    rover_map *m;
    rover_map_site s;
    worldgen_params p;
    int rc, attempt = 0;
    memset(&p, 0, sizeof p);
    p.kind = cfg->world_kind;
    p.seed = (uint64_t)cfg->world_seed;
    p.robots = cfg->robots;
    p.formation = cfg->formation;
    if (!parse_size(cfg->world_size ? cfg->world_size : "30x20", &p.width_m, &p.height_m)) {
        fprintf(stderr, "formation: --world-size: '%s' is not WxH (m)\n", cfg->world_size);
        return 2;
    }
    if (!(m = malloc(sizeof *m)))
        return 1;
    rc = worldgen_make(m, &s, &p, &attempt);
    if (rc != WORLDGEN_OK) {
        fprintf(stderr, "formation: --world random --world-kind %s --world-seed %ld: %s\n",
                worldgen_kind_name(p.kind), cfg->world_seed, worldgen_strerror(rc));
        free(m);
        return rc == WORLDGEN_ERR_ARG ? 2 : 1;
    }
    if (scenario_mkdir(cfg->out) != 0 ||
        world_file_write(cfg->out, "world", m, &s, why, sizeof why) != 0) {
        if (why[0])
            fprintf(stderr, "formation: %s\n", why);
        free(m);
        return 1;
    }
    free(m);
    fprintf(stderr, "formation: %s world of seed %ld (sub-seed %d) in %s/world.yaml\n",
            worldgen_kind_name(p.kind), cfg->world_seed, attempt, cfg->out);
    snprintf(cfg->world_copy, sizeof cfg->world_copy, "%s/world.yaml", cfg->out);
    cfg->wopt.file = cfg->world_copy;
    return 0;
}

int fm_keep_world(fm_cfg *cfg)
{
    char why[WORLD_FILE_WHY_MAX];
    cfg->child_world = cfg->wopt;
    if (!cfg->wopt.file)
        return 0;
    if (cfg->world != FM_WORLD_RANDOM && world_opts_save(&cfg->wopt, cfg->out, "formation") != 0)
        return 1;
    if (world_file_write_svg(cfg->out, "world", &cfg->layout, why, sizeof why) != 0)
        fprintf(stderr, "formation: %s\n", why); /* the picture only: the run goes on */
    snprintf(cfg->world_copy, sizeof cfg->world_copy, "%s/world.yaml", cfg->out);
    cfg->child_world.file = cfg->world_copy;
    cfg->child_world.start = NULL;
    cfg->child_world.goal = NULL;
    cfg->world = ROVER_WORLD_FILE;
    return 0;
}

const char *fm_world_arg(const fm_cfg *cfg)
{
    return cfg->world == ROVER_WORLD_FILE ? "open" : rover_world_name(cfg->world);
}
