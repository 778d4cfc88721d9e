/* Command-line parsing shared by every subcommand: long options (--name VALUE
 * or --name=VALUE), short aliases, typed targets, generated --help. */
#ifndef PB_CLI_H
#define PB_CLI_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/result.h"
#include "scene/scene.h"

typedef enum pb_opt_kind {
  PB_OPT_FLAG,   /* int, set to 1 */
  PB_OPT_STRING, /* const char* */
  PB_OPT_U32,    /* uint32_t */
  PB_OPT_U64,    /* uint64_t */
  PB_OPT_FLOAT,  /* double */
  PB_OPT_CHOICE, /* int: index into `choices` (NULL-terminated) */
  PB_OPT_FLAG_CLEAR, /* int, set to 0 (--no-temporal: a setting on by default) */
} pb_opt_kind;

typedef struct pb_opt {
  const char *name;     /* long name without "--" */
  char short_name;      /* 0: none */
  pb_opt_kind kind;
  void *target;
  const char *metavar;  /* "N", "FILE", ... */
  const char *help;
  const char *const *choices; /* PB_OPT_CHOICE */
  double min, max;      /* numeric range, inclusive; both 0: unchecked */
  const char *group;    /* --help heading ("Output", "Sampling", ...); NULL:
                         * "Options". Headings print in a fixed order (cli.c),
                         * then any other in the order of first use. */
  int advanced;         /* PB_OPT_ADVANCED: listed by --help-all only
                         * (algorithm choices, benchmarks, ablations) */
} pb_opt;

enum { PB_OPT_ADVANCED = 1 };

/* The --help levels pb_cli_parse reports. */
enum { PB_HELP_NONE = 0, PB_HELP_USER = 1, PB_HELP_ALL = 2 };

typedef struct pb_command {
  const char *name;
  const char *usage;    /* "SCENE [options]" */
  const char *summary;  /* one line for `photonbridge help` */
  int (*run)(int argc, char **argv); /* argv[0] is the subcommand name */
} pb_command;

/* Parses argv[1..] against opts. Positional arguments are collected into
 * `pos` (at most max_pos). `--help`/`-h` sets *help to PB_HELP_USER,
 * `--help-all` to PB_HELP_ALL, and stops. Errors are
 * PB_ERR_USAGE with the message set. */
pb_result pb_cli_parse(const pb_command *cmd, int argc, char **argv,
                       const pb_opt *opts, size_t opt_count, const char **pos,
                       size_t max_pos, size_t *pos_count, int *help);

/* pb_cli_parse, and given[i] set to 1 for each opts[i] the command line
 * gave (given: n entries, zeroed here; render/settings.h's rows record
 * which settings the user set). */
pb_result pb_cli_parse_given(const pb_command *cmd, int argc, char **argv, const pb_opt *opts, size_t opt_count,
                             const char **pos, size_t max_pos, size_t *pos_count, int *help, unsigned char *given);

/* The name closest to word[0, len) within two edits (Levenshtein), or NULL:
 * the "did you mean" of a misspelt subcommand, option or value. names: the
 * first of count `const char *`, stride bytes apart (an array of names, or
 * the name field of an array of structs). */
const char *pb_cli_closest(const char *word, size_t len, const char *const *names, size_t count, size_t stride);

/* The help of cmd at 80 columns: usage, summary, details (each line wider
 * than 80 wrapped at spaces, under its own indentation), then the options
 * under their headings. level PB_HELP_USER leaves out the advanced ones
 * (and says how many, and --help-all); PB_HELP_ALL lists them too. */
void pb_cli_print_help(FILE *f, int level, const pb_command *cmd, const pb_opt *opts,
                       size_t opt_count, const char *details);

/* Writes text wrapped at width columns: the first line continues from
 * column `at` (already written), the others start with indent spaces.
 * Breaks at spaces only (a word longer than the line stays whole). */
void pb_cli_wrap(FILE *f, const char *text, int at, int indent, int width);

/* Prints the one-line error for r (with the recorded message) and returns the
 * process exit code from the result table. */
int pb_cli_exit(const pb_command *cmd, pb_result r);

/* A CPU Vulkan device (lavapipe, SwiftShader) runs the GPU pipeline much
 * slower than a GPU: one warning line on stderr saying so, naming the
 * device, for `cmd` (render, view, serve). Nothing for a GPU. */
typedef struct pb_gpu pb_gpu;
void pb_cli_warn_cpu_device(const char *cmd, pb_gpu *g);

/* The Vulkan device of a rendering command. pb_cli_gpu_open makes it, and
 * pb_cli_gpu_close destroys it, except while `batch` keeps devices
 * (pb_cli_gpu_keep(1)): then close keeps it, with its compiled pipelines,
 * for the next job, and open hands a kept device made from an equal
 * description back (its per-render statistics restarted: pb_gpu_restart).
 * pb_cli_gpu_keep(0) destroys the kept devices. */
typedef struct pb_gpu_desc pb_gpu_desc;
pb_result pb_cli_gpu_open(const pb_gpu_desc *d, pb_gpu **out);
void pb_cli_gpu_close(pb_gpu *g);
void pb_cli_gpu_keep(int on);
/* Pipelines created and taken from the cache by kept devices between their
 * open and close since the last call (`batch`'s line for each job). */
void pb_cli_gpu_job_pipelines(uint64_t *created, uint64_t *reused);

/* One warning line when camera `camera` of s can see no surface because its
 * clip range excludes every vertex (pb_camera_clip_sees): the image would
 * be the world alone, without a word. */
void pb_cli_warn_clip(const char *cmd, const pb_scene *s, int camera);

/* The options every rendering subcommand takes. */
typedef struct pb_core_opts {
  const char *out;      /* -o */
  uint32_t width, height; /* 0: from the camera */
  const char *camera;   /* NULL: first camera */
  uint64_t seed;
  const char *json;     /* --json FILE */
  int light_units;      /* pb_light_units */
  int allow_external_files;
  int quiet, verbose;
} pb_core_opts;

/* The scene-loading options (shared by info and every renderer). */
#define PB_SCENE_OPTS(c)                                                       \
  {"light-units", 0, PB_OPT_CHOICE, &(c)->light_units, "MODE",                 \
   "how KHR_lights_punctual intensities were exported: standard (photometric, "\
   "Blender's default) or unitless", pb_light_units_names, 0, 0, "Scene", 0},              \
  {"allow-external-files", 0, PB_OPT_FLAG, &(c)->allow_external_files, NULL,   \
   "allow buffer/image URIs outside the scene's folder", NULL, 0, 0, "Scene", 0},          \
  {"json", 0, PB_OPT_STRING, &(c)->json, "FILE",                               \
   "write machine-readable statistics to FILE ('-' for stdout)", NULL, 0, 0, "Reporting", 0},  \
  {"quiet", 'q', PB_OPT_FLAG, &(c)->quiet, NULL, "errors only", NULL, 0, 0, "Reporting", 0},    \
  {"verbose", 'v', PB_OPT_FLAG, &(c)->verbose, NULL, "more detail", NULL, 0, 0, "Reporting", 0}

/* The image options every rendering subcommand takes; out_help: what -o
 * writes; width_help: --width's help (its default). */
#define PB_RENDER_OPTS(c) PB_RENDER_OPTS_OUT(c, "output file (EXR)")
#define PB_WIDTH_HELP_640 "image width (default 640, or from --height and the camera's aspect)"
#define PB_RENDER_OPTS_OUT(c, out_help) PB_RENDER_OPTS_OUT_W(c, out_help, PB_WIDTH_HELP_640)
#define PB_RENDER_OPTS_OUT_W(c, out_help, width_help)                          \
  {"output", 'o', PB_OPT_STRING, &(c)->out, "OUT", out_help, NULL, 0, 0, "Output", 0},      \
  {"width", 0, PB_OPT_U32, &(c)->width, "W", width_help, NULL, 1, 16384, "Output", 0},      \
  {"height", 0, PB_OPT_U32, &(c)->height, "H",                                 \
   "image height (default from the camera's aspect ratio)", NULL, 1, 16384, "Output", 0},  \
  {"camera", 0, PB_OPT_STRING, &(c)->camera, "NAME|N",                         \
   "camera to render, by name or by its number in 'info' (default: 0)", NULL, \
   0, 0, "Output", 0},                                                                      \
  {"seed", 0, PB_OPT_U64, &(c)->seed, "N", "random seed (default 0)", NULL,   \
   0, 0, "Sampling", 0},                                                                      \
  PB_SCENE_OPTS(c)

extern const char *const pb_light_units_names[];

/* --frame N and --fps F of the single-image commands (reference,
 * export-pov): the scene's animation (nodes, skins, morph weights) posed at
 * t = N / F seconds, as `render --frames N:N` does. frame: NAN when not
 * given (the file's own pose). */
typedef struct pb_pose_opts {
  double frame, fps;
} pb_pose_opts;
#define PB_POSE_OPTS(p)                                                        \
  {"frame", 0, PB_OPT_FLOAT, &(p)->frame, "N",                                 \
   "pose the scene's animation at frame N (t = N / fps; default: the file's "  \
   "own pose)", NULL, 0, 0, "Animation", 0},                                                   \
  {"fps", 0, PB_OPT_FLOAT, &(p)->fps, "F",                                     \
   "--frame: frames per second (default 24)", NULL, 0.001, 1e6, "Animation", 0}

/* Poses s per --frame / --fps (nothing without --frame; a warning when the
 * scene has no animation). *t (may be NULL): the time posed at, NAN when
 * not posed. */
pb_result pb_cli_pose(pb_scene *s, const pb_pose_opts *p, double *t);

/* Applies --quiet/--verbose and fills a load desc from the core options. */
void pb_core_opts_apply(const pb_core_opts *c, pb_load_desc *desc);

/* Loads the scene named on the command line with the core options. */
pb_result pb_cli_load_scene(const char *path, const pb_core_opts *c,
                            pb_scene *scene);

/* Picks the camera (--camera) and image size (--width/--height). */
pb_result pb_cli_pick_camera(const pb_scene *s, const pb_core_opts *c,
                             int *camera, uint32_t *w, uint32_t *h);

/* The subcommand table (main.c). */
extern const pb_command pb_commands[];
extern const size_t pb_command_count;

#endif
