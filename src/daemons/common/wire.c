/* wire: raw-byte check of an LCM message against its generated layout
 * (see wire.h). */
#include <string.h>
#include "wire.h"
#include "tandem_wire_types.h"

#define WIRE_MAX_FIELDS 64
#define WIRE_MAX_DEPTH 4

static int64_t be_int(const uint8_t *p, int size)
{
    uint64_t v = 0;
    int i;
    for (i = 0; i < size; i++)
        v = (v << 8) | p[i];
    /* sign-extend from size bytes (LCM integers are two's complement) */
    if (size < 8 && (v >> (8 * size - 1)) & 1u)
        v |= ~(uint64_t)0 << (8 * size);
    return (int64_t)v;
}

static int walk(const wire_type *t, const uint8_t *b, size_t len, size_t *pos, int depth);

static int walk_string(const wire_field *f, const uint8_t *b, size_t len, size_t *pos)
{
    int64_t n;
    if (len - *pos < 4)
        return WIRE_ERR_SHORT;
    n = be_int(b + *pos, 4);
    *pos += 4;
    if (n < 1 || n > f->size)
        return WIRE_ERR_STRING;
    if (len - *pos < (size_t)n)
        return WIRE_ERR_SHORT;
    /* exactly one NUL, at the end: what lcm-gen encodes (strlen + 1). A
     * NUL inside would hide the bytes after it from every reader (the
     * decoded string ends there) and re-encode shorter. */
    if (memchr(b + *pos, 0, (size_t)n) != b + *pos + (size_t)n - 1)
        return WIRE_ERR_STRING;
    *pos += (size_t)n;
    return WIRE_OK;
}

/* One element of field f; records integer scalars in *val. */
static int walk_element(const wire_field *f, const uint8_t *b, size_t len, size_t *pos, int depth,
                        int64_t *val)
{
    switch (f->kind) {
    case WIRE_STRING: return walk_string(f, b, len, pos);
    case WIRE_STRUCT: return walk(f->nested, b, len, pos, depth + 1);
    default:
        if (len - *pos < (size_t)f->size)
            return WIRE_ERR_SHORT;
        if (f->kind == WIRE_INT)
            *val = be_int(b + *pos, f->size);
        *pos += (size_t)f->size;
        return WIRE_OK;
    }
}

static int walk(const wire_type *t, const uint8_t *b, size_t len, size_t *pos, int depth)
{
    int64_t vals[WIRE_MAX_FIELDS];
    int i;
    if (depth > WIRE_MAX_DEPTH || t->n_fields > WIRE_MAX_FIELDS)
        return WIRE_ERR_DEPTH;
    for (i = 0; i < t->n_fields; i++) {
        const wire_field *f = &t->fields[i];
        int64_t count = f->count, k;
        vals[i] = 0;
        if (f->len_field >= 0) {
            count = vals[f->len_field];
            if (count < 0 || count > f->cap)
                return WIRE_ERR_LENGTH;
            /* lcm-gen decodes a 1-byte array (int8_t, byte) with memcpy
             * into lcm_malloc(0) = NULL when it is empty: memcpy(NULL, p, 0)
             * is undefined in C. No tandem message sends an empty one. */
            if (count == 0 && f->kind != WIRE_STRING && f->kind != WIRE_STRUCT && f->size == 1)
                return WIRE_ERR_LENGTH;
        }
        for (k = 0; k < count; k++) {
            const int rc = walk_element(f, b, len, pos, depth, &vals[i]);
            if (rc != WIRE_OK)
                return rc;
        }
    }
    return WIRE_OK;
}

int wire_check(const wire_type *t, const void *buf, size_t len)
{
    const uint8_t *b = buf;
    size_t pos = 8;
    int rc;
    if (!buf || len < 8)
        return WIRE_ERR_SHORT;
    if (be_int(b, 8) != t->hash())
        return WIRE_ERR_FINGERPRINT;
    rc = walk(t, b, len, &pos, 0);
    if (rc != WIRE_OK)
        return rc;
    return pos == len ? WIRE_OK : WIRE_ERR_TRAILING;
}

/* The most bytes one element of f can take. */
static size_t element_max(const wire_field *f)
{
    switch (f->kind) {
    case WIRE_STRING: return 4u + (size_t)f->size;
    case WIRE_STRUCT: return wire_max_size(f->nested) - 8u; /* a nested struct has no fingerprint */
    default: return (size_t)f->size;
    }
}

size_t wire_max_size(const wire_type *t)
{
    size_t n = 8; /* the fingerprint; nested structs have none, see element_max */
    int i;
    for (i = 0; i < t->n_fields; i++) {
        const wire_field *f = &t->fields[i];
        n += element_max(f) * (size_t)(f->len_field >= 0 ? f->cap : f->count);
    }
    return n;
}

const wire_type *wire_find(const void *buf, size_t len)
{
    int i;
    int64_t h;
    if (!buf || len < 8)
        return NULL;
    h = be_int(buf, 8);
    for (i = 0; i < WIRE_N_TYPES; i++)
        if (wire_all_types[i]->hash() == h)
            return wire_all_types[i];
    return NULL;
}

int64_t wire_seq(const void *buf, size_t len)
{
    return len >= 16 ? be_int((const uint8_t *)buf + 8, 8) : WIRE_SEQ_SHORT;
}
