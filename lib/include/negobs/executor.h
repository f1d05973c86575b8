/*
 * Caller-supplied executor: how the library hands independent jobs (the row
 * bands of the disparity engine) to whatever threads the caller has. The
 * library never creates a thread; without an executor it runs every job
 * itself, in order. port/ implements one with a pthread pool
 * (negobs_port/pool.h); a microcontroller passes none.
 */
#ifndef NEGOBS_EXECUTOR_H
#define NEGOBS_EXECUTOR_H

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/**
 * One job: `job` in [0, n_jobs) names the work, `worker` in [0, workers)
 * the executor thread that runs it. Two jobs never run at the same time
 * on the same worker, so the library keeps one scratch area per worker.
 */
typedef void (*negobs_job_fn)(void *arg, int32_t job, int32_t worker);

/**
 * run() must call fn(arg, j, worker) exactly once for every j in
 * [0, n_jobs), in any order and on any of its `workers` threads, and
 * return only after every call has returned. The results do not depend on
 * the order or on the number of workers. The library numbers the jobs
 * costliest first, so starting them in index order, each on the first
 * idle worker, finishes soonest.
 */
typedef struct negobs_executor {
    int32_t workers; /**< threads run() may use at once (>= 1)   */
    void (*run)(void *user, int32_t n_jobs, negobs_job_fn fn, void *arg);
    void *user;
} negobs_executor_t;

#ifdef __cplusplus
}
#endif

#endif /* NEGOBS_EXECUTOR_H */
