/* Unit tests of the journal (daemons/common/journal.c): records come back
 * exactly; a torn, garbage, edited (its mac recomputed without the key),
 * reordered or foreign-mode journal is refused naming the record; a disk
 * that takes no more (/dev/full) leaves the file with whole records only
 * and says so; every code has a distinct name. */
#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "journal.h"

typedef struct fixture {
    char path[64];
    journal_key key;
} fixture;

static int setup(void **state)
{
    static fixture f;
    int fd;
    memset(&f, 0, sizeof f);
    snprintf(f.path, sizeof f.path, "/tmp/test_journal_XXXXXX");
    fd = mkstemp(f.path);
    if (fd < 0)
        return -1;
    close(fd);
    memset(f.key.bytes, 0x5a, sizeof f.key.bytes);
    f.key.keyed = 1;
    *state = &f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    remove(f->path);
    return 0;
}

/* Three records of three values (record k holds k, k + 0.1, -k) into f's file. */
static void write_three(const fixture *f, const journal_key *key)
{
    journal j;
    int k;
    assert_int_equal(journal_open(&j, f->path, key, JOURNAL_TRUNCATE), JOURNAL_OK);
    for (k = 1; k <= 3; k++) {
        const double v[3] = { k, k + 0.1, -k };
        assert_int_equal(journal_append(&j, v, 3), JOURNAL_OK);
    }
    assert_int_equal(j.seq, 3);
    journal_close(&j);
}

static char *slurp(const char *path, long *len)
{
    FILE *fp = fopen(path, "rb");
    char *buf = calloc(1, 65536);
    assert_non_null(fp);
    *len = (long)fread(buf, 1, 65535, fp);
    fclose(fp);
    return buf;
}

static void spit(const char *path, const char *buf, long len)
{
    FILE *fp = fopen(path, "wb");
    assert_non_null(fp);
    assert_int_equal(fwrite(buf, 1, (size_t)len, fp), (size_t)len);
    fclose(fp);
}

static void test_round_trip_and_append_on(void **state)
{
    fixture *f = *state;
    double v[8];
    journal_report rep;
    journal j;
    const double more[2] = { 1e-300, 0.1 + 0.2 };
    write_three(f, &f->key);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 8, &rep), 3);
    assert_true(v[0] == 3.0 && v[1] == 3.1 && v[2] == -3.0);
    assert_int_equal(rep.records, 3);
    assert_int_equal(rep.last_seq, 3);
    /* a restart appends on from the last seq */
    assert_int_equal(journal_open(&j, f->path, &f->key, JOURNAL_APPEND), JOURNAL_OK);
    j.seq = rep.last_seq;
    assert_int_equal(journal_append(&j, more, 2), JOURNAL_OK);
    journal_close(&j);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 8, &rep), 2);
    assert_true(v[0] == 1e-300 && v[1] == 0.1 + 0.2); /* exact */
    assert_int_equal(rep.last_seq, 4);
}

static void test_missing_and_empty_are_none(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_NONE); /* empty */
    remove(f->path);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep),
                     JOURNAL_ERR_NONE); /* missing */
}

static void test_torn_tail_refused(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    long len;
    char *buf;
    write_three(f, &f->key);
    buf = slurp(f->path, &len);
    spit(f->path, buf, len - 7); /* the last record cut off mid-mac */
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_TORN);
    assert_int_equal(rep.line, 3);
    spit(f->path, buf, len - 1); /* only its end of line missing */
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_TORN);
    assert_int_equal(rep.line, 3);
    free(buf);
}

static void test_garbage_refused(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    long len;
    char *buf;
    spit(f->path, "hello\nworld\n", 12);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_FORMAT);
    assert_int_equal(rep.line, 1);
    /* a garbage line after good records: refused, not skipped */
    write_three(f, &f->key);
    buf = slurp(f->path, &len);
    /* NOLINTNEXTLINE(bugprone-not-null-terminated-result): garbage bytes appended to a file image, not a string */
    memcpy(buf + len, "\x01\x02garbage\n", 10);
    spit(f->path, buf, len + 10);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_FORMAT);
    assert_int_equal(rep.line, 4);
    assert_true(strlen(rep.why) > 0);
    free(buf);
}

/* The second record edited: its value changed and its mac recomputed as
 * anyone without the key could (unkeyed, or another key). */
static void test_edited_record_refused(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    journal_key other = f->key;
    journal j;
    const double nan_pose[3] = { NAN, 2.1, -2.0 };
    long len;
    char *buf, *p;
    write_three(f, &f->key);
    buf = slurp(f->path, &len);
    p = strstr(buf, "J2 K 2 3 2 ");
    assert_non_null(p);
    p[9] = '7'; /* 2 -> 7, mac left */
    spit(f->path, buf, len);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_MAC);
    assert_int_equal(rep.line, 2);
    free(buf);
    /* rewritten whole with another key: every record's mac is wrong for ours */
    other.bytes[0] ^= 1;
    assert_int_equal(journal_open(&j, f->path, &other, JOURNAL_TRUNCATE), JOURNAL_OK);
    assert_int_equal(journal_append(&j, nan_pose, 3), JOURNAL_OK);
    journal_close(&j);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_MAC);
    assert_int_equal(rep.line, 1);
}

static void test_mode_mismatch_refused(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    journal_key none;
    memset(&none, 0, sizeof none);
    write_three(f, &none); /* --insecure wrote it */
    assert_int_equal(journal_load_last(f->path, &none, v, 4, &rep), 3);
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_MODE);
    assert_int_equal(rep.line, 1);
    write_three(f, &f->key);
    assert_int_equal(journal_load_last(f->path, &none, v, 4, &rep), JOURNAL_ERR_MODE);
}

static void test_missing_record_refused(void **state)
{
    fixture *f = *state;
    double v[4];
    journal_report rep;
    long len;
    char *buf, *second, *third;
    write_three(f, &f->key);
    buf = slurp(f->path, &len);
    second = strchr(buf, '\n') + 1;
    third = strchr(second, '\n') + 1;
    memmove(second, third, (size_t)(buf + len - third));
    spit(f->path, buf, len - (third - second)); /* record 2 deleted */
    assert_int_equal(journal_load_last(f->path, &f->key, v, 4, &rep), JOURNAL_ERR_SEQUENCE);
    assert_int_equal(rep.line, 2);
    free(buf);
}

static void test_disk_full_says_so(void **state)
{
    journal j;
    const double v[2] = { 1.0, 2.0 };
    (void)state;
    if (access("/dev/full", W_OK) != 0)
        skip();
    memset(&j, 0, sizeof j);
    assert_int_equal(journal_open(&j, "/dev/full", &((fixture *)*state)->key, JOURNAL_APPEND),
                     JOURNAL_OK);
    assert_int_equal(journal_append(&j, v, 2), JOURNAL_ERR_WRITE);
    assert_int_equal(j.err_no, ENOSPC);
    assert_int_equal(j.seq, 0); /* not counted: the next try has the same seq */
    assert_int_equal(journal_append(&j, v, 2), JOURNAL_ERR_WRITE);
    journal_close(&j);
}

static void test_bad_arguments(void **state)
{
    fixture *f = *state;
    journal j;
    double v[JOURNAL_MAX_VALUES + 1];
    memset(v, 0, sizeof v);
    assert_int_equal(journal_open(&j, f->path, &f->key, JOURNAL_TRUNCATE), JOURNAL_OK);
    assert_int_equal(journal_append(&j, v, 0), JOURNAL_ERR_ARG);
    assert_int_equal(journal_append(&j, v, JOURNAL_MAX_VALUES + 1), JOURNAL_ERR_ARG);
    assert_int_equal(journal_append(&j, v, JOURNAL_MAX_VALUES), JOURNAL_OK);
    journal_close(&j);
    assert_int_equal(journal_append(&j, v, 1), JOURNAL_ERR_ARG); /* closed */
    assert_int_equal(journal_open(&j, "/nonexistent-dir/j", &f->key, JOURNAL_APPEND),
                     JOURNAL_ERR_OPEN);
}

static void test_strerror_names_distinct(void **state)
{
    static const int codes[] = { JOURNAL_OK,       JOURNAL_ERR_OPEN,     JOURNAL_ERR_WRITE,
                                 JOURNAL_ERR_NONE, JOURNAL_ERR_ARG,      JOURNAL_ERR_SYNC,
                                 JOURNAL_ERR_READ, JOURNAL_ERR_FORMAT,   JOURNAL_ERR_TORN,
                                 JOURNAL_ERR_MAC,  JOURNAL_ERR_SEQUENCE, JOURNAL_ERR_MODE };
    const int n = (int)(sizeof codes / sizeof codes[0]);
    int i, k;
    (void)state;
    for (i = 0; i < n; i++)
        for (k = 0; k < i; k++) {
            assert_int_not_equal(codes[i], codes[k]);
            assert_string_not_equal(journal_strerror(codes[i]), journal_strerror(codes[k]));
        }
    assert_string_equal(journal_strerror(JOURNAL_ERR_MAC), "JOURNAL_ERR_MAC");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_round_trip_and_append_on, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_and_empty_are_none, setup, teardown),
        cmocka_unit_test_setup_teardown(test_torn_tail_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_garbage_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_edited_record_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_mode_mismatch_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_missing_record_refused, setup, teardown),
        cmocka_unit_test_setup_teardown(test_disk_full_says_so, setup, teardown),
        cmocka_unit_test_setup_teardown(test_bad_arguments, setup, teardown),
        cmocka_unit_test(test_strerror_names_distinct),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
