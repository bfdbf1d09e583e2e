/* scenario_util: JSON / CSV / gnuplot helpers for tandem-scenario. */
#include "scenario.h"
#include "proc.h"
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int scenario_failed_criteria(const scenario_criterion *k, int n, char *buf, size_t cap)
{
    size_t used = 0;
    int i, failed = 0;
    buf[0] = '\0';
    for (i = 0; i < n; i++)
        if (k[i].failed) {
            const int w = snprintf(buf + used, used < cap ? cap - used : 0, "%s%s",
                                   failed ? " " : "", k[i].what);
            used += w > 0 ? (size_t)w : 0;
            failed++;
        }
    return failed;
}

int scenario_mkdir(const char *dir)
{
    if (proc_mkdir_p(dir) != 0) {
        fprintf(stderr, "tandem-scenario: cannot create '%s': %s\n", dir, strerror(errno));
        return SCENARIO_ERR_IO;
    }
    return 0;
}

FILE *scenario_fopen(const char *dir, const char *file)
{
    char path[1024];
    FILE *f;
    snprintf(path, sizeof path, "%s/%s", dir, file);
    f = fopen(path, "w");
    if (!f)
        fprintf(stderr, "tandem-scenario: cannot write '%s': %s\n", path, strerror(errno));
    return f;
}

int json_open(json_out *j, const char *dir, const char *file)
{
    j->f = scenario_fopen(dir, file);
    j->n = 0;
    j->outer_n = j->items = 0;
    if (!j->f)
        return SCENARIO_ERR_IO;
    fputs("{\n", j->f);
    return 0;
}

static void key(json_out *j, const char *k)
{
    fprintf(j->f, "%s  \"%s\": ", j->n++ ? ",\n" : "", k);
}

void json_num(json_out *j, const char *k, double v)
{
    key(j, k);
    if (isfinite(v))
        fprintf(j->f, "%.6g", v);
    else
        fputs("null", j->f);
}

void json_int(json_out *j, const char *k, long long v)
{
    key(j, k);
    fprintf(j->f, "%lld", v);
}

void json_str(json_out *j, const char *k, const char *v)
{
    key(j, k);
    fputc('"', j->f);
    for (; *v; v++) {
        if (*v == '"' || *v == '\\')
            fputc('\\', j->f);
        fputc(*v, j->f);
    }
    fputc('"', j->f);
}

void json_point(json_out *j, const char *k, const double p[3], const char *fmt)
{
    char buf[96];
    snprintf(buf, sizeof buf, fmt, p[0], p[1], p[2]);
    json_str(j, k, buf);
}

void json_bool(json_out *j, const char *k, int v)
{
    key(j, k);
    fputs(v ? "true" : "false", j->f);
}

void json_array_begin(json_out *j, const char *k)
{
    key(j, k);
    fputs("[\n", j->f);
    j->outer_n = j->n;
    j->items = 0;
}

void json_object_begin(json_out *j)
{
    fputs(j->items++ ? ",\n    {" : "    {", j->f);
    j->n = 0;
}

void json_object_end(json_out *j)
{
    fputs(" }", j->f);
}

void json_array_end(json_out *j)
{
    fputs("\n  ]", j->f);
    j->n = j->outer_n;
}

void json_close(json_out *j)
{
    if (!j->f)
        return;
    fputs("\n}\n", j->f);
    fclose(j->f);
    j->f = NULL;
}

int scenario_gnuplot(const char *dir, const char *script)
{
    char cmd[2048];
    const char *off = getenv("TANDEM_NO_PLOTS");
    int rc;
    if (off && *off && strcmp(off, "0") != 0) {
        fprintf(stderr, "tandem-scenario: TANDEM_NO_PLOTS: CSV written, PNG plots skipped\n");
        return 0; /* a fleet's benchmark: the run's CPU, not the drawing's */
    }
    /* NOLINTNEXTLINE(cert-env33-c): asks the shell whether gnuplot is installed */
    if (system("command -v gnuplot >/dev/null 2>&1") != 0) {
        fprintf(stderr, "tandem-scenario: gnuplot not found; CSV written, PNG plots skipped\n");
        return 0;
    }
    snprintf(cmd, sizeof cmd, "cd '%s' && gnuplot '%s'", dir, script);
    /* NOLINTNEXTLINE(cert-env33-c): gnuplot on the scenario's own script in its --out directory */
    rc = system(cmd);
    if (rc != 0)
        fprintf(stderr, "tandem-scenario: gnuplot %s failed (%d)\n", script, rc);
    return rc == 0 ? SCENARIO_OK : SCENARIO_ERR_IO;
}

double scenario_wall_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int scenario_parse_drop(scenario_drop *d, const char *v, long seed)
{
    char *e;
    const double p = strtod(v, &e);
    if (e == v || *e || !(p >= 0.0 && p < 1.0)) {
        fprintf(stderr, "tandem-scenario: --drop-rate: '%s' is not a probability in [0, 1)\n", v);
        return SCENARIO_ERR_ARG;
    }
    snprintf(d->rate, sizeof d->rate, "%s", p > 0.0 ? v : "");
    snprintf(d->seed, sizeof d->seed, "%ld", seed);
    return 0;
}

void scenario_argv_drop(const scenario_drop *d, char **argv, int *n, int cap)
{
    if (d->rate[0] && *n + 4 < cap) {
        argv[(*n)++] = "--drop-rate";
        argv[(*n)++] = (char *)d->rate;
        argv[(*n)++] = "--drop-seed";
        argv[(*n)++] = (char *)d->seed;
    }
    argv[*n < cap ? *n : cap - 1] = NULL;
}

int scenario_parse_fault(scenario_fault *f, const char *v)
{
    const char *name = v + 5, *colon = strchr(name, ':');
    char *e;
    memset(f, 0, sizeof *f);
    f->restart_s = -1.0;
    if (strncmp(v, "kill:", 5) != 0 || !colon || colon == name ||
        (size_t)(colon - name) >= sizeof f->daemon)
        goto bad;
    memcpy(f->daemon, name, (size_t)(colon - name));
    f->kill_s = strtod(colon + 1, &e);
    if (e == colon + 1 || !isfinite(f->kill_s) || f->kill_s < 0.0)
        goto bad;
    if (*e == ':') {
        const char *r = e + 1;
        f->restart_s = strtod(r, &e);
        if (e == r || !isfinite(f->restart_s) || f->restart_s <= f->kill_s)
            goto bad;
    }
    if (*e)
        goto bad;
    return 0;
bad:
    fprintf(stderr,
            "tandem-scenario: --fault: '%s' is not kill:DAEMON:T[:RESTART_T] (RESTART_T > T)\n", v);
    return SCENARIO_ERR_ARG;
}
