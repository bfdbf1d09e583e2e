/* slot_assign: the goal's slots given to the robots by the least sum of
 * squared distances (docs/method/formation.md §6, "Arrival").
 *
 * Once the team is arriving, which robot takes which of the goal's slots
 * goes by where the robots are, not by their ids. The assignment chosen
 * is the one that minimises the sum of the squared distances from each
 * robot to its slot, found exactly (the Hungarian method, Kuhn-Munkres
 * with potentials, O(n^3)). Why the global optimum and not any local one:
 * if every robot drives straight to its slot, arriving together, the
 * optimal assignment stays optimal all the way (Turpin, Michael and
 * Kumar's CAPT, 2014: the cost of the assignment flown falls faster than
 * that of any other), and robots that start and end a distance s apart
 * stay s / sqrt(2) apart on the way. So the same
 * rule evaluated afresh each period keeps giving the same answer while
 * the team does what it says, which a local optimum reached from a fixed
 * starting order does not (it is path dependent: as the robots move the
 * swaps find another local optimum, and the team swirled round the goal
 * trading slots). Every robot computes it from the same team messages,
 * and the method is deterministic (ties go to the lower index), so every
 * robot finds the same assignment.
 *
 * Pure computation; fixed capacity SLOT_ASSIGN_MAX; no allocation.
 */
#ifndef TANDEM_SLOT_ASSIGN_H
#define TANDEM_SLOT_ASSIGN_H

#include "formation.h"

#define SLOT_ASSIGN_MAX FORMATION_MAX_ROBOTS

#define SLOT_ASSIGN_OK 0
#define SLOT_ASSIGN_ERR_ARG (-1) /* NULL, n out of 1..SLOT_ASSIGN_MAX, a coordinate not finite */

/* slot_of[j] = the slot of robot j (robot j at xy_m[j], slot k at
 * slot_m[k]) in the assignment of least sum of squared distances;
 * *cost_sum_m2 (if not NULL) that sum. SLOT_ASSIGN_OK or SLOT_ASSIGN_ERR_ARG
 * (slot_of untouched). */
int slot_assign_min_sq(const double xy_m[][2], const double slot_m[][2], int n, int *slot_of,
                       double *cost_sum_m2);

/* The same on one axis (robot j at x_m[j], slot k at s_m[k]): there the
 * least sum of squares pairs the robots and the slots in sorted order
 * (exchange argument: for a < b and c < d, (a - c)^2 + (b - d)^2 <=
 * (a - d)^2 + (b - c)^2, the difference being 2 (b - a)(d - c) >= 0), so a
 * stable sort of each, O(n log n) instead of O(n^3); equal keys keep their
 * index order. Same results and errors as slot_assign_min_sq. */
int slot_assign_sorted(const double x_m[], const double s_m[], int n, int *slot_of,
                       double *cost_sum_m2);

#endif
