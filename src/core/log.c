#define _POSIX_C_SOURCE 200809L
#include "core/log.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static pb_log_level level = PB_LOG_NORMAL;
/* The progress whose line is drawn on the terminal now (NULL: none). */
static pb_progress *drawn;
static void draw(pb_progress *p, int final);

void pb_progress_clear_line(void) {
  if (!drawn) return;
  fprintf(stderr, "\r%*s\r", drawn->drawn_width, "");
  drawn->drawn_width = 0;
  drawn = NULL;
  fflush(stderr);
}

void pb_log_set_level(pb_log_level l) { level = l; }
pb_log_level pb_log_get_level(void) { return level; }

static void vlog(pb_log_level min, const char *prefix, const char *fmt, va_list ap) {
  if (level < min) return;
  pb_progress *p = drawn;
  pb_progress_clear_line();
  fputs(prefix, stderr);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  if (p && p->active) draw(p, 0);
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

/* "12.3s", "4m05s", "1h02m" */
static void fmt_seconds(char *buf, size_t size, double s) {
  if (!(s >= 0)) s = 0;
  if (s < 60) snprintf(buf, size, "%.1fs", s);
  else if (s < 3600) snprintf(buf, size, "%dm%02ds", (int)(s / 60), (int)s % 60);
  else snprintf(buf, size, "%dh%02dm", (int)(s / 3600), (int)(s / 60) % 60);
}

/* A progress with stages: "label: stage [bar] 40% 2.1s, 3.2s left". */
static void draw_stage(pb_progress *p, int final) {
  double now = pb_time_now();
  double frac = p->total ? (double)p->done / (double)p->total : -1.0;
  if (frac > 1.0) frac = 1.0;
  double st_el = now - p->stage_start_s;
  double eta = p->eta_s;
  if (eta < 0 && frac > 0) eta = st_el / frac - st_el;
  char el_s[32], eta_s[48], line[256];
  fmt_seconds(el_s, sizeof el_s, now - p->start_s);
  if (final) snprintf(eta_s, sizeof eta_s, "done");
  else if (eta >= 0) {
    char t[32];
    fmt_seconds(t, sizeof t, eta);
    snprintf(eta_s, sizeof eta_s, "about %s left", t);
  } else snprintf(eta_s, sizeof eta_s, "time left unknown");
  if (p->is_tty) {
    int k;
    if (frac >= 0) {
      enum { W = 20 };
      char bar[W + 1];
      int fill = (int)(frac * W);
      for (int i = 0; i < W; ++i) bar[i] = i < fill ? '#' : '.';
      bar[W] = 0;
      k = snprintf(line, sizeof line, "%s: %s [%s] %3.0f%% %s, %s", p->label, p->stage, bar, 100 * frac, el_s, eta_s);
    } else {
      k = snprintf(line, sizeof line, "%s: %s ... %s, %s", p->label, p->stage, el_s, eta_s);
    }
    if (k > (int)sizeof line - 1) k = (int)sizeof line - 1;
    /* Blank what a longer previous line left. */
    int pad = p->drawn_width > k ? p->drawn_width - k : 0;
    fprintf(stderr, "\r%s%*s", line, pad, "");
    if (pad) fprintf(stderr, "\r%s", line);
    p->drawn_width = k;
    drawn = p;
    if (final) {
      fputc('\n', stderr);
      p->drawn_width = 0;
      drawn = NULL;
    }
  } else {
    double interval = p->plain_interval_s > 0 ? p->plain_interval_s : 5.0;
    if (!final && now - p->last_line_s < interval) return;
    if (final && p->last_line_s == p->start_s) return; /* a short run: no lines */
    if (frac >= 0)
      fprintf(stderr, "%s: %s (%.0f%%, %s, %s)\n", p->label, p->stage, 100 * frac, el_s, eta_s);
    else
      fprintf(stderr, "%s: %s (%s, %s)\n", p->label, p->stage, el_s, eta_s);
    p->last_line_s = now;
  }
  fflush(stderr);
}

static void draw(pb_progress *p, int final) {
  if (p->stage[0]) {
    draw_stage(p, final);
    return;
  }
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
    p->drawn_width = (int)strlen(p->label) + 59;
    drawn = p;
    if (final) {
      fputc('\n', stderr);
      p->drawn_width = 0;
      drawn = NULL;
    }
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
  memset(p, 0, sizeof *p);
  p->label = label;
  p->total = total;
  p->done = 0;
  p->start_s = pb_time_now();
  p->last_decile = -1;
  p->is_tty = isatty(STDERR_FILENO);
  p->active = level >= PB_LOG_NORMAL;
  p->eta_s = -1;
  p->last_line_s = p->start_s;
  p->stage_start_s = p->start_s;
  if (p->active && total) draw(p, 0);
}

void pb_progress_stage(pb_progress *p, const char *stage, uint64_t done, uint64_t total, double eta_s) {
  if (strncmp(p->stage, stage, sizeof p->stage) != 0 || done < p->done) p->stage_start_s = pb_time_now();
  snprintf(p->stage, sizeof p->stage, "%s", stage);
  p->done = done;
  p->total = total;
  p->eta_s = eta_s;
  if (p->active) draw(p, 0);
}
void pb_progress_update(pb_progress *p, uint64_t done) {
  p->done = done;
  if (p->active) draw(p, 0);
}
void pb_progress_end(pb_progress *p) {
  p->done = p->total;
  if (p->active) {
    if (p->stage[0] && p->is_tty) {
      /* A finished stage line has nothing to keep: the summary follows. */
      if (drawn == p) pb_progress_clear_line();
    } else {
      draw(p, 1);
    }
  }
  if (drawn == p) drawn = NULL;
  p->active = 0;
}
