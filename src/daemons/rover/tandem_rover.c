/* tandem-rover: distributed formation controller of one Pioneer (or of
 * several, --id A-B, each with its own state, talking only over LCM)
 * (docs/method/formation.md, lockstep.md §6). Thin: LCM in, rover_ctl_step, LCM out.
 *
 * In:  ROVERk_SENSORS (encoders), ROVERk_SONAR, ROVERk_BEACONS, TEAM, or
 *      the same frames batched (ROVERS_SENSORS, ROVERS_BEACONS).
 * Out: ROVERk_COMMAND (V, w), TEAM (10 Hz), ROVERk_STATE, health; with
 *      --batch the commands and states of all hosted robots go out as one
 *      ROVERS_COMMAND and one ROVERS_STATE per tick, and their team
 *      messages as TEAMS (the robots' radio, each element what the robot
 *      would send on TEAM: a host speaks for its robots in one datagram a
 *      chunk, not one each, which every process on the bus would wake for).
 * The team frame and each robot's initial pose come from the launch
 * configuration (--robots N --world W --formation F, see rover_world.h);
 * after that a robot knows itself only by odometry and its mates by their
 * team messages and its camera. No ground truth is read.
 *
 * Determinism in lockstep: a team message is used only from the first
 * cycle whose step is later than the step it was sent at, so the order in
 * which the hosts happen to answer a step cannot change what anyone saw.
 * And a cycle runs only on complete inputs (rover_inputs_complete):
 * the frames of the hosted robots for this step, and from every mate the
 * team message of its last 10 Hz tick. A frame or team message lost on
 * the way leaves the step unanswered; the simulator announces it again,
 * everyone who already answered publishes its last outputs again
 * (republish), copies already taken are ignored (duplicates), and the
 * cycle runs when the inputs are there: with loss, the same run. A source
 * silent for ROVER_INPUT_WAIT_NS of wall time whose process is gone or
 * hangs (peer_dead: a killed robot; a mate's process is known by the
 * pid in its SIM_ACK) is taken as gone and not waited for again until it
 * speaks; a mate whose process is alive, however slow or stopped, is
 * waited for, so a loaded machine runs the same run.
 *
 * Restart (--journal PATH): after every cycle each hosted robot appends
 * its controller snapshot (rover_ctl_snapshot: own pose with the encoder
 * readings it belongs to, landmark filter, formation protocol, escape) to
 * PATH (PATH-K when hosting several robots). A process started on an
 * existing journal resumes each robot from its last intact snapshot; its
 * first encoder frame then adds the wheels' travel while it was down, and
 * the mates' next team messages rebuild its view of the team.
 *
 * All of its state is one rover_daemon (rover_daemon.h), created here in
 * main and handed to the cycle and to every handler.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "rover_daemon.h"
#include "formation.h"
#include "options.h"
#include "rover_status.h"
#include "shell_status.h"

hosted *rover_find_hosted(rover_daemon *rd, int32_t id)
{
    return (id >= rd->id_lo && id <= rd->id_hi) ? &rd->h[id - rd->id_lo] : NULL;
}

static int parse_ids(rover_daemon *rd, const char *s)
{
    char *end;
    long a, b;
    a = strtol(s, &end, 10);
    if (end == s)
        return ROVER_DAEMON_ERR_IDS;
    if (*end == '-') {
        const char *t = end + 1;
        b = strtol(t, &end, 10);
        if (end == t || *end)
            return ROVER_DAEMON_ERR_IDS;
    } else if (*end) {
        return ROVER_DAEMON_ERR_IDS;
    } else {
        b = a;
    }
    if (a < 1 || b < a || b - a + 1 > HOST_MAX)
        return ROVER_DAEMON_ERR_IDS;
    rd->id_lo = (int32_t)a;
    rd->id_hi = (int32_t)b;
    return 0;
}

/* --id K|A-B */
static int parse_id(const char *prog, void *dest, char *value)
{
    if (parse_ids(dest, value) != 0) {
        fprintf(stderr, "%s: --id: '%s' is not K or A-B (1 <= A <= B, at most %d)\n", prog, value,
                HOST_MAX);
        return OPTIONS_ERR_SAID;
    }
    return 0;
}

/* --ref-heading goal|mean: the reference heading's pull toward the goal */
static int parse_ref_heading(const char *prog, void *dest, char *value)
{
    double *gain = dest;
    (void)prog;
    if (!strcmp(value, "mean"))
        *gain = 0.0;
    else if (!strcmp(value, "goal"))
        *gain = 1.0;
    else
        return OPTIONS_ERR_VALUE;
    return 0;
}

static const char *const blend_names[] = { "weighted", "subsumption", "vecsum", NULL };
static const int blend_values[] = { BEH_BLEND_WEIGHTED, BEH_BLEND_SUBSUMPTION, BEH_BLEND_VECSUM };
static const char *const goal_path_names[] = { "map", "direct", NULL };
static const int goal_path_values[] = { ROVER_GOAL_PATH_MAP, ROVER_GOAL_PATH_DIRECT };
static const char *const law_names[] = { "seed", "kanayama", NULL };
static const int law_values[] = { ROVER_LAW_SEED, ROVER_LAW_KANAYAMA };

#define ROVER_ROBOTS_DEFAULT 3 /* --robots */
/* Into the rover_daemon main made; the values it holds before are the
 * defaults. --stale-ms is stored as s. */
static const option_entry rover_options[] = {
    { .name = "id",
      .type = OPTION_CALL,
      OPTION_ALL(rover_daemon),
      .call = parse_id,
      .meta = "K|A-B",
      .help = "robot id(s), 1..N (required)" },
    { .name = "robots",
      .type = OPTION_INT,
      OPTION_AT(rover_daemon, robots),
      .min = 1,
      .max = ROVER_TEAM_MAX,
      .meta = "N",
      .help = "team size in the launch configuration",
      .def = OPTION_DEF(ROVER_ROBOTS_DEFAULT) },
    FLEET_OPTIONS(rover_daemon, teams, per_team, team_goals),
    { .name = "world",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, world),
      .choices = options_world_names,
      .values = options_world_values,
      .meta = "NAME",
      .def = "open" },
    WORLD_FILE_OPTIONS(rover_daemon, wopt),
    { .name = "formation",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, formation),
      .choices = options_formation_names,
      .values = options_formation_values,
      .meta = "F",
      .def = "line" },
    { .name = "blend",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, blend),
      .choices = blend_names,
      .values = blend_values,
      .meta = "B",
      .def = "weighted" },
    { .name = "formation-law",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, params.formation_law),
      .choices = law_names,
      .values = law_values,
      .help = "seed: the seed's law, O ahead of the axle; kanayama: slot tracking, for comparison",
      .def = "seed" },
    { .name = "goal-path",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, goal_path),
      .choices = goal_path_names,
      .values = goal_path_values,
      .help = "map: steer by the world's navigation function where the goal is not in plain "
              "view (docs/method/formation.md 14); direct: for the goal straight, as the seed",
      .def = "map" },
    { .name = "ref-heading",
      .type = OPTION_CALL,
      OPTION_AT(rover_daemon, params.goal_heading_gain),
      .call = parse_ref_heading,
      .meta = "goal|mean",
      .help =
          "team reference heading: goal (bearing of the goal) | mean (the seed's mean of the headings)",
      .def = "goal" },
    { .name = "ref-arrive",
      .type = OPTION_DOUBLE,
      OPTION_AT(rover_daemon, params.arrive_m),
      .min = 0.0,
      .max = 100.0,
      .meta = "M",
      .help = "within M of the goal the team reference turns onto the goal's slot frame "
              "and its speed fades (0: off)",
      .def = "0" },
    { .name = "localize",
      .type = OPTION_CHOICE,
      OPTION_AT(rover_daemon, localize),
      .choices = options_on_off,
      .values = options_on_off_flags,
      .help =
          "fuse the world's LED landmarks with odometry (EKF); off: odometry and frame consensus only",
      .def = "on" },
    { .name = "stale-ms",
      .type = OPTION_DOUBLE,
      OPTION_AT(rover_daemon, params.stale_s),
      .min = 10.0,
      .max = 10000.0,
      .scale = 1e-3,
      .meta = "MS",
      .help = "sensors older than this stop the robot",
      .def = OPTION_DEF(ROVER_CTL_STALE_MS) },
    { .name = "batch",
      .type = OPTION_FLAG,
      OPTION_AT(rover_daemon, batch),
      .help =
          "publish all hosted robots' commands and states as one ROVERS_COMMAND / ROVERS_STATE message "
          "per tick (sensors are taken per robot and batched alike)" },
    { .name = "journal",
      .type = OPTION_STRING,
      OPTION_AT(rover_daemon, journal),
      .meta = "PATH",
      .help =
          "append each robot's controller snapshot to PATH (PATH-K when hosting several) after every "
          "cycle (authenticated, fsynced); a process started on an existing journal resumes there, or "
          "refuses to start (exit 1) when a record does not check out" },
    OPTION_JOURNAL_RESET_ENTRY(rover_daemon, journal_reset),
    { .name = NULL }
};

STATUS_STRERROR(rover_daemon_strerror, ROVER_DAEMON_CODES)

/* 0, or a negative options_parse result (--help, --version, bad options). */
static int parse_args(rover_daemon *rd, int argc, char **argv)
{
    const option_program prog = {
        .name = "tandem-rover",
        .usage = "usage: tandem-rover --id K|A-B --robots N [options]\n"
                 "Distributed behaviour-based formation controller of Pioneer robot K (or\n"
                 "of robots A..B, each with its own state, in one process): odometry,\n"
                 "team messages at 10 Hz, team-average reference, four behaviours blended\n"
                 "(eq. 11), narrow-passage protocol, dead-zone escape, heartbeat membership.\n\n",
        .epilog = "\nThe control period (--period-ms) is 50 ms (20 Hz) unless given.\n",
        .groups = { { rover_options, rd }, { options_daemon_common, &rd->d } },
        .n_groups = 2,
    };
    const int rc = options_parse(&prog, argc, argv, 1);
    if (rc < 0)
        return rc;
    if (rd->id_lo == 0) {
        fprintf(stderr, "tandem-rover: --id is required\n");
        return OPTIONS_ERR_ARG;
    }
    if (rd->teams > 1) {
        if ((long)rd->teams * rd->per_team > MATES_MAX) {
            fprintf(stderr,
                    "tandem-rover: --teams %d --robots-per-team %d: %ld robots, more than a "
                    "fleet's mates table holds (ROVER_WORLD_MAX_ROBOTS = %d)\n",
                    rd->teams, rd->per_team, (long)rd->teams * rd->per_team, MATES_MAX);
            return OPTIONS_ERR_ARG;
        }
        rd->robots = rd->teams * rd->per_team;
    }
    if (rd->id_hi > rd->robots) {
        fprintf(stderr, "tandem-rover: --id %d-%d outside the team of --robots %d\n",
                (int)rd->id_lo, (int)rd->id_hi, rd->robots);
        return OPTIONS_ERR_ARG;
    }
    return 0;
}

/* The constant tables the controllers run on, checked before they run:
 * the controller parameters (the defaults with the options applied), the
 * journal's snapshot layout and the option table. */
static int check_tables(const rover_daemon *rd)
{
    const char *prog = rd->d.name;
    if (daemon_check_table(prog, "rover_ctl_params", "rover_ctl_params_validate",
                           rover_ctl_params_validate(&rd->params), rover_ctl_strerror) != 0 ||
        daemon_check_table(prog, "rover_snapshot field table", "rover_snapshot_validate",
                           rover_snapshot_validate(), rover_ctl_strerror) != 0 ||
        daemon_check_table(prog, "rover_options", "options_table_validate",
                           options_table_validate(rover_options), options_strerror) != 0)
        return DAEMON_ERR_TABLE;
    return 0;
}

static int cycle(daemon *d, void *user)
{
    rover_daemon *rd = user;
    const int64_t step = d->lockstep ? d->pending_step : d->step;
    const double t_s = (double)(step < 0 ? 0 : step) * DAEMON_SIM_DT_S;
    const double dt = rd->last_t_s > 0.0 && t_s > rd->last_t_s ? t_s - rd->last_t_s : d->period_s;
    const int64_t utime = daemon_utime_now();
    rover_outbox *ob;
    int j, n = 0, stopped = 0, held;
    if (step < 0)
        return DAEMON_CONTINUE; /* no simulator clock yet */
    if (d->lockstep && step == rd->last_step)
        return DAEMON_CONTINUE; /* a repeated clock: answer again only */
    if (rover_too_early(rd, step))
        return DAEMON_CONTINUE;
    if (rd->first_step < 0)
        rd->first_step = step;
    if (d->lockstep && !rover_inputs_complete(rd, step)) {
        d->skip_ack = 1; /* wait for the announcement again */
        return DAEMON_CONTINUE;
    }
    rd->last_step = step;
    for (j = rd->id_lo; j <= rd->id_hi; j++)
        rover_apply_frames(rd, &rd->h[j - rd->id_lo]);
    rd->cur ^= 1; /* keep the cycle before for republish */
    ob = &rd->out[rd->cur];
    rover_deliver_team(rd, step, t_s);
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        rover_ctl_out o;
        /* real time: a silent simulator is stale input too (wall clock) */
        if (!d->lockstep && h->last_rx_ns > 0 &&
            (double)(rtloop_now_ns() - h->last_rx_ns) * 1e-9 > h->c.p.stale_s) {
            memset(&o, 0, sizeof o);
            o.mode = ROVER_MODE_SAFE_STOP;
        } else if (rover_ctl_step(&h->c, t_s, dt, &o) != 0) {
            d->msgs.rejected++;
        }
        if (o.mode == ROVER_MODE_SAFE_STOP)
            stopped++;
        rover_report_changes(h, &o, t_s);
        if (o.send_team)
            rover_publish_team(rd, h, &o, step, utime);
        rover_fill_outputs(h, &o, step, utime, &ob->cmd[n], &ob->st[n]);
        n++;
    }
    ob->n = n;
    ob->step = step;
    ob->utime = utime;
    ob->batch_seq = rd->batch_seq;
    rd->batch_seq += BATCH_CHUNKS(n);
    /* the record first: a robot whose record is not written stops */
    held = rover_journal_cycle(rd, step);
    rover_journal_hold(rd, ob);
    rover_publish_outbox(rd, ob);
    if (rd->batch)
        rover_publish_teams(rd, 0);
    rd->last_t_s = t_s;
    d->safe_hold = stopped > 0 || held > 0;
    if (held > 0)
        snprintf(d->status, sizeof d->status,
                 "safe stop: journal not written, %d of %d robots stopped", held,
                 rd->id_hi - rd->id_lo + 1);
    else
        snprintf(d->status, sizeof d->status, "%s: %d of %d robots stopped (stale input)%s",
                 stopped ? "safe stop" : "running", stopped, rd->id_hi - rd->id_lo + 1,
                 rd->journal_errors ? ", journal not written before" : "");
    return DAEMON_CONTINUE;
}

/* The launch configuration (world_opts_fleet_layout) and the ids this
 * process listens to: its robots' teams. 0, or an exit status (said). */
static int rover_layout(rover_daemon *rd)
{
    int32_t lo, hi;
    rd->listen_lo = 1;
    rd->listen_hi = rd->robots;
    if (world_opts_fleet_layout(&rd->layout, &rd->fleet, &rd->wopt, rd->robots, rd->teams,
                                rd->per_team, rd->team_goals, rd->formation, "tandem-rover") != 0)
        return 2;
    /* --batch: every robot's frames reach this process */
    rd->d.fleet_robots = rd->batch ? rd->robots : rd->id_hi - rd->id_lo + 1;
    if (rd->teams == 1)
        return 0;
    rover_fleet_members(&rd->fleet, rover_fleet_team_of(&rd->fleet, rd->id_lo), &lo, &hi);
    rd->listen_lo = lo;
    rover_fleet_members(&rd->fleet, rover_fleet_team_of(&rd->fleet, rd->id_hi), &lo, &hi);
    rd->listen_hi = hi;
    return 0;
}

/* Robot j's controller in its team's frame (fleet.h: its own team's with
 * --teams; the team frame of the layout with one): its start, its team's
 * goal and the landmarks, and the ids of its team. 0, or non-zero. */
static int robot_init(rover_daemon *rd, hosted *h, int32_t j)
{
    const rover_fleet *f = rd->teams > 1 ? &rd->fleet : NULL;
    const pose2 frame = rover_fleet_frame_of(&rd->layout, f, j);
    const int team = f ? rover_fleet_team_of(f, j) : 0;
    double goal[2], lm[ROVER_WORLD_MAX_LANDMARKS][2], way_a[2], way_b[2];
    pose2 goal_w, goal_t, start;
    int32_t lo = 1, hi = rd->robots;
    int k;
    if (f)
        rover_fleet_members(f, team, &lo, &hi);
    goal_w.x_m = f ? f->goal_m[team][0] : rd->layout.goal_m[0];
    goal_w.y_m = f ? f->goal_m[team][1] : rd->layout.goal_m[1];
    goal_w.theta_rad = 0.0;
    /* the posts it localizes on: all of a world's 64, or the 64 of a
     * fleet's world nearest its team's way (rover_world_landmarks_near) */
    way_a[0] = frame.x_m;
    way_a[1] = frame.y_m;
    way_b[0] = goal_w.x_m;
    way_b[1] = goal_w.y_m;
    h->n_posts = rover_world_landmarks_near(&rd->layout, way_a, way_b, h->post);
    for (k = 0; k < h->n_posts; k++) {
        const double *p = rd->layout.landmark_m[h->post[k]];
        const pose2 lw = { p[0], p[1], 0.0 };
        pose2 lt;
        rover_frame_to(&frame, &lw, &lt);
        lm[k][0] = lt.x_m;
        lm[k][1] = lt.y_m;
    }
    rover_frame_to(&frame, &goal_w, &goal_t);
    goal[0] = goal_t.x_m;
    goal[1] = goal_t.y_m;
    rover_frame_to(&frame, &rd->layout.start_c[j - 1], &start);
    return h->n_posts < 0 || rover_ctl_init(&h->c, &rd->params, j, &start, goal) != 0 ||
           rover_ctl_set_team(&h->c, lo, hi) != 0 ||
           rover_ctl_set_landmarks(&h->c, (const double(*)[2])lm, h->n_posts) != 0;
}

int main(int argc, char **argv)
{
    int j, rc;
    char name[DAEMON_NAME_MAX];
    static rover_daemon app;
    rover_daemon *rd = &app;
    daemon *d = &rd->d;
    lcm_subscription_t *subs[DAEMON_EXPLICIT_MAX]; /* kept for the whole run: never unsubscribed */
    rd->last_step = -1;
    rd->first_step = -1;
    rd->wait_step = -1;
    rd->out[0].step = rd->out[1].step = -1;
    for (j = 0; j <= MATES_MAX; j++)
        rd->mate_step[j] = -1;
    rd->robots = ROVER_ROBOTS_DEFAULT;
    rd->teams = 1;
    rd->per_team = ROVER_ROBOTS_DEFAULT;
    rd->team_goals = ROVER_FLEET_GOALS_CROSS;
    rd->world = ROVER_WORLD_OPEN;
    rd->localize = 1;
    rd->goal_path = ROVER_GOAL_PATH_MAP;
    rover_ctl_params_default(&rd->params);
    daemon_defaults(d, "tandem-rover", 0.05);
    if ((rc = parse_args(rd, argc, argv)) < 0)
        return options_exit_status(rc);
    rd->params.formation = rd->formation;
    rd->params.blend_mode = rd->blend;
    rd->params.localize = rd->localize;
    if (rd->id_lo == rd->id_hi)
        snprintf(name, sizeof name, "tandem-rover-%d", (int)rd->id_lo);
    else
        snprintf(name, sizeof name, "tandem-rover-%d-%d", (int)rd->id_lo, (int)rd->id_hi);
    snprintf(d->name, sizeof d->name, "%s", name);
    if (check_tables(rd) != 0)
        return 1;
    rd->wopt.world = rd->world;
    if ((rc = rover_layout(rd)) != 0)
        return rc;
    if (rd->goal_path == ROVER_GOAL_PATH_MAP && rd->teams == 1) {
        navfield_params np;
        navfield_params_default(&np);
        if ((rc = navfield_build(&rd->nav, &np, &rd->layout)) != NAVFIELD_OK) {
            fprintf(stderr,
                    "tandem-rover: --goal-path map: no navigation function for this world: %s\n",
                    navfield_strerror(rc));
            return 2;
        }
    }
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        if (robot_init(rd, h, j) != 0) {
            fprintf(stderr, "tandem-rover: bad controller parameters\n");
            return 2;
        }
        rover_ctl_set_navfield(
            &h->c, rd->goal_path == ROVER_GOAL_PATH_MAP && rd->teams == 1 ? &rd->nav : NULL);
        snprintf(h->ch_cmd, sizeof h->ch_cmd, "ROVER%d_COMMAND", j);
        snprintf(h->ch_state, sizeof h->ch_state, "ROVER%d_STATE", j);
        h->shown_mode = h->shown_type = h->shown_yield = h->shown_esc = -1;
        h->sens_step = h->sonar_step = h->camera_step = -1;
    }
    auth_bus_identity(&rd->d.bus, AUTH_ROLE_ROVER, rd->id_lo, rd->id_hi);
    daemon_queue_for_burst(d, rd->listen_hi - rd->listen_lo + 1); /* its teams' TEAM messages */
    if (daemon_start(d) != 0)
        return 1;
    /* its own robots' channels by name (daemon_subscribe_numbered) */
    daemon_subscribe_numbered(d, "ROVER", rd->id_lo, rd->id_hi, "_SENSORS", rover_on_sensors, rd,
                              subs, DAEMON_EXPLICIT_MAX);
    daemon_subscribe_numbered(d, "ROVER", rd->id_lo, rd->id_hi, "_SONAR", rover_on_sonar, rd, subs,
                              DAEMON_EXPLICIT_MAX);
    daemon_subscribe_numbered(d, "ROVER", rd->id_lo, rd->id_hi, "_BEACONS", rover_on_beacons, rd,
                              subs, DAEMON_EXPLICIT_MAX);
    if (rover_journal_start(rd) != 0) {
        daemon_finish(d);
        return 1;
    }
    daemon_subscribe(d, "ROVERS_SENSORS", rover_on_sensors_batch, rd);
    daemon_subscribe(d, "ROVERS_BEACONS", rover_on_beacons_batch, rd);
    daemon_subscribe(d, "TEAM", rover_on_team, rd);
    daemon_subscribe(d, "TEAMS", rover_on_teams, rd);
    if (d->lockstep)
        daemon_subscribe(d, "SIM_ACK", rover_on_ack, rd);
    d->repeat_fn = rover_republish;
    rc = daemon_run(d, cycle, rd);
    rover_journal_stop(rd);
    daemon_finish(d);
    return rc;
}
