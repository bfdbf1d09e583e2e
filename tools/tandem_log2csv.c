/* tandem-log2csv: turns an lcm-logger file into CSV for plotting.
 *   tandem-log2csv LOGFILE CHANNEL > out.csv
 * Knows ARM1_STATE / ARM2_STATE (arm_state_t), PETRI_MARKING and
 * ROVER_TRUTH; other channels are refused with a clear message. Events
 * that fail to decode are counted and reported on stderr, never guessed. */
#include <stdio.h>
#include <string.h>
#include <lcm/lcm.h>
#include "tandem_arm_state_t.h"
#include "tandem_petri_marking_t.h"
#include "tandem_rover_truth_t.h"

typedef int (*row_fn)(const lcm_eventlog_event_t *ev, int header);

static int arm_row(const lcm_eventlog_event_t *ev, int header)
{
    tandem_arm_state_t s;
    int i;
    if (header) {
        printf("sim_time_s,q1,q2,q3,q4,q5,q6,tool_x_m,tool_y_m,tool_z_m,max_contact_N,holding\n");
        return 0;
    }
    if (tandem_arm_state_t_decode(ev->data, 0, ev->datalen, &s) < 0)
        return -1;
    printf("%.4f", s.sim_time_s);
    for (i = 0; i < 6; i++)
        printf(",%.6f", s.q_rad[i]);
    printf(",%.5f,%.5f,%.5f,%.3f,%d\n", s.tool_position_m[0], s.tool_position_m[1], s.tool_position_m[2],
           s.max_contact_force_N, (int)s.holding_workpiece);
    return 0;
}

static int marking_row(const lcm_eventlog_event_t *ev, int header)
{
    tandem_petri_marking_t m;
    int i;
    if (header) {
        printf("step,last_fired,fired_count,marking\n");
        return 0;
    }
    if (tandem_petri_marking_t_decode(ev->data, 0, ev->datalen, &m) < 0)
        return -1;
    printf("%lld,%d,%lld,", (long long)m.step, (int)m.last_fired, (long long)m.fired_count);
    for (i = 0; i < m.n_places; i++)
        putchar('0' + m.marking[i]);
    putchar('\n');
    tandem_petri_marking_t_decode_cleanup(&m);
    return 0;
}

static int truth_row(const lcm_eventlog_event_t *ev, int header)
{
    tandem_rover_truth_t t;
    int i;
    if (header) {
        printf("sim_time_s,robot,x_m,y_m,theta_rad\n");
        return 0;
    }
    if (tandem_rover_truth_t_decode(ev->data, 0, ev->datalen, &t) < 0)
        return -1;
    for (i = 0; i < t.n; i++)
        printf("%.3f,%d,%.4f,%.4f,%.4f\n", t.sim_time_s, (int)t.robot[i], t.x_m[i], t.y_m[i], t.theta_rad[i]);
    tandem_rover_truth_t_decode_cleanup(&t);
    return 0;
}

int main(int argc, char **argv)
{
    lcm_eventlog_t *log;
    lcm_eventlog_event_t *ev;
    row_fn fn;
    long rows = 0, bad = 0;
    if (argc != 3) {
        fprintf(stderr, "usage: tandem-log2csv LOGFILE CHANNEL > out.csv\n"
                        "channels: ARM1_STATE ARM2_STATE PETRI_MARKING ROVER_TRUTH\n");
        return 2;
    }
    if (!strcmp(argv[2], "ARM1_STATE") || !strcmp(argv[2], "ARM2_STATE"))
        fn = arm_row;
    else if (!strcmp(argv[2], "PETRI_MARKING"))
        fn = marking_row;
    else if (!strcmp(argv[2], "ROVER_TRUTH"))
        fn = truth_row;
    else {
        fprintf(stderr, "tandem-log2csv: no CSV layout for channel '%s'\n", argv[2]);
        return 2;
    }
    log = lcm_eventlog_create(argv[1], "r");
    if (!log) {
        fprintf(stderr, "tandem-log2csv: cannot open '%s'\n", argv[1]);
        return 1;
    }
    fn(NULL, 1);
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        if (strcmp(ev->channel, argv[2]) == 0) {
            if (fn(ev, 0) == 0)
                rows++;
            else
                bad++;
        }
        lcm_eventlog_free_event(ev);
    }
    lcm_eventlog_destroy(log);
    fprintf(stderr, "tandem-log2csv: %ld rows, %ld undecodable events skipped\n", rows, bad);
    return 0;
}
