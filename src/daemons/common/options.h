/* options: the command line of every tandem program from one const table.
 *
 * A program describes its options once, as a table of option_entry (long
 * name, optional short letter, type, range or choices, where the value
 * goes, help text, the default shown in help); options_parse fills the
 * program's option struct from argv and checks every value, and
 * options_print_help writes the usage text from the same table, so the
 * help cannot miss an option the parser knows or show another range.
 *
 * Destinations are offsets (OPTION_AT) into a struct whose address the
 * program gives at run time in an option_group: the table stays a static
 * const, and one table (options_daemon_common, into a `daemon`) serves
 * every program that embeds that struct. Start-up code only: stdio, no
 * allocation.
 *
 * Syntax, as getopt_long: --name VALUE, --name=VALUE, unique prefixes of
 * long names (not in programs that pass unknown options on), -x VALUE for
 * entries with a letter, "--" ends the options. A value is the next word
 * whatever it starts with (--arm-q0 -0.5,...). An option given twice takes
 * the last value, except the repeatable ones (OPTION_LIST, OPTION_CALL),
 * which see every occurrence.
 */
#ifndef TANDEM_OPTIONS_H
#define TANDEM_OPTIONS_H

#include <stddef.h>
#include <stdio.h>

/* options_parse results (>= 0: index of the first argument left over) */
#define OPTIONS_EXIT (-1)    /* --help or --version printed: exit 0 */
#define OPTIONS_ERR_ARG (-2) /* bad option, message printed: exit 2 */
/* an OPTION_CALL handler's own result: the value is bad and the handler
 * has already said why (a handler returning OPTIONS_ERR_VALUE leaves the
 * message to the parser: "PROG: --NAME: 'VALUE' is not META") */
#define OPTIONS_ERR_SAID (-3)
/* an OPTION_CALL handler's result: the value is bad (the parser says so);
 * an `other` callback's: the word is refused (the callback said why) */
#define OPTIONS_ERR_VALUE (-1)
/* options_table_validate: the table is unsound (the entry named on stderr) */
#define OPTIONS_ERR_TABLE (-4)

#define OPTIONS_EXIT_BAD_ARGS 2 /* the exit status of every program on bad options */

typedef enum option_type {
    OPTION_FLAG,   /* no value: stores 1 in an int (with call: calls it, value NULL) */
    OPTION_INT,    /* integer in [min, max]; into an int, long or int64_t (by the field's size) */
    OPTION_DOUBLE, /* finite number in [min, max], stored times scale (scale 0: as is);
                        nargs > 1: that many words into a double array */
    OPTION_STRING, /* the word itself (const char *), at least min and (max > 0) at most max chars */
    OPTION_CHOICE, /* one of choices (NULL-terminated): stores its index, or values[index], in an int */
    OPTION_LIST, /* repeatable: appends the word to a const char *[max]; count in an int at count */
    OPTION_CALL, /* the word goes to call(prog, dest, word): 0 ok, OPTIONS_ERR_VALUE, OPTIONS_ERR_SAID;
                        may be repeated (each occurrence is a call) */
    OPTION_HELP,   /* prints the help on stdout; options_parse returns OPTIONS_EXIT */
    OPTION_VERSION /* prints the version; options_parse returns OPTIONS_EXIT */
} option_type;

typedef int (*option_call_fn)(const char *prog, void *dest, char *value);

typedef struct option_entry {
    const char *name; /* long name, without "--"; NULL ends a table */
    char letter;      /* short option, 0 for none */
    option_type type;
    size_t offset, size;        /* destination in the group's struct (OPTION_AT) */
    double min, max;            /* numbers: accepted range; strings: length range (max 0: any) */
    double scale;               /* OPTION_DOUBLE: stored value = value * scale (0: 1) */
    int nargs;                  /* OPTION_DOUBLE: words taken (0: 1) */
    const char *const *choices; /* OPTION_CHOICE: the accepted words, NULL-terminated */
    const int *values;          /* OPTION_CHOICE: what each word stores (NULL: its index) */
    size_t count;               /* OPTION_LIST: offset of the int that counts the words */
    option_call_fn call;        /* OPTION_CALL */
    size_t seen;                /* 0, or OPTION_SEEN: 1 + offset of an int set to 1 when given */
    int required;               /* the program does not run without it */
    int repeatable;             /* OPTION_CALL: each occurrence adds (said in help) */
    const char *meta;           /* the value's name in help and messages ("N", "MS") */
    const char *help;           /* what it does; may hold '\n' for a new line */
    const char *def;            /* the default shown in help; NULL: none shown */
} option_entry;

/* Destination of an entry: member of struct type, e.g. OPTION_AT(sim_app, w.seed). */
#define OPTION_AT(type, member) \
    .offset = offsetof(type, member), .size = sizeof(((type *)0)->member)
/* The whole struct as destination (OPTION_CALL handlers that fill several fields). */
#define OPTION_ALL(type) .offset = 0, .size = sizeof(type)
#define OPTION_SEEN(type, member) .seen = 1 + offsetof(type, member)

/* Entries several tables share, written once so their names and help stay
 * one: --help (letter: its short form, 0 for none) and --version in a
 * tool's table (a daemon has them from options_daemon_common), and
 * --journal-reset, the flag of a daemon with a --journal. */
#define OPTION_HELP_ENTRY(letter_)                                                    \
    {                                                                                 \
        .name = "help", .letter = (letter_), .type = OPTION_HELP, .help = "this text" \
    }
#define OPTION_VERSION_ENTRY                                                 \
    {                                                                        \
        .name = "version", .type = OPTION_VERSION, .help = "program version" \
    }
#define OPTION_JOURNAL_RESET_ENTRY(owner, field)                                          \
    {                                                                                     \
        .name = "journal-reset", .type = OPTION_FLAG, OPTION_AT(owner, field),            \
        .help = "start fresh on purpose: empty the --journal instead of resuming from it" \
    }

/* A default written once, as a number the program sets and the text
 * help shows: .def = OPTION_DEF(NAME) with #define NAME 8 gives "8". */
#define OPTION_DEF_TEXT(x) #x
#define OPTION_DEF(x) OPTION_DEF_TEXT(x)

/* One table and the struct its offsets point into. */
typedef struct option_group {
    const option_entry *table; /* ends with an entry whose name is NULL */
    void *base;
} option_group;

#define OPTIONS_MAX_GROUPS 4

/* What a non-option word (or, with pass_unknown, an unknown option) means. */
enum {
    OPTIONS_ARGS_NONE = 0, /* none allowed: "unexpected argument" */
    OPTIONS_ARGS_STOP = 1  /* the first one ends the options (tandem-kin COMMAND ...) */
};

typedef struct option_program {
    const char *name;   /* in messages: "tandem-sim", "tandem-scenario carry" */
    const char *usage;  /* printed before the options: synopsis and description */
    const char *epilog; /* printed after the options (exit status, notes); may be NULL */
    option_group groups[OPTIONS_MAX_GROUPS];
    int n_groups;
    int args; /* OPTIONS_ARGS_* */
    /* non-NULL: every word that is not one of the table's options (unknown
     * options, their values, other arguments) goes here, in order; exact
     * names only (no prefixes: a prefix may be meant for the receiver).
     * 0 ok, OPTIONS_ERR_VALUE (message printed). */
    int (*other)(void *user, const char *word);
    void *other_user;
} option_program;

/* Parses argv[first..argc-1] into the groups' structs. Returns the index
 * of the first word left over (argc when none; with OPTIONS_ARGS_STOP the
 * first non-option word), OPTIONS_EXIT after --help / --version (exit 0)
 * or OPTIONS_ERR_ARG after a message naming the option and what it
 * accepts (exit OPTIONS_EXIT_BAD_ARGS). */
int options_parse(const option_program *p, int argc, char **argv, int first);
/* The exit status for a negative options_parse result. */
int options_exit_status(int rc);
/* Writes usage, every option of every group (with range, choices and
 * default) and the epilog to f. */
void options_print_help(const option_program *p, FILE *f);
/* Checks a table: names unique and non-empty, ranges ordered, choices,
 * destinations of the right size. 0 ok, OPTIONS_ERR_TABLE (names the entry
 * on stderr). */
int options_table_validate(const option_entry *table);

/* The options every daemon (and tandem-sim) takes, into a `daemon`:
 * --lcm-url --rt --lockstep --period-ms --help --version --key-file
 * --insecure --drop-rate --drop-seed. */
extern const option_entry options_daemon_common[];
/* --lcm-url, --key-file and --insecure alone, for the bus tools, into an
 * options_bus (the base of the group): the URL, and the tool's bus the
 * key options go to (set before parsing). */
typedef struct options_bus {
    const char *url;
    struct auth_bus *bus;
} options_bus;
extern const option_entry options_bus_tool[];

/* Choice lists several programs share (values: the core's enum ids). */
extern const char *const options_world_names[]; /* ROVER_WORLD_* */
extern const int options_world_values[];
extern const char *const options_formation_names[]; /* FORMATION_* */
extern const int options_formation_values[];
extern const char *const options_arm_model_names[]; /* arm_model_by_name */
extern const char *const options_on_off[];          /* on = 0, off = 1 */
extern const char *const options_team_goal_names[]; /* ROVER_FLEET_GOALS_* (fleet.h) */
extern const int options_on_off_flags[];            /* values: on 1, off 0 */

#endif
