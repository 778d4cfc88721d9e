/* Work spread over worker threads: items handed out one at a time by an
 * atomic counter, so a slow item does not hold up the others. */
#ifndef PB_CORE_PARALLEL_H
#define PB_CORE_PARALLEL_H

#include <stdint.h>

#include "core/result.h"

/* The CPUs this process may run on (its affinity mask), at least 1. */
uint32_t pb_cpu_count(void);

/* Runs fn(user, item, thread) for every item in [0, count) on `threads`
 * threads (at most count; 0 counts as 1), thread in [0, threads). The
 * calling thread waits and, when tick is given, calls tick(tick_user,
 * items done) about every 100 ms (progress). Fails only when no thread can
 * be started; the items are then not run. */
typedef void (*pb_parallel_fn)(void *user, uint32_t item, uint32_t thread);
pb_result pb_parallel_for(uint32_t threads, uint32_t count, pb_parallel_fn fn, void *user,
                          void (*tick)(void *tick_user, uint32_t done), void *tick_user);

#endif
