/* sim_rovers: the state of the Pioneer team model (sim_rovers_ops), one
 * struct handed to every function of sim_rovers.c (world, commands,
 * physics) and sim_rovers_sense.c (sonar, camera, ground truth), and the
 * calls between the two files; extra hooks for benchmarks.
 *
 * Capacity: up to RV_MAX robots (ROVER_WORLD_MAX_ROBOTS, a build setting);
 * every per-robot array is allocated once when the model is created, for
 * the --rovers asked, and nothing is allocated while it steps. The
 * batched link (--rover-batch) carries BATCH_MAX robots a message (the
 * bound of the ROVERS_* messages), a larger fleet in several a tick.
 */
#ifndef TANDEM_SIM_ROVERS_H
#define TANDEM_SIM_ROVERS_H

#include <stdint.h>
#include "sim.h"
#include "prng.h"
#include "fleet.h"
#include "rover_world.h"
#include "sonar.h"
#include "vec2.h"
#include "pgrid.h"
#include "tandem_beacon_obs_t.h"
#include "tandem_rover_sensors_t.h"
#include "tandem_sonar_scan_t.h"

#define RV_MAX ROVER_WORLD_MAX_ROBOTS
#define RV_WHEEL_R 0.0825                          /* m */
#define RV_TRACK 0.33                              /* m, between the wheels' contacts */
#define RV_SENSORS_STEPS ROVER_SENSOR_PERIOD_STEPS /* the control tick */
#define RV_SEEN_MAX (ROVER_TEAM_MAX + ROVER_WORLD_MAX_LANDMARKS) /* LEDs one frame holds */

typedef struct sim_rover {
    int32_t id;
    int alive;
    dBodyID chassis, wheel[2];
    dJointID hinge[2];
    dGeomID box;
    double cmd_v, cmd_w; /* held (clipped) command */
    double v_ref, w_ref; /* after the acceleration ramp */
    int64_t cmd_rx_step;
    int64_t cmd_step; /* the step the held command answers (-1 none) */
    int have_cmd, stale;
    double slip[2];
    double enc[2]; /* accumulated wheel angles */
    double range[SONAR_N];
    int bump_now, bump_prev, collisions;
    int free;              /* --rover-far kinematic: far from everything, moved by its wheels */
    int hash_slot;         /* its chassis' index in the simulator's hashed bodies (-1 none) */
    double motor_radps[2]; /* the wheel motors' rates (the hinges' dParamVel) */
    /* while free (sim_rovers_free.c): C when it left the solver and now,
     * each wheel's turn since, and the rolling */
    pose2 free_c0, free_c;
    double free_spin_rad[2];
    double free_v_mps, free_w_radps;
    double min_clear;
    prng_state rng;
    int prim;  /* its box in the sonar world */
    int fired; /* transducer fired last */
    int64_t seq_sens, seq_sonar, seq_beacon;
} sim_rover;

/* The camera frames last drawn: a re-announced step publishes them again. */
typedef struct sim_rovers_frames {
    int n;
    tandem_beacon_obs_t *obs; /* [robots] */
    int32_t (*target)[RV_SEEN_MAX];
    double (*range_m)[RV_SEEN_MAX];
    double (*bearing_rad)[RV_SEEN_MAX];
} sim_rovers_frames;

/* Work arrays of the sensor publication, one slot per robot, allocated at
 * creation (the stack would not hold them for thousands of robots). */
typedef struct sim_rovers_scratch {
    tandem_rover_sensors_t *sens;
    tandem_sonar_scan_t *scan;
    pose2 *pose, *cam;
    double *x, *y, *th, *cl;
    int32_t *id, *col, *near;
    int8_t *al;
    int *alive;
    pgrid *cam_grid;             /* the camera's neighbours */
    pgrid *post_grid;            /* the world's LED posts (built once) */
    int32_t *post_near;          /* [ROVER_WORLD_MAX_POSTS]: posts in a camera's reach */
    rover_clearance_work *clear; /* the truth's clearance */
} sim_rovers_scratch;

typedef struct sim_rovers {
    int n;
    sim_rover *r; /* [n] */
    rover_world_config layout;
    rover_fleet fleet; /* the teams (fleet.h) when the run holds more than one */
    sonar_world sw;
    sonar_model sm;
    dWorldID world;        /* the rovers' own ODE world (sim_rovers.c) */
    dWorldID park;         /* free robots' bodies, never stepped (sim_rovers_free.c) */
    int64_t free_overlaps; /* free robots found touching something (none expected) */
    dSpaceID space;
    dJointGroupID contacts;
    dGeomID obst[ROVER_WORLD_MAX_OBST];
    double sonar_angle_rad[SONAR_N];
    sim_world *w;
    int batch; /* 1: ROVERS_* messages, not ROVERk_* */
    int64_t batch_seq[2];
    double v_max, w_max, stale_s;
    int phys_steps;
    int far_kinematic;    /* --rover-far kinematic (sim_rovers_free.c) */
    int chassis_contacts; /* chassis contact joints this step */
    int64_t quick_steps;  /* steps that fell back to QuickStep */
    int64_t last_after_step;
    sim_rovers_frames frames;
    sim_rovers_scratch s;
    int brute;            /* TANDEM_SIM_NEIGHBOURS=scan: every robot scanned (the old way) */
    int64_t seen_dropped; /* LEDs in view past a frame's RV_SEEN_MAX */
    int64_t truth_seq, rejected, rays;
    int formation;
} sim_rovers;

/* Sonar rays cast since the rover model was created. */
int64_t sim_rovers_rays_cast(const sim_rovers *team);

/* Hold command (V, w) for robot id as if received at sim step `step`
 * (benchmarks drive the robots without LCM). 0, or SIM_ROVERS_ERR_ARG. */
#define SIM_ROVERS_ERR_ARG (-1) /* no such robot, or a speed not finite */
int sim_rovers_set_command(sim_rovers *team, int32_t id, double v_mps, double w_radps,
                           int64_t step);

/* The sonar model the robots carry (the Pioneer P2DX default). */
void sim_rovers_sonar_model(sonar_model *m);

/* Between sim_rovers.c and sim_rovers_sense.c: */
/* Pose of robot r's axle centre C from its chassis body. */
void sim_rover_pose_c(const sim_rover *r, pose2 *c);
/* The after_step hook: sonar firings, sensor frames, camera, truth. */
void sim_rovers_after_step(void *model, sim_world *w);
/* Every robot's axle pose, alive flag and ground-truth clearance into
 * team->s.pose, .alive, .cl (the truth's, and the far robots' check). */
void sim_rovers_clearance(sim_rovers *team);
/* Indexes the layout's LED posts for the camera (once, at creation). */
int sim_rovers_index_posts(sim_rovers *team);
/* sim_rovers_free.c: with --rover-far kinematic, every RV_FREE_CHECK_PHYS rover steps
 * the robots clear of everything by sim_rovers_free_margin_m leave the
 * solver (and the others rejoin it); sim_rovers_free_move steps one of
 * them by its wheels. */
void sim_rovers_free_check(sim_rovers *team, const sim_world *w);
void sim_rovers_free_move(sim_rover *r, double dt);
/* The free robots' state (outside ODE) onto the simulator's state hash h. */
uint64_t sim_rovers_free_hash(const void *model, uint64_t h);
double sim_rovers_free_margin_m(const sim_rovers *team);

#endif
