/* The "pool" line of negobs_digest (digest_pool.c). */
#ifndef NEGOBS_TEST_DIGEST_POOL_H
#define NEGOBS_TEST_DIGEST_POOL_H

#include <stdint.h>

/* FNV-1a 64 of the detector's pooled maps on a generated walk (perturb:
 * one disparity of the first map changed); 0 if a fit could not be made. */
uint64_t digest_pool(int perturb);

#endif
