#define _POSIX_C_SOURCE 200809L
#include "core/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <time.h>
#include <unistd.h>

static pb_log_level level = PB_LOG_NORMAL;

void pb_log_set_level(pb_log_level l) { level = l; }
pb_log_level pb_log_get_level(void) { return level; }

static void vlog(pb_log_level min, const char *prefix, const char *fmt, va_list ap) {
  if (level < min) return;
  fputs(prefix, stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
}

#define PB_LOG_FN(name, min, prefix)                                           \
  void name(const char *fmt, ...) {                                            \
    va_list ap;                                                                \
    va_start(ap, fmt);                                                         \
    vlog(min, prefix, fmt, ap);                                                \
    va_end(ap);                                                                \
  }
PB_LOG_FN(pb_log_info, PB_LOG_NORMAL, "")
PB_LOG_FN(pb_log_verbose, PB_LOG_VERBOSE, "")
PB_LOG_FN(pb_log_warn, PB_LOG_NORMAL, "warning: ")
#undef PB_LOG_FN

double pb_time_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

double pb_thread_cpu_now(void) {
  struct timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void draw(pb_progress *p, int final) {
  double frac = p->total ? (double)p->done / (double)p->total : 1.0;
  if (frac > 1.0) frac = 1.0;
  double el = pb_time_now() - p->start_s;
  if (p->is_tty) {
    enum { W = 30 };
    char bar[W + 1];
    int fill = (int)(frac * W);
    for (int i = 0; i < W; ++i) bar[i] = i < fill ? '#' : '.';
    bar[W] = 0;
    double eta = frac > 0 ? el / frac - el : 0;
    fprintf(stderr, "\r%s [%s] %5.1f%% %6.1fs eta %6.1fs", p->label, bar,
            100 * frac, el, eta);
    if (final) fputc('\n', stderr);
  } else {
    int decile = (int)(frac * 10);
    if (decile > p->last_decile || final) {
      if (!final || decile > p->last_decile)
        fprintf(stderr, "%s: %d%% (%.1fs)\n", p->label, decile * 10, el);
      p->last_decile = decile;
    }
  }
  fflush(stderr);
}

void pb_progress_begin(pb_progress *p, const char *label, uint64_t total) {
  p->label = label;
  p->total = total;
  p->done = 0;
  p->start_s = pb_time_now();
  p->last_decile = -1;
  p->is_tty = isatty(STDERR_FILENO);
  p->active = level >= PB_LOG_NORMAL;
  if (p->active) draw(p, 0);
}
void pb_progress_update(pb_progress *p, uint64_t done) {
  p->done = done;
  if (p->active) draw(p, 0);
}
void pb_progress_end(pb_progress *p) {
  p->done = p->total;
  if (p->active) draw(p, 1);
  p->active = 0;
}
