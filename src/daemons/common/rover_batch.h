/* rover_batch: how a fleet's frames of one tick travel on one channel
 * (the rovers_*_t batch messages of tandem-rover and tandem-sim). The
 * message arrays hold one team (lcmtypes/capacities); a larger fleet is
 * cut into chunks, each a message.
 */
#ifndef TANDEM_ROVER_BATCH_H
#define TANDEM_ROVER_BATCH_H

#include "rover_world.h"

/* A batch holds at most BATCH_MAX robots (the bound of the rovers_*_t
 * arrays in lcmtypes/capacities: one team); a fleet's frames of one tick
 * go out as BATCH_CHUNKS(n) messages on the same channel (one, even
 * empty, up to BATCH_MAX), robots in id order, BATCH_MAX a message and
 * the rest in the last. */
#define BATCH_MAX ROVER_TEAM_MAX
#define BATCH_CHUNKS(n) ((n) > BATCH_MAX ? ((n) + BATCH_MAX - 1) / BATCH_MAX : 1)
/* Robots in chunk c of a batch of n. */
#define BATCH_CHUNK_N(n, c) ((n) - (c)*BATCH_MAX < BATCH_MAX ? (n) - (c)*BATCH_MAX : BATCH_MAX)

#endif
