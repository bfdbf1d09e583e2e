/* cell: the two-arm workcell layout of the carry task (docs/method/carry.md §5, §5).
 *
 * One const table shared by the simulator, the supervisor and the arm
 * controllers, so every program agrees where the arms stand and where the
 * table, pick zone, hand-over and delivery poses are. World frame: z up,
 * floor at z = 0; arm 1 stands at x < 0 facing +x, arm 2 mirrors it.
 * All tool poses have the gripper pointing down (flange z = -world z).
 * The poses were chosen inside the PUMA 560's reachable annulus for a
 * downward tool (radius ~0.45-0.7 m from the base axis at these heights)
 * and inside the joint ranges of docs/method/tdsd.md (checked in test_cell).
 */
#ifndef TANDEM_CELL_H
#define TANDEM_CELL_H

#define CELL_ERR_ARG (-1)       /* NULL layout                       */
#define CELL_ERR_NONFINITE (-2) /* a number is NaN or Inf            */
#define CELL_ERR_RANGE \
    (-3) /* a size, mass, offset or clearance
                                       <= 0, or a spread < 0             */
#define CELL_ERR_INCONSISTENT \
    (-4) /* parts that do not fit together:
                                       grasp points off the bar, a
                                       workpiece pose not resting on the
                                       table or outside it, the hand-over
                                       or the stand's second place not
                                       above it, the stand's places too
                                       near, the arms on one spot */

#define CELL_ARMS 2
#define CELL_TOOL_LENGTH_M 0.10 /* flange -> point between the fingers */
/* ABOVE_HANDOVER_1, _2: this far above the hand-over, where a bar set down
 * on a stand (tandem-sim --handover-stand) is approached and left
 * vertically. Not approach_height_m: 0.13 m above the hand-over is out of
 * the PUMA's reach with the tool down (0.10 m is the most, test_cell) */
#define CELL_STAND_CLEARANCE_M 0.06

typedef struct cell_layout {
    double base_xyz_m[CELL_ARMS][3]; /* mounting surface of each arm */
    double base_yaw_rad[CELL_ARMS];
    double table_center_m[3]; /* table box centre */
    double table_size_m[3];
    double workpiece_size_m[3]; /* a bar, long axis along world x */
    double workpiece_mass_kg;
    double grasp_offset_m;            /* grasp points at +- this along the bar */
    double grasp_tolerance_m;         /* gripper closes on a grasp point this near */
    double pick_center_m[3];          /* workpiece centre, middle of the pick zone */
    double pick_spread_m[2];          /* +- uniform spread of new workpieces in x, y */
    double deliver_center_m[3];       /* where arm 2 puts the workpiece down */
    double handover_center_m[3];      /* workpiece centre at the hand-over */
    double approach_height_m;         /* above-workpiece clearance */
    double home_tool_m[CELL_ARMS][3]; /* tool point at home */
    /* arm 2's own source of workpieces (tandem-sim --magazine, a task
     * where arm 2 works alone while arm 1 is down: docs/tasks.md §8): a
     * bar's centre, resting on the table, along world x, in arm 2's reach */
    double magazine_center_m[3];
    /* the stand's second place (tandem-sim --handover-stand, docs/tasks.md
     * §6): a bar's centre, along world x, behind the hand-over (its first
     * place) in both arms' reach, so that arm 1 sets a bar down at one
     * while arm 2 lifts the other off */
    double stand_b_center_m[3];
} cell_layout;

extern const cell_layout cell_default;

/* The layout is sound: every number finite, sizes, mass, grasp offset and
 * tolerance and approach height > 0, spreads >= 0, both grasp points on
 * the bar (within the tolerance of its ends), the pick zone (with its
 * spread), the delivery pose and the magazine resting on the table top
 * and inside its footprint, the hand-over workpiece and the stand's second
 * place above the table top, the two stand places apart by more than a
 * bar's width and a grasp tolerance each way, the arms at two different
 * places. 0 or CELL_ERR_*. For start-up checks. */
int cell_layout_validate(const cell_layout *c);

/* World <-> arm mounting frame (4x4, row-major) for arm index a (0, 1). */
void cell_world_from_arm(const cell_layout *c, int a, double T[16]);
/* Tool-down orientation for arm a, expressed in the arm's own frame. */
void cell_tool_down_R(const cell_layout *c, int a, double R_arm[9]);
/* Grasp point of arm a on a workpiece centred at centre_world (arm 1 takes
 * the end towards -x, arm 2 the end towards +x). */
void cell_grasp_point(const cell_layout *c, int a, const double centre_world[3], double p_world[3]);

#endif
