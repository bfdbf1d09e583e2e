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
 * And a cycle runs only on complete inputs (lockstep_inputs_complete):
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
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "formation.h"
#include "journal.h"
#include "rover_ctl.h"
#include "rover_world.h"
#include "tandem_beacon_obs_t.h"
#include "tandem_rover_command_t.h"
#include "tandem_rover_sensors_t.h"
#include "tandem_rover_state_t.h"
#include "tandem_rovers_beacons_t.h"
#include "tandem_rovers_command_t.h"
#include "tandem_rovers_sensors_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_sim_clock_t.h"
#include "tandem_sonar_scan_t.h"
#include "tandem_team_msg_t.h"

#define HOST_MAX   ROVER_WORLD_MAX_ROBOTS
#define TEAMQ_MAX  4096
#define ROVER_INPUT_WAIT_NS 300000000LL   /* a missing input: gone after 0.3 s */

typedef struct hosted {
    rover_ctl_state c;
    int64_t     cmd_seq, state_seq, team_seq;
    int64_t     last_rx_ns;             /* wall time of the last sensor message */
    int64_t     sens_step, sonar_step, camera_step;   /* last frames taken (-1 none) */
    /* frames taken but not yet applied: the cycle applies them in one
     * order (encoders, sonar, camera), whatever order they arrived in */
    int         new_enc, new_sonar, new_cam;
    double      enc_rad[2];
    double      sonar_m[BEH_SONAR_N];
    int         cam_n;
    int32_t     cam_target[ROVER_WORLD_MAX_ROBOTS + ROVER_WORLD_MAX_LANDMARKS];
    double      cam_range_m[ROVER_WORLD_MAX_ROBOTS + ROVER_WORLD_MAX_LANDMARKS];
    double      cam_bearing_rad[ROVER_WORLD_MAX_ROBOTS + ROVER_WORLD_MAX_LANDMARKS];
    int         silent;                 /* lockstep: frames stopped (killed body) */
    tandem_team_msg_t last_team;        /* for republish (robot 0: none yet) */
    char        ch_cmd[24], ch_state[24];
    int         shown_mode, shown_type, shown_yield;   /* last printed (-1: none yet) */
    char        journal_path[600];      /* "" without --journal */
    journal     jr;
} hosted;

typedef struct teamq_item {
    int64_t step;
    rover_team_msg m;
} teamq_item;

static struct {
    int32_t id_lo, id_hi;
    int     robots;
    int     world, formation, blend;
    rover_world_config layout;
    rover_ctl_params params;
    hosted  h[HOST_MAX];
    teamq_item q[TEAMQ_MAX];
    int     nq;
    double  last_t_s;
    int64_t last_step;
    int64_t dropped_q;
    int     batch;                      /* --batch: ROVERS_COMMAND / ROVERS_STATE */
    int     localize;                   /* --localize: landmarks fused (1) */
    int64_t batch_seq;
    /* lockstep: what each mate last said on TEAM, and what we published */
    int64_t mate_step[ROVER_WORLD_MAX_ROBOTS + 1];   /* -1: nothing yet */
    int     mate_gone[ROVER_WORLD_MAX_ROBOTS + 1];
    int64_t wait_step, wait_since_ns;                 /* incomplete inputs */
    int64_t gone_count;
    struct outbox {
        tandem_rover_command_t cmd[HOST_MAX];
        tandem_rover_state_t   st[HOST_MAX];
        int     n;
        int64_t step, utime, batch_seq;               /* step -1: empty */
    } out[2];                                         /* out[cur]: the last cycle */
    int     cur;
    const char *journal;                /* --journal PATH, NULL: none */
    int64_t first_step;                 /* the first step this process ran a cycle for (-1) */
    int64_t journal_errors;
} A;

static hosted *find_hosted(int32_t id)
{
    return (id >= A.id_lo && id <= A.id_hi) ? &A.h[id - A.id_lo] : NULL;
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

static int parse_ids(const char *s)
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
    A.id_lo = (int32_t)a;
    A.id_hi = (int32_t)b;
    return 0;
}

static int parse_args(daemon *d, int argc, char **argv)
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
        int rc = daemon_parse_common(d, c, optarg);
        if (rc == 2) { usage(); exit(0); }
        if (rc < 0) return -1;
        if (rc == 1) continue;
        switch (c) {
        case 'i':
            if (parse_ids(optarg) != 0) {
                fprintf(stderr, "tandem-rover: --id: '%s' is not K or A-B (1 <= A <= B, at most %d)\n",
                        optarg, HOST_MAX);
                return -1;
            }
            break;
        case 'n':
            if (parse_int_opt("tandem-rover", "--robots", optarg, 1, ROVER_WORLD_MAX_ROBOTS, &v) < 0)
                return -1;
            A.robots = (int)v;
            break;
        case 'w':
            A.world = rover_world_id(optarg);
            if (A.world < 0) {
                fprintf(stderr, "tandem-rover: --world: '%s' is not open|obstacles|corridor|deadzone\n", optarg);
                return -1;
            }
            break;
        case 'f':
            if (!strcmp(optarg, "line")) A.formation = FORMATION_LINE;
            else if (!strcmp(optarg, "triangle")) A.formation = FORMATION_TRIANGLE;
            else if (!strcmp(optarg, "column")) A.formation = FORMATION_COLUMN;
            else {
                fprintf(stderr, "tandem-rover: --formation: '%s' is not line|triangle|column\n", optarg);
                return -1;
            }
            break;
        case 'b':
            if (!strcmp(optarg, "weighted")) A.blend = BEH_BLEND_WEIGHTED;
            else if (!strcmp(optarg, "subsumption")) A.blend = BEH_BLEND_SUBSUMPTION;
            else if (!strcmp(optarg, "vecsum")) A.blend = BEH_BLEND_VECSUM;
            else {
                fprintf(stderr, "tandem-rover: --blend: '%s' is not weighted|subsumption|vecsum\n", optarg);
                return -1;
            }
            break;
        case 'B':
            A.batch = 1;
            break;
        case 'J':
            A.journal = optarg;
            break;
        case 'L':
            if (!strcmp(optarg, "seed")) A.params.formation_law = ROVER_LAW_SEED;
            else if (!strcmp(optarg, "kanayama")) A.params.formation_law = ROVER_LAW_KANAYAMA;
            else {
                fprintf(stderr, "tandem-rover: --formation-law: '%s' is not seed|kanayama\n", optarg);
                return -1;
            }
            break;
        case 'H':
            if (!strcmp(optarg, "mean")) A.params.goal_heading_gain = 0.0;
            else if (!strcmp(optarg, "goal")) A.params.goal_heading_gain = 1.0;
            else {
                fprintf(stderr, "tandem-rover: --ref-heading: '%s' is not mean|goal\n", optarg);
                return -1;
            }
            break;
        case 'z':
            if (!strcmp(optarg, "on")) A.localize = 1;
            else if (!strcmp(optarg, "off")) A.localize = 0;
            else {
                fprintf(stderr, "tandem-rover: --localize: '%s' is not on|off\n", optarg);
                return -1;
            }
            break;
        case 's':
            if (parse_double_opt("tandem-rover", "--stale-ms", optarg, 10.0, 10000.0, &ms) < 0)
                return -1;
            A.params.stale_s = ms * 1e-3;
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
    if (A.id_lo == 0) {
        fprintf(stderr, "tandem-rover: --id is required\n");
        return -1;
    }
    if (A.id_hi > A.robots) {
        fprintf(stderr, "tandem-rover: --id %d-%d outside the team of --robots %d\n",
                (int)A.id_lo, (int)A.id_hi, A.robots);
        return -1;
    }
    return 0;
}

/* ---- messages in ------------------------------------------------------------ */

static daemon D;

static int64_t now_ns(void) { return rtloop_now_ns(); }

/* Lockstep start-up: the simulator publishes step 0 once, possibly before
 * every host has subscribed; whether a host saw it must not change the
 * run, so lockstep hosts ignore step 0 and start at their first period. */
static int too_early(int64_t step)
{
    return D.lockstep && step < D.period_steps;
}

static int all_ranges(const double *r, int n)
{
    int i;
    for (i = 0; i < n; i++)
        if (!isfinite(r[i]) || r[i] < 0.0) return 0;
    return 1;
}

/* A frame at or before the last one taken of its kind is a copy (the
 * simulator announcing a step again, or a replay): counted, ignored. */
static int is_copy(int64_t step, const int64_t *last)
{
    if (step > *last) return 0;
    D.msgs.duplicate++;
    return 1;
}

/* The hardware frames of one robot, from its own channels or from a
 * batch: only hosted robots count; bad values are dropped and counted. */
static void take_sensors(const tandem_rover_sensors_t *m)
{
    hosted *h = find_hosted(m->robot);
    if (!h || too_early(m->step)) return;      /* another host's robot / start-up */
    D.msgs.received++;
    if (is_copy(m->step, &h->sens_step)) return;
    if (m->step < 0 || !isfinite(m->wheel_left_rad) || !isfinite(m->wheel_right_rad)) {
        D.msgs.rejected++;
        return;
    }
    h->enc_rad[0] = m->wheel_left_rad;
    h->enc_rad[1] = m->wheel_right_rad;
    h->new_enc = 1;
    h->sens_step = m->step;
    h->silent = 0;
    h->last_rx_ns = now_ns();
}

static void take_sonar(const tandem_sonar_scan_t *m)
{
    hosted *h = find_hosted(m->robot);
    if (!h || too_early(m->step)) return;
    D.msgs.received++;
    if (is_copy(m->step, &h->sonar_step)) return;
    if (m->n != BEH_SONAR_N || m->step < 0 || !all_ranges(m->range_m, m->n)) {
        D.msgs.rejected++;
        return;
    }
    memcpy(h->sonar_m, m->range_m, sizeof h->sonar_m);
    h->new_sonar = 1;
    h->sonar_step = m->step;
}

static void take_beacons(const tandem_beacon_obs_t *m)
{
    hosted *h = find_hosted(m->observer);
    int i;
    if (!h || too_early(m->step)) return;
    D.msgs.received++;
    if (is_copy(m->step, &h->camera_step)) return;
    if (m->n < 0 || m->n > ROVER_WORLD_MAX_ROBOTS + ROVER_WORLD_MAX_LANDMARKS) {
        D.msgs.rejected++;
        return;
    }
    h->camera_step = m->step;
    h->cam_n = 0;
    for (i = 0; i < m->n; i++)
        if (isfinite(m->range_m[i]) && isfinite(m->bearing_rad[i]) && m->range_m[i] >= 0.0) {
            h->cam_target[h->cam_n] = m->target[i];
            h->cam_range_m[h->cam_n] = m->range_m[i];
            h->cam_bearing_rad[h->cam_n] = m->bearing_rad[i];
            h->cam_n++;
        }
    h->new_cam = 1;
}

/* The frames taken since the last cycle, into the controller. */
static void apply_frames(hosted *h)
{
    int i;
    if (h->new_enc && rover_ctl_encoders(&h->c, h->enc_rad[0], h->enc_rad[1],
                                         (double)h->sens_step * DAEMON_SIM_DT_S) != 0)
        D.msgs.rejected++;
    if (h->new_sonar && rover_ctl_sonar(&h->c, h->sonar_m, (double)h->sonar_step * DAEMON_SIM_DT_S) != 0)
        D.msgs.rejected++;
    /* unknown targets (not heard yet) are fine: skipped */
    for (i = 0; h->new_cam && i < h->cam_n; i++)
        rover_ctl_beacon(&h->c, h->cam_target[i], h->cam_range_m[i], h->cam_bearing_rad[i]);
    h->new_enc = h->new_sonar = h->new_cam = 0;
}

/* A message that does not decode is counted once, as received and rejected. */
#define ROVER_DECODE(type, rb, m) \
    (type##_decode((rb)->data, 0, (rb)->data_size, (m)) >= 0 ? 1 \
     : (D.msgs.received++, D.msgs.rejected++, 0))

static void on_sensors(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_rover_sensors_t m;
    (void)ch; (void)u;
    if (ROVER_DECODE(tandem_rover_sensors_t, rb, &m)) take_sensors(&m);
}

static void on_sonar(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_sonar_scan_t m;
    (void)ch; (void)u;
    if (!ROVER_DECODE(tandem_sonar_scan_t, rb, &m)) return;
    take_sonar(&m);
    tandem_sonar_scan_t_decode_cleanup(&m);
}

static void on_beacons(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_beacon_obs_t m;
    (void)ch; (void)u;
    if (!ROVER_DECODE(tandem_beacon_obs_t, rb, &m)) return;
    take_beacons(&m);
    tandem_beacon_obs_t_decode_cleanup(&m);
}

/* tandem-sim --rover-batch: every robot's frames in one message */
static void on_sensors_batch(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_rovers_sensors_t m;
    int i;
    (void)ch; (void)u;
    if (!ROVER_DECODE(tandem_rovers_sensors_t, rb, &m)) return;
    for (i = 0; i < m.n; i++) {
        take_sensors(&m.sensors[i]);
        take_sonar(&m.sonar[i]);
    }
    tandem_rovers_sensors_t_decode_cleanup(&m);
}

static void on_beacons_batch(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_rovers_beacons_t m;
    int i;
    (void)ch; (void)u;
    if (!ROVER_DECODE(tandem_rovers_beacons_t, rb, &m)) return;
    for (i = 0; i < m.n; i++) take_beacons(&m.obs[i]);
    tandem_rovers_beacons_t_decode_cleanup(&m);
}

static int team_msg_valid(const tandem_team_msg_t *m)
{
    return m->robot >= 1 && isfinite(m->x_m) && isfinite(m->y_m) && isfinite(m->theta_rad) &&
           isfinite(m->v_mps) && isfinite(m->w_radps) && isfinite(m->formation_scale) &&
           m->formation_scale > 0.0 && m->formation_scale <= 1.0 &&
           m->formation >= FORMATION_LINE && m->formation <= FORMATION_COLUMN &&
           m->announce >= FORMATION_ANN_NONE && m->announce <= FORMATION_ANN_RESTORE &&
           isfinite(m->goal_m[0]) && isfinite(m->goal_m[1]) && m->step >= 0;
}

static void on_team(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    tandem_team_msg_t m;
    teamq_item *q;
    (void)ch; (void)u;
    D.msgs.received++;
    if (tandem_team_msg_t_decode(rb->data, 0, rb->data_size, &m) < 0 || !team_msg_valid(&m)) {
        D.msgs.rejected++;
        return;
    }
    if (m.robot > A.robots) {
        D.msgs.rejected++;
        return;
    }
    if (is_copy(m.step, &A.mate_step[m.robot])) return;
    A.mate_step[m.robot] = m.step;
    A.mate_gone[m.robot] = 0;
    if (A.nq >= TEAMQ_MAX) {
        A.dropped_q++;
        D.msgs.stale++;
        return;
    }
    q = &A.q[A.nq++];
    memset(q, 0, sizeof *q);
    q->step = m.step;
    q->m.m.robot = m.robot;
    q->m.m.x_m = m.x_m;
    q->m.m.y_m = m.y_m;
    q->m.m.theta_rad = m.theta_rad;
    q->m.m.v_mps = m.v_mps;
    q->m.m.w_radps = m.w_radps;
    q->m.m.formation = m.formation;
    q->m.m.scale = m.formation_scale;
    q->m.m.announce = m.announce;
    q->m.m.announce_seq = m.announce_seq;
    q->m.goal_m[0] = m.goal_m[0];
    q->m.goal_m[1] = m.goal_m[1];
}

/* This process started after the run had (a restart): its first cycle
 * was later than the first period. */
static int joined_late(void)
{
    return A.first_step > D.period_steps;
}

/* Deliver queued team messages sent before `step` (all of them in real
 * time). Lockstep: only those sent after this process's first cycle; what
 * a mate sent up to that step may or may not have reached a process that
 * was just starting (republished on a repeated step, or not), so it must
 * not count. */
static void deliver_team(int64_t step, double t_s)
{
    int i, k = 0, j;
    for (i = 0; i < A.nq; i++) {
        if (D.lockstep && A.q[i].step >= step) {
            A.q[k++] = A.q[i];
            continue;
        }
        if (D.lockstep && joined_late() && A.q[i].step <= A.first_step)
            continue;
        for (j = A.id_lo; j <= A.id_hi; j++)
            if (j != A.q[i].m.m.robot && rover_ctl_team_msg(&A.h[j - A.id_lo].c, &A.q[i].m, t_s) < 0)
                D.msgs.rejected++;
    }
    A.nq = k;
}

/* ---- the cycle ------------------------------------------------------------------ */

static void publish_team(hosted *h, const rover_ctl_out *o, int64_t step, int64_t utime)
{
    tandem_team_msg_t t;
    memset(&t, 0, sizeof t);
    t.seq = h->team_seq++;
    t.utime = utime;
    t.step = step;
    t.robot = h->c.id;
    t.x_m = o->team.x_m;
    t.y_m = o->team.y_m;
    t.theta_rad = o->team.theta_rad;
    t.v_mps = o->team.v_mps;
    t.w_radps = o->team.w_radps;
    t.formation = (int8_t)o->team.formation;
    t.formation_scale = o->team.scale;
    t.announce = (int8_t)o->team.announce;
    t.announce_seq = o->team.announce_seq;
    t.goal_m[0] = h->c.goal_m[0];
    t.goal_m[1] = h->c.goal_m[1];
    AUTH_PUBLISH(tandem_team_msg_t, D.lcm, "TEAM", &t);
    h->last_team = t;
}

/* One robot's command and own-view state for this tick, into *cmd / *st. */
static void fill_outputs(hosted *h, const rover_ctl_out *o, int64_t step, int64_t utime,
                         tandem_rover_command_t *cmd, tandem_rover_state_t *st)
{
    int i;
    cmd->seq = h->cmd_seq++;
    cmd->utime = utime;
    cmd->step = step;
    cmd->robot = h->c.id;
    cmd->v_mps = o->u.v_mps;
    cmd->w_radps = o->u.w_radps;
    memset(st, 0, sizeof *st);
    st->seq = h->state_seq++;
    st->utime = utime;
    st->step = step;
    st->robot = h->c.id;
    st->x_m = o->o.x_m;
    st->y_m = o->o.y_m;
    st->theta_rad = o->o.theta_rad;
    st->v_mps = h->c.v_est_mps;
    st->w_radps = h->c.w_est_radps;
    st->mode = (int8_t)o->mode;
    st->formation = (int8_t)h->c.fsm.type;
    for (i = 0; i < 4; i++) st->weight[i] = o->weight[i];
    st->formation_err_m = o->slot_err_m;
    st->team_size = (int16_t)o->team_size;
    st->formation_scale = h->c.fsm.scale;
}

/* The hosted robots' commands and states of one cycle: one message each
 * per robot, or (--batch) one ROVERS_COMMAND and one ROVERS_STATE for all
 * of them. Published again as they were by republish. */
static void publish_outbox(struct outbox *o)
{
    int i;
    if (o->step < 0) return;
    if (A.batch) {
        tandem_rovers_command_t bc;
        tandem_rovers_state_t bs;
        BATCH_HEADER(bc, o->batch_seq, o->utime, o->step, o->n);
        BATCH_HEADER(bs, o->batch_seq, o->utime, o->step, o->n);
        bc.cmd = o->cmd;
        bs.state = o->st;
        AUTH_PUBLISH(tandem_rovers_command_t, D.lcm, "ROVERS_COMMAND", &bc);
        AUTH_PUBLISH(tandem_rovers_state_t, D.lcm, "ROVERS_STATE", &bs);
        return;
    }
    for (i = 0; i < o->n; i++) {
        hosted *h = find_hosted(o->cmd[i].robot);
        AUTH_PUBLISH(tandem_rover_command_t, D.lcm, h->ch_cmd, &o->cmd[i]);
        AUTH_PUBLISH(tandem_rover_state_t, D.lcm, h->ch_state, &o->st[i]);
    }
}

/* A step this host already answered was announced again: something it
 * sent may have been lost. The last two cycles' outputs (a state is read
 * one cycle later) and each robot's last team message, unchanged. */
static void republish(daemon *d, void *user)
{
    int j;
    (void)d; (void)user;
    publish_outbox(&A.out[A.cur ^ 1]);
    publish_outbox(&A.out[A.cur]);
    for (j = A.id_lo; j <= A.id_hi; j++)
        if (A.h[j - A.id_lo].last_team.robot > 0)
            AUTH_PUBLISH(tandem_team_msg_t, D.lcm, "TEAM", &A.h[j - A.id_lo].last_team);
}

/* One console line per change of what a robot is doing (mode, formation
 * type, giving way), so that a run can be followed without lcm-spy. */
static void report_changes(hosted *h, int mode, double t_s)
{
    static const char *modes[] = { "formation", "dead-zone escape", "changing formation", "at goal",
                                   "safe stop (stale input)" };
    static const char *types[] = { "line", "triangle", "column" };
    const int type = h->c.fsm.type, yield = h->c.esc_yield;
    if (mode != h->shown_mode && mode >= 0 && mode <= ROVER_MODE_SAFE_STOP)
        printf("[%9.3f] robot %d: %s\n", t_s, (int)h->c.id, modes[mode]);
    if (type != h->shown_type && h->shown_type >= 0 && type >= 0 && type <= FORMATION_COLUMN)
        printf("[%9.3f] robot %d: formation %s -> %s (scale %.2f)\n", t_s, (int)h->c.id,
               types[h->shown_type], types[type], h->c.fsm.scale);
    if (yield != h->shown_yield && h->shown_yield >= 0)
        printf("[%9.3f] robot %d: %s\n", t_s, (int)h->c.id, yield ? "gives way to a leaving mate" : "done giving way");
    if (mode != h->shown_mode || type != h->shown_type || yield != h->shown_yield)
        fflush(stdout);
    h->shown_mode = mode;
    h->shown_type = type;
    h->shown_yield = yield;
}

/* The frame a lockstep cycle at `step` needs: the last one of its period,
 * if that falls after start-up and not before this process's first cycle
 * (a process restarted at step k never saw what was sent before k: a
 * frame or team message it cannot have must not decide anything, or
 * whether it waited would depend on the machine's speed) (-1: none). */
static int64_t frame_due(int64_t step, int64_t period)
{
    const int64_t due = step - step % period;
    return due >= D.period_steps && due >= A.first_step ? due : -1;
}

/* Lockstep: are this step's inputs all here (see the top of the file)? A
 * hosted robot needs its encoder/sonar frame and camera frame of this
 * step's periods; every robot's last team tick (sent every team period)
 * must be in for the robots that listen to it. */
static int inputs_missing(int64_t step, int mark_gone)
{
    const int64_t sens = frame_due(step, ROVER_SENSOR_PERIOD_STEPS);
    const int64_t cam = frame_due(step, ROVER_CAMERA_PERIOD_STEPS);
    const int64_t team_w = (int64_t)llround(A.params.team_period_s / DAEMON_SIM_DT_S);
    const int64_t team_from = joined_late() ? A.first_step + 1 : 0;   /* see deliver_team */
    int j, missing = 0;
    for (j = A.id_lo; j <= A.id_hi; j++) {
        hosted *h = &A.h[j - A.id_lo];
        if (h->silent) continue;
        if (h->sens_step < sens || h->sonar_step < sens || h->camera_step < cam) {
            missing++;
            if (mark_gone) h->silent = 1;
        }
    }
    for (j = 1; j <= A.robots; j++) {
        const int listened = A.id_lo != A.id_hi || A.id_lo != j;
        if (!listened || A.mate_gone[j] || step - team_w < team_from || A.mate_step[j] >= step - team_w)
            continue;
        missing++;
        if (mark_gone) A.mate_gone[j] = 1;
    }
    return missing;
}

static int lockstep_inputs_complete(int64_t step)
{
    const int64_t now = now_ns();
    int n;
    if (inputs_missing(step, 0) == 0) return 1;
    if (A.wait_step != step) {
        A.wait_step = step;
        A.wait_since_ns = now;
    }
    if (now - A.wait_since_ns < ROVER_INPUT_WAIT_NS) return 0;
    /* announced again and again for 0.3 s: not lost, gone (a killed
     * robot, a dead mate). Go on without it until it speaks again. */
    n = inputs_missing(step, 1);
    A.gone_count += n;
    fprintf(stderr, "%s: step %lld: %d input source(s) silent for %.1f s, taken as gone\n",
            D.name, (long long)step, n, (double)ROVER_INPUT_WAIT_NS * 1e-9);
    return 1;
}

/* ---- journal (--journal) --------------------------------------------------------- */

/* At start-up: each hosted robot resumes from its journal's last intact
 * snapshot (step, then rover_ctl_snapshot's values), and appends to it. */
static int journal_start(void)
{
    int j;
    for (j = A.id_lo; j <= A.id_hi && A.journal; j++) {
        hosted *h = &A.h[j - A.id_lo];
        double v[1 + ROVER_CTL_SNAPSHOT_VALUES];
        int n;
        if (A.id_lo == A.id_hi) snprintf(h->journal_path, sizeof h->journal_path, "%s", A.journal);
        else snprintf(h->journal_path, sizeof h->journal_path, "%s-%d", A.journal, j);
        n = journal_load_last(h->journal_path, v, 1 + ROVER_CTL_SNAPSHOT_VALUES);
        if (n == 1 + ROVER_CTL_SNAPSHOT_VALUES && rover_ctl_resume(&h->c, v + 1) == ROVER_CTL_OK) {
            printf("%s: robot %d resumed from %s (step %.0f, escapes %d, formation changes %d)\n", D.name, j,
                   h->journal_path, v[0], h->c.escapes, h->c.formation_changes);
            fflush(stdout);
        } else if (n != JOURNAL_ERR_NONE) {
            fprintf(stderr, "%s: journal %s: last snapshot is not robot %d's; starting from the launch pose\n",
                    D.name, h->journal_path, j);
        }
        if (journal_open(&h->jr, h->journal_path) != JOURNAL_OK) {
            fprintf(stderr, "%s: cannot open journal %s\n", D.name, h->journal_path);
            return -1;
        }
    }
    return 0;
}

/* After a cycle's outputs are out: one snapshot per robot (a robot before
 * its first encoder frame has nothing to keep). */
static void journal_cycle(int64_t step)
{
    int j;
    for (j = A.id_lo; j <= A.id_hi && A.journal; j++) {
        hosted *h = &A.h[j - A.id_lo];
        double v[1 + ROVER_CTL_SNAPSHOT_VALUES];
        v[0] = (double)step;
        if (rover_ctl_snapshot(&h->c, v + 1) == ROVER_CTL_OK &&
            journal_append(&h->jr, v, 1 + ROVER_CTL_SNAPSHOT_VALUES) != JOURNAL_OK)
            A.journal_errors++;
    }
}

static void journal_stop(void)
{
    int j;
    for (j = A.id_lo; j <= A.id_hi && A.journal; j++)
        journal_close(&A.h[j - A.id_lo].jr);
}

static int cycle(daemon *d, void *user)
{
    const int64_t step = d->lockstep ? d->pending_step : d->step;
    const double t_s = (double)(step < 0 ? 0 : step) * DAEMON_SIM_DT_S;
    const double dt = A.last_t_s > 0.0 && t_s > A.last_t_s ? t_s - A.last_t_s : d->period_s;
    const int64_t utime = daemon_utime_now();
    struct outbox *ob;
    int j, n = 0, stopped = 0;
    (void)user;
    if (step < 0) return DAEMON_CONTINUE;                      /* no simulator clock yet */
    if (d->lockstep && step == A.last_step) return DAEMON_CONTINUE;   /* a repeated clock: answer again only */
    if (too_early(step)) return DAEMON_CONTINUE;
    if (A.first_step < 0)
        A.first_step = step;
    if (d->lockstep && !lockstep_inputs_complete(step)) {
        d->skip_ack = 1;                       /* wait for the announcement again */
        return DAEMON_CONTINUE;
    }
    A.last_step = step;
    for (j = A.id_lo; j <= A.id_hi; j++) apply_frames(&A.h[j - A.id_lo]);
    A.cur ^= 1;                                /* keep the cycle before for republish */
    ob = &A.out[A.cur];
    deliver_team(step, t_s);
    for (j = A.id_lo; j <= A.id_hi; j++) {
        hosted *h = &A.h[j - A.id_lo];
        rover_ctl_out o;
        /* real time: a silent simulator is stale input too (wall clock) */
        if (!d->lockstep && h->last_rx_ns > 0 &&
            (double)(now_ns() - h->last_rx_ns) * 1e-9 > h->c.p.stale_s) {
            memset(&o, 0, sizeof o);
            o.mode = ROVER_MODE_SAFE_STOP;
        } else if (rover_ctl_step(&h->c, t_s, dt, &o) != 0) {
            D.msgs.rejected++;
        }
        if (o.mode == ROVER_MODE_SAFE_STOP) stopped++;
        report_changes(h, o.mode, t_s);
        if (o.send_team) publish_team(h, &o, step, utime);
        fill_outputs(h, &o, step, utime, &ob->cmd[n], &ob->st[n]);
        n++;
    }
    ob->n = n;
    ob->step = step;
    ob->utime = utime;
    ob->batch_seq = A.batch_seq++;
    publish_outbox(ob);
    journal_cycle(step);
    A.last_t_s = t_s;
    d->safe_hold = stopped > 0;
    snprintf(d->status, sizeof d->status, "%s: %d of %d robots stopped (stale input)%s",
             stopped ? "safe stop" : "running", stopped, A.id_hi - A.id_lo + 1,
             A.journal_errors ? ", journal not written" : "");
    return DAEMON_CONTINUE;
}



int main(int argc, char **argv)
{
    int j;
    char name[DAEMON_NAME_MAX];
    pose2 goal_w = { 0, 0, 0 }, goal_t;
    double goal[2], lm[ROVER_WORLD_MAX_LANDMARKS][2];
    memset(&A, 0, sizeof A);
    A.last_step = -1;
    A.first_step = -1;
    A.wait_step = -1;
    A.out[0].step = A.out[1].step = -1;
    for (j = 0; j <= ROVER_WORLD_MAX_ROBOTS; j++) A.mate_step[j] = -1;
    A.robots = 3;
    A.world = ROVER_WORLD_OPEN;
    A.localize = 1;
    rover_ctl_params_default(&A.params);
    daemon_defaults(&D, "tandem-rover", 0.05);
    if (parse_args(&D, argc, argv) != 0) return 2;
    A.params.formation = A.formation;
    A.params.blend_mode = A.blend;
    A.params.localize = A.localize;
    if (A.id_lo == A.id_hi) snprintf(name, sizeof name, "tandem-rover-%d", (int)A.id_lo);
    else snprintf(name, sizeof name, "tandem-rover-%d-%d", (int)A.id_lo, (int)A.id_hi);
    snprintf(D.name, sizeof D.name, "%s", name);
    if (rover_world_layout(&A.layout, A.world, A.robots, 1.0, A.formation) != 0) {
        fprintf(stderr, "tandem-rover: no layout for %d robots\n", A.robots);
        return 2;
    }
    goal_w.x_m = A.layout.goal_m[0];
    goal_w.y_m = A.layout.goal_m[1];
    rover_world_to_team(&A.layout, &goal_w, &goal_t);
    goal[0] = goal_t.x_m;
    goal[1] = goal_t.y_m;
    for (j = 0; j < A.layout.n_landmarks; j++) {
        const pose2 lw = { A.layout.landmark_m[j][0], A.layout.landmark_m[j][1], 0.0 };
        pose2 lt;
        rover_world_to_team(&A.layout, &lw, &lt);
        lm[j][0] = lt.x_m;
        lm[j][1] = lt.y_m;
    }
    for (j = A.id_lo; j <= A.id_hi; j++) {
        hosted *h = &A.h[j - A.id_lo];
        pose2 start;
        rover_world_to_team(&A.layout, &A.layout.start_c[j - 1], &start);
        if (rover_ctl_init(&h->c, &A.params, j, &start, goal) != 0 ||
            rover_ctl_set_landmarks(&h->c, (const double (*)[2])lm, A.layout.n_landmarks) != 0) {
            fprintf(stderr, "tandem-rover: bad controller parameters\n");
            return 2;
        }
        snprintf(h->ch_cmd, sizeof h->ch_cmd, "ROVER%d_COMMAND", j);
        snprintf(h->ch_state, sizeof h->ch_state, "ROVER%d_STATE", j);
        h->shown_mode = h->shown_type = h->shown_yield = -1;
        h->sens_step = h->sonar_step = h->camera_step = -1;
    }
    if (journal_start() != 0) return 1;
    auth_bus_identity(AUTH_ROLE_ROVER, A.id_lo, A.id_hi);
    if (daemon_start(&D) != 0) return 1;
    daemon_subscribe(&D, "ROVER[0-9]+_SENSORS", on_sensors, NULL);
    daemon_subscribe(&D, "ROVER[0-9]+_SONAR", on_sonar, NULL);
    daemon_subscribe(&D, "ROVER[0-9]+_BEACONS", on_beacons, NULL);
    daemon_subscribe(&D, "ROVERS_SENSORS", on_sensors_batch, NULL);
    daemon_subscribe(&D, "ROVERS_BEACONS", on_beacons_batch, NULL);
    daemon_subscribe(&D, "TEAM", on_team, NULL);
    D.repeat_fn = republish;
    daemon_run(&D, cycle, NULL);
    journal_stop();
    daemon_finish(&D);
    return 0;
}
