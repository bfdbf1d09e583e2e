/* proc: start tandem programs as child processes and stop them again
 * (shared by tandem-scenario and the integration tests). */
#ifndef TANDEM_PROC_H
#define TANDEM_PROC_H

#include <sys/types.h>
#include "auth_child.h"

#define PROC_MAX 16

/* Failures of proc_spawn (as a pid) and proc_poll. */
#define PROC_ERR_SYS (-1)     /* pipe or fork failed: errno says why */
#define PROC_ERR_FULL (-3)    /* PROC_MAX children already, or no argv[0] */
#define PROC_ERR_UNKNOWN (-4) /* proc_poll: not a child of this set */
#define PROC_ERR_KEY (-2)     /* proc_spawn: the child's role file cannot be made (said) */

typedef struct proc_set {
    char bin[256]; /* directory of the programs */
    pid_t pid[PROC_MAX];
    int alive[PROC_MAX];  /* 0 once reaped (its output stays readable) */
    int out_fd[PROC_MAX]; /* read end of the stdout pipe, -1 if none */
    int status[PROC_MAX]; /* exit status once reaped */
    int n;
    auth_child_keys keys; /* the children's role files (auth_child.h) */
} proc_set;

/* bin_dir NULL: $TANDEM_BIN, else the running program's own directory;
 * bus: this process's, whose roster the children's role files list (NULL:
 * the default roster; auth_child.h). */
void proc_init(proc_set *p, const struct auth_bus *bus, const char *bin_dir);
/* In a child before it execs, with the pid of the parent that forked it:
 * the child gets SIGTERM when that parent dies (Linux's parent-death
 * signal; elsewhere nothing), so a launcher killed outright (a test's
 * timeout, SIGKILL) leaves no daemons running on without it; a child whose
 * parent is already gone exits. */
void proc_die_with_parent(pid_t parent);
/* argv[0] is a program name under bin (NULL-terminated argv). The child
 * gets LCM_DEFAULT_URL = lcm_url (if not NULL) and, when this process
 * holds the cell's master, the role file of the principal argv names in
 * $TANDEM_KEY_FILE (auth_child.h), never the master itself. stdout goes to out_path
 * (created/truncated) or, if out_path is NULL, to a pipe (proc_read).
 * stderr is appended to err_path if not NULL (else inherited).
 * Returns the pid, or PROC_ERR_FULL or PROC_ERR_SYS. */
pid_t proc_spawn(proc_set *p, const char *const argv[], const char *lcm_url, const char *out_path,
                 const char *err_path);
/* Non-blocking reap: 1 if pid has exited (status in *status), 0 if it
 * runs, PROC_ERR_UNKNOWN. */
int proc_poll(proc_set *p, pid_t pid, int *status);
/* Reads whatever the child wrote to its stdout pipe (NUL terminated). */
int proc_read(proc_set *p, pid_t pid, char *buf, int cap);
/* SIGKILL to one child (a fault injected on purpose), reaped at once. */
void proc_kill(proc_set *p, pid_t pid);
/* SIGTERM to every child, SIGKILL after grace_s; closes the pipes and
 * removes the children's role files. */
void proc_kill_all(proc_set *p, double grace_s);
/* mkdir -p DIR (mode 0755); 0, or PROC_ERR_SYS with errno set. */
int proc_mkdir_p(const char *dir);

#endif
