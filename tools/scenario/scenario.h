/* tandem-scenario: runs a named experiment in lockstep and writes
 * DIR/summary.json, CSV time series and PNG plots (docs/method/lockstep.md §8).
 * Each scenario is one file scenario_<name>.c exporting a scenario_def;
 * this header holds the shared output helpers. */
#ifndef TANDEM_SCENARIO_H
#define TANDEM_SCENARIO_H

#include <stdio.h>

/* Results of the shared helpers (0 = ok); each has printed why. */
#define SCENARIO_OK 0
#define SCENARIO_ERR_ARG (-1) /* a bad option value (--drop-rate, --fault, ...) */
#define SCENARIO_ERR_IO (-2)  /* a directory or file not made, or gnuplot failed */
/* A scenario's setup step: no exit status yet, the run goes on (a setup
 * that fails returns the exit status, >= 0). */
#define SCENARIO_GO_ON (-1)

typedef struct scenario_def {
    const char *name;
    const char *summary;               /* one line for --help */
    int (*run)(int argc, char **argv); /* argv[0] = scenario name; exit code */
} scenario_def;

/* summary.json writer: keys in insertion order, a flat object, which may
 * hold one level of arrays of flat objects (json_array_begin). */
typedef struct json_out {
    FILE *f;
    int n;
    int outer_n, items; /* inside an array: the object's keys before it, its elements */
} json_out;

/* Opens DIR/FILE and the object: 0, or SCENARIO_ERR_IO (said). */
int json_open(json_out *j, const char *dir, const char *file);
void json_num(json_out *j, const char *key, double v); /* NaN/inf -> null */
void json_int(json_out *j, const char *key, long long v);
void json_str(json_out *j, const char *key, const char *v);
/* A point as a string, printed with fmt (three doubles, e.g. "%.3f %.3f %.3f"). */
void json_point(json_out *j, const char *key, const double p[3], const char *fmt);
void json_bool(json_out *j, const char *key, int v);
/* "key": [ {..}, {..} ]: json_array_begin, then for each element
 * json_object_begin, its values, json_object_end; then json_array_end. */
void json_array_begin(json_out *j, const char *key);
void json_object_begin(json_out *j);
void json_object_end(json_out *j);
void json_array_end(json_out *j);
void json_close(json_out *j);

/* One success criterion of a run: its summary key and whether it failed. */
typedef struct scenario_criterion {
    int failed;
    const char *what;
} scenario_criterion;

/* Writes the failed criteria's names into buf, space separated (empty
 * when all hold); returns how many failed. */
int scenario_failed_criteria(const scenario_criterion *k, int n, char *buf, size_t cap);

/* --drop-rate P: fault injection handed to every daemon a scenario starts;
 * their receive paths drop messages with probability P (deterministic for
 * the run's seed: --drop-seed). Lockstep makes the run the same as without
 * loss, only slower. */
typedef struct scenario_drop {
    char rate[24]; /* "" = off */
    char seed[24];
} scenario_drop;
/* Parses P (0 <= P < 1); 0 ok, SCENARIO_ERR_ARG with a message. */
int scenario_parse_drop(scenario_drop *d, const char *v, long seed);
/* Appends "--drop-rate P --drop-seed S" (when on) to argv at *n; argv has
 * room for cap pointers including the closing NULL, which is written. */
void scenario_argv_drop(const scenario_drop *d, char **argv, int *n, int cap);

/* --fault kill:DAEMON:T[:RESTART_T]: the scenario kills DAEMON (SIGKILL,
 * no goodbye) at simulated time T and, with RESTART_T, starts it again
 * then, holding the lockstep until it has answered: deterministic. */
#define SCENARIO_MAX_FAULTS 8
typedef struct scenario_fault {
    char daemon[24];          /* arm1, arm2, supervisor, roverK */
    double kill_s, restart_s; /* restart_s < 0: left down */
    int stage;                /* 0 armed, 1 killed, 2 restarting, 3 done */
    int slot;                 /* the scenario's index of the daemon */
} scenario_fault;
/* Parses one --fault value; 0 ok, SCENARIO_ERR_ARG with a message. */
int scenario_parse_fault(scenario_fault *f, const char *v);

/* mkdir -p; 0 ok, SCENARIO_ERR_IO. */
int scenario_mkdir(const char *dir);
/* fopen(dir/file) for writing, with an error message on failure. */
FILE *scenario_fopen(const char *dir, const char *file);
/* Runs gnuplot on dir/script (written by the caller); a missing gnuplot
 * only prints a warning (plots are optional, the numbers are not), and
 * TANDEM_NO_PLOTS=1 in the environment skips it (a benchmark's runs).
 * 0 ok, SCENARIO_ERR_IO when gnuplot fails. */
int scenario_gnuplot(const char *dir, const char *script);
/* Monotonic wall clock in seconds. */
double scenario_wall_s(void);

#endif
