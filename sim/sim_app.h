/* sim_app: the state of tandem-sim, one struct created in main and handed
 * to every function of sim_main.c (command line, table checks, start-up)
 * and sim_loop.c (messages in and out, the step, the two timing modes),
 * and the calls between the two files. It owns every model's state; a
 * model's hooks get theirs through sim_model.state.
 */
#ifndef TANDEM_SIM_APP_H
#define TANDEM_SIM_APP_H

#include <stdint.h>
#include "sim.h"
#include "sim_arms.h"
#include "sim_rovers.h"
#include "sim_workpieces.h"
#include "world_file.h"

#define SIM_MODELS_MAX 3 /* arms, workpieces, rovers */

typedef struct sim_app {
    sim_world w;
    sim_config cfg;
    int64_t max_steps;                /* 0 = run forever */
    int expect;                       /* lockstep: participants to wait for at start */
    sim_model models[SIM_MODELS_MAX]; /* in step order */
    int n_models;
    int reset_pending;
    uint64_t next_seed;
    /* options that are not stored as given */
    int no_arms;     /* --no-arms: cfg.arms = 0 */
    int world;       /* --world: index in options_world_names */
    world_opts wopt; /* --world-file, --start, --goal (world_file.h) */
    int arm_model;   /* --arm-model: index in options_arm_model_names, -1 not given */
    /* the models' states */
    sim_arms arms;
    sim_workpieces workpieces;
    sim_rovers rovers;
} sim_app;

/* sim_loop.c */
/* SIM_ACK and SIM_CONTROL, handed app. */
void sim_subscribe(sim_app *app);
/* The world with every model in it; SIM_ERR_CREATE (said) if a model
 * cannot be built. */
int sim_build_world(sim_app *app);
void sim_destroy_world(sim_app *app);
void sim_run_lockstep(sim_app *app);
void sim_run_realtime(sim_app *app);
void sim_publish_status(sim_app *app);
/* sim_state_hash, and the state each model keeps outside the bodies. */
uint64_t sim_app_state_hash(const sim_app *app);

#endif
