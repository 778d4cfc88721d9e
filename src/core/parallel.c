/* A small pool of worker threads (core/parallel.h). */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* sched_getaffinity, CPU_COUNT */
#endif
#include <pthread.h>
#include <sched.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#include "core/parallel.h"

uint32_t pb_cpu_count(void) {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) {
    int n = CPU_COUNT(&set);
    if (n > 0) return (uint32_t)n;
  }
  long n = sysconf(_SC_NPROCESSORS_ONLN);
  return n > 0 ? (uint32_t)n : 1u;
}

typedef struct pool {
  uint32_t count;
  atomic_uint next;
  atomic_uint done;
  pb_parallel_fn fn;
  void *user;
  pthread_mutex_t mu;
  pthread_cond_t cv;
  uint32_t finished;
} pool;

typedef struct worker_arg {
  pool *p;
  uint32_t thread;
} worker_arg;

static void *worker(void *arg) {
  worker_arg *w = arg;
  pool *p = w->p;
  for (;;) {
    uint32_t i = atomic_fetch_add(&p->next, 1u);
    if (i >= p->count) break;
    p->fn(p->user, i, w->thread);
    atomic_fetch_add(&p->done, 1u);
  }
  pthread_mutex_lock(&p->mu);
  p->finished++;
  pthread_cond_signal(&p->cv);
  pthread_mutex_unlock(&p->mu);
  return NULL;
}

pb_result pb_parallel_for(uint32_t threads, uint32_t count, pb_parallel_fn fn,
                          void *user, void (*tick)(void *, uint32_t), void *tick_user) {
  if (count == 0) return PB_OK;
  if (threads > count) threads = count;
  if (threads == 0) threads = 1;
  pool p;
  memset(&p, 0, sizeof p);
  p.count = count;
  atomic_init(&p.next, 0u);
  atomic_init(&p.done, 0u);
  p.fn = fn;
  p.user = user;
  pthread_mutex_init(&p.mu, NULL);
  pthread_cond_init(&p.cv, NULL);
  pthread_t *tid = malloc(threads * sizeof *tid);
  worker_arg *args = malloc(threads * sizeof *args);
  if (!tid || !args) {
    free(tid);
    free(args);
    pthread_mutex_destroy(&p.mu);
    pthread_cond_destroy(&p.cv);
    return pb_fail(PB_ERR_NOMEM, "out of memory for %u worker threads", threads);
  }
  uint32_t started = 0;
  pb_result r = PB_OK;
  for (; started < threads; ++started) {
    args[started].p = &p;
    args[started].thread = started;
    int e = pthread_create(&tid[started], NULL, worker, &args[started]);
    if (e) {
      if (started == 0)
        r = pb_fail(PB_ERR_INTERNAL, "cannot start a worker thread: %s", strerror(e));
      break; /* the threads already running finish the work */
    }
  }
  if (started > 0) {
    pthread_mutex_lock(&p.mu);
    while (p.finished < started) {
      struct timespec ts;
      clock_gettime(CLOCK_REALTIME, &ts);
      ts.tv_nsec += 100 * 1000 * 1000;
      if (ts.tv_nsec >= 1000000000L) {
        ts.tv_sec++;
        ts.tv_nsec -= 1000000000L;
      }
      pthread_cond_timedwait(&p.cv, &p.mu, &ts);
      if (tick && p.finished < started) {
        pthread_mutex_unlock(&p.mu);
        tick(tick_user, atomic_load(&p.done));
        pthread_mutex_lock(&p.mu);
      }
    }
    pthread_mutex_unlock(&p.mu);
    for (uint32_t i = 0; i < started; ++i) pthread_join(tid[i], NULL);
  }
  free(tid);
  free(args);
  pthread_mutex_destroy(&p.mu);
  pthread_cond_destroy(&p.cv);
  return r;
}
