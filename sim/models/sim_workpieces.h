/* sim_workpieces: the state of the carry task's model (sim_workpieces_ops,
 * sim_workpieces.c): the table, the pool of bars, the camera's last frame.
 * The grippers are the arms' (sim_arms): the model holds the pair it
 * attaches bars to.
 */
#ifndef TANDEM_SIM_WORKPIECES_H
#define TANDEM_SIM_WORKPIECES_H

#include <stdint.h>
#include "sim.h"
#include "sim_arms.h"
#include "prng.h"
#include "tandem_workpiece_t.h"

#define WP_POOL 4
/* the hand-over stand's places: cell handover_center_m, stand_b_center_m */
#define SIM_STAND_PLACES 2

enum { WP_PARKED = 0, WP_ON_PICK, WP_HELD, WP_FREE, WP_IN_MAGAZINE };

typedef struct sim_workpiece {
    dBodyID body;
    dGeomID geom;
    int state;
    int32_t id;
    dJointID hold[SIM_ARMS]; /* fixed joint to arm k's flange, or 0 */
    double rest_s;
} sim_workpiece;

typedef struct sim_workpieces {
    sim_arms *arms; /* the grippers: set by the owner before create */
    sim_workpiece pool[WP_POOL];
    dGeomID table_geom;
    dGeomID stand_geom[SIM_STAND_PLACES]; /* --handover-stand, or NULL */
    prng_state rng;
    const sim_config *cfg;
    int32_t spawned, delivered, dropped, next_id;
    double clear_s; /* the pick zone has been clear this long */
    int64_t vision_seq;
    int64_t last_after_step;              /* the step wp_after_step last ran for */
    tandem_workpiece_t last_det[WP_POOL]; /* the detections of the last camera frame */
    int last_n_det;
    int spawn_requests; /* SPAWN_WORKPIECE requests not served yet */
} sim_workpieces;

#endif
