/* wire: checks an LCM message on its raw bytes before lcm-gen's decoder
 * runs. lcm-gen's decoders trust the length fields: a negative or huge
 * count makes them ask for a huge allocation (or abort under the
 * sanitizers), and a decoder that fails half-way leaks what it already
 * allocated. The checker walks the encoding with the layout tables
 * generated from lcmtypes/ (tools/wire/lcm-wire-gen.awk) and accepts only
 * a buffer that decodes completely with every array inside its capacity
 * (lcmtypes/capacities), every string NUL-terminated, no trailing bytes.
 * It allocates nothing and its work is bounded by the capacities.
 */
#ifndef TANDEM_WIRE_H
#define TANDEM_WIRE_H

#include <stddef.h>
#include <stdint.h>

enum wire_kind { WIRE_INT, WIRE_RAW, WIRE_STRING, WIRE_STRUCT };

/* Named results of wire_check (0 = the buffer is a well-formed message). */
enum {
    WIRE_OK = 0,
    WIRE_ERR_SHORT = -1,       /* buffer ends inside a field */
    WIRE_ERR_FINGERPRINT = -2, /* not this type (or unknown to wire_find) */
    WIRE_ERR_LENGTH = -3,      /* array length negative, over capacity, or an empty byte array */
    WIRE_ERR_STRING = -4,      /* string length out of range, or its NUL not (only) at the end */
    WIRE_ERR_TRAILING = -5,    /* bytes left over after the message */
    WIRE_ERR_DEPTH = -6        /* nesting deeper than any tandem type */
};

struct wire_type;

typedef struct wire_field {
    const char *name;
    int kind;                       /* enum wire_kind */
    int size;                       /* bytes of one element (WIRE_INT / WIRE_RAW);
                                   WIRE_STRING: capacity in bytes incl. the NUL */
    int count;                      /* fixed element count (1 = scalar); 0 = variable */
    int len_field;                  /* variable: index of the length field, else -1 */
    int cap;                        /* variable: capacity in elements */
    const struct wire_type *nested; /* WIRE_STRUCT */
} wire_field;

typedef struct wire_type {
    const char *name; /* e.g. tandem_arm_state_t */
    const wire_field *fields;
    int n_fields;
    int64_t (*hash)(void); /* lcm-gen's fingerprint */
} wire_type;

/* 0 if buf[0, len) is exactly one well-formed message of type t. */
int wire_check(const wire_type *t, const void *buf, size_t len);
/* The longest encoding of type t (every array at its capacity, every
 * string at its longest): the receive path refuses anything longer before
 * spending a MAC on it. */
size_t wire_max_size(const wire_type *t);
/* The type whose fingerprint starts buf, or NULL. */
const wire_type *wire_find(const void *buf, size_t len);
/* The message's leading int64 `seq` field (every tandem message starts
 * with one), WIRE_SEQ_SHORT if the buffer is too short. Used before
 * decoding, on a buffer that passed wire_check. */
#define WIRE_SEQ_SHORT (-1) /* wire_seq: the buffer ends before seq */
int64_t wire_seq(const void *buf, size_t len);

#endif
