/* tdsd_setup: the two experiments of seed 002 (docs/method/tdsd.md §8 S1, S2) as data:
 * arm, tool, path, gains and start pose. Pure (no I/O): the scenarios and
 * test/unit/tdsd/test_tdsd_scenario.c use the very same set-up.
 */
#ifndef TANDEM_TDSD_SETUP_H
#define TANDEM_TDSD_SETUP_H

#include "tdsd_run.h"

#define TDSD_SETUP_ERR_START (-1) /* the start pose is not reachable inside the ranges */

/* S1, shoulder singularity (seed-002 arm). method: TDSDRUN_TDSD | PINV | DLS.
 * Fills c, p and the start pose q0 (IK of A on branch right-up-noflip).
 * 0 ok, TDSD_SETUP_ERR_START. */
int tdsd_setup_singularity(tdsdrun_cfg *c, tdsdrun_path *p, tdsdrun_method method,
                           double q0_rad[ARM_NJ]);

/* S2, liquid transport (PUMA 560). full = 0: TDSD with the tool axis and the
 * q4..q6 mid-range criterion; full = 1: 6-D clipped pseudo-inverse.
 * 0 ok, TDSD_SETUP_ERR_START. */
int tdsd_setup_liquid(tdsdrun_cfg *c, tdsdrun_path *p, int full, double q0_rad[ARM_NJ]);

#endif
