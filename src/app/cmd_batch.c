/* photonbridge batch JOBS: many renders in one process. Each line of JOBS is
 * a `render` command line as typed after `photonbridge`; the jobs share the
 * Vulkan device and its pipeline cache (gpu/pipeline.c), so a scene after
 * the first skips the pipeline creation a process of its own pays (seconds
 * for each shading kernel on lavapipe; a pause on GPU drivers). Each job
 * runs exactly as `photonbridge render` would: the same options, checks,
 * outputs, messages and exit code. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "core/log.h"
#include "gpu/gpu.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_batch) return &pb_commands[i];
  return NULL;
}

typedef struct job {
  unsigned line;
  int argc;
  char **argv; /* argv[0] "render", NULL-terminated */
} job;

/* Frees the jobs' words, and the array itself when `array`. */
static void jobs_free(job *jobs, size_t n, int array) {
  for (size_t i = 0; jobs && i < n; ++i) {
    for (int k = 0; k < jobs[i].argc; ++k) free(jobs[i].argv[k]);
    free(jobs[i].argv);
  }
  if (array) free(jobs);
}

/* Splits one line into words as a POSIX shell does for quoting alone:
 * blanks separate words, '...' keeps everything, "..." keeps everything but
 * \" \\ \$ \` (a backslash before them is dropped), a backslash outside quotes
 * keeps the next character. No expansion of any kind. */
static pb_result split(const char *file, unsigned line, const char *s, job *j) {
  size_t cap = 8, len = strlen(s);
  j->argv = calloc(cap, sizeof *j->argv);
  char *word = malloc(len + 1);
  if (!j->argv || !word) {
    free(word);
    return pb_fail(PB_ERR_NOMEM, "batch: %s:%u: out of memory", file, line);
  }
  const char *p = s;
  for (;;) {
    while (*p == ' ' || *p == '\t' || *p == '\r') ++p;
    if (!*p) break;
    size_t n = 0;
    while (*p && *p != ' ' && *p != '\t' && *p != '\r') {
      if (*p == '\'') {
        const char *e = strchr(p + 1, '\'');
        if (!e) goto unterminated;
        memcpy(word + n, p + 1, (size_t)(e - p - 1));
        n += (size_t)(e - p - 1), p = e + 1;
      } else if (*p == '"') {
        ++p;
        while (*p && *p != '"') {
          if (*p == '\\' && p[1] && strchr("\"\\$`", p[1])) ++p;
          word[n++] = *p++;
        }
        if (*p != '"') goto unterminated;
        ++p;
      } else if (*p == '\\') {
        if (!p[1]) {
          free(word);
          return pb_fail(PB_ERR_USAGE, "batch: %s:%u: a backslash ends the line (one job a line)", file, line);
        }
        word[n++] = p[1], p += 2;
      } else {
        word[n++] = *p++;
      }
    }
    if ((size_t)j->argc + 2 > cap) {
      char **a = realloc(j->argv, 2 * cap * sizeof *a);
      if (!a) {
        free(word);
        return pb_fail(PB_ERR_NOMEM, "batch: %s:%u: out of memory", file, line);
      }
      j->argv = a, cap *= 2;
    }
    if (!(j->argv[j->argc] = malloc(n + 1))) {
      free(word);
      return pb_fail(PB_ERR_NOMEM, "batch: %s:%u: out of memory", file, line);
    }
    memcpy(j->argv[j->argc], word, n);
    j->argv[j->argc++][n] = 0;
    j->argv[j->argc] = NULL;
  }
  free(word);
  return PB_OK;
unterminated:
  free(word);
  return pb_fail(PB_ERR_USAGE, "batch: %s:%u: unterminated quote", file, line);
}

/* One line of a jobs file into j: argc 0 for a blank or comment line. */
static pb_result parse_line(const char *name, unsigned line, char *buf, size_t len, job *j) {
  *j = (job){.line = line};
  if (len > 0 && buf[len - 1] == '\n') buf[--len] = 0;
  if (len != strlen(buf)) return pb_fail(PB_ERR_USAGE, "batch: %s:%u: a NUL byte in the line", name, line);
  const char *t = buf + strspn(buf, " \t\r");
  if (!*t || *t == '#') return PB_OK;
  pb_result r = split(name, line, t, j);
  if (r == PB_OK && (j->argc == 0 || strcmp(j->argv[0], "render") != 0))
    r = pb_fail(PB_ERR_USAGE, "batch: %s:%u: '%s': a job is a render command line ('render SCENE -o OUT "
                "[options]')", name, line, j->argc ? j->argv[0] : "");
  return r;
}

/* Every job of a file, checked before any runs. */
static pb_result read_jobs(const char *path, job **out, size_t *count) {
  *out = NULL, *count = 0;
  FILE *f = fopen(path, "r");
  if (!f) return pb_fail(PB_ERR_IO, "batch: %s: cannot open: %s", path, strerror(errno));
  char *buf = NULL;
  size_t bcap = 0, cap = 0;
  unsigned line = 0;
  pb_result r = PB_OK;
  ssize_t got;
  job *jobs = NULL;
  while ((got = getline(&buf, &bcap, f)) >= 0) {
    job j;
    r = parse_line(path, ++line, buf, (size_t)got, &j);
    if (r == PB_OK && j.argc == 0) continue;
    if (r == PB_OK && *count == cap) {
      job *a = realloc(jobs, (cap ? 2 * cap : 16) * sizeof *a);
      if (!a) r = pb_fail(PB_ERR_NOMEM, "batch: %s: out of memory", path);
      else jobs = a, cap = cap ? 2 * cap : 16;
    }
    if (r != PB_OK) {
      jobs_free(&j, 1, 0);
      break;
    }
    jobs[(*count)++] = j;
  }
  if (r == PB_OK && ferror(f)) r = pb_fail(PB_ERR_IO, "batch: %s: read failed: %s", path, strerror(errno));
  free(buf);
  fclose(f);
  if (r != PB_OK) {
    jobs_free(jobs, *count, 1);
    *count = 0;
    return r;
  }
  *out = jobs;
  return PB_OK;
}

/* Runs job number `index` (1-based) and prints its line. */
static int run_job(size_t index, const job *j, pb_log_level level) {
  pb_log_set_level(level); /* a job's -q or -v is its own */
  pb_error_clear();         /* so is its error (the first one of a run is kept) */
  uint32_t v0 = pb_gpu_validation_total();
  uint64_t created = 0, reused = 0;
  double t0 = pb_time_now();
  int jrc = pb_cmd_render(j->argc, j->argv);
  uint32_t nv = pb_gpu_validation_total() - v0;
  if (nv && jrc == 0) { /* as main does for one command */
    fprintf(stderr, "photonbridge render: error: Vulkan validation reported %u message%s (printed above)\n", nv,
            nv == 1 ? "" : "s");
    jrc = pb_result_exit_code(PB_ERR_VULKAN);
  }
  pb_cli_gpu_job_pipelines(&created, &reused);
  printf("{\"job\":%zu,\"line\":%u,\"exit\":%d,\"wall_ms\":%.1f,\"pipelines_created\":%llu,"
         "\"pipelines_reused\":%llu}\n",
         index, j->line, jrc, (pb_time_now() - t0) * 1e3, (unsigned long long)created, (unsigned long long)reused);
  fflush(stdout);
  return jrc;
}

/* Standard input: each job runs as its line arrives (a program sends the
 * next after reading the last one's line); a bad line is that job's error
 * (exit 2, its line printed) and the next lines still run. */
static int run_stream(const pb_command *cmd, pb_log_level level) {
  char *buf = NULL;
  size_t bcap = 0, n = 0;
  unsigned line = 0;
  int rc = 0;
  ssize_t got;
  while ((got = getline(&buf, &bcap, stdin)) >= 0) {
    job j;
    pb_error_clear();
    pb_result r = parse_line("standard input", ++line, buf, (size_t)got, &j);
    if (r == PB_OK && j.argc == 0) continue;
    int jrc;
    ++n;
    if (r != PB_OK) {
      jrc = pb_cli_exit(cmd, r);
      printf("{\"job\":%zu,\"line\":%u,\"exit\":%d,\"wall_ms\":0,\"pipelines_created\":0,"
             "\"pipelines_reused\":0}\n", n, line, jrc);
      fflush(stdout);
    } else {
      jrc = run_job(n, &j, level);
    }
    jobs_free(&j, 1, 0);
    if (jrc && !rc) rc = jrc;
  }
  free(buf);
  if (ferror(stdin)) {
    int e = pb_cli_exit(cmd, pb_fail(PB_ERR_IO, "batch: standard input: read failed: %s", strerror(errno)));
    if (!rc) rc = e;
  }
  return rc;
}

int pb_cmd_batch(int argc, char **argv) {
  const pb_command *cmd = self();
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, NULL, 0, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, NULL, 0,
                      "Runs the render jobs in JOBS (a file, or - for standard input) in one\n"
                      "process, in order. Each line is a render command line as typed after\n"
                      "'photonbridge':\n"
                      "  render shots/a.gltf -o out/a.exr --spp 64\n"
                      "  render \"shots/b c.gltf\" -o out/b.png --photons 1048576\n"
                      "Blank lines and lines starting with # are skipped; words are split as a\n"
                      "shell does for '...', \"...\" and backslashes, without any expansion;\n"
                      "relative paths are the current folder's. In a file every line is checked\n"
                      "before the first job runs; from standard input each job runs as its line\n"
                      "arrives (a program sends the next after reading the last one's line), a bad\n"
                      "line being that job's error (exit 2).\n"
                      "The jobs share the Vulkan device and its compiled pipelines: a scene after\n"
                      "the first skips the pipeline creation (seconds for each shading kernel on a\n"
                      "CPU Vulkan device). Each job runs as 'photonbridge render' would, with its\n"
                      "own messages, outputs and checks; after it, one JSON line on standard\n"
                      "output:\n"
                      "  {\"job\":1,\"line\":3,\"exit\":0,\"wall_ms\":812.5,\"pipelines_created\":4,\n"
                      "   \"pipelines_reused\":21}\n"
                      "Every job runs; the exit code is 0 when all succeeded, else the first failed\n"
                      "job's (the table in 'photonbridge help render').");
    return 0;
  }
  if (npos != 1) return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "batch: expected JOBS (a file, or -)"));
  pb_log_level level = pb_log_get_level();
  int rc = 0;
  if (strcmp(pos[0], "-") == 0) {
    pb_cli_gpu_keep(1);
    rc = run_stream(cmd, level);
    pb_cli_gpu_keep(0);
    return rc;
  }
  job *jobs;
  size_t count;
  if ((r = read_jobs(pos[0], &jobs, &count)) != PB_OK) return pb_cli_exit(cmd, r);
  if (count == 0) pb_log_warn("batch: %s: no jobs", pos[0]);
  pb_cli_gpu_keep(1);
  for (size_t i = 0; i < count; ++i) {
    int jrc = run_job(i + 1, &jobs[i], level);
    if (jrc && !rc) rc = jrc;
  }
  pb_cli_gpu_keep(0);
  jobs_free(jobs, count, 1);
  return rc;
}
