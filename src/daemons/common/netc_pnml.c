/* netc_pnml: reads a place/transition net from PNML (ISO/IEC 15909-2,
 * ptnet) with libxml2 into the tables of docs/method/carry.md §5: places
 * with their initial marking, transitions, arcs with their weights, and
 * PIPE's inhibitor arcs (<type value="inhibitor"/> on the arc). The subset
 * read is docs/tasks.md §2. Indices follow the order of the document.
 */
#include <stdlib.h>
#include <string.h>
#include <libxml/parser.h>
#include <libxml/tree.h>
#include "netc.h"

#define MAX_ARCS (2 * PETRI_MAX_PLACES * PETRI_MAX_TRANSITIONS)

typedef struct {
    char src[NETC_MAX_NAME], dst[NETC_MAX_NAME];
    int weight, inhibitor;
} pnml_arc;

typedef struct {
    netc_task *t;
    pnml_arc arcs[MAX_ARCS];
    int n_arcs;
    FILE *err;
    const char *path;
    int rc;
} pnml_reader;

static int is_el(const xmlNode *n, const char *name)
{
    return n->type == XML_ELEMENT_NODE && xmlStrcmp(n->name, (const xmlChar *)name) == 0;
}

static const xmlNode *child(const xmlNode *n, const char *name)
{
    const xmlNode *c;
    for (c = n->children; c; c = c->next)
        if (is_el(c, name))
            return c;
    return NULL;
}

/* label_text, copy_attr: the text did not fit the fixed field (refused,
 * never truncated: two long ids cut to one would join two nodes) */
#define TEXT_TOO_LONG (-1)

/* s into out (size bytes): 1, or TEXT_TOO_LONG. Frees s. */
static int take_text(xmlChar *s, char *out, size_t size)
{
    const int n = snprintf(out, size, "%s", s ? (const char *)s : "");
    xmlFree(s);
    return n >= 0 && (size_t)n < size ? 1 : TEXT_TOO_LONG;
}

/* A label's text: <name><text>..</text></name> (ISO), or PIPE's
 * <name><value>..</value></name>; 1, 0 if absent, or TEXT_TOO_LONG. */
static int label_text(const xmlNode *n, const char *label, char *out, size_t size)
{
    const xmlNode *l = child(n, label), *tx = l ? child(l, "text") : NULL;
    if (l && !tx)
        tx = child(l, "value");
    if (!tx)
        return 0;
    return take_text(xmlNodeGetContent(tx), out, size);
}

/* An attribute's value ("" if absent): 1 or TEXT_TOO_LONG. */
static int copy_attr(const xmlNode *n, const char *name, char *out, size_t size)
{
    return take_text(xmlGetProp(n, (const xmlChar *)name), out, size);
}

/* A name or id longer than the tables hold: refused naming the limit. */
static void too_long(pnml_reader *r, const char *what)
{
    netc_say(r->err, "%s: %s longer than %d characters (TASKDEF_MAX_NAME)\n", r->path, what,
             NETC_MAX_NAME - 1);
    r->rc = NETC_ERR_CAPACITY;
}

/* An integer label: "3", or PIPE's "Default,3"; `dflt` when absent. */
static int label_int(pnml_reader *r, const xmlNode *n, const char *label, int dflt,
                     const char *what)
{
    char buf[64], *p, *end;
    long v;
    const int got = label_text(n, label, buf, sizeof buf);
    if (got == 0)
        return dflt;
    p = strrchr(buf, ',');
    p = p ? p + 1 : buf;
    v = strtol(p, &end, 10);
    while (*end == ' ' || *end == '\n' || *end == '\t' || *end == '\r')
        end++;
    if (got == TEXT_TOO_LONG || end == p || *end || v < 0 || v > PETRI_TOKEN_MAX) {
        netc_say(r->err, "%s: %s \"%s\": not an integer 0..%d\n", r->path, what, buf,
                 PETRI_TOKEN_MAX);
        r->rc = NETC_ERR_PNML;
        return 0;
    }
    return (int)v;
}

static void add_node(pnml_reader *r, const xmlNode *n, int is_place)
{
    netc_task *t = r->t;
    int *count = is_place ? &t->n_places : &t->n_transitions;
    /* NOLINTNEXTLINE(bugprone-branch-clone): the two capacities are equal today, not by rule */
    const int max = is_place ? PETRI_MAX_PLACES : PETRI_MAX_TRANSITIONS;
    char *id, *name;
    if (*count >= max) {
        netc_say(r->err, "%s: more than %d %s (PETRI_MAX_%s)\n", r->path, max,
                 is_place ? "places" : "transitions", is_place ? "PLACES" : "TRANSITIONS");
        r->rc = NETC_ERR_CAPACITY;
        return;
    }
    id = is_place ? t->place_id[*count] : t->trans_id[*count];
    name = is_place ? t->place_name[*count] : t->trans_name[*count];
    if (copy_attr(n, "id", id, NETC_MAX_NAME) == TEXT_TOO_LONG) {
        too_long(r, is_place ? "a place id" : "a transition id");
        return;
    }
    switch (label_text(n, "name", name, NETC_MAX_NAME)) {
    case TEXT_TOO_LONG: {
        char what[NETC_MAX_NAME + 16];
        snprintf(what, sizeof what, "the name of %s", id);
        too_long(r, what);
        return;
    }
    case 0: snprintf(name, NETC_MAX_NAME, "%s", id); break;
    default:
        if (!name[0])
            snprintf(name, NETC_MAX_NAME, "%s", id);
    }
    if (is_place)
        t->m0[*count] = (uint8_t)label_int(r, n, "initialMarking", 0, "initial marking");
    (*count)++;
}

static void add_arc(pnml_reader *r, const xmlNode *n)
{
    pnml_arc *a;
    const xmlNode *ty = child(n, "type");
    if (r->n_arcs >= MAX_ARCS) {
        netc_say(r->err, "%s: more than %d arcs\n", r->path, MAX_ARCS);
        r->rc = NETC_ERR_CAPACITY;
        return;
    }
    a = &r->arcs[r->n_arcs++];
    if (copy_attr(n, "source", a->src, sizeof a->src) == TEXT_TOO_LONG ||
        copy_attr(n, "target", a->dst, sizeof a->dst) == TEXT_TOO_LONG) {
        too_long(r, "an arc's source or target");
        return;
    }
    a->weight = label_int(r, n, "inscription", 1, "arc weight");
    a->inhibitor = 0;
    if (ty) {
        char v[32];
        (void)copy_attr(ty, "value", v, sizeof v); /* a longer one is no type we read either */
        if (strcmp(v, "inhibitor") == 0)
            a->inhibitor = 1;
        else if (strcmp(v, "normal") != 0 && v[0]) {
            netc_say(r->err, "%s: arc %s -> %s: type \"%s\" not read (normal, inhibitor)\n",
                     r->path, a->src, a->dst, v);
            r->rc = NETC_ERR_PNML;
        }
    }
}

/* Places, transitions and arcs of a net or page, pages nested. */
static void walk(pnml_reader *r, const xmlNode *n)
{
    const xmlNode *c;
    for (c = n->children; c && r->rc == 0; c = c->next) {
        if (is_el(c, "place"))
            add_node(r, c, 1);
        else if (is_el(c, "transition"))
            add_node(r, c, 0);
        else if (is_el(c, "arc"))
            add_arc(r, c);
        else if (is_el(c, "page"))
            walk(r, c);
    }
}

static int find_id(char ids[][NETC_MAX_NAME], int n, const char *id)
{
    int i;
    for (i = 0; i < n; i++)
        if (strcmp(ids[i], id) == 0)
            return i;
    return -1;
}

/* One arc into the tables: place -> transition (N- or inhibitor) or
 * transition -> place (N+), weight 1 in all (the engine's 0/1 entries). */
static void resolve_arc(pnml_reader *r, const pnml_arc *a)
{
    netc_task *t = r->t;
    int p = find_id(t->place_id, t->n_places, a->src);
    int j = find_id(t->trans_id, t->n_transitions, a->dst);
    int8_t *e;
    if (p >= 0 && j >= 0)
        e = a->inhibitor ? &t->n_inhibit[p * t->n_transitions + j]
                         : &t->n_minus[p * t->n_transitions + j];
    else if ((j = find_id(t->trans_id, t->n_transitions, a->src)) >= 0 &&
             (p = find_id(t->place_id, t->n_places, a->dst)) >= 0 && !a->inhibitor)
        e = &t->n_plus[p * t->n_transitions + j];
    else {
        netc_say(r->err, "%s: arc %s -> %s: not place -> transition or transition -> place%s\n",
                 r->path, a->src, a->dst,
                 a->inhibitor ? " (an inhibitor arc goes from a place)" : "");
        r->rc = NETC_ERR_PNML;
        return;
    }
    if (a->weight != 1 || *e != 0) {
        netc_say(r->err,
                 "%s: arc %s -> %s: weight %d; the supervisor's engine takes "
                 "weight 1 and one arc per pair (petri.h: entries 0/1)\n",
                 r->path, a->src, a->dst, *e ? *e + a->weight : a->weight);
        r->rc = NETC_ERR_CAPACITY;
        return;
    }
    *e = 1;
    t->has_inhibit |= a->inhibitor;
}

static const xmlNode *find_net(const xmlNode *n)
{
    for (; n; n = n->next) {
        const xmlNode *f;
        if (is_el(n, "net"))
            return n;
        if ((f = find_net(n->children)) != NULL)
            return f;
    }
    return NULL;
}

/* The net of a parsed document (doc NULL: not readable XML) into t; path
 * names it in what is said. Frees doc. */
static int read_doc(netc_task *t, xmlDoc *doc, const char *path, FILE *err)
{
    pnml_reader *r = calloc(1, sizeof *r);
    const xmlNode *net;
    int i, rc;
    if (!r) {
        xmlFreeDoc(doc);
        return NETC_ERR_IO;
    }
    r->t = t;
    r->err = err;
    r->path = path;
    net = doc ? find_net(xmlDocGetRootElement(doc)) : NULL;
    if (!net) {
        netc_say(err, "%s: %s\n", path, doc ? "no <net> element" : "not readable XML");
        r->rc = doc ? NETC_ERR_PNML : NETC_ERR_IO;
    } else {
        if (!t->task[0])
            if (copy_attr(net, "id", t->task, sizeof t->task) == TEXT_TOO_LONG)
                too_long(r, "the net's id");
        walk(r, net);
    }
    for (i = 0; i < r->n_arcs && r->rc == 0; i++)
        resolve_arc(r, &r->arcs[i]);
    if (r->rc == 0 && (t->n_places == 0 || t->n_transitions == 0)) {
        netc_say(err, "%s: no places or no transitions\n", path);
        r->rc = NETC_ERR_PNML;
    }
    rc = r->rc;
    xmlFreeDoc(doc);
    free(r);
    netc_task_bind(t);
    return rc;
}

/* No network, no entity expansion from outside, no messages of libxml2's
 * own on stderr: what is wrong is said by this reader. */
#define PNML_PARSE_OPTIONS (XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING)

int netc_pnml_read(netc_task *t, const char *path, FILE *err)
{
    return read_doc(t, xmlReadFile(path, NULL, PNML_PARSE_OPTIONS), path, err);
}

int netc_pnml_read_memory(netc_task *t, const char *buf, int len, const char *name, FILE *err)
{
    if (!buf || len < 0)
        return NETC_ERR_PNML;
    return read_doc(t, xmlReadMemory(buf, len, name, NULL, PNML_PARSE_OPTIONS), name, err);
}
