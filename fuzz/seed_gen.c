/* seed_gen: writes the seed corpus fuzz/corpus/TYPE/ from the generated
 * wire table: every field zero, every variable-length array with 0, 1 and
 * 3 elements, every string empty. Valid messages of every type, so the
 * fuzzer starts from inputs the checker accepts.
 * Usage: seed_gen DIR */
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include "wire.h"
#include "tandem_wire_types.h"

static int is_length_field(const wire_type *t, int i)
{
    int k;
    for (k = i + 1; k < t->n_fields; k++)
        if (t->fields[k].len_field == i)
            return 1;
    return 0;
}

static size_t put_int(unsigned char *b, size_t pos, int size, long v)
{
    int i;
    for (i = 0; i < size; i++)
        b[pos + (size_t)i] = (unsigned char)((unsigned long)v >> (8 * (size - 1 - i)));
    return pos + (size_t)size;
}

static size_t emit(const wire_type *t, unsigned char *b, size_t pos, int n)
{
    int i, k;
    for (i = 0; i < t->n_fields; i++) {
        const wire_field *f = &t->fields[i];
        const int count = f->len_field >= 0 ? n : f->count;
        for (k = 0; k < count; k++) {
            if (f->kind == WIRE_STRING) {
                pos = put_int(b, pos, 4, 1);
                b[pos++] = 0;
            } else if (f->kind == WIRE_STRUCT) {
                pos = emit(f->nested, b, pos, n);
            } else {
                pos = put_int(b, pos, f->size,
                              f->kind == WIRE_INT && is_length_field(t, i) ? n : 0);
            }
        }
    }
    return pos;
}

int main(int argc, char **argv)
{
    static unsigned char buf[1 << 16];
    static const int counts[] = { 0, 1, 3 };
    char path[512];
    int i, c;
    if (argc != 2)
        return 2;
    for (i = 0; i < WIRE_N_TYPES; i++) {
        const wire_type *t = wire_all_types[i];
        snprintf(path, sizeof path, "%s/%s", argv[1], t->name + strlen("tandem_"));
        mkdir(path, 0777);
        for (c = 0; c < 3; c++) {
            size_t n = put_int(buf, 0, 8, (long)t->hash());
            FILE *f;
            n = emit(t, buf, n, counts[c]);
            if (wire_check(t, buf, n) != WIRE_OK)
                continue; /* a nested-only type, or arrays this short are refused */
            snprintf(path, sizeof path, "%s/%s/seed-%d", argv[1], t->name + strlen("tandem_"),
                     counts[c]);
            if (!(f = fopen(path, "wb")) || fwrite(buf, 1, n, f) != n)
                return 1;
            fclose(f);
        }
    }
    return 0;
}
