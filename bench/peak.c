/* Peak memory of one command, for bench/run_bench.py (which compiles this
 * with `cc` into bench/cache/ on first use):
 *
 *   pb_peak OUTFILE COMMAND [ARGS...]
 *
 * Runs COMMAND as a child, waits for it with wait4 and writes the child's
 * ru_maxrss (KiB; the child and the descendants it waited for) to OUTFILE;
 * exits with the child's status (128 + signal when killed). A process forked
 * from Python instead starts with the interpreter's resident set (about
 * 17 MiB), which exec keeps as the child's high-water mark; forked from this
 * small program the floor is about 1 MiB. */
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

static pid_t child;

static void forward(int sig) {
  if (child > 0) kill(child, sig);
}

int main(int argc, char **argv) {
  if (argc < 3) {
    fprintf(stderr, "usage: pb_peak OUTFILE COMMAND [ARGS...]\n");
    return 2;
  }
  signal(SIGTERM, forward);
  signal(SIGINT, forward);
  child = fork();
  if (child < 0) {
    perror("pb_peak: fork");
    return 127;
  }
  if (child == 0) {
    execvp(argv[2], argv + 2);
    perror("pb_peak: exec");
    _exit(127);
  }
  int status = 0;
  struct rusage ru;
  while (wait4(child, &status, 0, &ru) < 0) {
    if (errno != EINTR) {
      perror("pb_peak: wait4");
      return 127;
    }
  }
  FILE *f = fopen(argv[1], "w");
  if (f) {
    fprintf(f, "%ld\n", ru.ru_maxrss);
    fclose(f);
  }
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  return 128 + (WIFSIGNALED(status) ? WTERMSIG(status) : 0);
}
