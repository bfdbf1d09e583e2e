/* world_file: rover worlds from files in the ROS map_server format (a YAML
 * file beside a PGM image, P5 or P2) with tandem's own keys under
 * `tandem:` (start, goal, landmarks), the options that choose a world
 * (--world NAME | --world-file PATH, --start, --goal) and the layout they
 * give (docs/formation.md, "Worlds from files"; docs/method/sonar.md §8).
 *
 * map_server's meaning of the keys: `image` (relative to the YAML file's
 * folder), `resolution` (m per cell), `origin` [x, y, yaw] (the pose of the
 * image's lower-left pixel; yaw must be 0 here), `negate`,
 * `occupied_thresh`, `free_thresh`; a pixel's occupancy is p = (max - v) /
 * max (v / max with negate: 1); p > occupied_thresh is occupied, p <
 * free_thresh free, anything between (unknown) is taken as occupied: the
 * robots must not drive where the map does not know. Image rows go top to
 * bottom. `mode`, if present, must be `trinary`.
 */
#ifndef TANDEM_WORLD_FILE_H
#define TANDEM_WORLD_FILE_H

#include <stddef.h>
#include "options.h"
#include "fleet.h"
#include "rover_map.h"
#include "rover_world.h"

#define WORLD_FILE_OK 0
#define WORLD_FILE_ERR_OPEN (-1)   /* the YAML file cannot be read */
#define WORLD_FILE_ERR_YAML (-2)   /* not YAML, or not a mapping at the top */
#define WORLD_FILE_ERR_FIELD (-3)  /* a key missing or its value wrong */
#define WORLD_FILE_ERR_IMAGE (-4)  /* the image missing, not a PGM, or its data short */
#define WORLD_FILE_ERR_MAP (-5)    /* the map refused by rover_map (size, start, goal, boxes) */
#define WORLD_FILE_ERR_OPTION (-6) /* --start / --goal malformed, or given without --world-file */
#define WORLD_FILE_ERR_MEMORY (-7)
#define WORLD_FILE_ERR_WRITE (-8) /* an output file cannot be written */

#define WORLD_FILE_WHY_MAX 512

/* The world options of a program (a member of its options struct). */
typedef struct world_opts {
    int world;         /* --world: ROVER_WORLD_* (built-in) */
    const char *file;  /* --world-file: NULL for a built-in world */
    const char *start; /* --start X,Y,THETA: NULL keeps the file's */
    const char *goal;  /* --goal X,Y: NULL keeps the file's */
} world_opts;

/* The three option entries after a program's --world entry. */
#define WORLD_FILE_OPTIONS(owner, member)                                                        \
    { .name = "world-file",                                                                      \
      .type = OPTION_STRING,                                                                     \
      OPTION_AT(owner, member.file),                                                             \
      .min = 1,                                                                                  \
      .meta = "PATH",                                                                            \
      .help = "the world from a map_server YAML file (with its PGM image) instead of --world" }, \
        { .name = "start",                                                                       \
          .type = OPTION_STRING,                                                                 \
          OPTION_AT(owner, member.start),                                                        \
          .min = 1,                                                                              \
          .meta = "X,Y,THETA",                                                                   \
          .help = "with --world-file: the team's start (m, m, rad) instead of the file's" },     \
    {                                                                                            \
        .name = "goal", .type = OPTION_STRING, OPTION_AT(owner, member.goal), .min = 1,          \
        .meta = "X,Y", .help = "with --world-file: the goal (m) instead of the file's"           \
    }

/* --teams T --robots-per-team K --team-goals ahead|cross (fleet.h), the
 * same on tandem-sim, tandem-rover and tandem-scenario formation: the
 * owner's int members teams_m, per_team_m and goals_m
 * (ROVER_FLEET_GOALS_*), 1, 3 and cross unless the owner sets others. */
#define FLEET_OPTIONS(owner, teams_m, per_team_m, goals_m)                                      \
    { .name = "teams",                                                                          \
      .type = OPTION_INT,                                                                       \
      OPTION_AT(owner, teams_m),                                                                \
      .min = 1,                                                                                 \
      .max = ROVER_FLEET_MAX_TEAMS,                                                             \
      .meta = "T",                                                                              \
      .help = "teams in one world (fleet.h), robots numbered team by team, each team its own "  \
              "formation, lane and goal; T > 1: the open world sized for them, goals straight " \
              "(--goal-path direct), T K robots",                                               \
      .def = "1" },                                                                             \
        { .name = "robots-per-team",                                                            \
          .type = OPTION_INT,                                                                   \
          OPTION_AT(owner, per_team_m),                                                         \
          .min = 1,                                                                             \
          .max = ROVER_TEAM_MAX,                                                                \
          .meta = "K",                                                                          \
          .help = "with --teams T > 1: each team's size",                                       \
          .def = "3" },                                                                         \
    {                                                                                           \
        .name = "team-goals", .type = OPTION_CHOICE, OPTION_AT(owner, goals_m),                 \
        .choices = options_team_goal_names,                                                     \
        .help = "with --teams T > 1: ahead, each team's goal 12 m ahead in its own lane; "      \
                "cross, in the lane of the neighbour it is paired with (lanes 1-2, 3-4, "       \
                "...), the two teams of a pair crossing each other's way half-way",             \
        .def = "ahead"                                                                          \
    }

const char *world_file_strerror(int rc);

/* Reads the YAML at path and its image into m (row 0 the bottom) and s.
 * On failure why holds "PATH: FIELD: reason". */
int world_file_read(const char *path, rover_map *m, rover_map_site *s, char *why, size_t why_n);

/* `landmarks: auto` on a map: w's posts placed along the team's way to
 * the goal (the navigation function's, docs/method/formation.md §14),
 * not the straight line from start to goal, so a corridor's bends have
 * posts in view (rover_map_landmarks_along). WORLD_FILE_OK (w unchanged
 * where no field can be built), or WORLD_FILE_ERR_MEMORY. */
int world_landmarks_on_way(rover_world_config *w, const rover_map *m);

/* Writes DIR/NAME.yaml and DIR/NAME.pgm (P5) holding m and s. */
int world_file_write(const char *dir, const char *name, const rover_map *m, const rover_map_site *s,
                     char *why, size_t why_n);

/* DIR/NAME.svg: a picture of the world w as laid out on its map (the
 * merged boxes, each robot's start, the goal, the landmarks), 20 px/m. */
int world_file_write_svg(const char *dir, const char *name, const rover_world_config *w, char *why,
                         size_t why_n);

/* The layout the options choose: a built-in world by name, or the file
 * with --start / --goal applied. Said on stderr as "PROG: PATH: FIELD:
 * reason" on failure. */
int world_opts_layout(rover_world_config *w, const world_opts *o, int n, double spacing_m,
                      int formation, const char *prog);
/* The layout of a run of `teams` teams (fleet.h): with one team
 * world_opts_layout's for n robots (f untouched); with more the fleet of
 * teams x per_team robots on the open world (f its lanes and goals),
 * refused (said) for another world or a file. 0, or non-zero (said). */
int world_opts_fleet_layout(rover_world_config *w, rover_fleet *f, const world_opts *o, int n,
                            int teams, int per_team, int goals, int formation, const char *prog);

/* With a file world: DIR/world.yaml + world.pgm, the world as run (start
 * and goal after the options). Nothing for a built-in world. */
int world_opts_save(const world_opts *o, const char *dir, const char *prog);

/* The options as argv words for a child program (--world-file P [--start S]
 * [--goal G], or nothing): appended at argv[*n], at most cap words. */
void world_opts_argv(const world_opts *o, char **argv, int *n, int cap);

#endif
