/* The check every <module>_strerror gets (include/tandem/base/status.h):
 * walked over the module's code list, every code has a text that is not
 * NULL, not empty, not the fallback and no other code's; a value below and
 * one above every code get the stated fallback (STATUS_UNKNOWN_TEXT for
 * the modules whose strerror is STATUS_STRERROR).
 * Usage, in a CMocka test:
 *   static const int codes[] = { PETRI_CODES(STATUS_CODE) };
 *   status_check(petri_strerror, codes, sizeof codes / sizeof codes[0], STATUS_UNKNOWN_TEXT);
 * or STATUS_CHECK(petri_strerror, PETRI_CODES) for the same. */
#ifndef TANDEM_TEST_STATUS_CHECK_H
#define TANDEM_TEST_STATUS_CHECK_H

#include <stddef.h>
#include <string.h>
#include "status.h"

static void status_check(const char *(*strerror_fn)(int), const int *codes, size_t n,
                         const char *fallback)
{
    size_t i, k;
    int lo = 0, hi = 0;
    assert_true(n >= 1);
    for (i = 0; i < n; i++) {
        const char *t = strerror_fn(codes[i]);
        assert_non_null(t);
        assert_true(t[0] != '\0');
        assert_string_not_equal(t, fallback);
        for (k = 0; k < i; k++)
            assert_string_not_equal(t, strerror_fn(codes[k]));
        lo = codes[i] < lo ? codes[i] : lo;
        hi = codes[i] > hi ? codes[i] : hi;
    }
    assert_string_equal(strerror_fn(lo - 1), fallback);
    assert_string_equal(strerror_fn(hi + 1), fallback);
}

#define STATUS_CHECK(fn, LIST)                                                           \
    do {                                                                                 \
        static const int codes_[] = { LIST(STATUS_CODE) };                               \
        status_check(fn, codes_, sizeof codes_ / sizeof codes_[0], STATUS_UNKNOWN_TEXT); \
    } while (0)

#endif
