/* renew: a daemon's LCM handle renewed beside its control thread
 * (docs/security.md §5).
 *
 * LCM keeps every channel name it sees, so a daemon bounds that table by
 * opening a new handle when a flood of names has grown it (daemon.h,
 * names_watch) and closing the old one. Closing a handle that has seen a
 * flood frees every name it saw: 65-145 ms for some 250,000 names,
 * measured under tools/flood-names.sh; opening one with its subscriptions
 * (a socket, a receive thread, a pattern per channel) takes 0.3-1.5 ms.
 * Either is longer than a 1 ms cycle. So a worker thread of normal
 * priority opens the new handle and subscribes it (renew_request), and
 * closes the old one and gives its memory back to the system
 * (renew_retire); the control thread only swaps the two (renew_take,
 * then rx_commit_subscriptions) and hands what the old one still holds
 * on, within its drain budget. The control thread never waits for the
 * worker: it takes their lock with trylock and tries again next cycle
 * when the worker holds it (a worker of normal priority holding a lock a
 * SCHED_FIFO thread waits for is priority inversion).
 *
 * Ownership: a request's channel copies belong to the worker from
 * renew_request until renew_take; the new handle and its staged
 * subscriptions belong to the control thread from renew_take; a retired
 * handle belongs to the worker from renew_retire.
 */
#ifndef TANDEM_RENEW_H
#define TANDEM_RENEW_H

#include <pthread.h>
#include <stdint.h>
#include <lcm/lcm.h>
#include "rx.h"

/* The worker's stack: lcm_create, lcm_subscribe and lcm_destroy only.
 * Small because an mlockall'd daemon keeps all of it resident. */
#define RENEW_STACK_BYTES (256 * 1024)

#define RENEW_OK 0
#define RENEW_ERR_THREAD (-1) /* renew_start: the worker thread does not start */

typedef struct lcm_renewer {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    pthread_t thread;
    int started; /* the worker runs (renew_start succeeded) */
    int stop;    /* renew_stop: the worker ends */
    const char *url;
    int capacity; /* queue capacity of each staged subscription */
    /* the request: control thread -> worker */
    int requested, busy; /* asked for; the worker is making one or closing one */
    int n_req;
    char channel[RX_MAX_SUBS][RX_CHANNEL_NAME];
    rx_sub *sub[RX_MAX_SUBS]; /* NULL: not on the current handle */
    /* the result: worker -> control thread */
    int ready;
    lcm_t *fresh;
    lcm_subscription_t *staged[RX_MAX_SUBS];
    int64_t failures; /* new handles that did not open */
    /* the old handle: control thread -> worker */
    lcm_t *retired;
    lcm_t *to_retire; /* the control thread's, until the lock is free */
    int64_t closed;   /* old handles the worker closed */
} lcm_renewer;

/* Starts the worker for handles at url with queues of capacity messages
 * per subscription. RENEW_OK, or RENEW_ERR_THREAD (r is then not started:
 * a caller renews on its own thread, lcm_renew in daemon.h). */
int renew_start(lcm_renewer *r, const char *url, int capacity);
/* Control thread: asks for a new handle subscribed as every subscription
 * of rx on current. 1 when asked; 0 when a renewal is already under way
 * (asked, being made, made and not taken, or an old handle not closed
 * yet), or when the worker holds the lock now. */
int renew_request(lcm_renewer *r, rx_state *rx, const lcm_t *current);
/* Control thread: 1 when a new handle is made, with *fresh and *staged
 * (subscription i of the request's snapshot, r->n_req of them) the
 * caller's now; else 0. Also hands a retired handle left waiting on. */
int renew_take(lcm_renewer *r, lcm_t **fresh, lcm_subscription_t *const **staged, int *n_staged);
/* Control thread: the worker closes old (now, or after a later
 * renew_take when the lock is busy) and trims the heap. */
void renew_retire(lcm_renewer *r, lcm_t *old);
/* Ends the worker (waits for what it is doing) and closes every handle it
 * holds or made. r is not started afterwards. */
void renew_stop(lcm_renewer *r);
/* How many new handles did not open so far. Takes the lock. */
int64_t renew_failures(lcm_renewer *r);
/* 1 while a renewal is under way (renew_request would return 0):
 * for tests. Takes the lock. */
int renew_pending(lcm_renewer *r);

#endif
