/* supervisor_journal: tandem-supervisor's --journal: every change of the
 * discrete state (marking, running rows, the workpieces bound to tokens,
 * action ids) appended as one snapshot; the last one taken back at start.
 */
#include <stdio.h>
#include <string.h>
#include "supervisor_daemon.h"
#include "vec3.h"

#define SNAP_HEAD 25
#define SNAP_LEN  (SNAP_HEAD + CARRY_N_PLACES + 6 * CARRY_N_TRANSITIONS)
#define SNAP_VERSION 1

static int snapshot(supervisor_daemon *sv, double *v)
{
    int n = 0, i, a;
    v[n++] = SNAP_VERSION; v[n++] = (double)sv->d.step;
    v[n++] = sv->net.st.running; v[n++] = (double)sv->net.fired_count;
    v[n++] = sv->next_action_id; v[n++] = sv->wp_id;
    v[n++] = sv->wp_pos_m[0]; v[n++] = sv->wp_pos_m[1]; v[n++] = sv->wp_pos_m[2]; v[n++] = sv->wp_yaw_rad;
    v[n++] = sv->pick_id; v[n++] = sv->pick_pos_m[0]; v[n++] = sv->pick_pos_m[1]; v[n++] = sv->pick_pos_m[2];
    v[n++] = sv->pick_yaw_rad; v[n++] = sv->last_taken_id; v[n++] = sv->p1_bound; v[n++] = sv->detections;
    v[n++] = sv->last_fired; v[n++] = sv->blockages;
    v[n++] = sv->rows_reissued; v[n++] = sv->dones_recovered; v[n++] = sv->replans; v[n++] = sv->deadlocks;
    v[n++] = sv->faults;
    for (i = 0; i < CARRY_N_PLACES; i++) v[n++] = sv->net.st.m[i];
    for (i = 0; i < CARRY_N_TRANSITIONS; i++)
        for (a = 0; a < 2; a++) {
            v[n++] = sv->slot[i].state[a];
            v[n++] = sv->slot[i].action_id[a];
            v[n++] = (double)sv->slot[i].sent_step[a];
        }
    return n;
}

static int restore(supervisor_daemon *sv, const double *v)
{
    int n = SNAP_HEAD, i, a;
    petri_state st;
    memset(&st, 0, sizeof st);
    st.running = (uint32_t)v[2];
    for (i = 0; i < CARRY_N_PLACES; i++) {
        if (v[n] < 0 || v[n] > PETRI_TOKEN_MAX) return SUPERVISOR_ERR_SNAPSHOT;
        st.m[i] = (uint8_t)v[n++];
    }
    if (petri_set_state(&sv->net, &st) != 0) return SUPERVISOR_ERR_SNAPSHOT;
    sv->net.fired_count = (long)v[3];
    sv->next_action_id = (int32_t)v[4]; sv->wp_id = (int32_t)v[5];
    vec3_set(sv->wp_pos_m, v[6], v[7], v[8]); sv->wp_yaw_rad = v[9];
    sv->pick_id = (int32_t)v[10]; vec3_set(sv->pick_pos_m, v[11], v[12], v[13]); sv->pick_yaw_rad = v[14];
    sv->last_taken_id = (int32_t)v[15]; sv->p1_bound = v[16] != 0; sv->detections = (int32_t)v[17];
    sv->last_fired = (int)v[18]; sv->blockages = (int32_t)v[19];
    sv->rows_reissued = (int32_t)v[20]; sv->dones_recovered = (int32_t)v[21]; sv->replans = (int32_t)v[22];
    sv->deadlocks = (int32_t)v[23]; sv->faults = (int32_t)v[24];
    for (i = 0; i < CARRY_N_TRANSITIONS; i++)
        for (a = 0; a < 2; a++) {
            sv->slot[i].state[a] = (int)v[n++];
            sv->slot[i].action_id[a] = (int32_t)v[n++];
            sv->slot[i].sent_step[a] = (int64_t)v[n++];
        }
    return 0;
}

/* At start-up: the last snapshot of --journal, if any (checked against the
 * simulator's step in the first cycle). */
void sup_journal_resume(supervisor_daemon *sv)
{
    double *v = sv->journal_values;
    const int n = journal_load_last(sv->journal_path, v, JOURNAL_MAX_VALUES);
    if (n < 0)
        return;
    if (n != SNAP_LEN || v[0] != SNAP_VERSION || restore(sv, v) != 0) {
        fprintf(stderr, "tandem-supervisor: journal %s: last snapshot does not fit this net; starting fresh\n",
                sv->journal_path);
        petri_init(&sv->net, &carry_net);
        return;
    }
    sv->resumed = (int)v[1] + 1;     /* the snapshot's step + 1, checked in the first cycle */
    printf("tandem-supervisor: resumed from %s (step %lld, fired %ld, next row %d)\n", sv->journal_path,
           (long long)v[1], sv->net.fired_count, (int)sv->next_action_id);
}

void sup_journal_cycle(supervisor_daemon *sv)
{
    double *v = sv->journal_values;
    if (!sv->journal_path)
        return;
    if (!sv->journal_checked && sv->d.step >= 0) {
        sv->journal_checked = 1;
        if (sv->resumed && sv->d.step + 1 < sv->resumed) {
            printf("tandem-supervisor: the journal is from a later step than the simulator's: another run; starting fresh\n");
            memset(sv->slot, 0, sizeof sv->slot);
            petri_init(&sv->net, &carry_net);
            sv->resumed = 0;
        }
        sv->resumed = sv->resumed != 0;
        sv->dirty = 1;
    }
    if (sv->dirty && journal_append(&sv->jr, v, snapshot(sv, v)) != JOURNAL_OK) {
        fprintf(stderr, "tandem-supervisor: cannot write the journal %s\n", sv->journal_path);
        sv->d.safe_hold = 1;
    }
    sv->dirty = 0;
}

