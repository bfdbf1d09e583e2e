/* harness: tandem daemons on a private LCM bus for the integration tests:
 * proc.h starts and stops them, this adds the bus and lockstep helpers. */
#ifndef TANDEM_HARNESS_H
#define TANDEM_HARNESS_H

#include <stdint.h>
#include <sys/types.h>
#include <lcm/lcm.h>
#include "auth_bus.h"
#include "proc.h"

/* The last health message of one daemon: what the secure bus refused. */
#define HARNESS_MAX_HEALTH 16
typedef struct harness_health {
    char name[64];
    int pid, auth_on;
    int64_t refused[AUTH_BUS_KINDS]; /* auth_bus_health_refusals */
    int64_t msgs_rejected, msgs_lost;
} harness_health;

typedef struct harness {
    char url[96];
    lcm_t *lcm;
    auth_bus bus;   /* the test's side of the secure bus: it signs as each
                                channel's owner (auth_bus_sign_as_owner) */
    proc_set procs; /* the daemons under test (src/daemons/common/proc.h) */
    harness_health health[HARNESS_MAX_HEALTH]; /* harness_watch_health */
    int n_health;
} harness;

/* Private udpm port per test process so parallel tests never cross-talk.
 * The first call also makes a bus key for this test alone
 * (auth_bus_ephemeral_key: the daemons it starts inherit it through
 * $TANDEM_KEY_FILE); every call starts h->bus on it, signing every message
 * as its channel's owner, as the daemons it stands in for would. h stays
 * where it is until harness_close (subscriptions point into h->bus). */
int harness_open(harness *h, int port_offset);
/* argv[0] is a program name under build/bin (e.g. "tandem-sim"); NULL-terminated.
 * stdout of the child is captured (read with harness_read_output). */
pid_t harness_spawn(harness *h, const char *const argv[]);
/* Children started otherwise (fork) that must not outlive the test: killed
 * at exit if still running (harness_spawn does this for its own). */
void harness_track_child(pid_t pid);
/* Waits for the child to exit within timeout_s; returns its exit status or -1. */
int harness_wait(harness *h, pid_t pid, double timeout_s);
/* Reads all captured stdout of child pid into buf (NUL terminated). */
int harness_read_output(harness *h, pid_t pid, char *buf, int cap);
void harness_kill_all(harness *h);
void harness_close(harness *h);
/* Handle LCM messages for ms milliseconds. */
void harness_pump(harness *h, int ms);

/* Moves this test (and the daemons it will start) into a network namespace
 * of its own, so nothing else on the machine shares its bus (needs root or
 * CAP_SYS_ADMIN and iproute2; returns -1 and leaves things as they are
 * otherwise, or when TANDEM_SHARED_NET is set). Call first in main(). */
int harness_private_net(void);

/* One action row of a single joint move to q on ARMk_ACTION. */
void harness_send_joint_row(harness *h, int arm, int action_id, const double q[6]);

/* Keeps every daemon's last health (checked: auth_bus_subscribe) in
 * h->health; harness_health_of finds one by name (a zeroed entry if none
 * came yet). */
void harness_watch_health(harness *h);
harness_health harness_health_of(harness *h, const char *name);
int64_t harness_refused(const harness_health *d);
/* One line: the daemon's refusals by kind and its loss. */
void harness_print_refused(const harness_health *d);

/* system() of a printf-formatted command line. */
int harness_sh(const char *fmt, ...);

/* Lockstep participation for a test: answer step k on SIM_ACK. */
void harness_ack(harness *h, const char *name, int64_t step, int32_t period_steps);

/* A file's text into buf (NUL terminated); its length or -1. */
int harness_slurp(const char *path, char *buf, int cap);
/* The number under "key" in a summary.json text (true 1, false 0); NaN
 * if absent or null. */
double harness_json_value(const char *text, const char *key);
/* The child of `parent` running program `prog` (its argv[0]'s last part,
 * read from /proc) and, with opt not NULL, with the arguments opt value
 * (e.g. "--id", "2"); -1 when there is none. */
pid_t harness_child_named(pid_t parent, const char *prog, const char *opt, const char *value);
/* Runs a program (argv[0] under the build's bin) to its end, at most
 * timeout_s; its exit status, or -1 if it had to be killed. */
int harness_run(const char *const argv[], double timeout_s);
/* The same, with what it printed into buf (NUL terminated; buf NULL: not kept). */
int harness_run_output(const char *const argv[], double timeout_s, char *buf, int cap);

#endif
