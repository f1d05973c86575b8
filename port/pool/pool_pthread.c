/*
 * pthread pool behind negobs_executor_t (negobs_port/pool.h).
 *
 * One mutex guards the job counter: a frame has a handful of bands, each
 * several milliseconds of work, so a lock per job costs nothing measurable
 * and keeps the code obviously correct. Jobs are handed out in index order
 * to whichever worker asks first, so the library names its costliest band
 * job 0 (bands.c: stx_bands_order); the results do not depend on who ran
 * what. Waking a sleeping worker costs about 1 us a run on an idle
 * machine (docs/journal/2026-12-02-pipeline-threads.md), so the workers
 * sleep between runs rather than poll.
 */
#define _POSIX_C_SOURCE 200809L

#include <pthread.h>
#include <stdlib.h>
#include <unistd.h>

#include "negobs_port/pool.h"

struct negobs_pool {
    pthread_mutex_t mu;
    pthread_cond_t work; /* a new run (gen changed) or stop */
    pthread_cond_t done; /* the last job of a run finished  */
    pthread_t *tid;
    int32_t threads;
    int32_t started; /* threads running (threads - 1 once created) */
    int stop;
    uint32_t gen; /* run counter                               */
    /* the current run */
    negobs_job_fn fn;
    void *arg;
    int32_t n_jobs;
    int32_t next;     /* next job to hand out */
    int32_t finished; /* jobs returned        */
};

typedef struct worker_arg {
    negobs_pool_t *pool;
    int32_t index;
} worker_arg_t;

/* Take and run jobs of the current run until none is left (mu held on
 * entry and on return). */
static void drain(negobs_pool_t *p, int32_t worker)
{
    while (p->next < p->n_jobs) {
        int32_t job = p->next++;
        negobs_job_fn fn = p->fn;
        void *arg = p->arg;
        pthread_mutex_unlock(&p->mu);
        fn(arg, job, worker);
        pthread_mutex_lock(&p->mu);
        p->finished++;
        if (p->finished == p->n_jobs) {
            pthread_cond_signal(&p->done);
        }
    }
}

static void *worker_main(void *varg)
{
    worker_arg_t *wa = (worker_arg_t *)varg;
    negobs_pool_t *p = wa->pool;
    int32_t index = wa->index;
    uint32_t seen;
    free(wa);
    pthread_mutex_lock(&p->mu);
    seen = p->gen;
    for (;;) {
        while (!p->stop && p->gen == seen) {
            pthread_cond_wait(&p->work, &p->mu);
        }
        if (p->stop) {
            break;
        }
        seen = p->gen;
        drain(p, index);
    }
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

static void pool_run(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg)
{
    negobs_pool_t *p = (negobs_pool_t *)user;
    if (n_jobs <= 0 || fn == NULL) {
        return;
    }
    pthread_mutex_lock(&p->mu);
    p->fn = fn;
    p->arg = arg;
    p->n_jobs = n_jobs;
    p->next = 0;
    p->finished = 0;
    p->gen++;
    pthread_cond_broadcast(&p->work);
    drain(p, 0);
    while (p->finished < p->n_jobs) {
        pthread_cond_wait(&p->done, &p->mu);
    }
    /* workers that wake late find no job left and wait again */
    p->n_jobs = 0;
    p->next = 0;
    pthread_mutex_unlock(&p->mu);
}

static void stop_threads(negobs_pool_t *p)
{
    int32_t i;
    pthread_mutex_lock(&p->mu);
    p->stop = 1;
    pthread_cond_broadcast(&p->work);
    pthread_mutex_unlock(&p->mu);
    for (i = 0; i < p->started; i++) {
        (void)pthread_join(p->tid[i], NULL);
    }
    p->started = 0;
}

negobs_status_t negobs_pool_create(negobs_pool_t **out, int32_t threads)
{
    negobs_pool_t *p;
    int32_t i;
    if (out == NULL || threads < 1 || threads > NEGOBS_POOL_MAX_THREADS) {
        return NEGOBS_ERR_INVAL;
    }
    *out = NULL;
    p = (negobs_pool_t *)calloc(1, sizeof *p);
    if (p == NULL) {
        return NEGOBS_ERR_NOSPACE;
    }
    p->threads = threads;
    p->tid = (pthread_t *)calloc((size_t)threads, sizeof *p->tid);
    if (p->tid == NULL || pthread_mutex_init(&p->mu, NULL) != 0) {
        free(p->tid);
        free(p);
        return NEGOBS_ERR_NOSPACE;
    }
    (void)pthread_cond_init(&p->work, NULL);
    (void)pthread_cond_init(&p->done, NULL);
    for (i = 1; i < threads; i++) {
        worker_arg_t *wa = (worker_arg_t *)malloc(sizeof *wa);
        if (wa == NULL) {
            negobs_pool_destroy(p);
            return NEGOBS_ERR_NOSPACE;
        }
        wa->pool = p;
        wa->index = i;
        if (pthread_create(&p->tid[p->started], NULL, worker_main, wa) != 0) {
            free(wa);
            negobs_pool_destroy(p);
            return NEGOBS_ERR_NOSPACE;
        }
        p->started++;
    }
    *out = p;
    return NEGOBS_OK;
}

void negobs_pool_destroy(negobs_pool_t *pool)
{
    if (pool == NULL) {
        return;
    }
    stop_threads(pool);
    (void)pthread_cond_destroy(&pool->work);
    (void)pthread_cond_destroy(&pool->done);
    (void)pthread_mutex_destroy(&pool->mu);
    free(pool->tid);
    free(pool);
}

negobs_executor_t negobs_pool_executor(negobs_pool_t *pool)
{
    negobs_executor_t e;
    e.workers = (pool != NULL) ? pool->threads : 1;
    e.run = (pool != NULL) ? pool_run : NULL;
    e.user = pool;
    return e;
}

int32_t negobs_pool_online_cores(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    if (n < 1) {
        return 1;
    }
    return (n > NEGOBS_POOL_MAX_THREADS) ? NEGOBS_POOL_MAX_THREADS
                                         : (int32_t)n;
}
