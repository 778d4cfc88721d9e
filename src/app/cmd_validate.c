/* photonbridge validate SCENE -o DIR [options]: the cross-renderer report
 * (validation/validate.py). A thin wrapper: the options are checked here
 * against the table below (the script's own options, kept in step with its
 * argparse), --help is this program's, and the script runs with python3,
 * given this executable as --exe and every argument as is but -o/--output,
 * passed as the script's --out (--out itself still works).
 * The script is found through $PB_VALIDATION_DIR, else next to the
 * executable's folder (BUILD/../validation, the source tree's layout), else
 * in the installed data folder beside it (BIN/../share/photonbridge/validation,
 * cmake --install's layout: PB_DATA_FROM_BIN), else in the source tree the
 * binary was built from (PB_SOURCE_DIR), else ./validation. --help works
 * wherever the binary runs. Exit status: the script's
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

#include "app/cli.h"
#include "app/commands.h"
#include "core/version.h"

/* The installed data folder relative to the installed binary's folder
 * (CMakeLists.txt: GNUInstallDirs' bin and share/photonbridge). */
#ifndef PB_DATA_FROM_BIN
#define PB_DATA_FROM_BIN "../share/photonbridge"
#endif

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
      snprintf(out, n, "%s/%s/validation/validate.py", dir, PB_DATA_FROM_BIN);
      if (exists(out)) return 1;
    }
  }
  snprintf(out, n, "%s/validation/validate.py", PB_SOURCE_DIR);
  if (exists(out)) return 1;
  snprintf(out, n, "validation/validate.py");
  return exists(out);
}

static const char *const pov_quality_names[] = {"draft", "medium", "high", "direct", NULL};
static const char *const cycles_source_names[] = {"auto", "sample", "gltf", NULL};
static const char *const cycles_materials_names[] = {"model", "principled", NULL};

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_validate) return &pb_commands[i];
  return &pb_commands[0];
}

int pb_cmd_validate(int argc, char **argv) {
  const pb_command *cmd = self();
  char script[PATH_MAX + 96], exe[PATH_MAX];
  /* Parsed here for --help and for errors in the words of every other
   * subcommand; the values themselves are the script's to read. */
  const char *out = NULL, *old_out = NULL, *s_exe = NULL, *str = NULL;
  uint32_t u32 = 0;
  double dbl = 0;
  int flag = 0, choice = 0;
  const pb_opt opts[] = {
      {"output", 'o', PB_OPT_STRING, &out, "DIR", "report folder: DIR/index.html, DIR/report.json, every image "
       "and log (created if missing)", NULL, 0, 0, "Output", 0},
      {"out", 0, PB_OPT_STRING, &old_out, "DIR", "the same as --output (its former name)", NULL, 0, 0, "Output",
       PB_OPT_ADVANCED},
      {"render-only", 0, PB_OPT_FLAG, &flag, NULL, "run the renderers and write each one's record as "
       "DIR/render_NAME.json, no comparison or report (one task per scene and renderer on a farm; then "
       "--report-from)", NULL, 0, 0, "Output", 0},
      {"report-from", 0, PB_OPT_STRING, &str, "DIR[,DIR...]", "render nothing: gather what --render-only runs "
       "wrote into these folders (copied into -o DIR), then compare and write the report", NULL, 0, 0, "Output", 0},
      {"width", 0, PB_OPT_U32, &u32, "W", "image width of every render (default 384; the height from the "
       "camera's aspect)", NULL, 1, 16384, "Sampling", 0},
      {"spp", 0, PB_OPT_U32, &u32, "N", "photonbridge render samples per pixel (default 16)", NULL, 1, 1 << 20,
       "Sampling", 0},
      {"ref-spp", 0, PB_OPT_U32, &u32, "N", "reference samples per pixel (default 64)", NULL, 1, 1 << 24,
       "Sampling", 0},
      {"cycles-spp", 0, PB_OPT_U32, &u32, "N", "Cycles samples per pixel, as two independent halves for its own "
       "noise (default 64)", NULL, 1, 1 << 24, "Sampling", 0},
      {"pov-quality", 0, PB_OPT_CHOICE, &choice, "PRESET", "POV-Ray's radiosity and photon settings, as "
       "export-pov --quality (default medium)", pov_quality_names, 0, 0, "Sampling", 0},
      {"direct-only", 0, PB_OPT_FLAG, &flag, NULL, "direct light only, in every renderer", NULL, 0, 0, "Sampling", 0},
      {"frames", 0, PB_OPT_STRING, &str, "A:B", "a sequence (render --frames, with a reference per frame) "
       "instead of one picture", NULL, 0, 0, "Animation", 0},
      {"seq-ref-spp", 0, PB_OPT_U32, &u32, "N", "--frames: reference samples per pixel of each frame (default "
       "64)", NULL, 1, 1 << 24, "Animation", 0},
      {"renderers", 0, PB_OPT_STRING, &str, "LIST", "comma-separated renderers to run (default: reference, "
       "photonbridge, povray, cycles; also cycles45, Blender 4.5 LTS's Cycles through bpy, and luxcore and "
       "mitsuba, LuxCoreRender and Mitsuba 3 rendering export-peer's dump of the scene); the others are listed "
       "as skipped", NULL, 0, 0, "Renderers", 0},
      {"no-gpu", 0, PB_OPT_FLAG, &flag, NULL, "skip photonbridge render", NULL, 0, 0, "Renderers", 0},
      {"no-povray", 0, PB_OPT_FLAG, &flag, NULL, "skip POV-Ray", NULL, 0, 0, "Renderers", 0},
      {"no-cycles", 0, PB_OPT_FLAG, &flag, NULL, "skip Cycles", NULL, 0, 0, "Renderers", 0},
      {"cycles-source", 0, PB_OPT_CHOICE, &choice, "FROM", "where the Cycles scene comes from: sample (the "
       "sample's own Blender build), gltf (Blender's importer reads SCENE) or auto: sample for the samples, gltf "
       "for any other file (default auto)", cycles_source_names, 0, 0, "Renderers", PB_OPT_ADVANCED},
      {"cycles-materials", 0, PB_OPT_CHOICE, &choice, "KIND", "model: glTF's material model in Cycles nodes; "
       "principled: Blender's Principled BSDFs as Blender sets them up (default model)", cycles_materials_names,
       0, 0, "Renderers", PB_OPT_ADVANCED},
      {"render-args", 0, PB_OPT_STRING, &str, "ARGS", "more options for photonbridge render (one string)", NULL,
       0, 0, "Renderers", PB_OPT_ADVANCED},
      {"ref-args", 0, PB_OPT_STRING, &str, "ARGS", "more options for photonbridge reference (one string)", NULL,
       0, 0, "Renderers", PB_OPT_ADVANCED},
      {"exe", 0, PB_OPT_STRING, &s_exe, "FILE", "the photonbridge binary to test (default: this one)", NULL, 0, 0,
       "Renderers", PB_OPT_ADVANCED},
      {"ocio-config", 0, PB_OPT_STRING, &str, "FILE", "OpenColorIO config for every picture (as render's)", NULL,
       0, 0, "Colour", 0},
      {"display", 0, PB_OPT_STRING, &str, "NAME", "OCIO display of every picture", NULL, 0, 0, "Colour", 0},
      {"view", 0, PB_OPT_STRING, &str, "NAME", "OCIO view of every picture", NULL, 0, 0, "Colour", 0},
      {"look", 0, PB_OPT_STRING, &str, "NAME", "OCIO look applied with the view", NULL, 0, 0, "Colour", 0},
      {"exposure", 0, PB_OPT_FLOAT, &dbl, "STOPS", "scale by 2^STOPS before the view (default 0)", NULL, -64, 64,
       "Colour", 0},
      {"threads", 0, PB_OPT_U32, &u32, "N", "CPU threads for the reference, POV-Ray and Cycles (default 0: all)",
       NULL, 0, 0, "Device", 0},
      {"quiet", 'q', PB_OPT_FLAG, &flag, NULL, "errors only: no progress, no time estimate, no status lines",
       NULL, 0, 0, "Reporting", 0},
  };
  const size_t nopts = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, nopts, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, nopts,
                      "Renders SCENE with the reference, the GPU renderer, POV-Ray and (when Blender is installed) "
                      "Cycles at the same resolution, shows every picture through the same OCIO view, compares "
                      "every pair with compare's metrics and writes DIR/index.html and DIR/report.json. Before the "
                      "first render it prints an estimate of the run's time, measured on small probe renders of "
                      "the reference and photonbridge render (POV-Ray and Cycles modelled from the reference's "
                      "speed), also in report.json. The "
                      "renderers that are not installed are listed as skipped. Needs python3 and the "
                      "validation scripts (found through $PB_VALIDATION_DIR, ../validation beside this binary, "
                      "../share/photonbridge/validation where it was installed with cmake --install, or the "
                      "source tree it was built from).");
    return 0;
  }
  if (npos != 1 || (!out && !old_out))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "expected SCENE and -o DIR (see 'photonbridge validate --help')"));
  int found = find_script(script, sizeof script, exe, sizeof exe);
  if (!found) {
    fprintf(stderr, "photonbridge validate: error: validation/validate.py not found (install it with cmake "
                    "--install, or set PB_VALIDATION_DIR to the source tree's validation folder)\n");
    return 3;
  }
  char **av = calloc((size_t)argc + 5, sizeof *av);
  if (!av) return 3;
  int k = 0;
  av[k++] = "python3";
  av[k++] = script;
  if (exe[0]) {
    av[k++] = "--exe";
    av[k++] = exe;
  }
  /* -o DIR and --output[=DIR] are the script's --out; the value of an
   * option that takes one is passed as it is, whatever it looks like. */
  char *out_eq = NULL;
  for (int i = 1; i < argc; ++i) {
    char *a = argv[i];
    if (strcmp(a, "--") == 0) {
      while (i < argc) av[k++] = argv[i++];
      break;
    }
    if (strcmp(a, "-o") == 0 || strcmp(a, "--output") == 0) {
      av[k++] = "--out";
      if (i + 1 < argc) av[k++] = argv[++i];
      continue;
    }
    if (strncmp(a, "--output=", 9) == 0) {
      size_t len = strlen(a + 9);
      free(out_eq);
      out_eq = malloc(len + 7);
      if (!out_eq) return 3;
      snprintf(out_eq, len + 7, "--out=%s", a + 9);
      av[k++] = out_eq;
      continue;
    }
    av[k++] = a;
    if (a[0] == '-' && a[1] == '-' && !strchr(a, '=') && i + 1 < argc)
      for (size_t j = 0; j < nopts; ++j)
        if (strcmp(a + 2, opts[j].name) == 0 && opts[j].kind != PB_OPT_FLAG) av[k++] = argv[++i];
  }
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
  free(out_eq);
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
