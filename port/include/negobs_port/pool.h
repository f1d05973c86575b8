/*
 * A small pthread pool that runs the library's row bands
 * (negobs/executor.h). The calling thread is worker 0 and takes jobs
 * itself; threads - 1 more threads wait for work between frames.
 */
#ifndef NEGOBS_PORT_POOL_H
#define NEGOBS_PORT_POOL_H

#include <stdint.h>

#include "negobs/executor.h"
#include "negobs/status.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Most threads a pool takes (the matcher's NEGOBS_STEREO_MAX_BANDS). */
#define NEGOBS_POOL_MAX_THREADS 64

typedef struct negobs_pool negobs_pool_t;

/**
 * @brief Start a pool of `threads` workers (the caller plus threads - 1
 * started threads).
 * @return NEGOBS_OK; NEGOBS_ERR_INVAL for a NULL out or threads outside
 *         [1, NEGOBS_POOL_MAX_THREADS]; NEGOBS_ERR_NOSPACE when memory or
 *         a thread could not be had (nothing is left running then).
 */
negobs_status_t negobs_pool_create(negobs_pool_t **out, int32_t threads);

/** @brief Stop and join the threads, release the pool; NULL is fine. */
void negobs_pool_destroy(negobs_pool_t *pool);

/** @brief The executor that runs jobs on this pool (workers = threads).
 * One run at a time: the pool serves one caller thread. */
negobs_executor_t negobs_pool_executor(negobs_pool_t *pool);

/** @brief Online CPU cores (sysconf), at least 1, at most
 * NEGOBS_POOL_MAX_THREADS: the default thread count of the tools. */
int32_t negobs_pool_online_cores(void);

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_PORT_POOL_H */
