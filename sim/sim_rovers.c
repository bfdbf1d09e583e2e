/* sim_rovers: Pioneer-2-DX robots (SPEC.md §4, §5). Not built yet: asking
 * for rovers is refused with a clear message rather than simulated wrongly. */
#include "sim.h"
#include <stdio.h>

static int rovers_create(sim_world *w, const sim_config *cfg)
{
    (void)w; (void)cfg;
    fprintf(stderr, "tandem-sim: --rovers: the Pioneer model is not part of this build yet\n");
    return -1;
}
static void rovers_noop(sim_world *w) { (void)w; }

const sim_model_ops sim_rovers_ops = {
    "rovers", rovers_create, rovers_noop, rovers_noop, rovers_noop, NULL, NULL
};
