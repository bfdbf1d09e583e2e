/* netc_rows_yaml: a task's lookup table from YAML (docs/tasks.md §3.1),
 * the same fields as the CSV (docs/method/carry.md §6) by name, with
 * libyaml: a list of rows under `rows:`, each a mapping. A row's fields
 * become the CSV's field strings and go through the same parser
 * (netc_row_fields), so the two files cannot mean different things.
 */
#include <string.h>
#include <yaml.h>
#include "netc.h"

#define FIELD_CHARS 256

enum { F_TRANSITION, F_LIVE, F_GAINS, F_SYNC, F_ARM1, F_ARM2, F_NAME };

/* The keys of a row, in the CSV's order, and whether one must be given
 * (an arm left out does nothing, sync_group left out is 0). */
static const struct {
    const char *key;
    const char *dflt; /* NULL: required */
    const char *join; /* a list's items joined with this */
} FIELDS[NETC_ROW_FIELDS] = {
    { "transition", NULL, NULL }, { "live", NULL, NULL }, { "gains", NULL, " " },
    { "sync_group", "0", NULL },  { "arm1", "-", "; " },  { "arm2", "-", "; " },
    { "name", NULL, NULL },
};

typedef struct {
    yaml_document_t doc;
    const char *path;
    FILE *err;
    char text[NETC_ROW_FIELDS][FIELD_CHARS]; /* one row's fields as the CSV parser reads them */
} yrows;

static int say(const yrows *y, const yaml_node_t *n, const char *what)
{
    netc_say(y->err, "%s:%lu: %s\n", y->path, n ? (unsigned long)n->start_mark.line + 1 : 0UL,
             what);
    return NETC_ERR_ROWS;
}

static const char *scalar(const yaml_node_t *n)
{
    return n && n->type == YAML_SCALAR_NODE ? (const char *)n->data.scalar.value : NULL;
}

static yaml_node_t *map_get(yrows *y, const yaml_node_t *map, const char *key)
{
    yaml_node_pair_t *p;
    if (!map || map->type != YAML_MAPPING_NODE)
        return NULL;
    for (p = map->data.mapping.pairs.start; p < map->data.mapping.pairs.top; p++) {
        const char *k = scalar(yaml_document_get_node(&y->doc, p->key));
        if (k && strcmp(k, key) == 0)
            return yaml_document_get_node(&y->doc, p->value);
    }
    return NULL;
}

/* A field: a scalar as it is, or a list of scalars joined (gains: eight
 * numbers; an arm: its segments). 0, or -1 if it is neither or too long. */
static int field_text(yrows *y, const yaml_node_t *n, const char *join, char *out)
{
    yaml_node_item_t *it;
    size_t len = 0;
    if (scalar(n))
        return (size_t)snprintf(out, FIELD_CHARS, "%s", scalar(n)) < FIELD_CHARS ? 0 : -1;
    if (!join || n->type != YAML_SEQUENCE_NODE)
        return -1;
    out[0] = '\0';
    for (it = n->data.sequence.items.start; it < n->data.sequence.items.top; it++) {
        const char *s = scalar(yaml_document_get_node(&y->doc, *it));
        const int w = s ? snprintf(out + len, FIELD_CHARS - len, "%s%s", len ? join : "", s) : -1;
        if (w < 0 || len + (size_t)w >= FIELD_CHARS)
            return -1;
        len += (size_t)w;
    }
    if (len == 0)
        snprintf(out, FIELD_CHARS, "-"); /* an empty list: the arm does nothing */
    return 0;
}

/* YAML's booleans for live, as the CSV writes them. */
static void live_word(char *f)
{
    if (strcmp(f, "true") == 0 || strcmp(f, "True") == 0)
        snprintf(f, FIELD_CHARS, "yes");
    else if (strcmp(f, "false") == 0 || strcmp(f, "False") == 0)
        snprintf(f, FIELD_CHARS, "no");
}

static int read_row(yrows *y, netc_task *t, const yaml_node_t *row)
{
    char *f[NETC_ROW_FIELDS], why[160];
    const char *what = NULL;
    int k;
    if (row->type != YAML_MAPPING_NODE)
        return say(
            y, row,
            "a row is a mapping (transition:, live:, gains:, sync_group:, arm1:, arm2:, name:)");
    for (k = 0; k < NETC_ROW_FIELDS; k++) {
        const yaml_node_t *n = map_get(y, row, FIELDS[k].key);
        f[k] = y->text[k];
        if (!n && !FIELDS[k].dflt) {
            snprintf(why, sizeof why, "%s: missing", FIELDS[k].key);
            return say(y, row, why);
        }
        if (!n)
            snprintf(y->text[k], FIELD_CHARS, "%s", FIELDS[k].dflt);
        else if (field_text(y, n, FIELDS[k].join, y->text[k]) != 0) {
            snprintf(why, sizeof why, "%s: not %s", FIELDS[k].key,
                     FIELDS[k].join ? "a value or a list of values" : "a single value");
            return say(y, n, why);
        }
    }
    live_word(y->text[F_LIVE]);
    if (netc_row_fields(t, f, &what) != 0)
        return say(y, row, what);
    return NETC_OK;
}

int netc_is_yaml(const char *path)
{
    const size_t n = path ? strlen(path) : 0;
    return (n > 5 && strcmp(path + n - 5, ".yaml") == 0) ||
           (n > 4 && strcmp(path + n - 4, ".yml") == 0);
}

int netc_rows_read_yaml(netc_task *t, const char *path, FILE *err)
{
    yrows y;
    yaml_parser_t parser;
    const yaml_node_t *root, *rows;
    yaml_node_item_t *it;
    FILE *f = fopen(path, "rb");
    int rc = NETC_OK;
    if (!f) {
        netc_say(err, "%s: cannot read\n", path);
        return NETC_ERR_IO;
    }
    y.path = path;
    y.err = err;
    yaml_parser_initialize(&parser);
    yaml_parser_set_input_file(&parser, f);
    if (!yaml_parser_load(&parser, &y.doc)) {
        netc_say(err, "%s:%lu: not YAML: %s\n", path, (unsigned long)parser.problem_mark.line + 1,
                 parser.problem ? parser.problem : "?");
        yaml_parser_delete(&parser);
        fclose(f);
        return NETC_ERR_ROWS;
    }
    root = yaml_document_get_root_node(&y.doc);
    rows = root && root->type == YAML_SEQUENCE_NODE ? root : map_get(&y, root, "rows");
    if (!rows || rows->type != YAML_SEQUENCE_NODE)
        rc = say(&y, root, "rows: a list of rows, one per transition");
    for (it = rows && rc == NETC_OK ? rows->data.sequence.items.start : NULL;
         it && it < rows->data.sequence.items.top && rc == NETC_OK; it++)
        rc = read_row(&y, t, yaml_document_get_node(&y.doc, *it));
    yaml_document_delete(&y.doc);
    yaml_parser_delete(&parser);
    fclose(f);
    return rc == NETC_OK ? netc_rows_complete(t, path, err) : rc;
}
