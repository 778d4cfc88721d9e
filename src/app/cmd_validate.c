/* photonbridge validate SCENE --out DIR [options]: the cross-renderer report
 * (validation/validate.py). A thin wrapper: it runs validation/validate.py with
 * python3, passing this executable as --exe and every other argument as is.
 * The script is found through $PB_VALIDATION_DIR, else next to the
 * executable's folder (BUILD/../validation, the source tree's layout), else
 * in the source tree the binary was built from (PB_SOURCE_DIR), else
 * ./validation. --help works wherever the binary runs: without the script it
 * prints the wrapper's usage and where it looked. Exit status: the script's
 * (0 ok, 1 too few renders, 2 usage);
 * 3 when the script or python3 cannot be run. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#include "app/commands.h"
#include "core/version.h"

static int exists(const char *p) { return access(p, R_OK) == 0; }

/* SIGINT/SIGTERM while the script runs: passed on to its whole process group
 * (the script, and the renderers it started, which remove their temporaries),
 * then this process waits for it and exits 128 + signal like every command. */
static volatile sig_atomic_t child_group, forwarded;

static void forward(int sig) {
  forwarded = sig;
  if (child_group > 0) kill(-(pid_t)child_group, sig);
}

static int find_script(char *out, size_t n, char *exe, size_t exe_n) {
  ssize_t len = readlink("/proc/self/exe", exe, exe_n - 1);
  if (len < 0) len = 0;
  exe[len] = 0;
  const char *env = getenv("PB_VALIDATION_DIR");
  if (env && env[0]) {
    snprintf(out, n, "%s/validate.py", env);
    if (exists(out)) return 1;
  }
  if (len > 0) {
    char dir[PATH_MAX];
    snprintf(dir, sizeof dir, "%s", exe);
    char *slash = strrchr(dir, '/');
    if (slash) {
      *slash = 0;
      snprintf(out, n, "%s/../validation/validate.py", dir);
      if (exists(out)) return 1;
    }
  }
  snprintf(out, n, "%s/validation/validate.py", PB_SOURCE_DIR);
  if (exists(out)) return 1;
  snprintf(out, n, "validation/validate.py");
  return exists(out);
}

static const char usage[] =
    "usage: photonbridge validate SCENE --out DIR [options]\n\n"
    "Renders SCENE with the reference, the GPU renderer, POV-Ray and (when Blender is\n"
    "installed) Cycles at the same resolution, shows every picture through the same\n"
    "OCIO view, compares every pair with the shared metrics and writes DIR/index.html\n"
    "and DIR/report.json.";

int pb_cmd_validate(int argc, char **argv) {
  char script[PATH_MAX + 32], exe[PATH_MAX];
  int help = 0;
  for (int i = 1; i < argc; ++i)
    if (strcmp(argv[i], "--help") == 0 || strcmp(argv[i], "-h") == 0) help = 1;
  int found = find_script(script, sizeof script, exe, sizeof exe);
  if (help && !found) {
    printf("%s\n\nIts options are those of validation/validate.py, which was not found (looked in\n"
           "$PB_VALIDATION_DIR, ../validation next to this executable, %s/validation and\n"
           "./validation): set PB_VALIDATION_DIR to the source tree's validation folder.\n",
           usage, PB_SOURCE_DIR);
    return 0;
  }
  if (!found) {
    fprintf(stderr, "photonbridge validate: error: validation/validate.py not found "
                    "(set PB_VALIDATION_DIR to the source tree's validation folder)\n");
    return 3;
  }
  if (help) {
    printf("%s Runs %s; its options:\n\n", usage, script);
    fflush(stdout);
  }
  char **av = calloc((size_t)argc + 5, sizeof *av);
  if (!av) return 3;
  int k = 0;
  av[k++] = "python3";
  av[k++] = script;
  if (exe[0] && !help) {
    av[k++] = "--exe";
    av[k++] = exe;
  }
  for (int i = 1; i < argc; ++i) av[k++] = argv[i];
  av[k] = NULL;
  fflush(stdout);
  fflush(stderr);
  pid_t pid = fork();
  if (pid == 0) {
    setpgid(0, 0); /* its own group: a signal reaches it (and its children) only through forward() */
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
    execvp("python3", av);
    fprintf(stderr, "photonbridge validate: error: cannot run python3\n");
    _exit(127);
  }
  free(av);
  if (pid < 0) return 3;
  setpgid(pid, pid); /* also here: no race with the child's own call */
  child_group = pid;
  struct sigaction sa, old_int, old_term;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = forward;
  sigaction(SIGINT, &sa, &old_int);
  sigaction(SIGTERM, &sa, &old_term);
  int st = 0;
  pid_t w;
  while ((w = waitpid(pid, &st, 0)) < 0 && errno == EINTR) {
  }
  sigaction(SIGINT, &old_int, NULL);
  sigaction(SIGTERM, &old_term, NULL);
  if (forwarded) {
    fprintf(stderr, "photonbridge validate: interrupted by %s; no output written\n",
            forwarded == SIGINT ? "SIGINT" : "SIGTERM");
    return 128 + forwarded;
  }
  if (w < 0) return 3;
  if (WIFEXITED(st)) return WEXITSTATUS(st) == 127 ? 3 : WEXITSTATUS(st);
  return 3;
}
