/* photonbridge SUBCOMMAND [options]: dispatch only; each subcommand lives in
 * its own src/app/cmd_*.c. */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "app/cli.h"
#include "app/commands.h"
#include "core/fs.h"
#include "core/version.h"
#include "gpu/gpu.h"

static int cmd_help(int argc, char **argv);

/* Each summary fits `photonbridge help`'s 80 columns (17 for the name). */
const pb_command pb_commands[] = {
    {"help", "[SUBCOMMAND]", "List the subcommands, or show one's options.", cmd_help},
    {"info", "SCENE [options]", "Summarise a glTF scene: cameras, lights, materials, warnings.", pb_cmd_info},
    {"render", "SCENE -o OUT.exr|OUT.png [options]", "Render on the GPU (Vulkan compute photon mapping): EXR or PNG.",
     pb_cmd_render},
    {"display", "IMAGE.exr -o OUT.png [options]", "Scene-linear EXR to a PNG through an OCIO display/view/look.",
     pb_cmd_display},
    {"export-pov", "SCENE -o OUT.pov [options]", "Write the scene as POV-Ray 3.7 SDL, in matched units.",
     pb_cmd_export_pov},
    {"export-peer", "SCENE --format luxcore|mitsuba -o DIR [options]", "Write the scene for LuxCoreRender or Mitsuba 3.",
     pb_cmd_export_peer},
    {"reference", "SCENE -o OUT.exr [options]", "CPU reference renderer (path tracing, SPPM caustics) to EXR.",
     pb_cmd_reference},
    {"compare", "TEST.exr REFERENCE.exr [options]", "RMSE, relMSE, PSNR, SSIM of an image against a reference.",
     pb_cmd_compare},
    {"validate", "SCENE -o DIR [options]", "Render with every renderer and compare them: an HTML report.",
     pb_cmd_validate},
    {"batch", "JOBS|- [options]", "Render many jobs in one process, compiling pipelines once.",
     pb_cmd_batch},
    {"view", "SCENE [options]", "Interactive window: progressive refinement, fly, cameras, AOVs.", pb_cmd_view},
    {"serve", "SCENE [options]", "Persistent session of JSON-line requests (Blender's viewport).", pb_cmd_serve},
    {"settings", "[--python]", "The render settings: options, serve keys, ranges, defaults.", pb_cmd_settings},
};
const size_t pb_command_count = sizeof pb_commands / sizeof pb_commands[0];

static void usage(FILE *f) {
  fprintf(f, "photonbridge %s: physically based photon mapping for glTF scenes\n\n"
             "usage: photonbridge SUBCOMMAND [options]\n"
             "       photonbridge SUBCOMMAND --help\n"
             "       photonbridge --version\n\nsubcommands:\n",
          PB_VERSION);
  for (size_t i = 0; i < pb_command_count; ++i)
    fprintf(f, "  %-14s %s\n", pb_commands[i].name, pb_commands[i].summary);
}

static const pb_command *find(const char *name) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (strcmp(pb_commands[i].name, name) == 0) return &pb_commands[i];
  return NULL;
}

static int cmd_help(int argc, char **argv) {
  if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0 ||
                    strcmp(argv[1], "--help-all") == 0)) {
    printf("usage: photonbridge help [SUBCOMMAND]\n\n");
    usage(stdout);
    return 0;
  }
  if (argc < 2) {
    usage(stdout);
    return 0;
  }
  const pb_command *c = find(argv[1]);
  if (!c || c->run == cmd_help) {
    if (c) {
      usage(stdout);
      return 0;
    }
    const char *near = pb_cli_closest(argv[1], strlen(argv[1]), &pb_commands[0].name, pb_command_count,
                                      sizeof *pb_commands);
    if (near)
      fprintf(stderr, "photonbridge help: error: unknown subcommand '%s': did you mean '%s'?\n", argv[1], near);
    else
      fprintf(stderr, "photonbridge help: error: unknown subcommand '%s'\n", argv[1]);
    return pb_result_exit_code(PB_ERR_USAGE);
  }
  char *hv[] = {argv[1], "--help", NULL};
  return c->run(2, hv);
}

/* SIGINT/SIGTERM: remove the temporaries of outputs being written, then die
 * with the conventional status (128 + signal: 130, 143); no half-written file
 * survives. One line on stderr, "photonbridge render: interrupted by SIGINT;
 * no output written", preceded by a newline only on a terminal (to end a
 * progress bar). Everything the handler writes is prepared before it runs. */
static const char *sig_command = "";
static int sig_stderr_tty;

static void put(const char *s) {
  ssize_t ignored = write(STDERR_FILENO, s, strlen(s));
  (void)ignored;
}

static void on_signal(int sig) {
  pb_tmp_remove_all_signal_safe();
  if (sig_stderr_tty) put("\n");
  put("photonbridge");
  if (sig_command[0]) {
    put(" ");
    put(sig_command);
  }
  put(sig == SIGINT ? ": interrupted by SIGINT" : ": interrupted by SIGTERM");
  put("; ");
  put(pb_tmp_interrupt_note());
  put("\n");
  _exit(128 + sig);
}

int main(int argc, char **argv) {
  struct sigaction sa;
  memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sigaction(SIGINT, &sa, NULL);
  sigaction(SIGTERM, &sa, NULL);
  sig_stderr_tty = isatty(STDERR_FILENO);

  if (argc < 2) {
    usage(stderr);
    return pb_result_exit_code(PB_ERR_USAGE);
  }
  if (strcmp(argv[1], "--version") == 0 || strcmp(argv[1], "version") == 0) {
    printf("photonbridge %s (%s)\n", PB_VERSION, PB_GIT_DESCRIBE);
    return 0;
  }
  if (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0) {
    usage(stdout);
    return 0;
  }
  const pb_command *c = find(argv[1]);
  if (!c) {
    const char *near = pb_cli_closest(argv[1], strlen(argv[1]), &pb_commands[0].name, pb_command_count,
                                      sizeof *pb_commands);
    if (near)
      fprintf(stderr, "photonbridge: error: unknown subcommand '%s': did you mean '%s'? (see 'photonbridge help')\n",
              argv[1], near);
    else
      fprintf(stderr, "photonbridge: error: unknown subcommand '%s' (see 'photonbridge help')\n", argv[1]);
    return pb_result_exit_code(PB_ERR_USAGE);
  }
  sig_command = c->name;
  int rc = c->run(argc - 1, argv + 1);
  /* With PB_VK_VALIDATION=1 (or --validation) every validation message is an
   * error, also one reported after the last submission (e.g. an object leaked
   * at vkDestroyDevice), which no pb_gpu_submit saw. */
  uint32_t nv = pb_gpu_validation_total();
  if (nv && rc == 0) {
    fprintf(stderr, "photonbridge %s: error: Vulkan validation reported %u message%s (printed above)\n",
            c->name, nv, nv == 1 ? "" : "s");
    rc = pb_result_exit_code(PB_ERR_VULKAN);
  }
  /* Output on stdout (info, --json -) that could not be written, e.g. to a
   * full disk, is an I/O error like any other file's. */
  if ((fflush(stdout) != 0 || ferror(stdout)) && rc == 0) {
    fprintf(stderr, "photonbridge %s: error: standard output: write failed: %s\n", c->name, strerror(errno));
    rc = pb_result_exit_code(PB_ERR_IO);
  }
  return rc;
}
