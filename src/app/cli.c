#include "app/cli.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#include "app/color_opts.h"
#include "core/log.h"
#include "gpu/gpu.h"

const char *const pb_light_units_names[] = {"standard", "unitless", NULL};

/* Levenshtein distance of a and b (at most 63 characters each; longer
 * words count as far apart). */
static size_t edit_distance(const char *a, size_t la, const char *b, size_t lb) {
  enum { M = 64 };
  if (la >= M || lb >= M) return M;
  size_t row[M];
  for (size_t j = 0; j <= lb; ++j) row[j] = j;
  for (size_t i = 1; i <= la; ++i) {
    size_t diag = row[0];
    row[0] = i;
    for (size_t j = 1; j <= lb; ++j) {
      size_t up = row[j];
      size_t best = diag + (a[i - 1] != b[j - 1]);
      if (up + 1 < best) best = up + 1;
      if (row[j - 1] + 1 < best) best = row[j - 1] + 1;
      row[j] = best;
      diag = up;
    }
  }
  return row[lb];
}

const char *pb_cli_closest(const char *word, size_t len, const char *const *names, size_t count, size_t stride) {
  const char *best = NULL;
  size_t best_d = 3; /* suggestions within 2 edits only */
  for (size_t i = 0; i < count; ++i) {
    const char *n = *(const char *const *)((const char *)names + i * stride);
    size_t d = edit_distance(word, len, n, strlen(n));
    if (d < best_d) best_d = d, best = n;
  }
  return best;
}

/* " (one of: a, b, c)" of a choice option, into buf. */
static const char *choice_list(const pb_opt *o, char *buf, size_t size) {
  size_t k = (size_t)snprintf(buf, size, "one of: ");
  for (int i = 0; o->choices[i] && k < size; ++i)
    k += (size_t)snprintf(buf + k, size - k, "%s%s", i ? ", " : "", o->choices[i]);
  return buf;
}

static const pb_opt *find_long(const pb_opt *o, size_t n, const char *name,
                               size_t len) {
  for (size_t i = 0; i < n; ++i)
    if (strlen(o[i].name) == len && strncmp(o[i].name, name, len) == 0)
      return &o[i];
  return NULL;
}

static pb_result set_value(const pb_command *cmd, const pb_opt *o,
                           const char *v) {
  char *end = NULL;
  switch (o->kind) {
  case PB_OPT_FLAG:
    *(int *)o->target = 1;
    return PB_OK;
  case PB_OPT_FLAG_CLEAR:
    *(int *)o->target = 0;
    return PB_OK;
  case PB_OPT_STRING:
    *(const char **)o->target = v;
    return PB_OK;
  case PB_OPT_CHOICE:
    for (int i = 0; o->choices[i]; ++i)
      if (strcmp(o->choices[i], v) == 0) {
        *(int *)o->target = i;
        return PB_OK;
      }
  {
    char list[512];
    int count = 0;
    while (o->choices[count]) ++count;
    const char *near = pb_cli_closest(v, strlen(v), o->choices, (size_t)count, sizeof *o->choices);
    if (near)
      return pb_fail(PB_ERR_USAGE, "%s: --%s: unknown value '%s': did you mean '%s'? (%s)", cmd->name, o->name, v,
                     near, choice_list(o, list, sizeof list));
    return pb_fail(PB_ERR_USAGE, "%s: --%s: unknown value '%s' (%s)", cmd->name, o->name, v,
                   choice_list(o, list, sizeof list));
  }
  case PB_OPT_U32:
  case PB_OPT_U64: {
    errno = 0;
    if (v[0] == '-')
      return pb_fail(PB_ERR_USAGE, "%s: --%s: '%s' is not a non-negative integer",
                     cmd->name, o->name, v);
    unsigned long long x = strtoull(v, &end, 10);
    if (errno || end == v || *end)
      return pb_fail(PB_ERR_USAGE, "%s: --%s: '%s' is not a non-negative integer",
                     cmd->name, o->name, v);
    if ((o->min != 0 || o->max != 0) &&
        ((double)x < o->min || (double)x > o->max))
      return pb_fail(PB_ERR_USAGE, "%s: --%s: %llu is outside [%.0f, %.0f]",
                     cmd->name, o->name, x, o->min, o->max);
    if (o->kind == PB_OPT_U32) {
      if (x > UINT32_MAX)
        return pb_fail(PB_ERR_USAGE, "%s: --%s: %llu is too large", cmd->name,
                       o->name, x);
      *(uint32_t *)o->target = (uint32_t)x;
    } else {
      *(uint64_t *)o->target = (uint64_t)x;
    }
    return PB_OK;
  }
  case PB_OPT_FLOAT: {
    errno = 0;
    double x = strtod(v, &end);
    if (errno || end == v || *end || !isfinite(x))
      return pb_fail(PB_ERR_USAGE, "%s: --%s: '%s' is not a number", cmd->name,
                     o->name, v);
    if ((o->min != 0 || o->max != 0) && (x < o->min || x > o->max))
      return pb_fail(PB_ERR_USAGE, "%s: --%s: %g is outside [%g, %g]",
                     cmd->name, o->name, x, o->min, o->max);
    *(double *)o->target = x;
    return PB_OK;
  }
  }
  return pb_fail(PB_ERR_INTERNAL, "bad option kind");
}

/* A word that reads as an option: "-x" or "--name", but not "-" alone, a
 * negative number ("-1", "-0.5e3") or a word with a space (options for
 * another program in one string: validate --render-args "--spp 4"). */
static int looks_like_option(const char *a) {
  if (a[0] != '-' || a[1] == 0 || strchr(a, ' ')) return 0;
  char *end = NULL;
  errno = 0;
  (void)strtod(a, &end);
  return !(end != a && *end == 0);
}

pb_result pb_cli_parse(const pb_command *cmd, int argc, char **argv,
                       const pb_opt *opts, size_t n, const char **pos,
                       size_t max_pos, size_t *pos_count, int *help) {
  return pb_cli_parse_given(cmd, argc, argv, opts, n, pos, max_pos, pos_count, help, NULL);
}

pb_result pb_cli_parse_given(const pb_command *cmd, int argc, char **argv, const pb_opt *opts, size_t n,
                             const char **pos, size_t max_pos, size_t *pos_count, int *help, unsigned char *given) {
  if (given) memset(given, 0, n);
  *pos_count = 0;
  *help = 0;
  int only_pos = 0;
  for (int i = 1; i < argc; ++i) {
    const char *a = argv[i];
    const pb_opt *o = NULL;
    const char *val = NULL;
    if (!only_pos && strcmp(a, "--") == 0) {
      only_pos = 1;
      continue;
    }
    if (!only_pos && (strcmp(a, "--help") == 0 || strcmp(a, "-h") == 0)) {
      *help = PB_HELP_USER;
      return PB_OK;
    }
    if (!only_pos && strcmp(a, "--help-all") == 0) {
      *help = PB_HELP_ALL;
      return PB_OK;
    }
    if (!only_pos && a[0] == '-' && a[1] == '-') {
      const char *name = a + 2;
      const char *eq = strchr(name, '=');
      size_t len = eq ? (size_t)(eq - name) : strlen(name);
      o = find_long(opts, n, name, len);
      if (!o) {
        const char *near = pb_cli_closest(name, len, &opts[0].name, n, sizeof *opts);
        if (near)
          return pb_fail(PB_ERR_USAGE, "%s: unknown option '%.*s': did you mean '--%s'? (see '%s --help')",
                         cmd->name, (int)(len + 2), a, near, cmd->name);
        return pb_fail(PB_ERR_USAGE, "%s: unknown option '%.*s' (see '%s --help')",
                       cmd->name, (int)(len + 2), a, cmd->name);
      }
      if (eq) {
        if (o->kind == PB_OPT_FLAG || o->kind == PB_OPT_FLAG_CLEAR)
          return pb_fail(PB_ERR_USAGE, "%s: --%s takes no value", cmd->name,
                         o->name);
        val = eq + 1;
      }
    } else if (!only_pos && a[0] == '-' && a[1] && a[2] == 0) {
      for (size_t k = 0; k < n; ++k)
        if (opts[k].short_name == a[1]) o = &opts[k];
      if (!o)
        return pb_fail(PB_ERR_USAGE, "%s: unknown option '%s' (see '%s --help')",
                       cmd->name, a, cmd->name);
    } else {
      if (*pos_count >= max_pos)
        return pb_fail(PB_ERR_USAGE, "%s: unexpected argument '%s'", cmd->name, a);
      pos[(*pos_count)++] = a;
      continue;
    }
    if (o->kind != PB_OPT_FLAG && o->kind != PB_OPT_FLAG_CLEAR && !val) {
      if (i + 1 >= argc)
        return pb_fail(PB_ERR_USAGE, "%s: --%s needs a value", cmd->name, o->name);
      /* `--png --width 96`: the next word is an option, not this one's
       * value. "-" (stdout) and negative numbers are values; any other
       * value that begins with '-' must be written --name=VALUE. */
      if (looks_like_option(argv[i + 1]))
        return pb_fail(PB_ERR_USAGE, "%s: --%s needs a value, got the option '%s' (write --%s=VALUE for a value that starts with '-')",
                       cmd->name, o->name, argv[i + 1], o->name);
      val = argv[++i];
    }
    pb_result r = set_value(cmd, o, val);
    if (r != PB_OK) return r;
    if (given) given[o - opts] = 1;
  }
  return PB_OK;
}

void pb_cli_wrap(FILE *f, const char *text, int at, int indent, int width) {
  int col = at;
  const char *p = text;
  int first_word = 1;
  while (*p) {
    while (*p == ' ') ++p;
    if (!*p) break;
    size_t len = strcspn(p, " ");
    if (!first_word && col + 1 + (int)len > width) {
      fprintf(f, "\n%*s", indent, "");
      col = indent;
    } else if (!first_word) {
      fputc(' ', f);
      ++col;
    }
    fwrite(p, 1, len, f);
    col += (int)len;
    p += len;
    first_word = 0;
  }
}

static const char *const group_order[] = {"Output",   "Sampling",  "Renderers", "Photons", "Filtering", "Animation",
                                          "Colour",   "Scene",     "Device",  "Reporting", "Blender add-on",
                                          "Options",  NULL};

enum { HELP_WIDTH = 80, HELP_COLUMN = 28 };

static const char *group_of(const pb_opt *o) { return o->group ? o->group : "Options"; }

/* Details: every line as written, one wider than the help wrapped at its
 * spaces under its own indentation. */
static void print_details(FILE *f, const char *d) {
  while (*d) {
    size_t len = strcspn(d, "\n");
    int ind = (int)strspn(d, " ");
    if ((int)len <= HELP_WIDTH) {
      fwrite(d, 1, len, f);
    } else {
      char *line = malloc(len + 1);
      if (!line) return;
      memcpy(line, d, len);
      line[len] = 0;
      fprintf(f, "%*s", ind, "");
      pb_cli_wrap(f, line + ind, ind, ind, HELP_WIDTH);
      free(line);
    }
    fputc('\n', f);
    d += len;
    if (*d == '\n') ++d;
  }
}

static void print_option(FILE *f, const pb_opt *o) {
  char lhs[96];
  int k = 0;
  if (o->short_name) k = snprintf(lhs, sizeof lhs, "-%c, ", o->short_name);
  snprintf(lhs + k, sizeof lhs - (size_t)k, "--%s%s%s", o->name, o->metavar ? " " : "",
           o->metavar ? o->metavar : "");
  int w = 2 + (int)strlen(lhs);
  fprintf(f, "  %s", lhs);
  if (w + 1 > HELP_COLUMN) {
    fprintf(f, "\n%*s", HELP_COLUMN, "");
  } else {
    fprintf(f, "%*s", HELP_COLUMN - w, "");
  }
  char text[2048];
  size_t n = (size_t)snprintf(text, sizeof text, "%s", o->help);
  if (o->kind == PB_OPT_CHOICE && n < sizeof text) {
    n += (size_t)snprintf(text + n, sizeof text - n, " {");
    for (int c = 0; o->choices[c] && n < sizeof text; ++c)
      n += (size_t)snprintf(text + n, sizeof text - n, "%s%s", c ? ", " : "", o->choices[c]);
    if (n < sizeof text) snprintf(text + n, sizeof text - n, "}");
  }
  pb_cli_wrap(f, text, HELP_COLUMN, HELP_COLUMN, HELP_WIDTH);
  fputc('\n', f);
}

/* The options of one heading at this level; returns how many. */
static size_t print_group(FILE *f, int level, const char *group, const pb_opt *opts, size_t n) {
  size_t shown = 0;
  for (size_t i = 0; i < n; ++i) {
    if (strcmp(group_of(&opts[i]), group) != 0) continue;
    if (opts[i].advanced && level < PB_HELP_ALL) continue;
    if (!shown++) fprintf(f, "\n%s:\n", group);
    print_option(f, &opts[i]);
  }
  return shown;
}

void pb_cli_print_help(FILE *f, int level, const pb_command *cmd, const pb_opt *opts, size_t n,
                       const char *details) {
  char head[512];
  snprintf(head, sizeof head, "usage: photonbridge %s %s", cmd->name, cmd->usage);
  int ind = (int)strlen("usage: photonbridge ") + (int)strlen(cmd->name) + 1;
  pb_cli_wrap(f, head, 0, ind < 40 ? ind : 8, HELP_WIDTH);
  fputs("\n\n", f);
  pb_cli_wrap(f, cmd->summary, 0, 0, HELP_WIDTH);
  fputc('\n', f);
  if (details) {
    fputc('\n', f);
    print_details(f, details);
  }
  for (const char *const *g = group_order; *g; ++g)
    if (strcmp(*g, "Options") != 0) print_group(f, level, *g, opts, n);
  /* Headings outside the usual list, in the order of first use. */
  for (size_t i = 0; i < n; ++i) {
    const char *g = group_of(&opts[i]);
    int known = 0, seen = 0;
    for (const char *const *k = group_order; *k; ++k) known |= strcmp(*k, g) == 0;
    for (size_t j = 0; j < i; ++j) seen |= strcmp(group_of(&opts[j]), g) == 0;
    if (!known && !seen) print_group(f, level, g, opts, n);
  }
  size_t advanced = 0;
  for (size_t i = 0; i < n; ++i) advanced += opts[i].advanced != 0;
  print_group(f, level, "Options", opts, n);
  fprintf(f, "\nHelp:\n");
  fprintf(f, "  %-*s", HELP_COLUMN - 2, "-h, --help");
  pb_cli_wrap(f, "this help", HELP_COLUMN, HELP_COLUMN, HELP_WIDTH);
  fputc('\n', f);
  if (advanced) {
    char more[160];
    if (level < PB_HELP_ALL)
      snprintf(more, sizeof more, "also the %zu advanced options (algorithm choices, benchmarks, ablations, tuning)",
               advanced);
    else
      snprintf(more, sizeof more, "this help with the advanced options (as now)");
    fprintf(f, "  %-*s", HELP_COLUMN - 2, "--help-all");
    pb_cli_wrap(f, more, HELP_COLUMN, HELP_COLUMN, HELP_WIDTH);
    fputc('\n', f);
  }
}

void pb_cli_warn_cpu_device(const char *cmd, pb_gpu *g) {
  if (g && pb_gpu_get_limits(g)->cpu)
    pb_log_warn("%s: the GPU pipeline runs on %s, a CPU Vulkan device (no GPU driver was found or chosen): much "
                "slower than on a GPU (see 'photonbridge info --devices')", cmd, pb_gpu_device_name(g));
}

/* Devices `batch` keeps between its jobs, each with the description it was
 * made from (presentation hooks are never kept: `view` makes its own). */
enum { KEPT_MAX = 4 };
static struct kept_gpu {
  pb_gpu *g;
  pb_gpu_desc d;
  int busy;
  pb_gpu_pipeline_stats at_open;
} kept[KEPT_MAX];
static int keeping;
static uint64_t job_created, job_reused; /* pipelines of kept devices since the last reading */

static int same_desc(const pb_gpu_desc *a, const pb_gpu_desc *b) {
  return a->device_set == b->device_set && (!a->device_set || a->device == b->device) &&
         a->validation == b->validation && a->max_timestamps == b->max_timestamps &&
         a->memory_limit == b->memory_limit && a->traversal == b->traversal && !a->instance_extension_count &&
         !b->instance_extension_count && !a->can_present && !b->can_present;
}

pb_result pb_cli_gpu_open(const pb_gpu_desc *d, pb_gpu **out) {
  for (int i = 0; keeping && i < KEPT_MAX; ++i)
    if (kept[i].g && !kept[i].busy && same_desc(&kept[i].d, d)) {
      kept[i].busy = 1;
      kept[i].at_open = pb_gpu_pipeline_stats_get(kept[i].g);
      pb_gpu_restart(kept[i].g);
      *out = kept[i].g;
      return PB_OK;
    }
  pb_result r = pb_gpu_create(d, out);
  if (r != PB_OK || !keeping || d->instance_extension_count || d->can_present) return r;
  int slot = -1;
  for (int i = 0; i < KEPT_MAX && slot < 0; ++i)
    if (!kept[i].g) slot = i;
  for (int i = 0; i < KEPT_MAX && slot < 0; ++i) /* all taken: the first idle one goes */
    if (!kept[i].busy) {
      pb_gpu_destroy(kept[i].g);
      kept[i].g = NULL;
      slot = i;
    }
  if (slot >= 0) kept[slot] = (struct kept_gpu){.g = *out, .d = *d, .busy = 1, .at_open = pb_gpu_pipeline_stats_get(*out)};
  return PB_OK;
}

void pb_cli_gpu_close(pb_gpu *g) {
  if (!g) return;
  for (int i = 0; i < KEPT_MAX; ++i)
    if (kept[i].g == g) {
      pb_gpu_pipeline_stats now = pb_gpu_pipeline_stats_get(g);
      job_created += now.created - kept[i].at_open.created;
      job_reused += now.reused - kept[i].at_open.reused;
      kept[i].busy = 0;
      return;
    }
  pb_gpu_destroy(g);
}

void pb_cli_gpu_job_pipelines(uint64_t *created, uint64_t *reused) {
  *created = job_created, *reused = job_reused;
  job_created = job_reused = 0;
}

void pb_cli_gpu_keep(int on) {
  keeping = on;
  if (on) return;
  for (int i = 0; i < KEPT_MAX; ++i) {
    pb_gpu_destroy(kept[i].g);
    kept[i] = (struct kept_gpu){0};
  }
}

void pb_cli_warn_clip(const char *cmd, const pb_scene *s, int camera) {
  if (!s || camera < 0 || (uint32_t)camera >= s->camera_count) return;
  const pb_camera *c = &s->cameras[camera];
  float d[2];
  if (pb_camera_clip_sees(s, c, d)) return;
  char far[32] = "infinity";
  if (c->zfar > 0.0f) snprintf(far, sizeof far, "%g m", (double)c->zfar);
  pb_log_warn("%s: %s: camera '%s' sees no surface: every vertex lies %s its clip range %g m to %s (depths %g to %g m "
              "along its view): the image shows the world only (Blender: Camera > Clip Start / End)",
              cmd, s->path, c->name, d[1] < c->znear ? "nearer than" : "beyond", (double)c->znear, far,
              (double)d[0], (double)d[1]);
}

int pb_cli_exit(const pb_command *cmd, pb_result r) {
  if (r != PB_OK) {
    const char *m = pb_error_message();
    const char *name = cmd ? cmd->name : "";
    size_t nl = strlen(name);
    /* Messages made inside a command often start with its own name
     * ("serve: --socket ..."); the prefix already says it once. */
    if (nl && strncmp(m, name, nl) == 0 && m[nl] == ':' && m[nl + 1] == ' ') m += nl + 2;
    pb_progress_clear_line(); /* the error on a line of its own */
    fprintf(stderr, "photonbridge %s: error: %s\n", name, m[0] ? m : pb_result_message(r));
  }
  return pb_result_exit_code(r);
}

void pb_core_opts_apply(const pb_core_opts *c, pb_load_desc *desc) {
  if (c->quiet) pb_log_set_level(PB_LOG_QUIET);
  else if (c->verbose) pb_log_set_level(PB_LOG_VERBOSE);
  memset(desc, 0, sizeof *desc);
  desc->light_units = (pb_light_units)c->light_units;
  desc->allow_external_files = c->allow_external_files;
}

pb_result pb_cli_load_scene(const char *path, const pb_core_opts *c,
                            pb_scene *scene) {
  pb_load_desc desc;
  pb_core_opts_apply(c, &desc);
  pb_result r = pb_scene_load(path, &desc, scene);
  if (r != PB_OK) return r;
  for (uint32_t i = 0; i < scene->warning_count; ++i)
    pb_log_warn("%s: %s", path, scene->warnings[i]);
  return PB_OK;
}

pb_result pb_cli_pose(pb_scene *s, const pb_pose_opts *p, double *t) {
  if (t) *t = NAN;
  if (isnan(p->frame)) return PB_OK;
  if (!s->anim) {
    pb_log_warn("%s: --frame %g: the scene has no animation; the file's pose is used", s->path, p->frame);
    return PB_OK;
  }
  double time = p->frame / (p->fps > 0 ? p->fps : 24.0);
  if (t) *t = time;
  return pb_scene_set_time(s, time);
}

pb_result pb_cli_pick_camera(const pb_scene *s, const pb_core_opts *c,
                             int *camera, uint32_t *w, uint32_t *h) {
  *camera = pb_scene_find_camera(s, c->camera);
  if (*camera == PB_CAMERA_AMBIGUOUS) {
    char list[256];
    size_t k = 0;
    list[0] = 0;
    for (uint32_t i = 0; i < s->camera_count && k < sizeof list - 16; ++i)
      if (strcmp(s->cameras[i].name, c->camera) == 0)
        k += (size_t)snprintf(list + k, sizeof list - k, "%s%u", k ? ", " : "", i);
    return pb_fail(PB_ERR_USAGE, "%s: --camera: cameras %s are all named '%s': choose one by its number, e.g. --camera %lu (see 'photonbridge info')",
                   s->path, list, c->camera, strtoul(list, NULL, 10));
  }
  if (*camera < 0) {
    if (c->camera && c->camera[0] && !c->camera[strspn(c->camera, "0123456789")])
      return pb_fail(PB_ERR_USAGE, "%s: --camera: no camera %s (the scene has %u, numbered from 0; see 'photonbridge info')",
                     s->path, c->camera, s->camera_count);
    return pb_fail(PB_ERR_USAGE, "%s: --camera: no camera named '%s' (see 'photonbridge info')",
                   s->path, c->camera);
  }
  pb_camera_image_size(&s->cameras[*camera], c->width, c->height, w, h);
  return PB_OK;
}

pb_result pb_color_opts_open_scene(const pb_color_opts *o, const pb_scene *s, pb_color **out) {
  const pb_scene_view *sv = s ? &s->view : NULL;
  if (!sv || !sv->set) return pb_color_opts_open(o, out);
  int cli_view = o->display || o->view;
  /* The config: the command line's; else the one Blender used where this
   * machine has it; else, for a scene that names one not here, $OCIO or
   * the built-in config (which has Blender 4's AgX and Khronos PBR
   * Neutral; an older installed Blender's config may not); else the usual
   * defaults. */
  const char *config = o->ocio_config;
  if (!config && sv->config[0]) {
    if (access(sv->config, R_OK) == 0) {
      config = sv->config;
    } else {
      const char *env = getenv("OCIO");
      if (!env || !*env) config = "built-in";
      pb_log_warn("%s: the scene's OCIO config %s is not on this machine; %s%s is used", s->path, sv->config,
                  config ? "the built-in config" : "$OCIO=", config ? "" : env);
    }
  }
  pb_color_desc d = {config,
                     o->display ? o->display : sv->display,
                     o->view ? o->view : sv->view,
                     o->look ? o->look : (cli_view ? NULL : sv->look),
                     isnan(o->exposure) ? sv->exposure : o->exposure,
                     o->gamma != 0 ? o->gamma : sv->gamma,
                     PB_COLOR_PICTURE};
  pb_result r = pb_color_open(&d, out);
  if (r != PB_ERR_USAGE) return r;
  /* A name the config lacks: the scene's, or one given here? Without the
   * scene's names, a command-line name fails again and says so. A scene's
   * look the config lacks (the built-in config has Blender's Filmic and AgX
   * looks, not a custom config's) drops the look
   * only; anything else falls back to the config's defaults. */
  char why[512];
  snprintf(why, sizeof why, "%s", pb_error_message());
  pb_error_clear();
  if (!o->look && d.look && d.look[0] && strcmp(d.look, "None") != 0) {
    d.look = NULL;
    r = pb_color_open(&d, out);
    if (r != PB_ERR_USAGE) {
      if (r == PB_OK)
        pb_log_warn("%s: the scene's look '%s': %s; view '%s' is used without it", s->path, sv->look, why,
                    pb_color_view(*out));
      return r;
    }
    pb_error_clear();
  }
  d.display = o->display, d.view = o->view, d.look = o->look;
  r = pb_color_open(&d, out);
  if (r == PB_OK)
    pb_log_warn("%s: the scene's colour management (%s / %s%s%s): %s; %s / %s is used instead", s->path,
                sv->display, sv->view, sv->look[0] ? ", look " : "", sv->look, why, pb_color_display(*out),
                pb_color_view(*out));
  return r;
}
