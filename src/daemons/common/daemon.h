/* daemon: the thin shell every tandem daemon shares (docs/method/lockstep.md §1-3, §6-7).
 *
 * The common options' values (options_daemon_common in options.h fills
 * them), signals, optional SCHED_FIFO + mlockall, the LCM handle, the loop
 * driver for both timing modes (real time on rtloop; lockstep on the
 * simulator's SIM_CLOCK with an ack per answered step), and the
 * once-a-second health message.
 * Daemon-specific work lives in a cycle callback that calls the core.
 */
#ifndef TANDEM_DAEMON_H
#define TANDEM_DAEMON_H

#include <stdint.h>
#include <lcm/lcm.h>
#include "linalg.h"
#include "rtloop.h"
#include "auth_bus.h"
#include "guard.h"
#include "renew.h"
#include "rx.h"
#include "version.h"

#define DAEMON_DEFAULT_LCM_URL "udpm://239.255.76.67:7667?ttl=0"
#define DAEMON_SIM_DT_S 0.001 /* the simulator's fixed step */
#define DAEMON_NAME_MAX 64
/* Messages LCM keeps per subscription until the daemon handles them. LCM
 * keeps a fragmented message (over 1400 bytes) in memory of its own, so
 * this bounds what a flood of large forgeries can make a daemon hold
 * (docs/security.md, "Flooding"): 256 x 64 kB per subscription at worst.
 * It still takes a burst of a whole team's messages (TEAM, SIM_ACK: one
 * per robot and step, 128 robots at most) twice over. A daemon that
 * takes a larger burst (a fleet's TEAM messages on one host, a fleet's
 * commands at the simulator) sets its own before daemon_start
 * (daemon_queue_for_burst). */
#define DAEMON_QUEUE_CAPACITY 256
/* Lockstep: a daemon's outputs are published again (repeat_fn) at most
 * once in this long; the ack goes out every time. A host of a fleet
 * republishes hundreds of messages: a burst of announcements must not
 * make it a burst of bursts. */
#define DAEMON_REPEAT_GAP_NS 20000000LL
#define DAEMON_SIM_SILENT_NS 5000000000LL /* lockstep: no clock this long = no simulator */
/* LCM keeps every channel name it sees, subscribed or not, for good
 * (docs/security.md §5): a flood of made-up names grows every process on
 * the bus without end. The shell bounds it (names_watch below): when a
 * program's resident memory is this much above what it was after
 * start-up (or after the last renewal), it opens a new LCM handle,
 * subscribes it as the old one was, hands on what the old one still
 * holds and closes it, whose table of names goes with it. A daemon is a
 * few MB and allocates nothing after start-up, so 16 MB is taken by a
 * flood alone (at 50,000 names/s, after some 8 s). */
#define DAEMON_NAMES_SLACK_KB (16L * 1024L)
/* The slack in kB instead (DAEMON_NAMES_SLACK_MIN_KB..MAX_KB), for tests
 * that want renewals from a small flood (it_lockstep). */
#define DAEMON_NAMES_SLACK_ENV "TANDEM_NAMES_SLACK_KB"
#define DAEMON_NAMES_SLACK_MIN_KB 256L
#define DAEMON_NAMES_SLACK_MAX_KB (4L * 1024L * 1024L)
#define DAEMON_NAMES_CHECK_NS 100000000LL /* resident memory read at 10 Hz */
/* A process that takes a fleet's frames (the simulator, a rover host: every
 * ROVERS_* chunk of every robot reaches it) holds a fleet-sized burst of
 * them in LCM's and glib's buffers, and ODE's arena grows with the bodies
 * in contact: 10,000 robots grew the simulator by 28 MB and a host by
 * 16-18 MB in their first simulated second, each past the 16 MB slack,
 * and each renewal's new buffers set off the next (40 in 0.6 s). The
 * slack grows by this much a robot (80 MB more at 10,000, over 3x what
 * they grew), so a flood is still caught, later in proportion. */
#define DAEMON_NAMES_SLACK_ROBOT_KB 8L
/* The environment a launcher gives its daemons so that glib (2.74) frees
 * what it frees instead of keeping slices (daemon_defaults, docs/security.md §5). */
#define DAEMON_GLIB_SLICE_ENV "G_SLICE"
#define DAEMON_GLIB_SLICE_VALUE "always-malloc"

/* The bound on LCM's table of channel names of one program
 * (DAEMON_NAMES_SLACK_KB): the daemons' (daemon.names, daemon_names_watch)
 * and the tools' with their own handle (bus_names_watch). */
typedef struct names_watch {
    const char *who;  /* what it says on stderr is said as this */
    long slack_kb;    /* DAEMON_NAMES_SLACK_KB, or $TANDEM_NAMES_SLACK_KB */
    long base_kb;     /* resident memory the renewal counts from, 0 unset */
    int64_t check_ns; /* last time it was read */
    int64_t renewals; /* LCM handles renewed (a flood of names) */
} names_watch;

typedef struct daemon_counters {
    int64_t received;
    int64_t rejected;  /* failed decoding or validation: dropped */
    int64_t stale;     /* valid but too old to use */
    int64_t duplicate; /* a copy of a message already taken (lockstep
                           re-announcement): ignored, changes nothing */
} daemon_counters;

typedef struct daemon {
    char name[DAEMON_NAME_MAX]; /* e.g. tandem-arm-1 */
    char health_channel[DAEMON_NAME_MAX + 8];
    const char *lcm_url;
    int rt_prio;        /* 0 = normal scheduling */
    int dma_latency_fd; /* /dev/cpu_dma_latency, held open while we run (-1: none) */
    int heartbeat_fd;   /* $TANDEM_HEARTBEAT_DIR/PID, touched once a second (-1: none) */
    int lockstep;
    double period_s;
    int32_t period_steps; /* lockstep: answer every n-th step */
    lcm_t *lcm;
    rtloop loop;
    daemon_counters msgs;
    int64_t step; /* last SIM_CLOCK step seen */
    double sim_time_s;
    int64_t pending_step; /* lockstep: step to answer, -1 none */
    int queue_capacity;   /* messages LCM keeps per subscription (DAEMON_QUEUE_CAPACITY) */
    int64_t health_seq;
    int64_t ack_seq;
    int64_t last_health_ns;
    int safe_hold;
    int clock_source; /* 1 for tandem-sim: it publishes SIM_CLOCK,
                                           so it does not listen to it */
    int skip_ack;     /* lockstep: set by a cycle whose inputs
                                           have not arrived yet (no answer, so the
                                           simulator does not count on it yet) */
    char status[96];
    step_gate clock_gate;  /* SIM_CLOCK steps (guard.h) */
    int64_t answered_step; /* lockstep: last step acked, -1 none */
    /* lockstep: called when the simulator announces again a step this
     * daemon has already answered (its ack, or one of its outputs, was
     * lost on the way): publish the last outputs again, then the ack goes
     * out again; also while a cycle waits for a missing input (a mate
     * may be waiting for ours). NULL: only the ack is repeated. */
    void (*repeat_fn)(struct daemon *d, void *user);
    int64_t repeat_ns;   /* wall time repeat_fn last ran (DAEMON_REPEAT_GAP_NS) */
    int64_t repeats;     /* lockstep: steps answered again */
    int64_t clock_rx_ns; /* wall time of the last SIM_CLOCK (0 none) */
    int64_t input_waits; /* lockstep: announcements not answered
                                           yet because an input was missing */
    double drop_rate;    /* --drop-rate: fault injection (rx.h), 0 none */
    long drop_seed;      /* --drop-seed: seed of the drops, 1 by default */
    rx_state rx;         /* the receive path's tables and counts (rx.h) */
    auth_bus bus;        /* this daemon's side of the secure bus (auth_bus.h):
                            its identity, keys, counts, publish buffer */
    names_watch names;   /* the bound on LCM's table of channel names */
    int fleet_robots;    /* robots whose frames reach this process (names_watch_fleet):
                            set before daemon_start, 0: none */
    lcm_renewer renew;   /* its renewals, made beside the loop (renew.h) */
} daemon;

/* Cycle callback: read the latest inputs, call the core, publish outputs;
 * user is the daemon's own state (given to daemon_run). Returns
 * DAEMON_CONTINUE, or a status that ends daemon_run, which returns it
 * (the process's exit code). */
typedef int (*daemon_cycle_fn)(daemon *d, void *user);

/* Status codes of daemon_check_table, daemon_start and the option parsers
 * below (each has printed why on stderr). */
#define DAEMON_OK 0
#define DAEMON_ERR_NUMBER (-1) /* parse_*_opt: not a finite number / not an integer */
#define DAEMON_ERR_RANGE \
    (-2)                      /* parse_*_opt: outside [lo, hi]; daemon_start: period
                                   outside rtloop's range */
#define DAEMON_ERR_TABLE (-3) /* daemon_check_table: the validator refused the table */
#define DAEMON_ERR_AUTH (-4)  /* daemon_start: auth_bus_start refused (no key, ...) */
#define DAEMON_ERR_LCM \
    (-5) /* daemon_start: LCM does not open at the URL;
                                   daemon_renew_lcm: a new handle does not open
                                   (the old one is kept) */

#define DAEMON_CONTINUE 0    /* cycle: go on */
#define DAEMON_STOPPED 0     /* daemon_run: stopped by SIGINT/SIGTERM (exit 0) */
#define DAEMON_STOP_FAILED 1 /* cycle: stop, the daemon cannot go on (exit 1) */

/* Before daemon_start: LCM keeps twice `burst` messages per subscription
 * (a burst of one message per robot of what this daemon hears in a
 * step), never fewer than DAEMON_QUEUE_CAPACITY. */
void daemon_queue_for_burst(daemon *d, long burst);

void daemon_defaults(daemon *d, const char *name, double period_s);
/* Start-up check of one constant table: rc is what its validator returned
 * (0, or the module's negative *_ERR_* code), strerror_fn the module's
 * text of it (petri_strerror, ...). 0 when rc is 0; else prints
 * "PROG: TABLE is invalid (VALIDATOR: TEXT, RC)" on stderr and returns
 * DAEMON_ERR_TABLE (the daemon then exits 1 without running). */
int daemon_check_table(const char *prog, const char *table, const char *validator, int rc,
                       const char *(*strerror_fn)(int));
/* Loads the bus key (auth_bus_start on d->bus; the daemon has set its
 * identity with auth_bus_identity), hands --drop-rate / --drop-seed to the receive path
 * (rx_set_drop), opens LCM, installs SIGINT/SIGTERM handlers,
 * applies --rt. DAEMON_OK, or DAEMON_ERR_AUTH / _LCM / _RANGE (said). */
int daemon_start(daemon *d);
/* Minimal timer slack always (Linux); with prio > 0 also SCHED_FIFO at
 * prio, mlockall and the CPU latency hint; warns and goes on when not
 * permitted. *dma_latency_fd holds the latency hint's file, which must
 * stay open for the hint to hold: -1 before the first call, opened once. */
void daemon_rt_setup(const char *name, int prio, int *dma_latency_fd);
/* Runs the cycle until SIGINT/SIGTERM (returns DAEMON_STOPPED) or until
 * the cycle returns a status other than DAEMON_CONTINUE (returns that
 * status): the process exit code. */
int daemon_run(daemon *d, daemon_cycle_fn fn, void *user);
void daemon_finish(daemon *d);
int daemon_stop_requested(void);
void daemon_request_stop(void);
/* Publishes the health message now (daemon_run does it once a second). */
void daemon_publish_health(daemon *d);
/* lcm_subscribe through the receive path (rx.h) with a queue of
 * DAEMON_QUEUE_CAPACITY messages. */
lcm_subscription_t *daemon_subscribe(daemon *d, const char *channel, lcm_msg_handler_t handler,
                                     void *user);
/* Subscribes handler to PREFIX<k>SUFFIX for k = first..last, each by its
 * name, or, for more than DAEMON_EXPLICIT_MAX of them, to the one pattern
 * PREFIX[0-9]+SUFFIX. By name, a made-up channel (ROVER99999_SENSORS)
 * reaches no handler; but LCM matches every channel name it has not seen
 * before against every subscription (docs/security.md), so a large team
 * keeps the pattern. Up to cap subscriptions go into subs; returns how
 * many were made. */
#define DAEMON_EXPLICIT_MAX 8
int daemon_subscribe_numbered(daemon *d, const char *prefix, int first, int last,
                              const char *suffix, lcm_msg_handler_t handler, void *user,
                              lcm_subscription_t **subs, int cap);
/* Answers lockstep step `step` for participant `name` on SIM_ACK (the
 * first answer registers it with its period; leaving = 1 unregisters).
 * Daemons do this in daemon_run; scenarios and tests call it directly. */
/* Moves every subscription made on the handle old onto fresh, each with
 * its queue capacity, and returns how many: the receive path's
 * (rx_move_subscriptions, the daemons) or auth_bus's (auth_bus_move,
 * the tools). subs is its table. */
typedef int (*lcm_move_fn)(void *subs, lcm_t *old, lcm_t *fresh);
/* A new LCM handle at url in place of *lcm, with the same subscriptions
 * (move). The new one is subscribed before the old one is read for the
 * last time, so nothing that arrives meanwhile is lost (a datagram that
 * reaches both in that moment is handed on twice: a copy, as lockstep's
 * re-announcements make); what the old one still holds is handed on (at
 * most DAEMON_DRAIN_MAX messages, budget_ns) and then it is closed, its
 * table of channel names (LCM's, never emptied) with it. DAEMON_OK, or
 * DAEMON_ERR_LCM (nothing changed). */
int lcm_renew(lcm_t **lcm, const char *url, lcm_move_fn move, void *subs, int64_t budget_ns);
/* The first call of a tool's main (a daemon gets it from its launcher):
 * a program whose environment does not set G_SLICE=always-malloc is run
 * again (execv of /proc/self/exe with the same argv) with it, since glib
 * reads it only as it loads. Returns only when it is set, or when the
 * program cannot be run again. */
void names_watch_env(char **argv);
/* Before any thread starts (LCM's receive thread): malloc with one arena,
 * so that what a renewed handle frees goes back to the system; and w for
 * who, with its slack (DAEMON_NAMES_SLACK_ENV, said on stderr when it is
 * set but not a number of kB in range: then the default). A program
 * whose glib keeps freed slices (G_SLICE not always-malloc,
 * DAEMON_GLIB_SLICE_ENV) is told so on stderr. */
void names_watch_init(names_watch *w, const char *who);
/* The slack of a process that takes the frames of `robots` robots:
 * DAEMON_NAMES_SLACK_KB + robots DAEMON_NAMES_SLACK_ROBOT_KB, unless
 * DAEMON_NAMES_SLACK_ENV set it. */
void names_watch_fleet(names_watch *w, int robots);
/* At most every DAEMON_NAMES_CHECK_NS (now: rtloop_now_ns()): reads the
 * resident memory, renews *lcm (lcm_renew) once it is
 * DAEMON_NAMES_SLACK_KB above w's base, and says so on stderr. 1 when
 * renewed, else 0. */
int names_watch_tick(names_watch *w, int64_t now, lcm_t **lcm, const char *url, lcm_move_fn move,
                     void *subs, int64_t budget_ns);
/* The daemon's, called every cycle: the same bound, but the new handle is
 * made and the old one closed by a worker thread (renew.h), so a cycle
 * only swaps them (and hands on what the old one holds, within the drain
 * budget); on its own thread (names_watch_tick) when the worker did not
 * start. daemon_run calls it in its health tick; a program with a loop
 * of its own (tandem-sim) calls it where a renewal is harmless. 1 when
 * the handle was renewed. */
int daemon_names_watch(daemon *d);
/* daemon_names_watch's renewal, now: by the worker when it runs (waits
 * up to DAEMON_RENEW_WAIT_MS for it: for tests and tools, not a cycle),
 * else lcm_renew. DAEMON_OK, or DAEMON_ERR_LCM (a new handle does not
 * open, or not in time; the old one kept). */
#define DAEMON_RENEW_WAIT_MS 5000
int daemon_renew_lcm(daemon *d);
/* A tool's, with its own handle *lcm and checked subscriptions
 * (auth_bus_subscribe): names_watch_tick with auth_bus_move. Call it in
 * the tool's loop; *lcm may change (1 when it did). */
int bus_names_watch(names_watch *w, auth_bus *bus, lcm_t **lcm, const char *url);

void lockstep_ack(auth_bus *bus, lcm_t *lcm, const char *name, int64_t seq, int64_t step,
                  int32_t period_steps, int leaving);
/* A launcher's liveness check that no bus can fool: with
 * DAEMON_HEARTBEAT_ENV naming a directory, daemon_start opens DIR/PID
 * (daemon_heartbeat_open) and every health tick sets its modification
 * time, once a second from the loop (daemon_health_tick). A daemon
 * stopped (SIGSTOP), spinning in a cycle or blocked stops touching it; a
 * flood that drops its health messages on the bus does not
 * (tools/tandem-run --hang-s). No directory: no file (a daemon started by
 * hand); a file that cannot be opened is said on stderr. */
#define DAEMON_HEARTBEAT_ENV "TANDEM_HEARTBEAT_DIR"
void daemon_heartbeat_open(daemon *d);
/* Once a second (now_ns from rtloop_now_ns): the health message and the
 * heartbeat file. Every loop calls it, the simulator's included. */
void daemon_health_tick(daemon *d, int64_t now_ns);

/* Handles the LCM messages already queued, without blocking, for at most
 * DAEMON_DRAIN_MAX messages and a quarter of the period
 * (daemon_drain_budget_ns): a flood, even of messages refused at once,
 * cannot take the cycle's time. What is left waits for the next cycle;
 * such a drain is counted in rx.deferred (health rx_deferred). */
#define DAEMON_DRAIN_MAX 4096
void daemon_drain(daemon *d);
int64_t daemon_drain_budget_ns(const daemon *d);
/* Seconds between wall-clock now and a message's utime, for staleness. */
int64_t daemon_utime_now(void);

/* Decodes an LCM receive buffer into *msg, counting it as received and,
 * when it does not decode (wrong fingerprint, truncated), as rejected.
 * 1 on success (then call TYPE_decode_cleanup), 0 if dropped. */
#define DAEMON_DECODE(counters, type, rb, msg) \
    ((counters)->received++,                   \
     type##_decode((rb)->data, 0, (rb)->data_size, (msg)) >= 0 ? 1 : ((counters)->rejected++, 0))

/* The common head of the rovers_*_t batch messages (several robots' frames
 * of one tick in one message). */
#define BATCH_HEADER(b, seq_, utime_, step_, n_) \
    ((b).seq = (seq_), (b).utime = (utime_), (b).step = (step_), (b).n = (int16_t)(n_))
/* Strict number parsing for command-line values: the whole string must be
 * a finite number inside [lo, hi]; prints "NAME: --OPT: why" and returns
 * DAEMON_ERR_NUMBER or DAEMON_ERR_RANGE otherwise. */
int parse_double_opt(const char *prog, const char *opt, const char *s, double lo, double hi,
                     double *out);
int parse_int_opt(const char *prog, const char *opt, const char *s, long lo, long hi, long *out);

#endif
