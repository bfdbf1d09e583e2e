/* hang_watch: hung children of a scenario run (carry, formation). A child
 * that is alive but has sent no health message (HEALTH_<NAME>, once a
 * second of wall time from every daemon, whatever the simulated clock
 * does) for hang_s of wall time is hung: a stopped or deadlocked process
 * holds the whole lockstep and would end the run only at its wall-time
 * limit. A slow child still sends health and is waited for; its lockstep
 * answers (SIM_ACK; the simulator's SIM_CLOCK) count as signs of life
 * too, so a health message lost on a busy bus is not taken for a hang. The scenario
 * kills a hung child (SIGKILL) and restarts it as a --fault restart does.
 * Wall time, not simulated time: a hung child stops the simulated clock.
 *
 * Silence alone does not make a child hung on a loaded machine: as the
 * lockstep tells slow from dead (src/daemons/common/peer.h), a silent child
 * whose process is known is hung when it is stopped (SIGSTOP, a debugger),
 * or ran for more than a quarter of hang_s of CPU time since it last spoke
 * (it runs and says nothing), or stayed silent HANG_WATCH_STARVED_X times
 * as long (asleep for good, or deadlocked). One that was not given the
 * processor is slow: killing it made a loaded run another run (a rover
 * restarted from its journal at t = 0.1 s, truth.csv not the idle run's).
 */
#ifndef TANDEM_HANG_WATCH_H
#define TANDEM_HANG_WATCH_H

#include <lcm/lcm.h>

struct auth_bus;

#define HANG_WATCH_MAX 24
#define HANG_WATCH_DEFAULT_S 5.0 /* five missed health messages */
/* A child just started has this much more to say its first word: a
 * loaded machine can take seconds to start a program. */
#define HANG_WATCH_START_S 10.0

/* A silent child given no CPU time is hung only after this many times
 * the limit (see above). */
#define HANG_WATCH_STARVED_X 6.0
/* Its CPU time is read at most this often, after it spoke. */
#define HANG_WATCH_CPU_EVERY_S 1.0

/* Failures of hang_watch_add (0 = ok). */
#define HANG_WATCH_ERR_FULL (-1) /* HANG_WATCH_MAX children watched already */
#define HANG_WATCH_ERR_NAME (-2) /* empty or too long a daemon name */

/* The scenario itself away (descheduled on a loaded machine) for longer
 * than this between two looks: the children's silence meanwhile is not
 * theirs, and is forgiven. */
#define HANG_WATCH_AWAY_S 0.5

typedef struct hang_watch {
    double hang_s;   /* 0: off */
    double looked_s; /* wall time of the last hang_watch_look, 0 none */
    int n;
    char name[HANG_WATCH_MAX][48];     /* the daemon's name (its health's name) */
    double last_s[HANG_WATCH_MAX];     /* wall time of its last health, or of its start */
    int on[HANG_WATCH_MAX];            /* 0 while the child is down on purpose */
    int spoken[HANG_WATCH_MAX];        /* heard since its start */
    int pid[HANG_WATCH_MAX];           /* its process, 0 unknown (silence alone decides) */
    long long cpu_ns[HANG_WATCH_MAX];  /* its CPU time soon after it last spoke, -1 unknown */
    double cpu_for_s[HANG_WATCH_MAX];  /* the last_s that cpu_ns was read for */
    double cpu_read_s[HANG_WATCH_MAX]; /* wall time of that read */
    int hung_restarts;                 /* hung children killed and restarted */
    int subscribed;                    /* to HEALTH_.* (auth_bus_subscribe) */
    struct auth_bus *bus;              /* the bus it subscribed on (hang_watch_subscribe) */
} hang_watch;

void hang_watch_init(hang_watch *w, double hang_s);
/* Watches daemon `name` from wall time now_s; its slot (>= 0), or
 * HANG_WATCH_ERR_FULL / HANG_WATCH_ERR_NAME. */
int hang_watch_add(hang_watch *w, const char *name, double now_s);
/* The child of slot k was (re)started at now_s (it has hang_s to speak),
 * or is down on purpose (on = 0: not watched until started again). */
void hang_watch_started(hang_watch *w, int k, double now_s);
void hang_watch_down(hang_watch *w, int k);
/* The child of slot k is process pid (at its start and each restart). */
void hang_watch_pid(hang_watch *w, int k, int pid);
/* A health message (or another sign of life) from daemon `name` at wall
 * time now_s. */
void hang_watch_heard(hang_watch *w, const char *name, double now_s);
/* Before judging at now_s: 1 when every message that arrived on lcm has
 * been read (a scenario behind its bus would take the unread for silence),
 * and a gap since the last look longer than HANG_WATCH_AWAY_S forgiven. */
int hang_watch_look(hang_watch *w, lcm_t *lcm, double now_s);
/* 1 when the child of slot k is watched and silent for hang_s at now_s. */
int hang_watch_hung(const hang_watch *w, int k, double now_s);
/* Seconds the child of slot k has been silent at now_s. */
double hang_watch_silent_s(const hang_watch *w, int k, double now_s);
/* Subscribes to every HEALTH_ channel (checked: auth_bus_subscribe);
 * hang_watch_stop unsubscribes. */
void hang_watch_subscribe(hang_watch *w, struct auth_bus *bus, lcm_t *lcm);
void hang_watch_stop(hang_watch *w, lcm_t *lcm);
const char *hang_watch_strerror(int err);

#endif
