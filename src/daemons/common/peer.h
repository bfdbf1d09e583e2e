/* peer: is another process on the bus alive, only slow, or dead
 * (docs/method/lockstep.md §3, "alive, slow or dead"). In lockstep a
 * participant that does not answer is waited for while its process is
 * alive; wall-clock silence decides only for one that died or hangs. The
 * process is looked up by the pid its SIM_ACK carries (lockstep runs
 * every participant on the simulator's host). Hanging is told from slow
 * by the CPU time the process had: one that was given the processor for a
 * good part of the timeout and said nothing is stuck; one that was not
 * given it (a loaded machine) is only slow.
 */
#ifndef TANDEM_PEER_H
#define TANDEM_PEER_H

#include <stdint.h>

/* What the operating system says about a process. */
typedef enum peer_proc {
    PEER_PROC_UNKNOWN = 0, /* no pid known, or it cannot be asked */
    PEER_PROC_GONE,        /* no such process, or a zombie: it will never answer */
    PEER_PROC_STOPPED,     /* stopped (SIGSTOP, a debugger): alive, resumes later */
    PEER_PROC_RUNNING      /* running, runnable or sleeping */
} peer_proc;

/* What is known of one peer: its pid (0: none yet) and when it was last
 * heard from (monotonic ns; an ack, a health message, 0: never). */
typedef struct peer_watch {
    int32_t pid;
    int64_t heard_ns;
    int64_t heard_cpu_ns; /* its CPU time (user + system) then, -1 unknown */
} peer_watch;

peer_proc peer_proc_of(int32_t pid);
/* The CPU time (user + system) the process has had, -1 if unknown. */
int64_t peer_cpu_ns(int32_t pid);
/* Something came from the peer at now_ns; pid > 0 replaces the known pid. */
void peer_heard(peer_watch *w, int32_t pid, int64_t now_ns);
/* 1 when the peer is taken as dead at now_ns: its process is gone; or
 * nothing was heard from it for more than silent_ns and either its process
 * is not known or it ran for more than a quarter of silent_ns of CPU time
 * meanwhile (hangs). A stopped process, and one starved of the processor,
 * is never dead: it is waited for. */
int peer_dead(const peer_watch *w, int64_t now_ns, int64_t silent_ns);

/* The robots a daemon's name says it hosts: 1 and *lo..*hi for
 * "tandem-rover-K" / "tandem-rover-A-B" (tandem-rover's name), 0 for
 * any other name. */
int peer_rover_range(const char *name, long *lo, long *hi);

#endif
