/* world_file: the map_server YAML + PGM reader and writer, and the world
 * options (see world_file.h; docs/formation.md, "Worlds from files").
 * YAML is parsed by libyaml's document loader; the PGM by hand (its
 * header is four numbers).
 */
#include "world_file.h"
#include "navfield.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <yaml.h>

#define PGM_BYTES_MAX (64L * 1024L * 1024L)
#define PATH_MAX_LEN 4096

static int say(char *why, size_t n, int rc, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, n, fmt, ap);
    va_end(ap);
    return rc;
}

/* ---- YAML ------------------------------------------------------------------ */

typedef struct yreader {
    yaml_document_t doc;
    const char *path;
    char *why;
    size_t why_n;
} yreader;

static yaml_node_t *map_get(yreader *y, yaml_node_t *map, const char *key)
{
    yaml_node_pair_t *p;
    if (!map || map->type != YAML_MAPPING_NODE)
        return NULL;
    for (p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; p++) {
        yaml_node_t *k = yaml_document_get_node(&y->doc, p->key);
        if (k && k->type == YAML_SCALAR_NODE &&
            strcmp((const char *)k->data.scalar.value, key) == 0)
            return yaml_document_get_node(&y->doc, p->value);
    }
    return NULL;
}

static int scalar_number(const yaml_node_t *n, double *v)
{
    char *end;
    const char *s;
    if (!n || n->type != YAML_SCALAR_NODE)
        return 0;
    s = (const char *)n->data.scalar.value;
    errno = 0;
    *v = strtod(s, &end);
    return end != s && *end == '\0' && errno == 0 && isfinite(*v);
}

/* key: a finite number. */
static int get_number(yreader *y, yaml_node_t *map, const char *sect, const char *key, double *v,
                      int need)
{
    yaml_node_t *n = map_get(y, map, key);
    if (!n && !need)
        return WORLD_FILE_OK;
    if (!n)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: %s%s: missing", y->path, sect, key);
    if (!scalar_number(n, v))
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: %s%s: not a finite number", y->path,
                   sect, key);
    return WORLD_FILE_OK;
}

/* key: [a, b(, c)]: exactly len finite numbers. */
static int seq_numbers(yreader *y, yaml_node_t *n, const char *what, double *v, int len)
{
    int k = 0;
    yaml_node_item_t *it;
    if (!n || n->type != YAML_SEQUENCE_NODE)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: %s: not a list of %d numbers",
                   y->path, what, len);
    for (it = n->data.sequence.items.start; it < n->data.sequence.items.top; it++, k++)
        if (k >= len || !scalar_number(yaml_document_get_node(&y->doc, *it), &v[k]))
            return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                       "%s: %s: not a list of %d finite numbers", y->path, what, len);
    if (k != len)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: %s: %d numbers, need %d", y->path,
                   what, k, len);
    return WORLD_FILE_OK;
}

static int read_landmarks(yreader *y, yaml_node_t *n, rover_map_site *s)
{
    yaml_node_item_t *it;
    char what[64];
    int rc;
    if (n && n->type == YAML_SCALAR_NODE &&
        strcmp((const char *)n->data.scalar.value, "auto") == 0) {
        s->n_landmarks = ROVER_MAP_LANDMARKS_AUTO;
        return WORLD_FILE_OK;
    }
    if (!n || n->type != YAML_SEQUENCE_NODE)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                   "%s: tandem.landmarks: neither auto nor a list of [x, y]", y->path);
    s->n_landmarks = 0;
    for (it = n->data.sequence.items.start; it < n->data.sequence.items.top; it++) {
        if (s->n_landmarks >= ROVER_WORLD_MAX_LANDMARKS)
            return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                       "%s: tandem.landmarks: more than %d (ROVER_WORLD_MAX_LANDMARKS)", y->path,
                       ROVER_WORLD_MAX_LANDMARKS);
        snprintf(what, sizeof what, "tandem.landmarks[%d]", s->n_landmarks);
        if ((rc = seq_numbers(y, yaml_document_get_node(&y->doc, *it), what,
                              s->landmark_m[s->n_landmarks], 2)) != 0)
            return rc;
        s->n_landmarks++;
    }
    return WORLD_FILE_OK;
}

static int read_tandem(yreader *y, yaml_node_t *root, rover_map_site *s)
{
    yaml_node_t *t = map_get(y, root, "tandem");
    double v[3];
    int rc;
    if (!t || t->type != YAML_MAPPING_NODE)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                   "%s: tandem: missing (start, goal, landmarks)", y->path);
    if ((rc = seq_numbers(y, map_get(y, t, "start"), "tandem.start", v, 3)) != 0)
        return rc;
    s->start.x_m = v[0];
    s->start.y_m = v[1];
    s->start.theta_rad = v[2];
    if ((rc = seq_numbers(y, map_get(y, t, "goal"), "tandem.goal", s->goal_m, 2)) != 0)
        return rc;
    s->n_landmarks = ROVER_MAP_LANDMARKS_AUTO;
    if (map_get(y, t, "landmarks"))
        return read_landmarks(y, map_get(y, t, "landmarks"), s);
    return WORLD_FILE_OK;
}

/* map_server's keys; the image's name into image (relative to the YAML's folder). */
typedef struct map_keys {
    char image[PATH_MAX_LEN];
    double resolution, origin[3], negate, occupied_thresh, free_thresh;
} map_keys;

static int read_keys(yreader *y, yaml_node_t *root, map_keys *k)
{
    yaml_node_t *img = map_get(y, root, "image"), *mode = map_get(y, root, "mode");
    const char *slash = strrchr(y->path, '/');
    int rc;
    if (!img || img->type != YAML_SCALAR_NODE || img->data.scalar.length == 0)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: image: missing", y->path);
    if (img->data.scalar.value[0] == '/' || !slash)
        snprintf(k->image, sizeof k->image, "%s", (const char *)img->data.scalar.value);
    else
        snprintf(k->image, sizeof k->image, "%.*s/%s", (int)(slash - y->path), y->path,
                 (const char *)img->data.scalar.value);
    if ((rc = get_number(y, root, "", "resolution", &k->resolution, 1)) != 0)
        return rc;
    if (!(k->resolution > 0.0))
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                   "%s: resolution: must be > 0 (m per cell)", y->path);
    if ((rc = seq_numbers(y, map_get(y, root, "origin"), "origin", k->origin, 3)) != 0)
        return rc;
    if (k->origin[2] != 0.0)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                   "%s: origin: yaw must be 0 (rotated maps are not supported)", y->path);
    k->negate = 0.0;
    if ((rc = get_number(y, root, "", "negate", &k->negate, 0)) != 0)
        return rc;
    if (k->negate != 0.0 && k->negate != 1.0)
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: negate: must be 0 or 1", y->path);
    if ((rc = get_number(y, root, "", "occupied_thresh", &k->occupied_thresh, 1)) != 0 ||
        (rc = get_number(y, root, "", "free_thresh", &k->free_thresh, 1)) != 0)
        return rc;
    if (!(k->free_thresh >= 0.0 && k->free_thresh < k->occupied_thresh &&
          k->occupied_thresh <= 1.0))
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD,
                   "%s: free_thresh, occupied_thresh: need 0 <= free_thresh < occupied_thresh <= 1",
                   y->path);
    if (mode && (mode->type != YAML_SCALAR_NODE ||
                 strcmp((const char *)mode->data.scalar.value, "trinary") != 0))
        return say(y->why, y->why_n, WORLD_FILE_ERR_FIELD, "%s: mode: only trinary is supported",
                   y->path);
    return WORLD_FILE_OK;
}

/* ---- PGM ------------------------------------------------------------------- */

typedef struct pgm_buf {
    unsigned char *b;
    long n, at;
} pgm_buf;

static void pgm_skip_space(pgm_buf *p)
{
    while (p->at < p->n) {
        if (p->b[p->at] == '#') {
            while (p->at < p->n && p->b[p->at] != '\n')
                p->at++;
        } else if (p->b[p->at] == ' ' || p->b[p->at] == '\t' || p->b[p->at] == '\n' ||
                   p->b[p->at] == '\r') {
            p->at++;
        } else {
            break;
        }
    }
}

/* A non-negative decimal, at most max. -1 if none. */
static long pgm_number(pgm_buf *p, long max)
{
    long v = 0;
    int digits = 0;
    pgm_skip_space(p);
    while (p->at < p->n && p->b[p->at] >= '0' && p->b[p->at] <= '9') {
        v = v * 10 + (p->b[p->at++] - '0');
        if (v > max)
            return -1;
        digits++;
    }
    return digits ? v : -1;
}

static unsigned char *slurp(const char *path, long *n)
{
    FILE *f = fopen(path, "rb");
    unsigned char *b = NULL;
    long cap = 0, got = 0;
    size_t r;
    if (!f)
        return NULL;
    do {
        if (got == cap) {
            unsigned char *nb;
            cap = cap ? 2 * cap : 65536;
            if (cap > PGM_BYTES_MAX + 1 || !(nb = realloc(b, (size_t)cap))) {
                free(b);
                fclose(f);
                return NULL;
            }
            b = nb;
        }
        r = fread(b + got, 1, (size_t)(cap - got), f);
        got += (long)r;
    } while (r > 0);
    fclose(f);
    *n = got;
    return b;
}

/* The raster (P5: one byte a pixel, two big-endian above maxval 255; P2:
 * text) into m's cells by map_server's thresholds, image rows top down. */
static int pgm_pixels(pgm_buf *p, int ascii, long maxval, long count, const map_keys *k,
                      rover_map *m)
{
    long q;
    const int bytes = maxval > 255 ? 2 : 1;
    if (!ascii)
        p->at++; /* the single whitespace after maxval */
    if (!ascii && p->n - p->at < count * bytes)
        return 0;
    for (q = 0; q < count; q++) {
        long v;
        double occ;
        if (ascii) {
            if ((v = pgm_number(p, maxval)) < 0)
                return 0;
        } else if (bytes == 2) {
            v = 256L * p->b[p->at] + p->b[p->at + 1];
            p->at += 2;
            if (v > maxval)
                return 0;
        } else {
            v = p->b[p->at++];
            if (v > maxval)
                return 0;
        }
        occ = k->negate != 0.0 ? (double)v / maxval : (double)(maxval - v) / maxval;
        /* image row r (from the top) is map row height-1-r */
        m->cell[(long)(m->height - 1 - q / m->width) * m->width + q % m->width] =
            occ < k->free_thresh ? ROVER_MAP_FREE : ROVER_MAP_OCCUPIED;
    }
    return 1;
}

static int read_pgm(const char *yaml_path, const map_keys *k, rover_map *m, char *why, size_t why_n)
{
    pgm_buf p = { NULL, 0, 0 };
    long w, h, maxval;
    int ascii, rc = WORLD_FILE_OK;
    if (!(p.b = slurp(k->image, &p.n)))
        return say(why, why_n, WORLD_FILE_ERR_IMAGE, "%s: image: cannot read %s (%s)", yaml_path,
                   k->image, errno ? strerror(errno) : "too large");
    if (p.n < 2 || p.b[0] != 'P' || (p.b[1] != '5' && p.b[1] != '2')) {
        rc = say(why, why_n, WORLD_FILE_ERR_IMAGE, "%s: image: %s is not a PGM (P5 or P2)",
                 yaml_path, k->image);
        goto out;
    }
    ascii = p.b[1] == '2';
    p.at = 2;
    w = pgm_number(&p, 1000000L);
    h = pgm_number(&p, 1000000L);
    maxval = pgm_number(&p, 65535L);
    if (w < 1 || h < 1 || maxval < 1) {
        rc = say(why, why_n, WORLD_FILE_ERR_IMAGE,
                 "%s: image: %s: bad PGM header (width, height, maxval)", yaml_path, k->image);
        goto out;
    }
    if (w > ROVER_MAP_MAX_SIDE || h > ROVER_MAP_MAX_SIDE) {
        rc = say(why, why_n, WORLD_FILE_ERR_IMAGE,
                 "%s: image: %s is %ldx%ld pixels, more than %d a side (ROVER_MAP_MAX_SIDE)",
                 yaml_path, k->image, w, h, ROVER_MAP_MAX_SIDE);
        goto out;
    }
    m->width = (int)w;
    m->height = (int)h;
    m->resolution_m = k->resolution;
    m->origin_x_m = k->origin[0];
    m->origin_y_m = k->origin[1];
    if (!pgm_pixels(&p, ascii, maxval, w * h, k, m))
        rc = say(why, why_n, WORLD_FILE_ERR_IMAGE,
                 "%s: image: %s: pixel data short or above maxval (need %ldx%ld)", yaml_path,
                 k->image, w, h);
out:
    free(p.b);
    return rc;
}

int world_file_read(const char *path, rover_map *m, rover_map_site *s, char *why, size_t why_n)
{
    yreader y;
    yaml_parser_t parser;
    yaml_node_t *root;
    map_keys *k;
    FILE *f;
    int rc;
    memset(&y, 0, sizeof y);
    y.path = path;
    y.why = why;
    y.why_n = why_n;
    if (!(f = fopen(path, "rb")))
        return say(why, why_n, WORLD_FILE_ERR_OPEN, "%s: cannot open (%s)", path, strerror(errno));
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_file(&parser, f);
    if (!yaml_parser_load(&parser, &y.doc)) {
        rc = say(why, why_n, WORLD_FILE_ERR_YAML, "%s: line %lu: %s", path,
                 (unsigned long)parser.problem_mark.line + 1,
                 parser.problem ? parser.problem : "unreadable YAML");
        yaml_parser_delete(&parser);
        fclose(f);
        return rc;
    }
    yaml_parser_delete(&parser);
    fclose(f);
    root = yaml_document_get_root_node(&y.doc);
    if (!root || root->type != YAML_MAPPING_NODE) {
        yaml_document_delete(&y.doc);
        return say(why, why_n, WORLD_FILE_ERR_YAML,
                   "%s: not a YAML mapping (image, resolution, origin, ...)", path);
    }
    if (!(k = calloc(1, sizeof *k))) {
        yaml_document_delete(&y.doc);
        return say(why, why_n, WORLD_FILE_ERR_MEMORY, "%s: out of memory", path);
    }
    memset(s, 0, sizeof *s);
    rc = read_keys(&y, root, k);
    if (rc == WORLD_FILE_OK)
        rc = read_tandem(&y, root, s);
    if (rc == WORLD_FILE_OK)
        rc = read_pgm(path, k, m, why, why_n);
    free(k);
    yaml_document_delete(&y.doc);
    return rc;
}

/* ---- writing ---------------------------------------------------------------- */

static int write_pgm(const char *file, const rover_map *m)
{
    FILE *f = fopen(file, "wb");
    int i, j, ok;
    if (!f)
        return 0;
    fprintf(f, "P5\n# tandem world: 0 occupied, 254 free\n%d %d\n255\n", m->width, m->height);
    for (j = m->height - 1; j >= 0; j--)
        for (i = 0; i < m->width; i++)
            fputc(m->cell[(long)j * m->width + i] == ROVER_MAP_FREE ? 254 : 0, f);
    ok = !ferror(f);
    return fclose(f) == 0 && ok;
}

/* The shortest of %.15g, %.17g that reads back as v (a kept world must be
 * the same world bit for bit: a re-run from it is the same run). */
static const char *num(char buf[32], double v)
{
    snprintf(buf, 32, "%.15g", v);
    if (strtod(buf, NULL) != v)
        snprintf(buf, 32, "%.17g", v);
    return buf;
}

static int write_yaml(const char *file, const char *image, const rover_map *m,
                      const rover_map_site *s)
{
    FILE *f = fopen(file, "w");
    char a[32], b[32], c[32];
    int k, ok;
    if (!f)
        return 0;
    fprintf(f, "image: %s\nresolution: %s\norigin: [%s, %s, 0.0]\nnegate: 0\n", image,
            num(a, m->resolution_m), num(b, m->origin_x_m), num(c, m->origin_y_m));
    fprintf(f, "occupied_thresh: 0.65\nfree_thresh: 0.196\ntandem:\n  start: [%s, %s, %s]\n",
            num(a, s->start.x_m), num(b, s->start.y_m), num(c, s->start.theta_rad));
    fprintf(f, "  goal: [%s, %s]\n", num(a, s->goal_m[0]), num(b, s->goal_m[1]));
    if (s->n_landmarks == ROVER_MAP_LANDMARKS_AUTO) {
        fprintf(f, "  landmarks: auto\n");
    } else {
        fprintf(f, "  landmarks: [");
        for (k = 0; k < s->n_landmarks; k++)
            fprintf(f, "%s[%s, %s]", k ? ", " : "", num(a, s->landmark_m[k][0]),
                    num(b, s->landmark_m[k][1]));
        fprintf(f, "]\n");
    }
    ok = !ferror(f);
    return fclose(f) == 0 && ok;
}

int world_file_write(const char *dir, const char *name, const rover_map *m, const rover_map_site *s,
                     char *why, size_t why_n)
{
    char yaml[PATH_MAX_LEN], pgm[PATH_MAX_LEN], image[PATH_MAX_LEN];
    snprintf(yaml, sizeof yaml, "%s/%s.yaml", dir, name);
    snprintf(pgm, sizeof pgm, "%s/%s.pgm", dir, name);
    snprintf(image, sizeof image, "%s.pgm", name);
    if (!write_pgm(pgm, m))
        return say(why, why_n, WORLD_FILE_ERR_WRITE, "%s: cannot write (%s)", pgm, strerror(errno));
    if (!write_yaml(yaml, image, m, s))
        return say(why, why_n, WORLD_FILE_ERR_WRITE, "%s: cannot write (%s)", yaml,
                   strerror(errno));
    return WORLD_FILE_OK;
}

#define SVG_PX_PER_M 20.0

int world_file_write_svg(const char *dir, const char *name, const rover_world_config *w, char *why,
                         size_t why_n)
{
    char file[PATH_MAX_LEN];
    const double s = SVG_PX_PER_M, W = w->x_max_m - w->x_min_m, H = w->y_max_m - w->y_min_m;
    FILE *f;
    int k, ok;
    snprintf(file, sizeof file, "%s/%s.svg", dir, name);
    if (!(f = fopen(file, "w")))
        return say(why, why_n, WORLD_FILE_ERR_WRITE, "%s: cannot write (%s)", file,
                   strerror(errno));
    /* y up: the group flips the picture about the map's extent */
    fprintf(f,
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\">\n"
            "<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n"
            "<g transform=\"translate(%.6g %.6g) scale(%.6g %.6g)\">\n",
            W * s, H * s, -w->x_min_m * s, w->y_max_m * s, s, -s);
    for (k = 0; k < w->n_obst; k++) {
        const rover_obstacle *o = &w->obst[k];
        if (o->kind == ROVER_OBST_CIRCLE)
            fprintf(f, "<circle cx=\"%.6g\" cy=\"%.6g\" r=\"%.6g\" fill=\"#555\"/>\n", o->cx_m,
                    o->cy_m, o->r_m);
        else
            fprintf(f,
                    "<rect x=\"%.6g\" y=\"%.6g\" width=\"%.6g\" height=\"%.6g\" fill=\"#555\" "
                    "transform=\"rotate(%.6g %.6g %.6g)\"/>\n",
                    o->cx_m - o->hx_m, o->cy_m - o->hy_m, 2.0 * o->hx_m, 2.0 * o->hy_m,
                    o->angle_rad * 57.29577951308232, o->cx_m, o->cy_m);
    }
    for (k = 0; k < w->n_landmarks; k++)
        fprintf(f, "<circle cx=\"%.6g\" cy=\"%.6g\" r=\"0.12\" fill=\"#e8a800\"/>\n",
                w->landmark_m[k][0], w->landmark_m[k][1]);
    fprintf(
        f,
        "<circle cx=\"%.6g\" cy=\"%.6g\" r=\"0.5\" fill=\"none\" stroke=\"#d00\" stroke-width=\"0.08\"/>\n",
        w->goal_m[0], w->goal_m[1]);
    for (k = 0; k < w->n_robots; k++) {
        const pose2 *c = &w->start_c[k];
        fprintf(
            f,
            "<line x1=\"%.6g\" y1=\"%.6g\" x2=\"%.6g\" y2=\"%.6g\" stroke=\"#080\" stroke-width=\"0.1\"/>"
            "<circle cx=\"%.6g\" cy=\"%.6g\" r=\"0.2\" fill=\"#080\"/>\n",
            c->x_m, c->y_m, c->x_m + 0.4 * cos(c->theta_rad), c->y_m + 0.4 * sin(c->theta_rad),
            c->x_m, c->y_m);
    }
    fprintf(f, "</g>\n</svg>\n");
    ok = !ferror(f);
    if (fclose(f) != 0 || !ok)
        return say(why, why_n, WORLD_FILE_ERR_WRITE, "%s: cannot write", file);
    return WORLD_FILE_OK;
}

/* ---- the options -------------------------------------------------------------- */

/* "a,b(,c)": exactly len finite numbers. */
static int parse_numbers(const char *s, double *v, int len)
{
    int k;
    char *end = (char *)s; /* len 0: nothing parsed, the string must be empty */
    for (k = 0; k < len; k++) {
        errno = 0;
        v[k] = strtod(s, &end);
        if (end == s || errno || !isfinite(v[k]))
            return 0;
        if (k + 1 < len && *end != ',')
            return 0;
        s = end + 1;
    }
    return *end == '\0';
}

/* The file with the options applied, into m and s. */
static int opts_read(const world_opts *o, rover_map *m, rover_map_site *s, char *why, size_t why_n)
{
    double v[3];
    int rc = world_file_read(o->file, m, s, why, why_n);
    if (rc != WORLD_FILE_OK)
        return rc;
    if (o->start) {
        if (!parse_numbers(o->start, v, 3))
            return say(why, why_n, WORLD_FILE_ERR_OPTION, "--start %s: need X,Y,THETA (m, m, rad)",
                       o->start);
        s->start.x_m = v[0];
        s->start.y_m = v[1];
        s->start.theta_rad = v[2];
    }
    if (o->goal) {
        if (!parse_numbers(o->goal, v, 2))
            return say(why, why_n, WORLD_FILE_ERR_OPTION, "--goal %s: need X,Y (m)", o->goal);
        s->goal_m[0] = v[0];
        s->goal_m[1] = v[1];
    }
    return WORLD_FILE_OK;
}

static const char *map_field(int rc)
{
    switch (rc) {
    case ROVER_MAP_ERR_START: return "tandem.start";
    case ROVER_MAP_ERR_GOAL: return "tandem.goal";
    case ROVER_MAP_ERR_LANDMARKS: return "tandem.landmarks";
    case ROVER_MAP_ERR_RESOLUTION: return "resolution";
    default: return "image";
    }
}

int world_landmarks_on_way(rover_world_config *w, const rover_map *m)
{
    navfield_params np;
    navfield *f = malloc(sizeof *f); /* 2 MB, once at start-up */
    if (!f)
        return WORLD_FILE_ERR_MEMORY;
    navfield_params_default(&np);
    if (navfield_build(f, &np, w) == NAVFIELD_OK)
        rover_map_landmarks_on_way(w, m, f);
    free(f);
    return WORLD_FILE_OK;
}

int world_opts_layout(rover_world_config *w, const world_opts *o, int n, double spacing_m,
                      int formation, const char *prog)
{
    char why[WORLD_FILE_WHY_MAX];
    rover_map *m;
    rover_map_site s;
    int rc;
    if (!o->file) {
        if (o->start || o->goal) {
            fprintf(stderr, "%s: --start and --goal need --world-file\n", prog);
            return WORLD_FILE_ERR_OPTION;
        }
        if (rover_world_layout(w, o->world, n, spacing_m, formation) != 0) {
            fprintf(stderr, "%s: no layout of world %s for %d robots\n", prog,
                    rover_world_name(o->world), n);
            return WORLD_FILE_ERR_MAP;
        }
        return WORLD_FILE_OK;
    }
    if (!(m = malloc(sizeof *m))) {
        fprintf(stderr, "%s: %s: out of memory\n", prog, o->file);
        return WORLD_FILE_ERR_MEMORY;
    }
    rc = opts_read(o, m, &s, why, sizeof why);
    if (rc == WORLD_FILE_OK) {
        const int mrc = rover_world_from_map(w, m, &s, n, spacing_m, formation);
        if (mrc != ROVER_MAP_OK) {
            snprintf(why, sizeof why, "%s: %s: %s", o->file, map_field(mrc),
                     rover_map_strerror(mrc));
            rc = WORLD_FILE_ERR_MAP;
        } else if (s.n_landmarks == ROVER_MAP_LANDMARKS_AUTO &&
                   (rc = world_landmarks_on_way(w, m)) != WORLD_FILE_OK) {
            snprintf(why, sizeof why, "%s: out of memory", o->file);
        }
    }
    free(m);
    if (rc != WORLD_FILE_OK)
        fprintf(stderr, "%s: %s\n", prog, why);
    return rc;
}

int world_opts_fleet_layout(rover_world_config *w, rover_fleet *f, const world_opts *o, int n,
                            int teams, int per_team, int goals, int formation, const char *prog)
{
    if (teams <= 1)
        return world_opts_layout(w, o, n, 1.0, formation, prog);
    if (o->file || o->world != ROVER_WORLD_OPEN) {
        fprintf(stderr, "%s: --teams %d: teams fly the open world only (not %s)\n", prog, teams,
                o->file ? "--world-file" : rover_world_name(o->world));
        return WORLD_FILE_ERR_OPTION;
    }
    if (rover_fleet_layout(w, f, teams, per_team, 1.0, formation, goals) != 0) {
        fprintf(stderr,
                "%s: no fleet of %d teams of %d robots (at most %d teams of %d, %d robots in all: "
                "ROVER_FLEET_MAX_TEAMS, ROVER_TEAM_MAX, ROVER_WORLD_MAX_ROBOTS)\n",
                prog, teams, per_team, ROVER_FLEET_MAX_TEAMS, ROVER_TEAM_MAX,
                ROVER_WORLD_MAX_ROBOTS);
        return WORLD_FILE_ERR_OPTION;
    }
    return WORLD_FILE_OK;
}

int world_opts_save(const world_opts *o, const char *dir, const char *prog)
{
    char why[WORLD_FILE_WHY_MAX];
    rover_map *m;
    rover_map_site s;
    int rc;
    if (!o->file)
        return WORLD_FILE_OK;
    if (!(m = malloc(sizeof *m)))
        return WORLD_FILE_ERR_MEMORY;
    rc = opts_read(o, m, &s, why, sizeof why);
    if (rc == WORLD_FILE_OK)
        rc = world_file_write(dir, "world", m, &s, why, sizeof why);
    free(m);
    if (rc != WORLD_FILE_OK)
        fprintf(stderr, "%s: %s\n", prog, why);
    return rc;
}

void world_opts_argv(const world_opts *o, char **argv, int *n, int cap)
{
    if (!o->file || *n + 6 > cap)
        return;
    argv[(*n)++] = "--world-file";
    argv[(*n)++] = (char *)o->file;
    if (o->start) {
        argv[(*n)++] = "--start";
        argv[(*n)++] = (char *)o->start;
    }
    if (o->goal) {
        argv[(*n)++] = "--goal";
        argv[(*n)++] = (char *)o->goal;
    }
}
