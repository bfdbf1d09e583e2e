/* tandem-rover: distributed formation controller of one Pioneer (or of
 * several, --id A-B, each with its own state, talking only over LCM)
 * (SPEC.md §4, §7). Thin: LCM in, rover_ctl_step, LCM out.
 *
 * In:  ROVERk_SENSORS (encoders), ROVERk_SONAR, ROVERk_BEACONS, TEAM, or
 *      the same frames batched (ROVERS_SENSORS, ROVERS_BEACONS).
 * Out: ROVERk_COMMAND (V, w), TEAM (10 Hz), ROVERk_STATE, health; with
 *      --batch the commands and states of all hosted robots go out as one
 *      ROVERS_COMMAND and one ROVERS_STATE per tick (TEAM stays per robot:
 *      it is the robots' radio, not the simulator link).
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
 * silent for ROVER_INPUT_WAIT_NS of wall time is taken as gone (a killed
 * robot) and not waited for again until it speaks.
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

hosted *rover_find_hosted(rover_daemon *rd, int32_t id)
{
    return (id >= rd->id_lo && id <= rd->id_hi) ? &rd->h[id - rd->id_lo] : NULL;
}

static void usage(void)
{
    printf("usage: tandem-rover --id K|A-B --robots N [options]\n"
           "Distributed behaviour-based formation controller of Pioneer robot K (or\n"
           "of robots A..B, each with its own state, in one process): odometry,\n"
           "team messages at 10 Hz, team-average reference, four behaviours blended\n"
           "(eq. 11), narrow-passage protocol, dead-zone escape, heartbeat membership.\n\n"
           "  --id K | A-B       robot id(s), 1..N\n"
           "  --robots N         team size in the launch configuration (default 3)\n"
           "  --world NAME       open | obstacles | corridor | deadzone (default open)\n"
           "  --formation F      line | triangle | column (default line)\n"
           "  --blend B          weighted | subsumption | vecsum (default weighted)\n"
           "  --formation-law L  seed (the seed's law, O ahead of the axle) | kanayama\n"
           "                     (slot tracking, for comparison) (default seed)\n"
           "  --ref-heading H    team reference heading: goal (bearing of the goal,\n"
           "                     default) | mean (the seed's mean of the headings)\n"
           "  --localize on|off  fuse the world's LED landmarks with odometry (EKF);\n"
           "                     off: odometry and frame consensus only (default on)\n"
           "  --stale-ms MS      sensors older than this stop the robot (default 500)\n"
           "  --batch            publish all hosted robots' commands and states as one\n"
           "                     ROVERS_COMMAND / ROVERS_STATE message per tick\n"
           "                     (sensors are taken per robot and batched alike)\n"
           "  --journal PATH     append each robot's controller snapshot to PATH\n"
           "                     (PATH-K when hosting several) after every cycle; a\n"
           "                     process started on an existing journal resumes there\n"
           "  (control period --period-ms, default 50 ms = 20 Hz)\n"
           DAEMON_COMMON_HELP);
}

static int parse_ids(rover_daemon *rd, const char *s)
{
    char *end;
    long a, b;
    a = strtol(s, &end, 10);
    if (end == s) return -1;
    if (*end == '-') {
        const char *t = end + 1;
        b = strtol(t, &end, 10);
        if (end == t || *end) return -1;
    } else if (*end) {
        return -1;
    } else {
        b = a;
    }
    if (a < 1 || b < a || b - a + 1 > HOST_MAX) return -1;
    rd->id_lo = (int32_t)a;
    rd->id_hi = (int32_t)b;
    return 0;
}

static int parse_args(rover_daemon *rd, int argc, char **argv)
{
    static const struct option opts[] = {
        { "id", required_argument, 0, 'i' },
        { "robots", required_argument, 0, 'n' },
        { "world", required_argument, 0, 'w' },
        { "formation", required_argument, 0, 'f' },
        { "blend", required_argument, 0, 'b' },
        { "stale-ms", required_argument, 0, 's' },
        { "formation-law", required_argument, 0, 'L' },
        { "ref-heading", required_argument, 0, 'H' },
        { "localize", required_argument, 0, 'z' },
        { "batch", no_argument, 0, 'B' },
        { "journal", required_argument, 0, 'J' },
        DAEMON_COMMON_OPTIONS,
        { 0, 0, 0, 0 }
    };
    int c;
    long v;
    double ms;
    while ((c = getopt_long(argc, argv, "", opts, NULL)) != -1) {
        int rc = daemon_parse_common(&rd->d, c, optarg);
        if (rc == 2) { usage(); exit(0); }
        if (rc < 0) return -1;
        if (rc == 1) continue;
        switch (c) {
        case 'i':
            if (parse_ids(rd, optarg) != 0) {
                fprintf(stderr, "tandem-rover: --id: '%s' is not K or A-B (1 <= A <= B, at most %d)\n",
                        optarg, HOST_MAX);
                return -1;
            }
            break;
        case 'n':
            if (parse_int_opt("tandem-rover", "--robots", optarg, 1, ROVER_WORLD_MAX_ROBOTS, &v) < 0)
                return -1;
            rd->robots = (int)v;
            break;
        case 'w':
            rd->world = rover_world_id(optarg);
            if (rd->world < 0) {
                fprintf(stderr, "tandem-rover: --world: '%s' is not open|obstacles|corridor|deadzone\n", optarg);
                return -1;
            }
            break;
        case 'f':
            if (!strcmp(optarg, "line")) rd->formation = FORMATION_LINE;
            else if (!strcmp(optarg, "triangle")) rd->formation = FORMATION_TRIANGLE;
            else if (!strcmp(optarg, "column")) rd->formation = FORMATION_COLUMN;
            else {
                fprintf(stderr, "tandem-rover: --formation: '%s' is not line|triangle|column\n", optarg);
                return -1;
            }
            break;
        case 'b':
            if (!strcmp(optarg, "weighted")) rd->blend = BEH_BLEND_WEIGHTED;
            else if (!strcmp(optarg, "subsumption")) rd->blend = BEH_BLEND_SUBSUMPTION;
            else if (!strcmp(optarg, "vecsum")) rd->blend = BEH_BLEND_VECSUM;
            else {
                fprintf(stderr, "tandem-rover: --blend: '%s' is not weighted|subsumption|vecsum\n", optarg);
                return -1;
            }
            break;
        case 'B':
            rd->batch = 1;
            break;
        case 'J':
            rd->journal = optarg;
            break;
        case 'L':
            if (!strcmp(optarg, "seed")) rd->params.formation_law = ROVER_LAW_SEED;
            else if (!strcmp(optarg, "kanayama")) rd->params.formation_law = ROVER_LAW_KANAYAMA;
            else {
                fprintf(stderr, "tandem-rover: --formation-law: '%s' is not seed|kanayama\n", optarg);
                return -1;
            }
            break;
        case 'H':
            if (!strcmp(optarg, "mean")) rd->params.goal_heading_gain = 0.0;
            else if (!strcmp(optarg, "goal")) rd->params.goal_heading_gain = 1.0;
            else {
                fprintf(stderr, "tandem-rover: --ref-heading: '%s' is not mean|goal\n", optarg);
                return -1;
            }
            break;
        case 'z':
            if (!strcmp(optarg, "on")) rd->localize = 1;
            else if (!strcmp(optarg, "off")) rd->localize = 0;
            else {
                fprintf(stderr, "tandem-rover: --localize: '%s' is not on|off\n", optarg);
                return -1;
            }
            break;
        case 's':
            if (parse_double_opt("tandem-rover", "--stale-ms", optarg, 10.0, 10000.0, &ms) < 0)
                return -1;
            rd->params.stale_s = ms * 1e-3;
            break;
        default:
            usage();
            return -1;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "tandem-rover: unexpected argument '%s'\n", argv[optind]);
        return -1;
    }
    if (rd->id_lo == 0) {
        fprintf(stderr, "tandem-rover: --id is required\n");
        return -1;
    }
    if (rd->id_hi > rd->robots) {
        fprintf(stderr, "tandem-rover: --id %d-%d outside the team of --robots %d\n",
                (int)rd->id_lo, (int)rd->id_hi, rd->robots);
        return -1;
    }
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
    int j, n = 0, stopped = 0;
    if (step < 0) return DAEMON_CONTINUE;                      /* no simulator clock yet */
    if (d->lockstep && step == rd->last_step) return DAEMON_CONTINUE;   /* a repeated clock: answer again only */
    if (rover_too_early(rd, step)) return DAEMON_CONTINUE;
    if (rd->first_step < 0)
        rd->first_step = step;
    if (d->lockstep && !rover_inputs_complete(rd, step)) {
        d->skip_ack = 1;                       /* wait for the announcement again */
        return DAEMON_CONTINUE;
    }
    rd->last_step = step;
    for (j = rd->id_lo; j <= rd->id_hi; j++) rover_apply_frames(rd, &rd->h[j - rd->id_lo]);
    rd->cur ^= 1;                                /* keep the cycle before for republish */
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
        if (o.mode == ROVER_MODE_SAFE_STOP) stopped++;
        rover_report_changes(h, o.mode, t_s);
        if (o.send_team) rover_publish_team(rd, h, &o, step, utime);
        rover_fill_outputs(h, &o, step, utime, &ob->cmd[n], &ob->st[n]);
        n++;
    }
    ob->n = n;
    ob->step = step;
    ob->utime = utime;
    ob->batch_seq = rd->batch_seq++;
    rover_publish_outbox(rd, ob);
    rover_journal_cycle(rd, step);
    rd->last_t_s = t_s;
    d->safe_hold = stopped > 0;
    snprintf(d->status, sizeof d->status, "%s: %d of %d robots stopped (stale input)%s",
             stopped ? "safe stop" : "running", stopped, rd->id_hi - rd->id_lo + 1,
             rd->journal_errors ? ", journal not written" : "");
    return DAEMON_CONTINUE;
}

int main(int argc, char **argv)
{
    int j, rc;
    char name[DAEMON_NAME_MAX];
    pose2 goal_w = { 0, 0, 0 }, goal_t;
    double goal[2], lm[ROVER_WORLD_MAX_LANDMARKS][2];
    static rover_daemon app;
    rover_daemon *rd = &app;
    daemon *d = &rd->d;
    rd->last_step = -1;
    rd->first_step = -1;
    rd->wait_step = -1;
    rd->out[0].step = rd->out[1].step = -1;
    for (j = 0; j <= ROVER_WORLD_MAX_ROBOTS; j++) rd->mate_step[j] = -1;
    rd->robots = 3;
    rd->world = ROVER_WORLD_OPEN;
    rd->localize = 1;
    rover_ctl_params_default(&rd->params);
    daemon_defaults(d, "tandem-rover", 0.05);
    if (parse_args(rd, argc, argv) != 0) return 2;
    rd->params.formation = rd->formation;
    rd->params.blend_mode = rd->blend;
    rd->params.localize = rd->localize;
    if (rd->id_lo == rd->id_hi) snprintf(name, sizeof name, "tandem-rover-%d", (int)rd->id_lo);
    else snprintf(name, sizeof name, "tandem-rover-%d-%d", (int)rd->id_lo, (int)rd->id_hi);
    snprintf(d->name, sizeof d->name, "%s", name);
    if (rover_world_layout(&rd->layout, rd->world, rd->robots, 1.0, rd->formation) != 0) {
        fprintf(stderr, "tandem-rover: no layout for %d robots\n", rd->robots);
        return 2;
    }
    goal_w.x_m = rd->layout.goal_m[0];
    goal_w.y_m = rd->layout.goal_m[1];
    rover_world_to_team(&rd->layout, &goal_w, &goal_t);
    goal[0] = goal_t.x_m;
    goal[1] = goal_t.y_m;
    for (j = 0; j < rd->layout.n_landmarks; j++) {
        const pose2 lw = { rd->layout.landmark_m[j][0], rd->layout.landmark_m[j][1], 0.0 };
        pose2 lt;
        rover_world_to_team(&rd->layout, &lw, &lt);
        lm[j][0] = lt.x_m;
        lm[j][1] = lt.y_m;
    }
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        pose2 start;
        rover_world_to_team(&rd->layout, &rd->layout.start_c[j - 1], &start);
        if (rover_ctl_init(&h->c, &rd->params, j, &start, goal) != 0 ||
            rover_ctl_set_landmarks(&h->c, (const double (*)[2])lm, rd->layout.n_landmarks) != 0) {
            fprintf(stderr, "tandem-rover: bad controller parameters\n");
            return 2;
        }
        snprintf(h->ch_cmd, sizeof h->ch_cmd, "ROVER%d_COMMAND", j);
        snprintf(h->ch_state, sizeof h->ch_state, "ROVER%d_STATE", j);
        h->shown_mode = h->shown_type = h->shown_yield = -1;
        h->sens_step = h->sonar_step = h->camera_step = -1;
    }
    if (rover_journal_start(rd) != 0) return 1;
    auth_bus_identity(AUTH_ROLE_ROVER, rd->id_lo, rd->id_hi);
    if (daemon_start(d) != 0) return 1;
    daemon_subscribe(d, "ROVER[0-9]+_SENSORS", rover_on_sensors, rd);
    daemon_subscribe(d, "ROVER[0-9]+_SONAR", rover_on_sonar, rd);
    daemon_subscribe(d, "ROVER[0-9]+_BEACONS", rover_on_beacons, rd);
    daemon_subscribe(d, "ROVERS_SENSORS", rover_on_sensors_batch, rd);
    daemon_subscribe(d, "ROVERS_BEACONS", rover_on_beacons_batch, rd);
    daemon_subscribe(d, "TEAM", rover_on_team, rd);
    d->repeat_fn = rover_republish;
    rc = daemon_run(d, cycle, rd);
    rover_journal_stop(rd);
    daemon_finish(d);
    return rc;
}

