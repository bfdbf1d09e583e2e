/* options: one option table per program, one parser, one help printer
 * (see options.h). Messages go to stderr as "PROG: --NAME: why", the help
 * to the stream the caller gives. */
#include "options.h"
#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include "daemon.h"
#include "formation.h"
#include "rover_world.h"

#define HELP_COLUMN 22 /* descriptions start here */
#define HELP_WIDTH 79
#define DESC_MAX 1024

typedef struct found {
    const option_entry *e;
    void *base;
} found;

/* ---- finding an entry ------------------------------------------------------ */

/* find_long / find_letter: no such entry; find_long: a prefix of several */
#define FIND_NONE (-1)
#define FIND_AMBIGUOUS (-2)

/* The entry named by name[0..len) (exact, else a unique prefix when
 * prefixes are allowed). 0 found, FIND_NONE or FIND_AMBIGUOUS. */
static int find_long(const option_program *p, const char *name, size_t len, int prefixes,
                     found *out)
{
    int g, n_prefix = 0;
    const option_entry *e;
    for (g = 0; g < p->n_groups; g++)
        for (e = p->groups[g].table; e->name; e++) {
            if (strncmp(e->name, name, len) != 0)
                continue;
            if (e->name[len] == '\0') {
                out->e = e;
                out->base = p->groups[g].base;
                return 0;
            }
            if (prefixes && n_prefix++ == 0) {
                out->e = e;
                out->base = p->groups[g].base;
            }
        }
    return n_prefix == 1 ? 0 : n_prefix > 1 ? FIND_AMBIGUOUS : FIND_NONE;
}

static int find_letter(const option_program *p, char c, found *out)
{
    int g;
    const option_entry *e;
    for (g = 0; g < p->n_groups; g++)
        for (e = p->groups[g].table; e->name; e++)
            if (e->letter && e->letter == c) {
                out->e = e;
                out->base = p->groups[g].base;
                return 0;
            }
    return FIND_NONE;
}

static int takes_value(const option_entry *e)
{
    return e->type != OPTION_FLAG && e->type != OPTION_HELP && e->type != OPTION_VERSION;
}

static int nargs_of(const option_entry *e)
{
    return e->type == OPTION_DOUBLE && e->nargs > 1 ? e->nargs : 1;
}

/* ---- storing a value --------------------------------------------------------- */

static void *dest_of(const found *f)
{
    return (char *)f->base + f->e->offset;
}

static void set_int(void *dest, size_t size, long v)
{
    if (size == sizeof(int)) {
        int x = (int)v;
        memcpy(dest, &x, sizeof x);
    } else if (size == sizeof(long)) {
        memcpy(dest, &v, sizeof v);
    } else {
        int64_t x = v;
        memcpy(dest, &x, sizeof x);
    }
}

static int int_size_ok(size_t size)
{
    return size == sizeof(int) || size == sizeof(long) || size == sizeof(int64_t);
}

static int bad(const option_program *p, const option_entry *e, const char *why, const char *word)
{
    fprintf(stderr, "%s: --%s: '%s' %s\n", p->name, e->name, word, why);
    return OPTIONS_ERR_ARG;
}

static int store_int(const option_program *p, const found *f, const char *s)
{
    const option_entry *e = f->e;
    char *end;
    long v;
    errno = 0;
    v = strtol(s, &end, 10);
    if (s[0] == '\0' || *end != '\0' || errno != 0)
        return bad(p, e, "is not an integer", s);
    if (v < (long)e->min || v > (long)e->max) {
        fprintf(stderr, "%s: --%s: %ld is outside [%ld, %ld]\n", p->name, e->name, v, (long)e->min,
                (long)e->max);
        return OPTIONS_ERR_ARG;
    }
    set_int(dest_of(f), e->size, v);
    return 0;
}

static int store_double(const option_program *p, const found *f, char **words)
{
    const option_entry *e = f->e;
    double v[8];
    int i, n = nargs_of(e);
    for (i = 0; i < n; i++) {
        char *end;
        errno = 0;
        v[i] = strtod(words[i], &end);
        if (words[i][0] == '\0' || *end != '\0' || errno != 0 || !isfinite(v[i]))
            return bad(p, e, "is not a number", words[i]);
        if (v[i] < e->min || v[i] > e->max) {
            if (e->max >= HUGE_VAL)
                fprintf(stderr, "%s: --%s: %g is below %g\n", p->name, e->name, v[i], e->min);
            else
                fprintf(stderr, "%s: --%s: %g is outside [%g, %g]\n", p->name, e->name, v[i],
                        e->min, e->max);
            return OPTIONS_ERR_ARG;
        }
        if (e->scale != 0.0)
            v[i] *= e->scale;
    }
    memcpy(dest_of(f), v, (size_t)n * sizeof v[0]);
    return 0;
}

static int store_string(const option_program *p, const found *f, const char *s)
{
    const option_entry *e = f->e;
    const size_t len = strlen(s);
    if ((double)len < e->min || (e->max > 0.0 && (double)len > e->max)) {
        if (e->max > 0.0)
            fprintf(stderr, "%s: --%s: '%s' is not %g to %g characters long\n", p->name, e->name, s,
                    e->min, e->max);
        else
            fprintf(stderr, "%s: --%s: '%s' is empty\n", p->name, e->name, s);
        return OPTIONS_ERR_ARG;
    }
    memcpy(dest_of(f), &s, sizeof s);
    return 0;
}

static void print_choices(FILE *out, const option_entry *e, const char *sep)
{
    int i;
    for (i = 0; e->choices[i]; i++)
        fprintf(out, "%s%s", i ? sep : "", e->choices[i]);
}

static int store_choice(const option_program *p, const found *f, const char *s)
{
    const option_entry *e = f->e;
    int i, v;
    for (i = 0; e->choices[i] && strcmp(e->choices[i], s) != 0; i++)
        ;
    if (!e->choices[i]) {
        fprintf(stderr, "%s: --%s: '%s' is not ", p->name, e->name, s);
        print_choices(stderr, e, "|");
        fputc('\n', stderr);
        return OPTIONS_ERR_ARG;
    }
    v = e->values ? e->values[i] : i;
    memcpy(dest_of(f), &v, sizeof v);
    return 0;
}

static int store_list(const option_program *p, const found *f, const char *s)
{
    const option_entry *e = f->e;
    int n;
    memcpy(&n, (char *)f->base + e->count, sizeof n);
    if (n >= (int)e->max) {
        fprintf(stderr, "%s: --%s: at most %d\n", p->name, e->name, (int)e->max);
        return OPTIONS_ERR_ARG;
    }
    memcpy((char *)dest_of(f) + (size_t)n * sizeof s, &s, sizeof s);
    n++;
    memcpy((char *)f->base + e->count, &n, sizeof n);
    return 0;
}

static int store_call(const option_program *p, const found *f, char *s)
{
    const option_entry *e = f->e;
    const int rc = e->call(p->name, dest_of(f), s);
    if (rc == 0)
        return 0;
    if (rc == OPTIONS_ERR_SAID || !s)
        return OPTIONS_ERR_ARG;
    fprintf(stderr, "%s: --%s: '%s' is not %s\n", p->name, e->name, s, e->meta ? e->meta : "valid");
    return OPTIONS_ERR_ARG;
}

/* Applies one occurrence; words holds its nargs values (none for flags). */
static int apply(const option_program *p, const found *f, char **words)
{
    const option_entry *e = f->e;
    int rc = 0, one = 1;
    switch (e->type) {
    case OPTION_FLAG:
        if (e->call)
            rc = store_call(p, f, NULL);
        else
            memcpy(dest_of(f), &one, sizeof one);
        break;
    case OPTION_INT: rc = store_int(p, f, words[0]); break;
    case OPTION_DOUBLE: rc = store_double(p, f, words); break;
    case OPTION_STRING: rc = store_string(p, f, words[0]); break;
    case OPTION_CHOICE: rc = store_choice(p, f, words[0]); break;
    case OPTION_LIST: rc = store_list(p, f, words[0]); break;
    case OPTION_CALL: rc = store_call(p, f, words[0]); break;
    case OPTION_HELP: options_print_help(p, stdout); return OPTIONS_EXIT;
    case OPTION_VERSION: daemon_print_version(p->name); return OPTIONS_EXIT;
    }
    if (rc == 0 && e->seen)
        memcpy((char *)f->base + e->seen - 1, &one, sizeof one);
    return rc;
}

/* ---- parsing ------------------------------------------------------------------ */

/* A word that is neither a known option nor a value. */
static int other_word(const option_program *p, const char *w)
{
    if (p->other)
        return p->other(p->other_user, w) == 0 ? 0 : OPTIONS_ERR_ARG;
    if (w[0] == '-' && w[1] != '\0')
        fprintf(stderr, "%s: unknown option '%s' (%s --help lists them)\n", p->name, w, p->name);
    else
        fprintf(stderr, "%s: unexpected argument '%s'\n", p->name, w);
    return OPTIONS_ERR_ARG;
}

/* Finds the entry argv[*i] names; 0 found, 1 not an option of the
 * table (left to other_word), <0 error. *inline_value: the part after '='. */
static int lookup(const option_program *p, char *w, found *f, char **inline_value)
{
    *inline_value = NULL;
    if (w[0] == '-' && w[1] == '-') {
        char *eq = strchr(w + 2, '=');
        const size_t len = eq ? (size_t)(eq - (w + 2)) : strlen(w + 2);
        const int rc = find_long(p, w + 2, len, p->other == NULL, f);
        if (rc == FIND_AMBIGUOUS) {
            fprintf(stderr, "%s: option '%s' is ambiguous\n", p->name, w);
            return OPTIONS_ERR_ARG;
        }
        if (rc != 0)
            return 1;
        if (eq && !takes_value(f->e)) {
            fprintf(stderr, "%s: --%s takes no value\n", p->name, f->e->name);
            return OPTIONS_ERR_ARG;
        }
        if (eq)
            *inline_value = eq + 1;
        return 0;
    }
    if (w[0] == '-' && w[1] != '\0' && w[2] == '\0' && find_letter(p, w[1], f) == 0)
        return 0;
    return 1;
}

static int check_required(const option_program *p)
{
    int g, one;
    const option_entry *e;
    for (g = 0; g < p->n_groups; g++)
        for (e = p->groups[g].table; e->name; e++) {
            if (!e->required)
                continue;
            memcpy(&one, (char *)p->groups[g].base + e->seen - 1, sizeof one);
            if (!one) {
                fprintf(stderr, "%s: --%s %s is required\n", p->name, e->name,
                        e->meta ? e->meta : "");
                return OPTIONS_ERR_ARG;
            }
        }
    return 0;
}

int options_parse(const option_program *p, int argc, char **argv, int first)
{
    int i, rc;
    for (i = first; i < argc; i++) {
        char *w = argv[i], *inline_value, *words[8];
        found f;
        int k, n;
        if (!strcmp(w, "--") && !p->other) {
            i++;
            break;
        }
        rc = lookup(p, w, &f, &inline_value);
        if (rc < 0)
            return rc;
        if (rc == 1) {
            if (p->args == OPTIONS_ARGS_STOP && (w[0] != '-' || w[1] == '\0'))
                break;
            if ((rc = other_word(p, w)) != 0)
                return rc;
            continue;
        }
        n = takes_value(f.e) ? nargs_of(f.e) : 0;
        for (k = 0; k < n; k++) {
            if (k == 0 && inline_value) {
                words[0] = inline_value;
                continue;
            }
            if (i + 1 >= argc) {
                fprintf(stderr, "%s: --%s needs %s%s\n", p->name, f.e->name,
                        n > 1 ? "values " : "a value ", f.e->meta ? f.e->meta : "");
                return OPTIONS_ERR_ARG;
            }
            words[k] = argv[++i];
        }
        if ((rc = apply(p, &f, words)) != 0)
            return rc;
    }
    if (p->args == OPTIONS_ARGS_NONE && !p->other && i < argc)
        return other_word(p, argv[i]);
    for (; p->other && i < argc; i++)
        if (other_word(p, argv[i]) != 0)
            return OPTIONS_ERR_ARG;
    rc = check_required(p);
    return rc != 0 ? rc : i;
}

int options_exit_status(int rc)
{
    return rc == OPTIONS_EXIT ? 0 : OPTIONS_EXIT_BAD_ARGS;
}

/* ---- help ---------------------------------------------------------------------- */

/* Appends fmt (a literal of this file taking a string and up to two
 * numbers) to buf, truncating at cap. */
static void add(char *buf, size_t cap, const char *fmt, const char *s1, double v1, double v2)
{
    const size_t n = strlen(buf);
    if (n + 1 < cap)
        snprintf(buf + n, cap - n, fmt, s1 ? s1 : "", v1, v2);
}

static void describe(const option_entry *e, char *d, size_t cap)
{
    int i;
    d[0] = '\0';
    add(d, cap, "%s", e->help, 0, 0);
    if (e->type == OPTION_CHOICE && e->meta) {
        add(d, cap, "%s", d[0] ? ": " : "", 0, 0);
        for (i = 0; e->choices[i]; i++) {
            add(d, cap, "%s", i ? " | " : "", 0, 0);
            add(d, cap, "%s", e->choices[i], 0, 0);
        }
    }
    if (e->type == OPTION_INT || e->type == OPTION_DOUBLE) {
        if (e->max >= HUGE_VAL && e->min <= -HUGE_VAL)
            ;
        else if (e->max >= HUGE_VAL)
            add(d, cap, "%s>= %g", d[0] ? "; " : "", e->min, 0);
        else
            add(d, cap, e->type == OPTION_INT ? "%s%.0f..%.0f" : "%s%g..%g", d[0] ? "; " : "",
                e->min, e->max);
    }
    if (e->type == OPTION_STRING && e->max > 0.0)
        add(d, cap, "%s%g..%g characters", d[0] ? "; " : "", e->min, e->max);
    if (e->def) {
        add(d, cap, "%s", d[0] ? "; default " : "default ", 0, 0);
        add(d, cap, "%s", e->def, 0, 0);
    }
    if (e->type == OPTION_LIST || e->repeatable)
        add(d, cap, "%s", d[0] ? "; repeatable" : "repeatable", 0, 0);
    if (e->required)
        add(d, cap, "%s", d[0] ? " (required)" : "required", 0, 0);
}

static void print_entry(FILE *f, const option_entry *e)
{
    char d[DESC_MAX], left[256];
    const char *w;
    int col;
    /* the left part first, to know its width */
    if (e->letter)
        snprintf(left, sizeof left, "  -%c, --%s", e->letter, e->name);
    else
        snprintf(left, sizeof left, "  --%s", e->name);
    if (takes_value(e)) {
        size_t n = strlen(left);
        if (e->type == OPTION_CHOICE && !e->meta) {
            int i;
            for (i = 0; e->choices[i] && n + 2 < sizeof left; i++, n = strlen(left))
                snprintf(left + n, sizeof left - n, "%s%s", i ? "|" : " ", e->choices[i]);
        } else {
            snprintf(left + n, sizeof left - n, " %s", e->meta ? e->meta : "VALUE");
        }
    }
    describe(e, d, sizeof d);
    fputs(left, f);
    col = (int)strlen(left);
    if (col + 2 > HELP_COLUMN) {
        fputs("  ", f);
        col += 2;
    } else {
        fprintf(f, "%*s", HELP_COLUMN - col, "");
        col = HELP_COLUMN;
    }
    /* words, wrapped at HELP_WIDTH; '\n' in the help starts a new line */
    for (w = d; *w;) {
        const size_t len = strcspn(w, " \n");
        if (col > HELP_COLUMN && col + 1 + (int)len > HELP_WIDTH) {
            fprintf(f, "\n%*s", HELP_COLUMN, "");
            col = HELP_COLUMN;
        } else if (col > HELP_COLUMN) {
            fputc(' ', f);
            col++;
        }
        fwrite(w, 1, len, f);
        col += (int)len;
        w += len;
        if (*w == '\n') {
            fprintf(f, "\n%*s", HELP_COLUMN, "");
            col = HELP_COLUMN;
        }
        while (*w == ' ' || *w == '\n')
            w++;
    }
    fputc('\n', f);
}

void options_print_help(const option_program *p, FILE *f)
{
    int g;
    const option_entry *e;
    if (p->usage)
        fputs(p->usage, f);
    for (g = 0; g < p->n_groups; g++)
        for (e = p->groups[g].table; e->name; e++)
            print_entry(f, e);
    if (p->epilog)
        fputs(p->epilog, f);
}

/* ---- checking a table ------------------------------------------------------------ */

static int entry_bad(const option_entry *e, const char *why)
{
    fprintf(stderr, "option table: --%s: %s\n", e->name ? e->name : "(null)", why);
    return OPTIONS_ERR_TABLE;
}

static int entry_validate(const option_entry *e)
{
    if (!e->name[0] || e->name[0] == '-')
        return entry_bad(e, "empty name or leading '-'");
    if (e->required && !e->seen)
        return entry_bad(e, "required without OPTION_SEEN");
    switch (e->type) {
    case OPTION_FLAG:
        return e->call || e->size == sizeof(int) ? 0 : entry_bad(e, "a flag goes to an int");
    case OPTION_INT:
        if (!int_size_ok(e->size))
            return entry_bad(e, "destination is not an int, long or int64_t");
        return e->min <= e->max ? 0 : entry_bad(e, "min > max");
    case OPTION_DOUBLE:
        if (e->nargs > 8 || e->size != (size_t)nargs_of(e) * sizeof(double))
            return entry_bad(e, "destination is not nargs doubles (nargs <= 8)");
        return e->min <= e->max ? 0 : entry_bad(e, "min > max");
    case OPTION_STRING:
        return e->size == sizeof(const char *) ? 0
                                               : entry_bad(e, "destination is not a const char *");
    case OPTION_CHOICE:
        if (!e->choices || !e->choices[0])
            return entry_bad(e, "no choices");
        return e->size == sizeof(int) ? 0 : entry_bad(e, "a choice goes to an int");
    case OPTION_LIST:
        if (e->max < 1.0 || e->size != (size_t)e->max * sizeof(const char *))
            return entry_bad(e, "destination is not const char *[max]");
        return 0;
    case OPTION_CALL: return e->call ? 0 : entry_bad(e, "no handler");
    case OPTION_HELP:
    case OPTION_VERSION: return 0;
    }
    return entry_bad(e, "unknown type");
}

int options_table_validate(const option_entry *table)
{
    const option_entry *e, *o;
    for (e = table; e->name; e++) {
        if (entry_validate(e) != 0)
            return OPTIONS_ERR_TABLE;
        for (o = table; o != e; o++)
            if (!strcmp(o->name, e->name) || (e->letter && o->letter == e->letter))
                return entry_bad(e, "given twice");
    }
    return 0;
}

/* ---- shared tables ------------------------------------------------------------------ */

const char *const options_world_names[] = { "open", "obstacles", "corridor", "deadzone", NULL };
const int options_world_values[] = { ROVER_WORLD_OPEN, ROVER_WORLD_OBSTACLES, ROVER_WORLD_CORRIDOR,
                                     ROVER_WORLD_DEADZONE };
const char *const options_formation_names[] = { "line", "triangle", "column", NULL };
const int options_formation_values[] = { FORMATION_LINE, FORMATION_TRIANGLE, FORMATION_COLUMN };
const char *const options_arm_model_names[] = { "puma560", "seed002", NULL };
const char *const options_on_off[] = { "on", "off", NULL };
const char *const options_team_goal_names[] = { "ahead", "cross", NULL };
const int options_on_off_flags[] = { 1, 0 };

/* --key-file and --insecure onto the bus of the group's destination: a
 * daemon's (options_daemon_common) or a tool's (options_bus_tool) */
static int bus_option(auth_bus *bus, const char *prog, int opt, const char *value)
{
    return auth_bus_option(bus, prog, opt, value) > 0 ? 0 : OPTIONS_ERR_SAID;
}

static int daemon_key_file(const char *prog, void *dest, char *value)
{
    return bus_option(&((daemon *)dest)->bus, prog, OPT_KEY_FILE, value);
}

static int daemon_insecure(const char *prog, void *dest, char *value)
{
    return bus_option(&((daemon *)dest)->bus, prog, OPT_INSECURE, value);
}

static int tool_key_file(const char *prog, void *dest, char *value)
{
    return bus_option(((options_bus *)dest)->bus, prog, OPT_KEY_FILE, value);
}

static int tool_insecure(const char *prog, void *dest, char *value)
{
    return bus_option(((options_bus *)dest)->bus, prog, OPT_INSECURE, value);
}

#define BUS_KEY_ENTRIES(key_file, insecure)                                          \
    { .name = "key-file",                                                            \
      .type = OPTION_CALL,                                                           \
      .call = (key_file),                                                            \
      .repeatable = 1,                                                               \
      .meta = "PATH",                                                                \
      .help = "bus key (default $" AUTH_BUS_KEY_ENV                                  \
              ", else ${XDG_CONFIG_HOME:-~/.config}/tandem/bus.key "                 \
              "if it exists); twice while rotating: the first signs, both verify" }, \
    {                                                                                \
        .name = "insecure", .type = OPTION_FLAG, .call = (insecure),                 \
        .help = "no authentication: nothing signed, nothing checked"                 \
    }

const option_entry options_daemon_common[] = {
    { .name = "lcm-url",
      .type = OPTION_STRING,
      OPTION_AT(daemon, lcm_url),
      .min = 1,
      .meta = "URL",
      .help = "LCM provider",
      .def = DAEMON_DEFAULT_LCM_URL ", or $LCM_DEFAULT_URL when set" },
    { .name = "rt",
      .type = OPTION_INT,
      OPTION_AT(daemon, rt_prio),
      .min = 1,
      .max = 99,
      .meta = "PRIO",
      .help =
          "SCHED_FIFO priority and mlockall (warns and goes on without them when not permitted)" },
    { .name = "lockstep",
      .type = OPTION_FLAG,
      OPTION_AT(daemon, lockstep),
      .help = "follow the simulator's clock (deterministic) instead of the wall clock" },
    { .name = "period-ms",
      .type = OPTION_DOUBLE,
      OPTION_AT(daemon, period_s),
      .min = 0.05,
      .max = 10000.0,
      .scale = 1e-3,
      .meta = "MS",
      .help = "control period" },
    OPTION_HELP_ENTRY(0),
    { .name = "version",
      .type = OPTION_VERSION,
      .help = "program version (git describe at build time)" },
    BUS_KEY_ENTRIES(daemon_key_file, daemon_insecure),
    { .name = "drop-rate",
      .type = OPTION_DOUBLE,
      OPTION_AT(daemon, drop_rate),
      .min = 0.0,
      .max = 0.9,
      .meta = "P",
      .help = "fault injection: drop received messages with probability P" },
    { .name = "drop-seed",
      .type = OPTION_INT,
      OPTION_AT(daemon, drop_seed),
      .min = 0,
      .max = 2147483647.0,
      .meta = "S",
      .help = "seed of the drops: same seed, same drops",
      .def = "1" },
    { .name = NULL }
};

const option_entry options_bus_tool[] = { { .name = "lcm-url",
                                            .type = OPTION_STRING,
                                            OPTION_AT(options_bus, url),
                                            .meta = "URL",
                                            .help = "LCM provider",
                                            .def = "$LCM_DEFAULT_URL or " DAEMON_DEFAULT_LCM_URL },
                                          BUS_KEY_ENTRIES(tool_key_file, tool_insecure),
                                          { .name = NULL } };
