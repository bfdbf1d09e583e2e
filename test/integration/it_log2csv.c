/* Integration: tandem-log2csv on a log written here with lcm_eventlog.
 * (1) a channel without a curated layout (SIM_STATUS) comes out with every
 * field as a column and the values written; (2) a variable-length array of
 * structs (ROVERS_STATE) gives one column per field with the elements
 * joined by ';'; (3) the curated ARM1_STATE layout is kept; (4) a channel
 * of an unknown type, an absent channel and a file that is not a log exit
 * 1; (5) --help goes to stdout with exit 0, --version names the program. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "harness.h"
#include "tandem_arm_state_t.h"
#include "tandem_rovers_state_t.h"
#include "tandem_sim_status_t.h"

static char log_path[64];

static void write_event(lcm_eventlog_t *log, const char *channel, void *data, int len, int64_t t_us)
{
    lcm_eventlog_event_t ev;
    memset(&ev, 0, sizeof ev);
    ev.timestamp = t_us;
    ev.channellen = (int32_t)strlen(channel);
    ev.channel = (char *)channel;
    ev.datalen = len;
    ev.data = data;
    assert_int_equal(lcm_eventlog_write_event(log, &ev), 0);
}

#define WRITE_MSG(log, type, channel, msg, t_us)                \
    do {                                                        \
        int len_ = type##_encoded_size(msg);                    \
        char *buf_ = malloc((size_t)len_);                      \
        assert_true(type##_encode(buf_, 0, len_, msg) == len_); \
        write_event(log, channel, buf_, len_, t_us);            \
        free(buf_);                                             \
    } while (0)

static int write_log(void **state)
{
    lcm_eventlog_t *log;
    tandem_sim_status_t st;
    tandem_rover_state_t rs[2];
    tandem_rovers_state_t batch;
    tandem_arm_state_t arm;
    char junk[16] = "not a message";
    (void)state;
    snprintf(log_path, sizeof log_path, "/tmp/it_log2csv_%d.lcmlog", (int)getpid());
    assert_non_null(log = lcm_eventlog_create(log_path, "w"));
    memset(&st, 0, sizeof st);
    st.step = 1500;
    st.sim_time_s = 1.5;
    st.workpieces_delivered = 3;
    WRITE_MSG(log, tandem_sim_status_t, "SIM_STATUS", &st, 1000000);
    memset(rs, 0, sizeof rs);
    rs[0].robot = 4;
    rs[0].formation_err_m = 0.25;
    rs[1].robot = 7;
    rs[1].formation_err_m = 0.5;
    memset(&batch, 0, sizeof batch);
    batch.n = 2;
    batch.state = rs;
    WRITE_MSG(log, tandem_rovers_state_t, "ROVERS_STATE", &batch, 1250000);
    memset(&arm, 0, sizeof arm);
    arm.arm = 1;
    arm.sim_time_s = 2.0;
    arm.holding_workpiece = -1;
    WRITE_MSG(log, tandem_arm_state_t, "ARM1_STATE", &arm, 2000000);
    write_event(log, "JUNK", junk, (int)sizeof junk, 2100000);
    lcm_eventlog_destroy(log);
    return 0;
}

static int remove_log(void **state)
{
    (void)state;
    unlink(log_path);
    return 0;
}

/* Runs tandem-log2csv with up to three arguments; stdout into out. */
static int run(char *out, int cap, const char *a1, const char *a2, const char *a3)
{
    harness h;
    const char *argv[] = { "tandem-log2csv", a1, a2, a3, NULL };
    pid_t p;
    int rc;
    assert_int_equal(harness_open(&h, 60), 0);
    p = harness_spawn(&h, argv);
    assert_true(p > 0);
    rc = harness_wait(&h, p, 20.0);
    harness_read_output(&h, p, out, cap);
    harness_close(&h);
    return rc;
}

/* The cell of column `name` in the second line of csv, into cell. */
static void csv_cell(const char *csv, const char *name, char *cell, int cap)
{
    char header[4096], row[4096], *save1, *save2, *h, *r;
    const char *nl = strchr(csv, '\n');
    assert_non_null(nl);
    snprintf(header, sizeof header, "%.*s", (int)(nl - csv), csv);
    snprintf(row, sizeof row, "%s", nl + 1);
    row[strcspn(row, "\n")] = '\0';
    for (h = strtok_r(header, ",", &save1), r = strtok_r(row, ",", &save2); h && r;
         h = strtok_r(NULL, ",", &save1), r = strtok_r(NULL, ",", &save2)) {
        if (!strcmp(h, name)) {
            snprintf(cell, (size_t)cap, "%s", r);
            return;
        }
    }
    fail_msg("no column %s in: %s", name, csv);
}

static void test_every_field_of_any_channel(void **state)
{
    char out[8192], cell[64];
    (void)state;
    assert_int_equal(run(out, sizeof out, log_path, "SIM_STATUS", NULL), 0);
    assert_true(strncmp(out, "log_time_s,seq,", 15) == 0);
    csv_cell(out, "workpieces_delivered", cell, sizeof cell);
    assert_string_equal(cell, "3");
    csv_cell(out, "sim_time_s", cell, sizeof cell);
    assert_string_equal(cell, "1.5");
    csv_cell(out, "stick_position_m[2]", cell, sizeof cell);
    assert_string_equal(cell, "0");
}

static void test_variable_arrays_joined(void **state)
{
    char out[8192], cell[64];
    (void)state;
    assert_int_equal(run(out, sizeof out, log_path, "ROVERS_STATE", NULL), 0);
    csv_cell(out, "state[].robot", cell, sizeof cell);
    assert_string_equal(cell, "4;7");
    csv_cell(out, "state[].formation_err_m", cell, sizeof cell);
    assert_string_equal(cell, "0.25;0.5");
    csv_cell(out, "log_time_s", cell, sizeof cell);
    assert_string_equal(cell, "0.250000");
}

static void test_curated_layout_kept(void **state)
{
    char out[8192];
    (void)state;
    assert_int_equal(run(out, sizeof out, log_path, "ARM1_STATE", NULL), 0);
    assert_true(strncmp(out, "sim_time_s,q1,", 14) == 0);
    assert_int_equal(run(out, sizeof out, "--all-fields", log_path, "ARM1_STATE"), 0);
    assert_true(strncmp(out, "log_time_s,seq,", 15) == 0);
}

static void test_errors_exit_nonzero(void **state)
{
    char out[8192], text[96];
    FILE *f;
    (void)state;
    assert_int_equal(run(out, sizeof out, log_path, "JUNK", NULL), 1);
    assert_int_equal(run(out, sizeof out, log_path, "NO_SUCH_CHANNEL", NULL), 1);
    snprintf(text, sizeof text, "%s.txt", log_path);
    assert_non_null(f = fopen(text, "w"));
    fputs("root:x:0:0:root:/root:/bin/bash\n", f);
    fclose(f);
    assert_int_equal(run(out, sizeof out, text, "SIM_STATUS", NULL), 1);
    unlink(text);
    assert_int_equal(run(out, sizeof out, log_path, NULL, NULL), 2);
}

static void test_help_and_version(void **state)
{
    char out[8192];
    (void)state;
    assert_int_equal(run(out, sizeof out, "--help", NULL, NULL), 0);
    assert_non_null(strstr(out, "usage: tandem-log2csv"));
    assert_int_equal(run(out, sizeof out, "--version", NULL, NULL), 0);
    assert_true(strncmp(out, "tandem-log2csv (tandem) ", 24) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_field_of_any_channel),
        cmocka_unit_test(test_variable_arrays_joined),
        cmocka_unit_test(test_curated_layout_kept),
        cmocka_unit_test(test_errors_exit_nonzero),
        cmocka_unit_test(test_help_and_version),
    };
    return cmocka_run_group_tests(tests, write_log, remove_log);
}
