/* pb_scene -> POV-Ray 3.7 SDL. The unit mappings and their derivations are in
 * pov.h; the tests render with POV-Ray and compare with the analytic values. */
#include "core/srgb.h"
#include "core/half.h"
#include "pov/pov.h"
#include "scene/camera.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"

/* stb_image_write's implementation lives in src/image/png.c. */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

const char *const pb_pov_quality_names[] = {"draft", "medium", "high", "direct", NULL};

/* Radiosity and photon settings per quality. Photons are written only when
 * the scene has specular paths (PB_FEATURE_SPECULAR). Cost on this machine
 * (cornell_box, 64x64, 2 threads): draft ~1 s, medium ~7 s, high ~46 s (an
 * earlier high preset, count 1600, error_bound 0.15, recursion 5, took
 * 195 s). recursion_limit bounds the diffuse bounces radiosity
 * gathers: POV-Ray's image darkens against Cycles' 64 bounces as it drops. */
typedef struct preset {
  int radiosity;
  int count, nearest_count, recursion_limit;
  double error_bound, pretrace_end, low_error_factor;
  uint32_t photons;
  int max_trace_level;
} preset;

static const preset presets[] = {
    /* draft  */ {1, 50, 5, 2, 1.0, 0.04, 0.5, 20000, 10},
    /* medium */ {1, 300, 10, 3, 0.4, 0.01, 0.5, 200000, 16},
    /* high   */ {1, 800, 12, 4, 0.25, 0.005, 0.4, 2000000, 24},
    /* direct */ {0, 0, 0, 0, 0, 0, 0, 0, 16},
};

double pb_pov_point_color_scale(double f) { return 1.0 / (2.0 * M_PI * f * f); }
double pb_pov_parallel_color_scale(void) { return 1.0 / M_PI; }

static double diagonal(const pb_scene *s) {
  double d2 = 0;
  for (int k = 0; k < 3; ++k) {
    double e = (double)s->bounds_max[k] - s->bounds_min[k];
    d2 += e * e;
  }
  return sqrt(d2);
}

float pb_pov_default_fade_distance(const pb_scene *s) {
  double f = 1e-3 * diagonal(s);
  return (float)(f > 1e-6 ? f : 1e-6);
}

/* ---- report ------------------------------------------------------------ */

static pb_result note(pb_pov_report *r, int unsupported, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
static pb_result note(pb_pov_report *r, int unsupported, const char *fmt, ...) {
  char buf[512];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(buf, sizeof buf, fmt, ap);
  va_end(ap);
  char **n = realloc(r->notes, (r->note_count + 1) * sizeof *n);
  if (!n) return pb_fail(PB_ERR_NOMEM, "export-pov: out of memory");
  r->notes = n;
  if (!(n[r->note_count] = strdup(buf))) return pb_fail(PB_ERR_NOMEM, "export-pov: out of memory");
  r->note_count++;
  if (unsupported) r->unsupported_count++;
  return PB_OK;
}

void pb_pov_report_destroy(pb_pov_report *r) {
  if (!r) return;
  for (uint32_t i = 0; i < r->note_count; ++i) free(r->notes[i]);
  free(r->notes);
  memset(r, 0, sizeof *r);
}

/* ---- helpers ----------------------------------------------------------- */

/* glTF (right-handed) to POV-Ray (left-handed): mirror z. */
static void vec(FILE *f, const float *v) { fprintf(f, "<%.9g,%.9g,%.9g>", v[0], v[1], -v[2]); }
static void vecd(FILE *f, const double *v) { fprintf(f, "<%.9g,%.9g,%.9g>", v[0], v[1], -v[2]); }
/* Full precision, for the camera: POV-Ray warns when its vectors are not
 * perpendicular to about 1e-10. */
static void vec17(FILE *f, const double *v) { fprintf(f, "<%.17g,%.17g,%.17g>", v[0], v[1], -v[2]); }
static void rgb(FILE *f, double r, double g, double b) { fprintf(f, "rgb <%.9g,%.9g,%.9g>", r, g, b); }

/* A name safe inside an SDL comment or string. */
static void safe_name(char *out, size_t n, const char *in) {
  size_t j = 0;
  for (size_t i = 0; in[i] && j + 1 < n; ++i) {
    unsigned char ch = (unsigned char)in[i];
    out[j++] = (ch >= 32 && ch < 127 && ch != '"' && ch != '\\' && ch != '*' && ch != '/') ? (char)ch : '_';
  }
  out[j] = 0;
}

typedef struct png_sink {
  FILE *f;
  int failed;
} png_sink;

static void png_cb(void *ctx, void *data, int size) {
  png_sink *s = ctx;
  if (size > 0 && fwrite(data, 1, (size_t)size, s->f) != (size_t)size) s->failed = 1;
}

/* The base colour texture times the base colour factor, in the texture's own
 * encoding (sRGB textures are decoded, scaled and re-encoded), RGB 8-bit. A
 * float texture (pb_texture.rgbah, linear) is scaled, clamped to 1 and
 * encoded as sRGB for a colour slot (POV-Ray's image_map is 8-bit here). */
static pb_result write_texture(const char *path, const pb_texture *t, const float factor[3]) {
  const size_t n = (size_t)t->width * t->height;
  uint8_t *px = malloc(n * 3);
  if (!px) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  const int identity = factor[0] == 1.0f && factor[1] == 1.0f && factor[2] == 1.0f;
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      if (t->rgbah) {
        float x = pb_half_to_float(t->rgbah[i * 4 + (size_t)k]) * factor[k];
        x = x < 0 ? 0 : x > 1 ? 1 : x;
        if (t->srgb) x = pb_linear_to_srgb(x);
        px[i * 3 + (size_t)k] = (uint8_t)(x * 255.0f + 0.5f);
        continue;
      }
      uint8_t v = t->rgba8[i * 4 + (size_t)k];
      if (!identity) {
        float x = v / 255.0f;
        if (t->srgb) x = pb_linear_to_srgb(pb_srgb_to_linear(x) * factor[k]);
        else x *= factor[k];
        x = x < 0 ? 0 : x > 1 ? 1 : x;
        v = (uint8_t)(x * 255.0f + 0.5f);
      }
      px[i * 3 + (size_t)k] = v;
    }
  FILE *f;
  char *tmp;
  pb_result r = pb_atomic_open(path, &f, &tmp);
  if (r != PB_OK) {
    free(px);
    return r;
  }
  png_sink sink = {f, 0};
  int ok = stbi_write_png_to_func(png_cb, &sink, (int)t->width, (int)t->height, 3, px, (int)t->width * 3);
  free(px);
  if (!ok || sink.failed) {
    pb_atomic_abort(f, tmp);
    return pb_fail(PB_ERR_IO, "%s: cannot write texture", path);
  }
  return pb_atomic_commit(path, f, tmp);
}

/* ---- materials ----------------------------------------------------------- */

typedef struct export_ctx {
  const pb_scene *s;
  const char *path;
  char *stem;      /* path without ".pov" */
  pb_pov_report *rep;
  int photons;
} export_ctx;

/* The base colour: the factor times `tint` (a vertex's COLOR_0, or NULL) as
 * a plain pigment, or the texture (times the factor) as an image map. */
static pb_result write_pigment(export_ctx *x, FILE *f, uint32_t mi, const pb_material *m, double filter, const float *tint) {
  if (m->base_color_tex < 0 || (uint32_t)m->base_color_tex >= x->s->texture_count) {
    double c[3];
    for (int k = 0; k < 3; ++k) c[k] = m->base_color[k] * (tint ? tint[k] : 1.0f);
    fprintf(f, "    pigment { ");
    if (filter > 0)
      fprintf(f, "rgbf <%.9g,%.9g,%.9g,%.9g>", c[0], c[1], c[2], filter);
    else
      rgb(f, c[0], c[1], c[2]);
    fprintf(f, " }\n");
    return PB_OK;
  }
  const pb_texture *t = &x->s->textures[m->base_color_tex];
  size_t len = strlen(x->stem) + 32;
  char *file = malloc(len);
  if (!file) return pb_fail(PB_ERR_NOMEM, "export-pov: out of memory");
  snprintf(file, len, "%s_m%u.png", x->stem, mi);
  pb_result r = write_texture(file, t, m->base_color);
  if (r == PB_OK) {
    x->rep->texture_files++;
    /* POV-Ray's image v runs bottom to top; the mesh's uv_vectors carry
     * (u, 1 - v). gamma: how the PNG's bytes are encoded. */
    fprintf(f, "    pigment { uv_mapping image_map { png \"%s\" gamma %s%s%s } }\n", pb_basename(file),
            t->srgb ? "srgb" : "1.0", t->nearest ? "" : " interpolate 2", filter > 0 ? " filter all 1" : "");
    if (t->wrap_s != PB_WRAP_REPEAT || t->wrap_t != PB_WRAP_REPEAT)
      r = note(x->rep, 1, "texture '%s': wrap mode %s written as repeat (POV-Ray image maps tile)", t->name,
               (t->wrap_s == PB_WRAP_MIRROR || t->wrap_t == PB_WRAP_MIRROR) ? "mirrored repeat" : "clamp");
  }
  free(file);
  return r;
}

static int refractive(const pb_material *m) {
  pb_bsdf_kind kind = pb_material_kind(m);
  return kind == PB_BSDF_GLASS || (kind == PB_BSDF_GLOSSY && m->transmission > 0.5f);
}

/* The material's texture block, with the base colour times `tint` (a
 * vertex's COLOR_0 in a texture_list, or NULL); `notes`: add the material's
 * export notes (once per material). Its interior is write_interior's. */
static pb_result write_material(export_ctx *x, FILE *f, uint32_t mi, const float *tint, int notes) {
  const pb_material *m = &x->s->materials[mi];
  const pb_bsdf_kind kind = pb_material_kind(m);
  pb_result r = PB_OK;
  const int emissive = pb_material_is_emissive(m);

  if (m->unlit) {
    /* KHR_materials_unlit: the pigment (base colour) as emission, nothing
     * reflected; the mesh is no_radiosity (write_mesh), so it lights
     * nothing, as in the other renderers. */
    fprintf(f, "  texture {\n");
    r = write_pigment(x, f, mi, m, 0, tint);
    fprintf(f, "    finish { ambient 0 emission 1 diffuse 0 specular 0 phong 0 reflection 0 }\n  }\n");
    return r;
  }
  if (refractive(m)) {
    fprintf(f, "  texture {\n");
    r = write_pigment(x, f, mi, m, m->transmission, tint);
    fprintf(f, "    finish { ambient 0 emission 0 diffuse 0 specular 0 phong 0\n"
               "             reflection { 0, 1 fresnel on } conserve_energy }\n  }\n");
    if (notes && kind == PB_BSDF_GLOSSY && r == PB_OK)
      r = note(x->rep, 1, "material '%s': rough glass (roughness %.3g) written as smooth glass", m->name, m->roughness);
    return r;
  }
  fprintf(f, "  texture {\n");
  r = write_pigment(x, f, mi, m, 0, tint);
  if (r != PB_OK) return r;
  if (kind == PB_BSDF_MIRROR || (kind == PB_BSDF_GLOSSY && m->metallic > 0.5f)) {
    /* reflection metallic: the reflection is tinted by the pigment (F0 =
     * base colour), whitening towards grazing angles like Schlick's. */
    fprintf(f, "    finish { ambient 0 emission 0 diffuse 0 specular 0 phong 0 reflection { 1 metallic } }\n  }\n");
    if (notes && kind == PB_BSDF_GLOSSY)
      r = note(x->rep, 1, "material '%s': glossy metal (roughness %.3g) written as a mirror", m->name, m->roughness);
    return r;
  }
  /* Lambertian, optionally with emission and a specular layer. */
  double em[3] = {0, 0, 0};
  if (emissive) {
    /* POV-Ray multiplies emission by the pigment: divide it out. */
    for (int k = 0; k < 3; ++k) {
      double p = m->base_color[k] * (tint ? tint[k] : 1.0f);
      em[k] = m->emissive[k] / (p > 1e-4 ? p : 1e-4);
    }
    if (notes) {
      x->rep->emitter_count++;
      r = note(x->rep, 1,
               "material '%s': emissive (%.4g %.4g %.4g W/(m^2 sr)) shows its radiance but lights the scene "
               "only through radiosity (POV-Ray has no mesh lights)%s",
               m->name, m->emissive[0], m->emissive[1], m->emissive[2],
               m->base_color_tex >= 0 ? "; emission is divided by the factor, not the texture" : "");
    }
    if (r != PB_OK) return r;
  }
  fprintf(f, "    finish { ambient 0 emission ");
  rgb(f, em[0], em[1], em[2]);
  fprintf(f, " diffuse 1 brilliance 1 specular 0 phong 0 reflection 0");
  if (kind == PB_BSDF_GLOSSY) {
    /* A dielectric with a specular layer: a Fresnel mirror for the smooth
     * case, a highlight for the rough one; both approximate the GGX lobe. */
    double F0 = (m->ior - 1.0) / (m->ior + 1.0);
    F0 = F0 * F0 * m->specular *
         fmax(m->specular_color[0], fmax(m->specular_color[1], m->specular_color[2]));
    if (F0 > 1) F0 = 1;
    if (m->roughness < 0.2f)
      fprintf(f, "\n             reflection { %.9g, 1 fresnel on } conserve_energy", F0);
    else
      fprintf(f, "\n             specular %.9g roughness %.9g", F0, fmax(1e-4, m->roughness * m->roughness));
    if (notes)
      r = note(x->rep, 1, "material '%s': dielectric specular layer (roughness %.3g) approximated by a %s", m->name,
               m->roughness, m->roughness < 0.2f ? "Fresnel mirror" : "Blinn highlight");
  }
  fprintf(f, " }\n  }\n");
  return r;
}

/* The interior: the index of refraction of glass and of a smooth specular
 * layer, and KHR_materials_volume's absorption as a POV-Ray absorbing medium
 * (media { absorption sigma_a }: transmittance exp(-sigma_a d) over a path
 * d inside, Beer-Lambert exactly for a constant density). */
static void write_interior(const pb_material *m, int closed, FILE *f) {
  pb_bsdf_kind kind = pb_material_kind(m);
  int ior = refractive(m) || (kind == PB_BSDF_GLOSSY && m->roughness < 0.2f && !m->unlit);
  int media = closed && refractive(m) && (m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0);
  if (!ior) return;
  fprintf(f, "  interior { ior %.9g", m->ior > 0 ? m->ior : 1.5);
  if (media)
    fprintf(f, "\n    media { absorption <%.9g,%.9g,%.9g> method 3 intervals 1 samples 1,1 }\n ", m->attenuation[0],
            m->attenuation[1], m->attenuation[2]);
  fprintf(f, " }\n");
  /* POV-Ray blocks the media of an object that is not hollow. */
  if (media) fprintf(f, "  hollow on\n");
}

static pb_result material_notes(export_ctx *x, const pb_material *m) {
  pb_result r = PB_OK;
  if (x->s->colors && m->base_color_tex >= 0)
    r = note(x->rep, 1, "material '%s': vertex colours (COLOR_0) ignored on a textured material (POV-Ray cannot multiply an image map by them)",
             m->name);
  if (r == PB_OK && m->alpha_mode != PB_ALPHA_OPAQUE)
    r = note(x->rep, 1, "material '%s': alpha %s ignored (opaque)", m->name,
             m->alpha_mode == PB_ALPHA_MASK ? "mask" : "blend");
  if (r == PB_OK && m->normal_tex >= 0) r = note(x->rep, 1, "material '%s': normal map ignored", m->name);
  if (r == PB_OK && m->metallic_roughness_tex >= 0)
    r = note(x->rep, 1, "material '%s': metallic-roughness texture ignored (factors used)", m->name);
  if (r == PB_OK && m->emissive_tex >= 0)
    r = note(x->rep, 1, "material '%s': emissive texture ignored (factor used)", m->name);
  if (r == PB_OK && !m->double_sided)
    r = note(x->rep, 0, "material '%s': single-sided, rendered double-sided", m->name);
  return r;
}

/* ---- geometry ------------------------------------------------------------ */

static int cmp_edge(const void *p, const void *q) { return memcmp(p, q, 24); }

/* Whether every edge of the triangles of material mi is shared by exactly two
 * of them (a closed surface: POV-Ray may treat it as solid). */
static int closed_surface(const pb_scene *s, uint32_t mi) {
  /* Edges as (min, max) vertex pairs, counted by sorting. Vertices that
   * coincide in position but not in index (split normals) make a surface look
   * open, so positions are compared. */
  size_t n = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t)
    if (s->triangle_material[t] == mi) n += 3;
  if (n == 0) return 0;
  float (*e)[6] = malloc(n * sizeof *e);
  if (!e) return 0;
  size_t j = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (s->triangle_material[t] != mi) continue;
    for (int k = 0; k < 3; ++k) {
      const float *a = s->positions[s->triangles[t][k]], *b = s->positions[s->triangles[t][(k + 1) % 3]];
      int swap = memcmp(a, b, 12) > 0;
      memcpy(e[j], swap ? b : a, 12);
      memcpy(e[j] + 3, swap ? a : b, 12);
      ++j;
    }
  }
  qsort(e, n, sizeof *e, cmp_edge);
  int closed = 1;
  for (size_t i = 0; i < n && closed;) {
    size_t k = i + 1;
    while (k < n && memcmp(e[i], e[k], 24) == 0) ++k;
    if (k - i != 2) closed = 0;
    i = k;
  }
  free(e);
  return closed;
}

static pb_result write_mesh(export_ctx *x, FILE *f, uint32_t mi, uint32_t *remap, uint32_t *verts) {
  const pb_scene *s = x->s;
  const pb_material *m = &s->materials[mi];
  uint32_t nt = 0, nv = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (s->triangle_material[t] != mi) continue;
    ++nt;
    for (int k = 0; k < 3; ++k) {
      uint32_t v = s->triangles[t][k];
      if (remap[v] == UINT32_MAX) {
        remap[v] = nv;
        verts[nv++] = v;
      }
    }
  }
  if (nt == 0) return PB_OK;
  pb_result r = material_notes(x, m);
  if (r != PB_OK) return r;
  char name[PB_NAME_MAX];
  safe_name(name, sizeof name, m->name);
  const pb_bsdf_kind kind = pb_material_kind(m);
  const int textured = m->base_color_tex >= 0;
  fprintf(f, "\n// material %u '%s' (%s): %u triangles, %u vertices\nmesh2 {\n", mi, name,
          kind == PB_BSDF_DIFFUSE ? "diffuse" : kind == PB_BSDF_GLOSSY ? "glossy" : kind == PB_BSDF_MIRROR ? "mirror" : "glass",
          nt, nv);
  fprintf(f, "  vertex_vectors { %u", nv);
  for (uint32_t i = 0; i < nv; ++i) {
    fputs(i % 4 ? ", " : ",\n    ", f);
    vec(f, s->positions[verts[i]]);
  }
  fprintf(f, " }\n  normal_vectors { %u", nv);
  for (uint32_t i = 0; i < nv; ++i) {
    fputs(i % 4 ? ", " : ",\n    ", f);
    vec(f, s->normals[verts[i]]);
  }
  fprintf(f, " }\n");
  if (textured) {
    /* The base colour texture's uv set through its KHR_texture_transform
     * (pb_texture_uv); POV-Ray's image v runs bottom to top. */
    const pb_texture *tx = &s->textures[m->base_color_tex];
    fprintf(f, "  uv_vectors { %u", nv);
    for (uint32_t i = 0; i < nv; ++i) {
      float uv[2];
      pb_texture_uv(tx, s->uvs[verts[i]], s->uvs1 ? s->uvs1[verts[i]] : NULL, uv);
      fputs(i % 4 ? ", " : ",\n    ", f);
      fprintf(f, "<%.9g,%.9g>", uv[0], 1.0f - uv[1]);
    }
    fprintf(f, " }\n");
  }
  /* COLOR_0 on an untextured material: one texture per vertex, which
   * POV-Ray interpolates across each face (three texture indices per face). */
  const int tinted = s->colors && !textured;
  if (tinted) {
    fprintf(f, "  texture_list { %u,\n", nv);
    for (uint32_t i = 0; i < nv && r == PB_OK; ++i) r = write_material(x, f, mi, s->colors[verts[i]], i == 0);
    fprintf(f, "  }\n");
    if (r != PB_OK) return r;
  }
  fprintf(f, "  face_indices { %u", nt);
  uint32_t i = 0;
  for (uint32_t t = 0; t < s->triangle_count; ++t) {
    if (s->triangle_material[t] != mi) continue;
    fputs(i++ % 6 ? ", " : ",\n    ", f);
    uint32_t a = remap[s->triangles[t][0]], b = remap[s->triangles[t][1]], c = remap[s->triangles[t][2]];
    fprintf(f, "<%u,%u,%u>", a, b, c);
    if (tinted) fprintf(f, ", %u, %u, %u", a, b, c);
  }
  fprintf(f, " }\n");
  for (uint32_t k = 0; k < nv; ++k) remap[verts[k]] = UINT32_MAX;

  const int glass = refractive(m), closed = glass && closed_surface(s, mi);
  if (glass) {
    if (closed)
      fprintf(f, "  inside_vector <0,0,1>  // closed: solid, so refraction knows inside from outside\n");
    else
      r = note(x->rep, 1, "material '%s': glass surface is not closed; POV-Ray refracts it as a thin open mesh%s", m->name,
               m->attenuation[0] > 0 || m->attenuation[1] > 0 || m->attenuation[2] > 0 ? " without its absorbing medium" : "");
    if (r != PB_OK) return r;
  }
  if (!tinted && (r = write_material(x, f, mi, NULL, 1)) != PB_OK) return r;
  write_interior(m, closed, f);
  if (m->unlit) fprintf(f, "  no_radiosity  // unlit: seen, lights nothing\n");
  if (x->photons) {
    if (kind == PB_BSDF_MIRROR || glass || (kind == PB_BSDF_GLOSSY && m->metallic > 0.5f))
      fprintf(f, "  photons { target reflection on refraction %s collect off }\n", glass ? "on" : "off");
  }
  fprintf(f, "}\n");
  return PB_OK;
}

/* ---- lights and camera --------------------------------------------------- */

static pb_result write_lights(export_ctx *x, FILE *f, float fade) {
  const pb_scene *s = x->s;
  double center[3], diag = diagonal(s);
  for (int k = 0; k < 3; ++k) center[k] = 0.5 * ((double)s->bounds_min[k] + s->bounds_max[k]);
  const double kp = pb_pov_point_color_scale(fade), kd = pb_pov_parallel_color_scale();
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    char name[PB_NAME_MAX];
    safe_name(name, sizeof name, l->name);
    pb_result r = PB_OK;
    if (l->range > 0)
      r = note(x->rep, 1, "light '%s': range %.4g m ignored (POV-Ray has no cut-off; the inverse square law holds)",
               l->name, l->range);
    if (r != PB_OK) return r;
    /* Soft lights: POV-Ray's area_light is a grid of point lights, not
     * Cycles' models (scene.h); the export keeps what it can say exactly. */
    float soft;
    const char *softness = pb_light_softness(l, &soft);
    if (l->type != PB_LIGHT_POINT && l->type != PB_LIGHT_SPOT && l->type != PB_LIGHT_DIRECTIONAL) {
      if ((r = note(x->rep, 1, "light '%s': %s light not exported (the POV-Ray export writes point, spot and "
                                "directional lights)", l->name, pb_light_kind_name(l->type))) != PB_OK)
        return r;
      continue;
    }
    if (!pb_light_is_delta(l) &&
        (r = note(x->rep, 1, "light '%s': exported as a hard %s light (its %s of %.4g is ignored)", l->name,
                  l->type == PB_LIGHT_DIRECTIONAL ? "directional" : "point or spot", softness, soft)) != PB_OK)
      return r;
    if (l->type == PB_LIGHT_SPOT && l->spot_model != PB_SPOT_SMOOTHSTEP &&
        (r = note(x->rep, 1, "light '%s': Cycles' spot falloff exported as a smooth step between %.4g and %.4g "
                             "degrees", l->name, l->inner_cone * 180.0 / M_PI, l->outer_cone * 180.0 / M_PI)) != PB_OK)
      return r;
    if (l->type == PB_LIGHT_DIRECTIONAL) {
      /* E [W/m^2] -> colour E/pi; placed beyond the scene along -direction. */
      double far = 2.0 * diag + 1.0, p[3];
      for (int k = 0; k < 3; ++k) p[k] = center[k] - far * l->direction[k];
      fprintf(f, "\n// '%s': directional, E = %.9g W/m^2 x colour -> colour E/pi\nlight_source {\n  ", name,
              l->intensity);
      vecd(f, p);
      fprintf(f, "\n  color ");
      rgb(f, l->color[0] * l->intensity * kd, l->color[1] * l->intensity * kd, l->color[2] * l->intensity * kd);
      fprintf(f, "\n  parallel\n  point_at ");
      vecd(f, center);
      fprintf(f, "\n}\n");
      continue;
    }
    fprintf(f, "\n// '%s': %s, I = %.9g W/sr x colour -> colour I/(2 pi f^2), f = %.9g m\nlight_source {\n  ", name,
            l->type == PB_LIGHT_SPOT ? "spot" : "point", l->intensity, fade);
    vec(f, l->position);
    fprintf(f, "\n  color ");
    rgb(f, l->color[0] * l->intensity * kp, l->color[1] * l->intensity * kp, l->color[2] * l->intensity * kp);
    fprintf(f, "\n  fade_distance %.9g fade_power 2\n", fade);
    if (l->type == PB_LIGHT_SPOT) {
      /* cos^0 x smoothstep(cos falloff, cos radius, cos angle): exactly
       * pb_light's smoothstep(cos outer, cos inner, cos angle). */
      double target[3];
      for (int k = 0; k < 3; ++k) target[k] = (double)l->position[k] + l->direction[k];
      fprintf(f, "  spotlight radius %.9g falloff %.9g tightness 0\n  point_at ", l->inner_cone * 180.0 / M_PI,
              l->outer_cone * 180.0 / M_PI);
      vecd(f, target);
      fprintf(f, "\n");
    }
    fprintf(f, "}\n");
  }
  return PB_OK;
}

/* The camera's window (scene/camera.h) as POV-Ray vectors: ray = direction
 * + x right + y up, x, y in [-1/2, 1/2] (perspective), or from location + x
 * right + y up along direction (orthographic), scaled so that |up| = 1.
 * A lens shift puts the window's centre off the axis: direction is then not
 * perpendicular to right and up (POV-Ray warns and renders the skewed
 * window, which is the shifted lens). POV-Ray has no clip planes: znear and
 * zfar are not written (a note says so when they would cut geometry). */
static void write_camera(FILE *f, const pb_camera *c, uint32_t w, uint32_t h) {
  double ww, wh, cx, cy;
  pb_camera_window(c, w, h, &ww, &wh, &cx, &cy);
  /* Re-orthonormalise in double (the file's float basis is orthonormal to
   * ~1e-7): forward, up made perpendicular to it, right = forward x up. */
  double fw[3], up[3], rt[3], d[3], u[3], r3[3], loc[3];
  double n = 0, dot = 0;
  for (int k = 0; k < 3; ++k) n += (double)c->forward[k] * c->forward[k];
  for (int k = 0; k < 3; ++k) fw[k] = c->forward[k] / sqrt(n);
  for (int k = 0; k < 3; ++k) dot += fw[k] * c->up[k];
  n = 0;
  for (int k = 0; k < 3; ++k) {
    up[k] = c->up[k] - dot * fw[k];
    n += up[k] * up[k];
  }
  for (int k = 0; k < 3; ++k) up[k] /= sqrt(n);
  rt[0] = fw[1] * up[2] - fw[2] * up[1];
  rt[1] = fw[2] * up[0] - fw[0] * up[2];
  rt[2] = fw[0] * up[1] - fw[1] * up[0];
  for (int k = 0; k < 3; ++k) {
    u[k] = up[k];
    r3[k] = rt[k] * ww / wh;
    if (c->orthographic) {
      d[k] = fw[k];
      loc[k] = c->position[k] + rt[k] * cx + up[k] * cy;
    } else {
      d[k] = (fw[k] + rt[k] * cx + up[k] * cy) / wh;
      loc[k] = c->position[k];
    }
  }
  char name[PB_NAME_MAX];
  safe_name(name, sizeof name, c->name);
  if (c->orthographic) {
    fprintf(f,
            "\n// camera '%s': orthographic, %.9g x %.9g m, shift (%.9g, %.9g). Explicit vectors, mirrored like the\n"
            "// geometry (so the picture is not): ray from location + x right + y up along direction.\n"
            "camera {\n  orthographic\n  location ",
            name, ww, wh, c->shift[0], c->shift[1]);
    for (int k = 0; k < 3; ++k) u[k] *= wh, r3[k] *= wh;
  } else {
    fprintf(f,
            "\n// camera '%s': %.9g x %.9g deg, shift (%.9g, %.9g). Explicit vectors, mirrored like the geometry\n"
            "// (so the picture is not): ray = direction + x right + y up, x, y in [-1/2, 1/2].\n"
            "camera {\n  perspective\n  location ",
            name, 2.0 * atan(0.5 * ww) * 180.0 / M_PI, 2.0 * atan(0.5 * wh) * 180.0 / M_PI, c->shift[0], c->shift[1]);
  }
  if (c->aperture_radius > 0.0f || c->panorama != PB_CAMERA_PANO_NONE)
    fprintf(f, "// camera '%s': %s not exported (POV-Ray gets the pinhole %s camera)\n", name,
            c->panorama != PB_CAMERA_PANO_NONE ? "the panoramic projection" : "depth of field",
            c->orthographic ? "orthographic" : "perspective");
  vecd(f, loc);
  fprintf(f, "\n  right ");
  vec17(f, r3);
  fprintf(f, "\n  up ");
  vec17(f, u);
  fprintf(f, "\n  direction ");
  vec17(f, d);
  fprintf(f, "\n}\n");
}

static void write_global(FILE *f, const preset *p, int photons) {
  fprintf(f, "global_settings {\n  assumed_gamma 1.0\n  max_trace_level %d\n  adc_bailout 0.001\n"
             "  ambient_light rgb 0\n", p->max_trace_level);
  if (p->radiosity)
    fprintf(f,
            "  radiosity {\n    count %d\n    nearest_count %d\n    error_bound %.9g\n    recursion_limit %d\n"
            "    pretrace_start 0.08\n    pretrace_end %.9g\n    low_error_factor %.9g\n    gray_threshold 0\n"
            "    minimum_reuse 0.005\n    brightness 1\n    adc_bailout 0.001\n    always_sample off\n"
            "    normal off\n    media off\n  }\n",
            p->count, p->nearest_count, p->error_bound, p->recursion_limit, p->pretrace_end, p->low_error_factor);
  if (photons)
    fprintf(f, "  photons {\n    count %u\n    autostop 0\n    jitter 0.4\n    max_trace_level %d\n"
               "    adc_bailout 0.001\n    media 0\n  }\n",
            p->photons, p->max_trace_level);
  fprintf(f, "}\nbackground { rgb 0 }\n");
}

/* ---- the file -------------------------------------------------------------- */

pb_result pb_pov_export(const pb_scene *s, const pb_pov_desc *desc, const char *path, pb_pov_report *report) {
  static const pb_pov_desc zero_desc;
  if (!desc) desc = &zero_desc;
  pb_pov_report local = {0};
  pb_pov_report *rep = report ? report : &local;
  memset(rep, 0, sizeof *rep);
  if (s->triangle_count == 0) return pb_fail(PB_ERR_SCENE_EMPTY, "%s: no triangles to export", s->path ? s->path : "scene");
  if (desc->camera < 0 || (uint32_t)desc->camera >= s->camera_count)
    return pb_fail(PB_ERR_USAGE, "export-pov: camera %d does not exist (the scene has %u)", desc->camera, s->camera_count);
  if ((unsigned)desc->quality > PB_POV_DIRECT)
    return pb_fail(PB_ERR_USAGE, "export-pov: unknown quality %d", (int)desc->quality);
  if (!(desc->fade_distance >= 0) || !isfinite(desc->fade_distance))
    return pb_fail(PB_ERR_USAGE, "export-pov: fade distance must be a finite number >= 0");

  const pb_camera *cam = &s->cameras[desc->camera];
  uint32_t w, h;
  pb_camera_image_size(cam, desc->width, desc->height, &w, &h);
  rep->width = w;
  rep->height = h;
  const float fade = desc->fade_distance > 0 ? desc->fade_distance : pb_pov_default_fade_distance(s);
  rep->fade_distance = fade;
  const preset *p = &presets[(desc->quality == PB_POV_QUALITY_DEFAULT ? PB_POV_MEDIUM : desc->quality) - 1];
  const int photons = p->photons > 0 && (s->features & PB_FEATURE_SPECULAR);
  rep->photons = photons;

  export_ctx x = {s, path, NULL, rep, photons};
  size_t len = strlen(path);
  x.stem = malloc(len + 1);
  uint32_t *remap = malloc((size_t)(s->vertex_count ? s->vertex_count : 1) * sizeof *remap);
  uint32_t *verts = malloc((size_t)(s->vertex_count ? s->vertex_count : 1) * sizeof *verts);
  if (!x.stem || !remap || !verts) {
    free(x.stem);
    free(remap);
    free(verts);
    return pb_fail(PB_ERR_NOMEM, "export-pov: out of memory");
  }
  memcpy(x.stem, path, len + 1);
  if (len > 4 && strcmp(path + len - 4, ".pov") == 0) x.stem[len - 4] = 0;
  for (uint32_t i = 0; i < s->vertex_count; ++i) remap[i] = UINT32_MAX;

  FILE *f = NULL;
  char *tmp = NULL;
  pb_result r = pb_atomic_open(path, &f, &tmp);
  if (r != PB_OK) goto fail;

  fprintf(f, "// POV-Ray 3.7 scene written by photonbridge export-pov from %s\n", s->path ? s->path : "(memory)");
  fprintf(f, "// Render with the same size: povray +I%s +W%u +H%u +FE +O<out>.exr (see validation/run_povray.sh)\n",
          pb_basename(path), w, h);
  fprintf(f, "// Units (shared/VALIDATION.md): point/spot colour = I[W/sr] / (2 pi f^2) with fade_distance f =\n"
             "// %.9g m, fade_power 2 (relative error (f/d)^2 at distance d); parallel colour = E[W/m^2] / pi;\n"
             "// diffuse 1 brilliance 1 with pigment = albedo. glTF (x, y, z) is written as (x, y, -z).\n",
             fade);
  fprintf(f, "// Quality: %s%s.\n#version 3.7;\n\n",
          pb_pov_quality_names[(desc->quality == PB_POV_QUALITY_DEFAULT ? PB_POV_MEDIUM : desc->quality) - 1],
          photons ? ", photons on (specular paths)" : "");
  write_global(f, p, photons);
  write_camera(f, cam, w, h);
  r = write_lights(&x, f, fade);
  for (uint32_t mi = 0; r == PB_OK && mi < s->material_count; ++mi) r = write_mesh(&x, f, mi, remap, verts);
  if (r == PB_OK && s->anim && !isnan(desc->time))
    fprintf(f, "\n// Posed at t = %.9g s of the scene's animation (nodes, skins, morph weights).\n", desc->time);
  else if (r == PB_OK && s->anim)
    r = note(rep, 1, "%u animation(s): the scene is exported in the file's own pose (export-pov --frame N poses it)",
             s->animation_count);
  if (r == PB_OK && s->world.present)
    r = note(rep, 1, "world light not exported (the POV-Ray export has no sky or environment light)");
  if (r != PB_OK) {
    pb_atomic_abort(f, tmp);
    goto fail;
  }
  if (rep->note_count) {
    fprintf(f, "\n// Export notes:\n");
    for (uint32_t i = 0; i < rep->note_count; ++i) fprintf(f, "//   %s\n", rep->notes[i]);
  }
  r = pb_atomic_commit(path, f, tmp);
  if (r != PB_OK) goto fail;
  free(x.stem);
  free(remap);
  free(verts);
  if (!report) pb_pov_report_destroy(&local);
  return PB_OK;
fail:
  free(x.stem);
  free(remap);
  free(verts);
  pb_pov_report_destroy(rep);
  return r;
}
