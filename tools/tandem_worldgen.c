/* tandem-worldgen: writes a rover world in the map_server format (YAML +
 * PGM, tandem's keys under `tandem:`) and a preview (SVG): a random world
 * of a kind with a checked way from start to goal (worldgen.h), or one of
 * the built-in worlds rasterised (--export NAME) so users see the format.
 *
 *   tandem-worldgen --kind clutter|traps|corridor|mixed --seed W [--size WxH]
 *                   [--robots N] [--formation F] --out DIR
 *   tandem-worldgen --export open|obstacles|corridor|deadzone --out DIR
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "proc.h"
#include "formation.h"
#include "options.h"
#include "world_file.h"
#include "worldgen.h"

#define EXPORT_RESOLUTION_M 0.05

typedef struct gen_options {
    const char *kind, *exported, *out, *size;
    long seed, robots;
    int formation, seed_given, out_given;
} gen_options;

static const option_entry gen_table[] = {
    { .name = "kind",
      .type = OPTION_STRING,
      OPTION_AT(gen_options, kind),
      .meta = "K",
      .help =
          "clutter (convex obstacles) | traps (U, V, L pockets) | corridor (bends, narrowings) | mixed",
      .def = "mixed" },
    { .name = "seed",
      .type = OPTION_INT,
      OPTION_AT(gen_options, seed),
      OPTION_SEEN(gen_options, seed_given),
      .min = 0,
      .max = 2147483647.0,
      .meta = "W",
      .help = "the world's seed (the same seed, the same world)" },
    { .name = "size",
      .type = OPTION_STRING,
      OPTION_AT(gen_options, size),
      .meta = "WxH",
      .help = "map size in metres",
      .def = "30x20" },
    { .name = "robots",
      .type = OPTION_INT,
      OPTION_AT(gen_options, robots),
      .min = 1,
      .max = ROVER_TEAM_MAX,
      .meta = "N",
      .help = "team size: the start area holds it, the check places it",
      .def = "3" },
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(gen_options, formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .meta = "F",
      .help = "the team's start formation",
      .def = "line" },
    { .name = "export",
      .type = OPTION_STRING,
      OPTION_AT(gen_options, exported),
      .meta = "NAME",
      .help =
          "write built-in world NAME (open, obstacles, corridor, deadzone; 3 robots) as a map instead" },
    { .name = "out",
      .type = OPTION_STRING,
      OPTION_AT(gen_options, out),
      OPTION_SEEN(gen_options, out_given),
      .required = 1,
      .meta = "DIR",
      .help = "writes DIR/world.yaml, world.pgm and world.svg" },
    OPTION_HELP_ENTRY('h'),
    { .name = NULL }
};

/* A built-in world's obstacles rasterised at cell centres. */
static void rasterise(rover_map *m, rover_map_site *s, const rover_world_config *w)
{
    long i, j;
    int k;
    m->resolution_m = EXPORT_RESOLUTION_M;
    m->origin_x_m = w->x_min_m;
    m->origin_y_m = w->y_min_m;
    m->width = (int)ceil((w->x_max_m - w->x_min_m) / m->resolution_m);
    m->height = (int)ceil((w->y_max_m - w->y_min_m) / m->resolution_m);
    for (j = 0; j < m->height; j++)
        for (i = 0; i < m->width; i++) {
            const double x = m->origin_x_m + (i + 0.5) * m->resolution_m,
                         y = m->origin_y_m + (j + 0.5) * m->resolution_m;
            unsigned char v = ROVER_MAP_FREE;
            for (k = 0; k < w->n_obst && v == ROVER_MAP_FREE; k++)
                if (rover_obstacle_distance(&w->obst[k], x, y) <= 0.0)
                    v = ROVER_MAP_OCCUPIED;
            m->cell[j * m->width + i] = v;
        }
    memset(s, 0, sizeof *s);
    s->start = w->team_origin;
    s->goal_m[0] = w->goal_m[0];
    s->goal_m[1] = w->goal_m[1];
    s->n_landmarks = w->n_landmarks;
    memcpy(s->landmark_m, w->landmark_m, sizeof s->landmark_m);
}

static int parse_size(const char *v, double *w, double *h)
{
    char *end;
    *w = strtod(v, &end);
    if (end == v || *end != 'x')
        return 0;
    *h = strtod(end + 1, &end);
    return *end == '\0' && isfinite(*w) && isfinite(*h) && *w > 0.0 && *h > 0.0;
}

static int write_all(const char *dir, rover_map *m, const rover_map_site *s, int robots,
                     int formation)
{
    static rover_world_config w;
    char why[WORLD_FILE_WHY_MAX];
    int rc;
    if ((rc = rover_world_from_map(&w, m, s, robots, 1.0, formation)) != ROVER_MAP_OK) {
        fprintf(stderr, "tandem-worldgen: the world gives no layout: %s\n", rover_map_strerror(rc));
        return 1;
    }
    if (s->n_landmarks == ROVER_MAP_LANDMARKS_AUTO && world_landmarks_on_way(&w, m) != 0) {
        fprintf(stderr, "tandem-worldgen: out of memory\n");
        return 1;
    }
    if (world_file_write(dir, "world", m, s, why, sizeof why) != 0 ||
        world_file_write_svg(dir, "world", &w, why, sizeof why) != 0) {
        fprintf(stderr, "tandem-worldgen: %s\n", why);
        return 1;
    }
    printf(
        "tandem-worldgen: %s/world.yaml (%dx%d cells of %.2f m, %d boxes, %d landmarks), world.pgm, world.svg\n",
        dir, m->width, m->height, m->resolution_m, w.n_obst, w.n_landmarks);
    return 0;
}

int main(int argc, char **argv)
{
    gen_options o = { "mixed", NULL, NULL, "30x20", 0, 3, FORMATION_LINE, 0, 0 };
    const option_program prog = {
        .name = "tandem-worldgen",
        .usage =
            "usage: tandem-worldgen --kind clutter|traps|corridor|mixed --seed W [--size WxH] [--robots N]\n"
            "                       [--formation F] --out DIR\n"
            "       tandem-worldgen --export NAME --out DIR\n"
            "Writes a rover world as a map_server YAML + PGM with tandem's start, goal and\n"
            "landmarks (docs/formation.md, \"Worlds from files\") and a preview world.svg.\n"
            "A random world is kept only if a search finds a way for the robot body from\n"
            "every robot's start to the goal on the map inflated by the body radius plus a\n"
            "margin (0.32 + 0.25 m); otherwise the next sub-seed of W is tried (at most 64).\n\n",
        .epilog = "Exit status: 0 written, 1 no passable world or a write failed, 2 bad options.\n",
        .groups = { { gen_table, &o } },
        .n_groups = 1,
    };
    static rover_map m;
    rover_map_site s;
    worldgen_params p;
    int rc, attempt = 0;
    rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return options_exit_status(rc);
    if (proc_mkdir_p(o.out) != 0) {
        fprintf(stderr, "tandem-worldgen: cannot create '%s': %s\n", o.out, strerror(errno));
        return 1;
    }
    if (o.exported) {
        static rover_world_config w;
        const int id = rover_world_id(o.exported);
        if (id < 0 || rover_world_layout(&w, id, 3, 1.0, FORMATION_LINE) != 0) {
            fprintf(stderr,
                    "tandem-worldgen: --export: '%s' is not open|obstacles|corridor|deadzone\n",
                    o.exported);
            return 2;
        }
        rasterise(&m, &s, &w);
        return write_all(o.out, &m, &s, 3, FORMATION_LINE);
    }
    memset(&p, 0, sizeof p);
    if ((p.kind = worldgen_kind(o.kind)) < 0 || !o.seed_given ||
        !parse_size(o.size, &p.width_m, &p.height_m)) {
        fprintf(
            stderr,
            "tandem-worldgen: need --kind clutter|traps|corridor|mixed, --seed W and --size WxH (m)\n");
        return 2;
    }
    p.seed = (uint64_t)o.seed;
    p.robots = (int)o.robots;
    p.formation = o.formation;
    if ((rc = worldgen_make(&m, &s, &p, &attempt)) != WORLDGEN_OK) {
        fprintf(stderr, "tandem-worldgen: --kind %s --seed %ld --size %s --robots %ld: %s\n",
                o.kind, o.seed, o.size, o.robots, worldgen_strerror(rc));
        return rc == WORLDGEN_ERR_ARG ? 2 : 1;
    }
    printf("tandem-worldgen: %s world, seed %ld (sub-seed %d)\n", o.kind, o.seed, attempt);
    return write_all(o.out, &m, &s, p.robots, p.formation);
}
