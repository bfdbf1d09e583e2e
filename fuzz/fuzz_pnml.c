/* fuzz_pnml: libFuzzer target for the PNML reader (netc_pnml_read_memory,
 * src/daemons/common/netc_pnml.c), which tandem-supervisor --task runs on
 * a file it is given (built by tools/fuzz.sh as fuzz_pnml).
 *
 * Input: a PNML document. The reader must never crash, and what it takes
 * must be what the supervisor's tables can hold: sizes within
 * PETRI_MAX_PLACES and PETRI_MAX_TRANSITIONS, N-, N+ and inhibitor entries
 * 0/1, initial markings within PETRI_TOKEN_MAX, the net bound to the task's
 * own arrays. Anything else it must refuse; a net it takes that breaks
 * these aborts. The sanitizers catch overflows, leaks and undefined
 * behaviour in the parsing.
 */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "netc.h"

#define FUZZ_MAX_BYTES (1 << 20)

static netc_task task; /* large: one, reused */

static void check_taken(const netc_task *t)
{
    int k;
    if (t->n_places < 1 || t->n_places > PETRI_MAX_PLACES || t->n_transitions < 1 ||
        t->n_transitions > PETRI_MAX_TRANSITIONS || t->net.n_minus != t->n_minus ||
        t->net.m0 != t->m0 || t->net.n_places != t->n_places ||
        t->net.n_transitions != t->n_transitions)
        abort();
    for (k = 0; k < t->n_places * t->n_transitions; k++)
        if ((t->n_minus[k] | t->n_plus[k] | t->n_inhibit[k]) & ~1)
            abort();
    /* what the engine's validator may still refuse is the net's meaning,
     * never its shape */
    k = petri_net_validate(&t->net);
    if (k == PETRI_ERR_ARG || k == PETRI_ERR_SIZE || k == PETRI_ERR_ENTRY)
        abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size > FUZZ_MAX_BYTES)
        return 0;
    memset(&task, 0, sizeof task);
    if (netc_pnml_read_memory(&task, (const char *)data, (int)size, "fuzz.pnml", NULL) == NETC_OK)
        check_taken(&task);
    return 0;
}
