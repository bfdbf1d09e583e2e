/* renew: a daemon's LCM handle renewed beside its control thread (see renew.h). */
#include "renew.h"
#include <malloc.h>
#include <string.h>

/* Worker: a new handle subscribed as the request's snapshot. The
 * snapshot is the worker's while busy (renew_request asks only when it is
 * not), so it is read without the lock. */
static void make_fresh(lcm_renewer *r)
{
    lcm_t *fresh = lcm_create(r->url);
    int i;
    for (i = 0; fresh && i < r->n_req; i++)
        r->staged[i] = r->sub[i] ? rx_stage(fresh, r->channel[i], r->sub[i], r->capacity) : NULL;
    pthread_mutex_lock(&r->mu);
    r->busy = 0;
    if (fresh) {
        r->fresh = fresh;
        r->ready = 1;
    } else {
        r->failures++;
    }
    pthread_mutex_unlock(&r->mu);
}

/* Worker: closes an old handle, LCM's table of names with it, and gives
 * the freed memory back to the system (daemon.h, names_watch_init). */
static void close_old(lcm_renewer *r, lcm_t *old)
{
    lcm_destroy(old);
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    pthread_mutex_lock(&r->mu);
    r->busy = 0;
    r->closed++;
    pthread_mutex_unlock(&r->mu);
}

static void *worker(void *arg)
{
    lcm_renewer *r = arg;
    pthread_mutex_lock(&r->mu);
    while (!r->stop) {
        if (r->retired) {
            lcm_t *old = r->retired;
            r->retired = NULL;
            r->busy = 1;
            pthread_mutex_unlock(&r->mu);
            close_old(r, old);
            pthread_mutex_lock(&r->mu);
        } else if (r->requested) {
            r->requested = 0;
            r->busy = 1;
            pthread_mutex_unlock(&r->mu);
            make_fresh(r);
            pthread_mutex_lock(&r->mu);
        } else {
            pthread_cond_wait(&r->cv, &r->mu);
        }
    }
    pthread_mutex_unlock(&r->mu);
    return NULL;
}

int renew_start(lcm_renewer *r, const char *url, int capacity)
{
    pthread_attr_t attr;
    struct sched_param normal;
    int rc;
    memset(r, 0, sizeof *r);
    r->url = url;
    r->capacity = capacity;
    if (pthread_mutex_init(&r->mu, NULL) != 0)
        return RENEW_ERR_THREAD;
    if (pthread_cond_init(&r->cv, NULL) != 0) {
        pthread_mutex_destroy(&r->mu);
        return RENEW_ERR_THREAD;
    }
    /* normal priority whatever the daemon's: it must never take the CPU
     * from a SCHED_FIFO control thread */
    memset(&normal, 0, sizeof normal);
    pthread_attr_init(&attr);
    pthread_attr_setinheritsched(&attr, PTHREAD_EXPLICIT_SCHED);
    pthread_attr_setschedpolicy(&attr, SCHED_OTHER);
    pthread_attr_setschedparam(&attr, &normal);
    pthread_attr_setstacksize(&attr, RENEW_STACK_BYTES);
    rc = pthread_create(&r->thread, &attr, worker, r);
    pthread_attr_destroy(&attr);
    if (rc != 0) {
        pthread_cond_destroy(&r->cv);
        pthread_mutex_destroy(&r->mu);
        return RENEW_ERR_THREAD;
    }
    r->started = 1;
    return RENEW_OK;
}

/* With the lock held: a handle left waiting goes to the worker. */
static void hand_retired(lcm_renewer *r)
{
    if (r->to_retire && !r->retired) {
        r->retired = r->to_retire;
        r->to_retire = NULL;
        pthread_cond_signal(&r->cv);
    }
}

int renew_request(lcm_renewer *r, rx_state *rx, const lcm_t *current)
{
    int i, asked = 0;
    if (pthread_mutex_trylock(&r->mu) != 0)
        return 0;
    hand_retired(r);
    if (!r->requested && !r->busy && !r->ready && !r->retired && !r->to_retire) {
        for (i = 0; i < rx->n_subs; i++) {
            rx_sub *s = &rx->subs[i];
            memcpy(r->channel[i], s->channel, RX_CHANNEL_NAME);
            r->sub[i] = s->lcm == current && s->sub != NULL ? s : NULL;
        }
        r->n_req = rx->n_subs;
        r->requested = asked = 1;
        pthread_cond_signal(&r->cv);
    }
    pthread_mutex_unlock(&r->mu);
    return asked;
}

int renew_take(lcm_renewer *r, lcm_t **fresh, lcm_subscription_t *const **staged, int *n_staged)
{
    int taken = 0;
    if (pthread_mutex_trylock(&r->mu) != 0)
        return 0;
    hand_retired(r);
    if (r->ready) {
        *fresh = r->fresh;
        *staged = r->staged;
        *n_staged = r->n_req;
        r->fresh = NULL;
        r->ready = 0;
        taken = 1;
    }
    pthread_mutex_unlock(&r->mu);
    return taken;
}

void renew_retire(lcm_renewer *r, lcm_t *old)
{
    r->to_retire = old; /* renew_take tries again if the lock is busy */
    if (pthread_mutex_trylock(&r->mu) != 0)
        return;
    hand_retired(r);
    pthread_mutex_unlock(&r->mu);
}

int renew_pending(lcm_renewer *r)
{
    int pending;
    pthread_mutex_lock(&r->mu);
    pending = r->requested || r->busy || r->ready || r->retired || r->to_retire;
    pthread_mutex_unlock(&r->mu);
    return pending;
}

int64_t renew_failures(lcm_renewer *r)
{
    int64_t n;
    pthread_mutex_lock(&r->mu);
    n = r->failures;
    pthread_mutex_unlock(&r->mu);
    return n;
}

void renew_stop(lcm_renewer *r)
{
    if (!r->started)
        return;
    pthread_mutex_lock(&r->mu);
    r->stop = 1;
    pthread_cond_signal(&r->cv);
    pthread_mutex_unlock(&r->mu);
    pthread_join(r->thread, NULL);
    /* what the worker made and nobody took, and what it did not close */
    if (r->fresh)
        lcm_destroy(r->fresh);
    if (r->retired)
        lcm_destroy(r->retired);
    if (r->to_retire)
        lcm_destroy(r->to_retire);
    pthread_cond_destroy(&r->cv);
    pthread_mutex_destroy(&r->mu);
    r->fresh = r->retired = r->to_retire = NULL;
    r->started = 0;
}
