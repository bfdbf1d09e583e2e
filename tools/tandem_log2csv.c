/* tandem-log2csv: turns an lcm-logger file into CSV for plotting.
 *   tandem-log2csv LOGFILE CHANNEL > out.csv
 *   tandem-log2csv --list LOGFILE
 * Any channel: the message type is found from each event's fingerprint and
 * printed by the CSV printers generated from lcmtypes/ (tandem_csv.c, by
 * tools/lcm2csv_gen.py), one row per message after a log_time_s column.
 * ARM1_STATE / ARM2_STATE, PETRI_MARKING and ROVER_TRUTH keep their short
 * plotting layouts (--all-fields gives the generic one). Events that fail
 * to decode are counted and reported on stderr, never guessed; a file that
 * is not an LCM log is an error. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <lcm/lcm.h>
#include "options.h"
#include "tandem_csv.h"
#include "version.h"
#include "tandem_arm_state_t.h"
#include "tandem_petri_marking_t.h"
#include "tandem_rover_truth_t.h"

/* A row function's result: the event does not decode as its type (skipped) */
#define ROW_UNDECODABLE (-1)
/* is_lcm_log: the file does not open */
#define LOG_UNREADABLE (-1)

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
        return ROW_UNDECODABLE;
    printf("%.4f", s.sim_time_s);
    for (i = 0; i < 6; i++)
        printf(",%.6f", s.q_rad[i]);
    printf(",%.5f,%.5f,%.5f,%.3f,%d\n", s.tool_position_m[0], s.tool_position_m[1],
           s.tool_position_m[2], s.max_contact_force_N, (int)s.holding_workpiece);
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
        return ROW_UNDECODABLE;
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
        return ROW_UNDECODABLE;
    for (i = 0; i < t.n; i++)
        printf("%.3f,%d,%.4f,%.4f,%.4f\n", t.sim_time_s, (int)t.robot[i], t.x_m[i], t.y_m[i],
               t.theta_rad[i]);
    tandem_rover_truth_t_decode_cleanup(&t);
    return 0;
}

/* The curated layout of a channel, or NULL for the generic one. */
static row_fn curated(const char *channel)
{
    if (!strcmp(channel, "ARM1_STATE") || !strcmp(channel, "ARM2_STATE"))
        return arm_row;
    if (!strcmp(channel, "PETRI_MARKING"))
        return marking_row;
    if (!strcmp(channel, "ROVER_TRUTH"))
        return truth_row;
    return NULL;
}

static int64_t fingerprint(const lcm_eventlog_event_t *ev)
{
    const unsigned char *b = ev->data;
    uint64_t h = 0;
    int i;
    if (ev->datalen < 8)
        return 0;
    for (i = 0; i < 8; i++)
        h = (h << 8) | b[i];
    return (int64_t)h;
}

/* An LCM log starts with the event sync word 0xEDA1DA01. */
static int is_lcm_log(const char *path)
{
    unsigned char m[4];
    FILE *f = fopen(path, "rb");
    size_t n;
    if (!f)
        return LOG_UNREADABLE;
    n = fread(m, 1, 4, f);
    fclose(f);
    return n == 4 && m[0] == 0xED && m[1] == 0xA1 && m[2] == 0xDA && m[3] == 0x01;
}

/* Generic row: log time, then the type's own columns. */
static int generic_row(const tandem_csv_type *t, const lcm_eventlog_event_t *ev, int64_t t0)
{
    printf("%.6f,", (double)(ev->timestamp - t0) * 1e-6);
    if (t->row(ev->data, (int)ev->datalen) < 0) {
        printf("\n");
        return ROW_UNDECODABLE;
    }
    putchar('\n');
    return 0;
}

typedef struct {
    char name[256];
    const char *type;
    long count;
} chan_count;

static void list_channels(lcm_eventlog_t *log)
{
    static chan_count c[512];
    int n = 0, i;
    lcm_eventlog_event_t *ev;
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        const tandem_csv_type *t = tandem_csv_find(fingerprint(ev));
        for (i = 0; i < n && strcmp(c[i].name, ev->channel) != 0; i++) {
        }
        if (i == n && n < 512) {
            snprintf(c[n].name, sizeof c[n].name, "%s", ev->channel);
            c[n].type = t ? t->name : "(not a tandem type)";
            c[n++].count = 0;
        }
        if (i < n)
            c[i].count++;
        lcm_eventlog_free_event(ev);
    }
    for (i = 0; i < n; i++)
        printf("%-24s %-28s %ld\n", c[i].name, c[i].type, c[i].count);
}

typedef struct log2csv_options {
    int list, all_fields;
} log2csv_options;

static const option_entry log2csv_table[] = {
    { .name = "list",
      .type = OPTION_FLAG,
      OPTION_AT(log2csv_options, list),
      .help = "the channels in the log, their types and message counts" },
    { .name = "all-fields",
      .type = OPTION_FLAG,
      OPTION_AT(log2csv_options, all_fields),
      .help = "the generic layout for every channel" },
    OPTION_HELP_ENTRY(0),
    OPTION_VERSION_ENTRY,
    { .name = NULL }
};

static int convert(lcm_eventlog_t *log, const char *channel, int all_fields)
{
    row_fn fn = all_fields ? NULL : curated(channel);
    const tandem_csv_type *type = NULL;
    lcm_eventlog_event_t *ev;
    long rows = 0, bad = 0, other = 0;
    int64_t t0 = -1;
    while ((ev = lcm_eventlog_read_next_event(log)) != NULL) {
        if (t0 < 0)
            t0 = ev->timestamp;
        if (strcmp(ev->channel, channel) == 0) {
            const tandem_csv_type *t = fn ? NULL : tandem_csv_find(fingerprint(ev));
            if (!fn && !t) {
                other++;
            } else {
                if (rows + bad == 0) {
                    if (fn)
                        fn(NULL, 1);
                    else {
                        fputs("log_time_s,", stdout);
                        t->header();
                        putchar('\n');
                    }
                    type = t;
                }
                if (fn ? fn(ev, 0) : (t == type ? generic_row(t, ev, t0) : ROW_UNDECODABLE))
                    bad++;
                else
                    rows++;
            }
        }
        lcm_eventlog_free_event(ev);
    }
    fprintf(stderr, "tandem-log2csv: %s: %ld rows, %ld undecodable events skipped", channel, rows,
            bad);
    if (other)
        fprintf(stderr, ", %ld of an unknown type", other);
    fputc('\n', stderr);
    if (rows + bad == 0) {
        fprintf(
            stderr,
            "tandem-log2csv: no %s messages %s (tandem-log2csv --list LOGFILE shows the channels)\n",
            channel, other ? "of a tandem type" : "in the log");
        return 1;
    }
    return 0;
}

int main(int argc, char **argv)
{
    lcm_eventlog_t *log;
    log2csv_options o = { 0, 0 };
    const option_program prog = {
        .name = "tandem-log2csv",
        .usage = "usage: tandem-log2csv [--all-fields] LOGFILE CHANNEL > out.csv\n"
                 "       tandem-log2csv --list LOGFILE\n"
                 "Writes the messages of one channel of an lcm-logger file as CSV on stdout, one\n"
                 "row per message. Any tandem channel: the type is recognised by its fingerprint\n"
                 "and every field becomes a column (log_time_s first; arrays one column per\n"
                 "element; inside variable-length arrays one column per field, the elements'\n"
                 "values joined with ';'). ARM1_STATE, ARM2_STATE, PETRI_MARKING and ROVER_TRUTH\n"
                 "have short plotting layouts unless --all-fields is given.\n\n",
        .epilog = "Exit status: 0 rows written, 1 not an LCM log / unreadable / channel absent\n"
                  "or of an unknown type, 2 bad arguments.\n",
        .groups = { { log2csv_table, &o } },
        .n_groups = 1,
        .args = OPTIONS_ARGS_STOP, /* options before LOGFILE, as always */
    };
    int first, rc;
    if (version_requested(argc, argv, "tandem-log2csv"))
        return 0;
    first = options_parse(&prog, argc, argv, 1);
    if (first < 0)
        return options_exit_status(first);
    if (argc - first != (o.list ? 1 : 2)) {
        options_print_help(&prog, stderr);
        return 2;
    }
    rc = is_lcm_log(argv[first]);
    if (rc <= 0) {
        fprintf(
            stderr,
            rc < 0
                ? "tandem-log2csv: cannot open '%s'\n"
                : "tandem-log2csv: '%s' is not an LCM log (it does not start with an LCM event)\n",
            argv[first]);
        return 1;
    }
    if (!(log = lcm_eventlog_create(argv[first], "r"))) {
        fprintf(stderr, "tandem-log2csv: cannot open '%s'\n", argv[first]);
        return 1;
    }
    rc = 0;
    if (o.list)
        list_channels(log);
    else
        rc = convert(log, argv[first + 1], o.all_fields);
    lcm_eventlog_destroy(log);
    return rc;
}
