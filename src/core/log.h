/* Logging and progress on stderr. Progress is one redrawn line (\r) when
 * stderr is a terminal and plain lines when it is not, so CI logs and pipes
 * stay readable: "label: 40%" at most every 10 %, or with stages (render:
 * loading, BVH, photon map k/N, ...) a line at most every plain_interval_s
 * seconds. Nothing below PB_LOG_NORMAL (-q). A message logged while the
 * terminal line is drawn clears it first and redraws it after. */
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
  /* Stages (pb_progress_stage): what is being done and, where the caller
   * knows it, the seconds left (< 0: from done / total of the stage). */
  char stage[96];
  double stage_start_s;
  double eta_s;
  double plain_interval_s; /* plain mode with stages: seconds between lines */
  double last_line_s;      /* plain mode: when the last line was printed */
  int drawn_width;         /* terminal: characters of the line drawn */
} pb_progress;

void pb_progress_begin(pb_progress *p, const char *label, uint64_t total);
/* Thread-safe only from one thread; parallel renderers call it from the thread
 * that owns the progress. */
void pb_progress_update(pb_progress *p, uint64_t done);
void pb_progress_end(pb_progress *p);
/* A progress of stages: begin with pb_progress_begin(p, label, 0), then
 * name each stage (or its step: done of total, 0 when unknown) as it comes;
 * eta_s >= 0 is the caller's estimate of the time left, < 0 lets it follow
 * from done / total. Plain mode prints a line at most every
 * p->plain_interval_s seconds (default 5 s), so a short run prints none. */
void pb_progress_stage(pb_progress *p, const char *stage, uint64_t done, uint64_t total, double eta_s);
/* Clears the terminal line of the drawn progress, if any (before an error
 * message that ends the run). */
void pb_progress_clear_line(void);

/* Monotonic seconds. */
double pb_time_now(void);
/* CPU seconds this thread has run: the cost of a CPU-bound step on a shared
 * machine, where wall time also counts the other processes. */
double pb_thread_cpu_now(void);

#endif
