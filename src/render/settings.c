/* The render settings table (settings.h): its rows, defaults, options,
 * checks, the frame's pb_render_desc and the Python module. */
#include "render/settings.h"

#include <math.h>
#include <string.h>

#include "render/estimate/estimator.h"
#include "render/photon/photon.h"
#include "render/render.h"
#include "render/photon/tracer.h"
#include "shared/pb_image_maps.h"
#include "shared/pb_knn.h"
#include "shared/pb_lbvh.h"

/* The bounds the table states as numbers are the renderer's. */
_Static_assert(PB_IMAGE_MAPS_MAX == 15, "settings.h: image_maps' bound");
_Static_assert(PB_KNN_K_MAX == 512, "settings.h: knn_k's bound");
_Static_assert(PB_LBVH_MAX_FIXED_LEAF == 4096, "settings.h: leaf_size's bound");
_Static_assert(PB_RENDER_MAX_SPECULAR_DEPTH == 64, "settings.h: max_specular_depth's bound");
_Static_assert(PB_PHOTON_BOUNCE_CAP == 255, "settings.h: photon_bounces' bound");
_Static_assert(PB_SETTING_COUNT <= 64, "pb_settings.given holds one bit a setting");

/* In pb_photon_first_bounce order from PB_FIRST_BOUNCE_TRACE. */
const char *const pb_settings_first_bounce_names[] = {"traced", "rsm", "auto", NULL};

const pb_setting_info pb_setting_table[PB_SETTING_COUNT] = {
#define X(id_, kind_, cli_, lo_, hi_, def_, surf_, flags_, group_, mv_, choices_, needs_, help_)                     \
  {.id = #id_, .cli = cli_, .kind = PB_SETTING_##kind_, .lo = lo_, .hi = hi_, .def = def_, .surfaces = surf_,        \
   .flags = flags_, .group = group_, .metavar = mv_, .choices = choices_, .needs = needs_, .help = help_,             \
   .offset = offsetof(pb_settings, id_)},
    PB_SETTINGS(X)
#undef X
};

double pb_settings_get(const pb_settings *s, int i) {
  const pb_setting_info *t = &pb_setting_table[i];
  const char *p = (const char *)s + t->offset;
  switch (t->kind) {
  case PB_SETTING_U32: return *(const uint32_t *)p;
  case PB_SETTING_F64: return *(const double *)p;
  default: return *(const int *)p;
  }
}

static void put(pb_settings *s, int i, double v) {
  const pb_setting_info *t = &pb_setting_table[i];
  char *p = (char *)s + t->offset;
  switch (t->kind) {
  case PB_SETTING_U32: *(uint32_t *)p = (uint32_t)v; break;
  case PB_SETTING_F64: *(double *)p = v; break;
  default: *(int *)p = (int)v; break;
  }
}

void pb_settings_set(pb_settings *s, int i, double v) {
  put(s, i, v);
  s->given |= 1ull << i;
}

void pb_settings_init(pb_settings *s) {
  memset(s, 0, sizeof *s);
  for (int i = 0; i < PB_SETTING_COUNT; ++i) put(s, i, pb_setting_table[i].def);
}

void pb_settings_init_live(pb_settings *s) {
  pb_settings_init(s);
  for (int i = 0; i < PB_SETTING_COUNT; ++i)
    if (pb_setting_table[i].flags & PB_SETTING_LIVE_OFF) put(s, i, 0);
}

void pb_settings_merge(pb_settings *to, const pb_settings *from) {
  for (int i = 0; i < PB_SETTING_COUNT; ++i)
    if (from->given & (1ull << i)) pb_settings_set(to, i, pb_settings_get(from, i));
}

#define GIVEN(s, id) (((s)->given & PB_SETTING_BIT(id)) != 0)

int pb_settings_needs_met(const pb_settings *s, int i) {
  const char *n = pb_setting_table[i].needs;
  if (!n) return 1;
  const char *eq = strchr(n, '=');
  for (int j = 0; j < PB_SETTING_COUNT; ++j) {
    const pb_setting_info *t = &pb_setting_table[j];
    if (strlen(t->id) != (size_t)(eq - n) || strncmp(t->id, n, (size_t)(eq - n)) != 0) continue;
    const char *name = t->choices[(int)pb_settings_get(s, j)];
    size_t len = strlen(name);
    for (const char *p = eq + 1; *p; p += strcspn(p, ",") + (p[strcspn(p, ",")] == ',')) {
      if (strncmp(p, name, len) == 0 && (p[len] == ',' || p[len] == 0)) return 1;
    }
    return 0;
  }
  return 1;
}

/* "--tracer images" or "--estimator knn or auto" of a needs column. */
static void needs_words(const char *n, char *buf, size_t cap) {
  const char *eq = strchr(n, '=');
  const char *cli = n;
  for (int j = 0; j < PB_SETTING_COUNT; ++j)
    if (strlen(pb_setting_table[j].id) == (size_t)(eq - n) &&
        strncmp(pb_setting_table[j].id, n, (size_t)(eq - n)) == 0)
      cli = pb_setting_table[j].cli;
  size_t k = (size_t)snprintf(buf, cap, "--%s ", cli);
  for (const char *p = eq + 1; *p && k < cap; ++p)
    k += *p == ',' ? (size_t)snprintf(buf + k, cap - k, " or ") : (size_t)snprintf(buf + k, cap - k, "%c", *p);
}

pb_result pb_settings_check(const char *command, const pb_settings *s, int given_needs) {
  if (s->alpha < 0 || !(s->alpha < 1))
    return pb_fail(PB_ERR_USAGE, "%s: --alpha %g must lie in (0, 1)", command, s->alpha);
  for (int i = 0; given_needs && i < PB_SETTING_COUNT; ++i) {
    if (!(s->given & (1ull << i)) || pb_settings_get(s, i) == pb_setting_table[i].def ||
        pb_settings_needs_met(s, i))
      continue;
    char words[96];
    needs_words(pb_setting_table[i].needs, words, sizeof words);
    return pb_fail(PB_ERR_USAGE, "%s: --%s needs %s", command, pb_setting_table[i].cli, words);
  }
  if (s->splat_smax != 0 && s->splat_smax < 1)
    return pb_fail(PB_ERR_USAGE, "%s: --splat-smax %g: a stretch of at least 1 (0: the default)", command,
                   s->splat_smax);
  if (!pb_estimator_built((uint32_t)s->estimator))
    return pb_fail(PB_ERR_USAGE, "%s: estimator '%s' is not built in this binary", command,
                   pb_estimator_names[s->estimator]);
  return PB_OK;
}

void pb_settings_render_desc(const pb_settings *s, int sequence, pb_render_desc *rd) {
  /* --max-bounces N: the reference's path-length limit. A photon stored at
   * its k-th bounce ends a path of k + 1 events at the eye's first smooth
   * vertex, so photons store at most N - 1; the eye's mirror/glass chain
   * before that vertex is limited to N - 1 as well (a path through both may
   * exceed N: the GPU does not count them together); 1 is direct light. */
  uint32_t bounces = s->photon_bounces, max_spec = s->max_specular_depth;
  int direct_only = s->direct_only || s->max_bounces == 1;
  if (s->max_bounces >= 2) {
    uint32_t n = s->max_bounces - 1;
    if (!bounces) bounces = n < PB_PHOTON_BOUNCE_CAP ? n : PB_PHOTON_BOUNCE_CAP;
    if (!max_spec) max_spec = n < PB_RENDER_MAX_SPECULAR_DEPTH ? n : PB_RENDER_MAX_SPECULAR_DEPTH;
  }
  /* Quality as a noise threshold unless the work is set: --iterations,
   * --spp and --time-limit render exactly what they say (benchmarks), as
   * do direct light alone (no photon maps) and sequences (their filters). */
  double nt = s->noise_threshold;
  if (!GIVEN(s, noise_threshold) &&
      (GIVEN(s, iterations) || GIVEN(s, spp) || s->time_limit > 0 || direct_only || sequence))
    nt = 0;
  if (sequence) nt = 0;
  /* A threshold or a time limit refines by photon maps: without
   * --iterations, as many as the option allows, the threshold or the time
   * ending the frame. */
  uint32_t iterations = s->iterations;
  if (!direct_only && !sequence && !GIVEN(s, iterations) && (nt > 0 || s->time_limit > 0))
    iterations = PB_SETTINGS_OPEN_ITERATIONS;
  rd->spp = s->spp;
  rd->max_specular_depth = max_spec;
  rd->glossy_path_roughness = !GIVEN(s, glossy_path_roughness) ? 0.0f
                              : s->glossy_path_roughness > 0   ? (float)s->glossy_path_roughness
                                                               : -1.0f;
  rd->direct_only = direct_only;
  rd->photons = s->photons;
  rd->iterations = iterations;
  rd->photon_bounces = bounces;
  rd->smoothing = (float)s->smoothing;
  rd->smoothing_caustic = (float)s->smoothing_caustic;
  rd->r_max = (float)s->r_max;
  rd->estimator = (pb_estimator_desc){
      .kind = (uint32_t)s->estimator,
      .knn = {.k = s->knn_k},
      .lbvh = {.constant_kernel = s->constant_kernel, .no_edge_correction = s->no_edge_correction,
               .leaf_size = s->leaf_size},
      .vsch = {.radius = (float)s->vsch_radius, .directional = s->vsch_directional ? 1u : 0u},
      .splat = {.s_l = (float)s->splat_lmax, .s_d = (float)s->splat_ntile, .s_u = (float)s->splat_smax,
                .tile = s->splat_tile}};
  rd->first_bounce = (uint32_t)(PB_FIRST_BOUNCE_TRACE + s->first_bounce);
  rd->caustic_share = !GIVEN(s, caustic_share) ? 0.0f : s->caustic_share == 0 ? -1.0f : (float)s->caustic_share;
  rd->tracer = (uint32_t)s->tracer;
  rd->image_maps = s->image_maps;
  rd->image_map_resolution = s->image_map_resolution;
  rd->bandwidth_c0 = (float)s->bandwidth_c0;
  /* A setting whose `needs` does not hold does nothing (a live session
   * keeps it for when it does). */
  rd->upsample_levels = pb_settings_needs_met(s, PB_SETTING_upsample_levels) ? s->upsample_levels : 0;
  rd->atrous_iterations = GIVEN(s, atrous_iterations) ? s->atrous_iterations : (sequence ? 4u : 0u);
  rd->atrous_gamma = !GIVEN(s, atrous_clip) ? 0.0f : s->atrous_clip > 0 ? (float)s->atrous_clip : -1.0f;
  rd->no_shading_correction = s->no_shading_correction;
  rd->progressive = s->progressive;
  rd->alpha = (float)s->alpha;
  rd->time_limit_s = sequence ? 0.0 : s->time_limit;
  rd->noise_threshold = nt;
}

/* ---- the add-on's module ---------------------------------------------------- */

static void py_string(FILE *f, const char *s) {
  if (!s) {
    fputs("None", f);
    return;
  }
  fputc('"', f);
  for (; *s; ++s) {
    if (*s == '"' || *s == '\\') fputc('\\', f);
    fputc(*s, f);
  }
  fputc('"', f);
}

static void py_number(FILE *f, pb_setting_kind kind, double v) {
  if (kind == PB_SETTING_F64) fprintf(f, "%.10g", v);
  else if (kind == PB_SETTING_BOOL) fputs(v != 0 ? "True" : "False", f);
  else fprintf(f, "%.0f", v);
}

void pb_settings_write_python(FILE *f) {
  fputs("\"\"\"The render settings of photonbridge, as its settings table declares them\n"
        "(src/render/settings.h). Generated by `photonbridge settings --python`;\n"
        "do not edit: a test compares this file with the binary's table.\n\n"
        "SETTINGS: one dict a setting, in the table's order: id (serve's JSON key),\n"
        "cli (the option, without --), kind (u32, f64, bool, choice), min and max\n"
        "(None: unchecked by range), default, choices (a choice's names, its value\n"
        "the index), needs (None, or \"SETTING=NAME,NAME\": it does something only\n"
        "with one of those choices of SETTING), surfaces (render, live, request,\n"
        "blender), advanced, group, help. A bool whose default is True has an\n"
        "option that clears it.\"\"\"\n\n"
        "SETTINGS = (\n",
        f);
  static const char *const kinds[] = {"u32", "f64", "bool", "choice"};
  static const char *const surfaces[] = {"render", "live", "request", "blender"};
  for (int i = 0; i < PB_SETTING_COUNT; ++i) {
    const pb_setting_info *t = &pb_setting_table[i];
    fputs("    {\"id\": ", f);
    py_string(f, t->id);
    fputs(", \"cli\": ", f);
    py_string(f, t->cli);
    fprintf(f, ", \"kind\": \"%s\",\n     \"min\": ", kinds[t->kind]);
    int ranged = t->lo != 0 || t->hi != 0;
    if (ranged) py_number(f, t->kind, t->lo);
    else fputs("None", f);
    fputs(", \"max\": ", f);
    if (ranged) py_number(f, t->kind, t->hi);
    else fputs("None", f);
    fputs(", \"default\": ", f);
    if (t->kind == PB_SETTING_CHOICE) py_string(f, t->choices[(int)t->def]);
    else py_number(f, t->kind, t->def);
    fputs(", \"choices\": ", f);
    if (t->choices) {
      fputc('(', f);
      for (int c = 0; t->choices[c]; ++c) {
        py_string(f, t->choices[c]);
        fputs(", ", f);
      }
      fputc(')', f);
    } else {
      fputs("None", f);
    }
    fputs(", \"needs\": ", f);
    py_string(f, t->needs);
    fputs(",\n     \"surfaces\": (", f);
    for (int b = 0; b < 4; ++b)
      if (t->surfaces & (1u << b)) fprintf(f, "\"%s\", ", surfaces[b]);
    fprintf(f, "), \"advanced\": %s, \"group\": ", t->flags & PB_SETTING_ADVANCED ? "True" : "False");
    py_string(f, t->group);
    fputs(",\n     \"help\": ", f);
    py_string(f, t->help);
    fputs("},\n", f);
  }
  fputs(")\n\nBY_ID = {s[\"id\"]: s for s in SETTINGS}\n", f);
}
