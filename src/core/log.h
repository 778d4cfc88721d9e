/* Logging and progress on stderr. Progress is a redrawn bar when stderr is a
 * terminal and plain lines ("label: 40%") at most every 10 % when it is not, so
 * CI logs and pipes stay readable. */
#ifndef PB_LOG_H
#define PB_LOG_H

#include <stdint.h>

typedef enum pb_log_level {
  PB_LOG_QUIET = 0, /* errors only */
  PB_LOG_NORMAL = 1,
  PB_LOG_VERBOSE = 2,
} pb_log_level;

void pb_log_set_level(pb_log_level level);
pb_log_level pb_log_get_level(void);
void pb_log_info(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void pb_log_verbose(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
void pb_log_warn(const char *fmt, ...) __attribute__((format(printf, 1, 2)));

typedef struct pb_progress {
  const char *label;
  uint64_t total;
  uint64_t done;
  double start_s;
  int last_decile; /* plain mode: last tenth printed */
  int is_tty;
  int active;
} pb_progress;

void pb_progress_begin(pb_progress *p, const char *label, uint64_t total);
/* Thread-safe only from one thread; parallel renderers call it from the thread
 * that owns the progress. */
void pb_progress_update(pb_progress *p, uint64_t done);
void pb_progress_end(pb_progress *p);

/* Monotonic seconds. */
double pb_time_now(void);
/* CPU seconds this thread has run: the cost of a CPU-bound step on a shared
 * machine, where wall time also counts the other processes. */
double pb_thread_cpu_now(void);

#endif
