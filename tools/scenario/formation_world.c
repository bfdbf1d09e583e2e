/* formation_world: the world of a formation run when it comes from a file
 * (docs/formation.md, "Worlds from files"): kept in the output directory
 * as world.yaml + world.pgm (start and goal as flown, after --start and
 * --goal), and that copy is what the simulator and the rovers read, so
 * the run can be flown again from its directory alone.
 */
#include "formation_scen.h"

#include <stdio.h>

int fm_keep_world(fm_state *fm)
{
    fm->child_world = fm->wopt;
    if (!fm->wopt.file) return 0;
    if (world_opts_save(&fm->wopt, fm->out, "formation") != 0) return 1;
    snprintf(fm->world_copy, sizeof fm->world_copy, "%s/world.yaml", fm->out);
    fm->child_world.file = fm->world_copy;
    fm->child_world.start = NULL;
    fm->child_world.goal = NULL;
    fm->world = ROVER_WORLD_FILE;
    return 0;
}

const char *fm_world_arg(const fm_state *fm)
{
    return fm->world == ROVER_WORLD_FILE ? "open" : rover_world_name(fm->world);
}
