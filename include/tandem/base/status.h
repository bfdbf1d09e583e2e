/* status: the text of a status code. Each module lists its codes once, as
 * X(CODE, "what failed") in a list macro <MODULE>_CODES (the domain's
 * <domain>_status.h); its <module>_strerror is a switch over that list
 * (STATUS_STRERROR), so a code listed twice, or two names of one value, does
 * not compile, and its unit test walks the same list (STATUS_CODE) and
 * checks every text is there, non-empty and distinct. A value no code has
 * gets STATUS_UNKNOWN_TEXT. tools/lint.sh checks that every *_ERR_* name
 * of a header is in a list.
 */
#ifndef TANDEM_STATUS_H
#define TANDEM_STATUS_H

/* what every <module>_strerror returns for a value that is none of its codes */
#define STATUS_UNKNOWN_TEXT "unknown status code"

#define STATUS_CASE(code, text) \
    case code:                  \
        return text;
#define STATUS_CODE(code, text) code,
/* defines const char *fn(int rc) over the code list LIST */
#define STATUS_STRERROR(fn, LIST)            \
    const char *fn(int rc)                   \
    {                                        \
        switch (rc) {                        \
            LIST(STATUS_CASE)                \
        default: return STATUS_UNKNOWN_TEXT; \
        }                                    \
    }

#endif
