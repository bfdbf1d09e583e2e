/* rover_outputs: what tandem-rover sends and keeps: each hosted robot's
 * command, own-view state and team message (per robot or batched, and
 * again on a repeated step), a console line per change of what a robot
 * does, and the --journal snapshots.
 */
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "rover_daemon.h"
#include "formation.h"
#include "tandem_rovers_command_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_teams_msg_t.h"

/* ---- outputs ------------------------------------------------------------------ */

void rover_publish_team(rover_daemon *rd, hosted *h, const rover_ctl_out *o, int64_t step,
                        int64_t utime)
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
    if (!rd->batch)
        AUTH_PUBLISH(tandem_team_msg_t, &rd->d.bus, rd->d.lcm, "TEAM", &t);
    h->last_team = t;
    h->team_due = rd->batch;
}

void rover_publish_teams(rover_daemon *rd, int again)
{
    int j, n = 0, c;
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        if ((again ? h->last_team.robot > 0 : h->team_due) && n < HOST_MAX)
            rd->teams_out[n++] = h->last_team;
        h->team_due = 0;
    }
    for (c = 0; n > 0 && c < BATCH_CHUNKS(n); c++) {
        tandem_teams_msg_t b;
        BATCH_HEADER(b, rd->teams_seq++, daemon_utime_now(), rd->teams_out[c * BATCH_MAX].step,
                     BATCH_CHUNK_N(n, c));
        b.team = rd->teams_out + c * BATCH_MAX;
        AUTH_PUBLISH(tandem_teams_msg_t, &rd->d.bus, rd->d.lcm, "TEAMS", &b);
    }
}

/* One robot's command and own-view state for this tick, into *cmd / *st. */
void rover_fill_outputs(hosted *h, const rover_ctl_out *o, int64_t step, int64_t utime,
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
    for (i = 0; i < 4; i++)
        st->weight[i] = o->weight[i];
    st->formation_err_m = o->slot_err_m;
    st->team_size = (int16_t)o->team_size;
    st->formation_scale = h->c.fsm.scale;
}

/* The hosted robots' commands and states of one cycle: one message each
 * per robot, or (--batch) one ROVERS_COMMAND and one ROVERS_STATE for all
 * of them (BATCH_MAX a message: a larger host in several). Published again as they were by rover_republish. */
void rover_publish_outbox(rover_daemon *rd, rover_outbox *o)
{
    int i, c;
    if (o->step < 0)
        return;
    for (c = 0; rd->batch && c < BATCH_CHUNKS(o->n); c++) {
        tandem_rovers_command_t bc;
        tandem_rovers_state_t bs;
        BATCH_HEADER(bc, o->batch_seq + c, o->utime, o->step, BATCH_CHUNK_N(o->n, c));
        BATCH_HEADER(bs, o->batch_seq + c, o->utime, o->step, BATCH_CHUNK_N(o->n, c));
        bc.cmd = o->cmd + c * BATCH_MAX;
        bs.state = o->st + c * BATCH_MAX;
        AUTH_PUBLISH(tandem_rovers_command_t, &rd->d.bus, rd->d.lcm, "ROVERS_COMMAND", &bc);
        AUTH_PUBLISH(tandem_rovers_state_t, &rd->d.bus, rd->d.lcm, "ROVERS_STATE", &bs);
    }
    if (rd->batch)
        return;
    for (i = 0; i < o->n; i++) {
        hosted *h = rover_find_hosted(rd, o->cmd[i].robot);
        AUTH_PUBLISH(tandem_rover_command_t, &rd->d.bus, rd->d.lcm, h->ch_cmd, &o->cmd[i]);
        AUTH_PUBLISH(tandem_rover_state_t, &rd->d.bus, rd->d.lcm, h->ch_state, &o->st[i]);
    }
}

/* A step this host already answered was announced again: something it
 * sent may have been lost. The last two cycles' outputs (a state is read
 * one cycle later) and each robot's last team message, unchanged. */
void rover_republish(daemon *d, void *user)
{
    rover_daemon *rd = user;
    int j;
    (void)d;
    rover_publish_outbox(rd, &rd->out[rd->cur ^ 1]);
    rover_publish_outbox(rd, &rd->out[rd->cur]);
    if (rd->batch) {
        rover_publish_teams(rd, 1);
        return;
    }
    for (j = rd->id_lo; j <= rd->id_hi; j++)
        if (rd->h[j - rd->id_lo].last_team.robot > 0)
            AUTH_PUBLISH(tandem_team_msg_t, &rd->d.bus, rd->d.lcm, "TEAM",
                         &rd->h[j - rd->id_lo].last_team);
}

/* One line per change of escape phase or of the wall side followed, with
 * the robot's own estimate of where it is (the leave rule compares its
 * distance to the goal with the one where the escape started). */
static void report_escape(hosted *h, const pose2 *o, double t_s)
{
    static const char *const phases[ROVER_ESC_COUNT] = {
        "escape over",
        "turns out of the trap",
        "follows the wall",
        "turns away from a leaving mate",
        "follows the wall out of a leaving mate's way",
        "stalled: turns toward its way"
    };
    const rover_ctl_state *c = &h->c;
    const int esc = c->esc.phase * 4 + (c->esc.side + 1);
    const double xy[2] = { o->x_m, o->y_m };
    /* as the leave rule measures it, like the hit point's */
    const double dist_m = rover_ctl_leave_measure_m(c, xy, c->goal_m);
    if (esc == h->shown_esc || c->esc.phase < ROVER_ESC_NONE || c->esc.phase >= ROVER_ESC_COUNT)
        return;
    if (h->shown_esc < 0 && c->esc.phase == ROVER_ESC_NONE) {
        h->shown_esc = esc; /* not escaping at the start: nothing to say */
        return;
    }
    if (c->esc.phase == ROVER_ESC_FOLLOW)
        printf(
            "[%9.3f] robot %d: %s on its %s at (%.2f, %.2f), %.2f m from the goal (%.2f m where it began)\n",
            t_s, (int)c->id, phases[c->esc.phase], c->esc.side < 0 ? "right" : "left", o->x_m,
            o->y_m, dist_m, c->esc.hit_dist_m);
    else
        printf("[%9.3f] robot %d: %s at (%.2f, %.2f)\n", t_s, (int)c->id, phases[c->esc.phase],
               o->x_m, o->y_m);
    h->shown_esc = esc;
    fflush(stdout);
}

/* One console line per change of what a robot is doing (mode, formation
 * type, giving way), so that a run can be followed without lcm-spy. */
void rover_report_changes(hosted *h, const rover_ctl_out *o, double t_s)
{
    const int mode = o->mode;
    static const char *const modes[] = { "formation", "dead-zone escape", "changing formation",
                                         "at goal", "safe stop (stale input)" };
    static const char *const types[] = { "line", "triangle", "column" };
    const int type = h->c.fsm.type, yield = h->c.esc.yield;
    if (mode != h->shown_mode && mode >= 0 && mode <= ROVER_MODE_SAFE_STOP)
        printf("[%9.3f] robot %d: %s\n", t_s, (int)h->c.id, modes[mode]);
    if (type != h->shown_type && h->shown_type >= 0 && type >= 0 && type <= FORMATION_COLUMN)
        printf("[%9.3f] robot %d: formation %s -> %s (scale %.2f)\n", t_s, (int)h->c.id,
               types[h->shown_type], types[type], h->c.fsm.scale);
    if (yield != h->shown_yield && h->shown_yield >= 0)
        printf("[%9.3f] robot %d: %s\n", t_s, (int)h->c.id,
               yield ? "gives way to a leaving mate" : "done giving way");
    report_escape(h, &o->o, t_s);
    if (mode != h->shown_mode || type != h->shown_type || yield != h->shown_yield)
        fflush(stdout);
    h->shown_mode = mode;
    h->shown_type = type;
    h->shown_yield = yield;
}
/* ---- journal (--journal) --------------------------------------------------------- */

/* A robot's journal that does not check out: file, record, why (exit 1
 * follows: resuming from a state that lies would drive the robot from a
 * pose it is not at). */
static int journal_refused(const rover_daemon *rd, const hosted *h, const journal_report *rep,
                           const char *code, const char *why)
{
    fprintf(
        stderr,
        "%s: journal %s: record %ld (line %ld): %s (%s); refusing to start (move the file away, "
        "or --journal-reset to start fresh on purpose)\n",
        rd->d.name, h->journal_path, rep->line, rep->line, why, code);
    return ROVER_DAEMON_ERR_JOURNAL;
}

/* Robot j's journal: its last record checked and taken back (0, also
 * when there is none), or refused. */
static int journal_resume(rover_daemon *rd, hosted *h, int j, const journal_key *key)
{
    double v[1 + ROVER_CTL_SNAPSHOT_VALUES];
    journal_report rep;
    const int n = journal_load_last(h->journal_path, key, v, 1 + ROVER_CTL_SNAPSHOT_VALUES, &rep);
    if (n == JOURNAL_ERR_NONE)
        return 0;
    if (n < 0)
        return journal_refused(rd, h, &rep, journal_strerror(n),
                               n == JOURNAL_ERR_READ ? strerror(rep.err_no) : rep.why);
    if (n != 1 + ROVER_CTL_SNAPSHOT_VALUES || !isfinite(v[0]) || v[0] < 0.0 || v[0] != floor(v[0]))
        return journal_refused(rd, h, &rep, "ROVER_CTL_ERR_SNAPSHOT",
                               "not a snapshot of this controller");
    if (rover_ctl_resume(&h->c, v + 1) != ROVER_CTL_OK)
        return journal_refused(rd, h, &rep, "ROVER_CTL_ERR_SNAPSHOT",
                               "another robot's snapshot, or a value out of its range");
    h->jr.seq = rep.last_seq;
    printf(
        "%s: robot %d resumed from %s record %ld (step %.0f, escapes %d, formation changes %d)\n",
        rd->d.name, j, h->journal_path, rep.records, v[0], h->c.escapes, h->c.formation_changes);
    fflush(stdout);
    return 0;
}

/* At start-up (after daemon_start: the journal key comes from the bus
 * key): each hosted robot resumes from its journal's last record (step,
 * then rover_ctl_snapshot's values) or, with --journal-reset, starts
 * fresh; then appends to it. */
int rover_journal_start(rover_daemon *rd)
{
    journal_key key;
    int j;
    if (!rd->journal)
        return 0;
    journal_key_from_bus(&rd->d.bus, &key, rd->d.name);
    for (j = rd->id_lo; j <= rd->id_hi; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        long seq = 0;
        if (rd->id_lo == rd->id_hi)
            snprintf(h->journal_path, sizeof h->journal_path, "%s", rd->journal);
        else
            snprintf(h->journal_path, sizeof h->journal_path, "%s-%d", rd->journal, j);
        if (!rd->journal_reset && journal_resume(rd, h, j, &key) != 0)
            return ROVER_DAEMON_ERR_JOURNAL;
        seq = h->jr.seq;
        if (journal_open(&h->jr, h->journal_path, &key,
                         rd->journal_reset ? JOURNAL_TRUNCATE : JOURNAL_APPEND) != JOURNAL_OK) {
            fprintf(stderr, "%s: cannot open journal %s: %s\n", rd->d.name, h->journal_path,
                    strerror(h->jr.err_no));
            return ROVER_DAEMON_ERR_JOURNAL;
        }
        h->jr.seq = seq;
    }
    return 0;
}

/* After a cycle's outputs are made, before they go out: one snapshot per
 * robot (a robot before its first encoder frame has nothing to keep). */
int rover_journal_cycle(rover_daemon *rd, int64_t step)
{
    int j, held = 0;
    for (j = rd->id_lo; j <= rd->id_hi && rd->journal; j++) {
        hosted *h = &rd->h[j - rd->id_lo];
        double v[1 + ROVER_CTL_SNAPSHOT_VALUES];
        int rc;
        v[0] = (double)step;
        h->journal_held = 0;
        if (rover_ctl_snapshot(&h->c, v + 1) != ROVER_CTL_OK)
            continue;
        rc = journal_append(&h->jr, v, 1 + ROVER_CTL_SNAPSHOT_VALUES);
        h->journal_held = rc != JOURNAL_OK;
        held += h->journal_held;
        /* said once when writing starts failing and once when it works again */
        if (rc != JOURNAL_OK && !rd->journal_failing)
            fprintf(
                stderr,
                "%s: cannot write the journal %s: %s (%s): robot %d STOPPED until it can be written\n",
                rd->d.name, h->journal_path, strerror(h->jr.err_no), journal_strerror(rc), j);
        else if (rc == JOURNAL_OK && rd->journal_failing)
            fprintf(stderr, "%s: journal %s written again: robot %d moves on\n", rd->d.name,
                    h->journal_path, j);
        rd->journal_failing = rc != JOURNAL_OK;
        if (rc != JOURNAL_OK)
            rd->journal_errors++;
    }
    return held;
}

void rover_journal_hold(rover_daemon *rd, rover_outbox *o)
{
    int i;
    for (i = 0; i < o->n; i++) {
        const hosted *h = rover_find_hosted(rd, o->cmd[i].robot);
        if (!h || !h->journal_held)
            continue;
        o->cmd[i].v_mps = 0.0;
        o->cmd[i].w_radps = 0.0;
        o->st[i].mode = ROVER_MODE_SAFE_STOP;
    }
}

void rover_journal_stop(rover_daemon *rd)
{
    int j;
    for (j = rd->id_lo; j <= rd->id_hi && rd->journal; j++)
        journal_close(&rd->h[j - rd->id_lo].jr);
}
