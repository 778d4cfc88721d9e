/* PHOTONBRIDGE_blender lights and world -> pb_light, pb_world (see
 * blender_lights.h). Conventions, each measured with Cycles 3.4.1 on this
 * machine (a Diffuse BSDF plane of albedo 0.8, direct light only, 256 spp;
 * the scenes are made by exporters/blender/light_scenes.py and the committed
 * renders are checked by the lights_cycles_ref and lights_cycles_gpu tests):
 *
 *  point, spot: I = P / (4 pi) W/sr (Cycles 3.4 kernel/light/light.h:
 *    eval_fac = invarea / (4 pi) on a disc of area pi r^2 = 1 / invarea);
 *    radius r > 0 is that disc, facing the lit point (on the axis at 1 m,
 *    r = 0.3 m: Cycles 1.8591, I / (1 + r^2) gives 1.8590).
 *  spot: Cycles' spot_light_attenuation, including its cos factor (scene.h
 *    PB_SPOT_CYCLES), the cone half-angle spot_size / 2 (blender/light.cpp
 *    sets spot_angle = spot_size, scene/light.cpp takes cos(spot_angle / 2)).
 *  sun: irradiance S W/m^2; angle > 0 is the disc of radius tan(angle / 2)
 *    at unit distance (distant_light_sample, pdf = eval_fac = invarea /
 *    cos^3): 10 degrees, normal incidence: Cycles 0.762487, the closed form
 *    0.8/pi S 2 (sqrt(1 + R^2) - 1) / R^2 gives 0.762486.
 *  area: radiance P / (4 A) (eval_fac = invarea / 4), A = x y (square,
 *    rectangle) or pi x y / 4 (disc, ellipse): a 100 W 0.5 m square 1 m
 *    above the plane gives 5.8753 in Cycles against 5.8782 from the form
 *    factor (P / (pi A) would give 7.484); a 0.5 m disc 5.99131 against
 *    5.99172. The contract's first draft said P / (pi A); it is corrected.
 *    Spread: scene/light.cpp's tan_spread and normalize_spread (scene.h).
 *  world: radiance = colour x strength (a uniform world of 1 over the plane
 *    gives 0.800002, i.e. 0.8 x 1); an Environment Texture replaces the
 *    colour, times its own strength; its direction mapping (scene.h
 *    pb_world) and the Mapping node's Euler XYZ (world.c) were checked with
 *    a map whose texels hold their own (u, v): every pixel of a Cycles
 *    render within 0.003 of the prediction, with and without rotation. */
#include "core/srgb.h"
#include "scene/blender_lights.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"
#include "image/decode.h"
#include "image/hdr.h"
#include "image/image.h"
#include "scene/world.h"

/* Defaults of a missing member: the contract's (PHOTONBRIDGE_blender.md),
 * which are Blender 3.4's startup-file values. */
#define DEF_POWER 1000.0
#define DEF_RADIUS 0.1
#define DEF_SPOT_SIZE 0.785398
#define DEF_SPOT_BLEND 0.15
#define DEF_SUN_ANGLE 0.00918043
#define DEF_AREA_SIZE 1.0
#define DEF_WORLD_COLOR 0.050876

static const double PI = 3.14159265358979323846;
/* Blender stores angles as floats: its pi is 3.14159274. Ranges that end at
 * pi accept that (and the value is clamped to pi). */
static const double PI_F32 = 3.1415927410125732;

typedef struct rd {
  const char *path;  /* scene file */
  const char *where; /* JSON path of the object being read */
} rd;

static pb_result type_error(const rd *r, const char *key, const char *want) {
  return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s: not %s", r->path, r->where, key, want);
}

/* An optional number in [lo, hi] (open ends where *_open), default dflt.
 * `range` says the allowed range in words for the error. */
static pb_result number(const rd *r, const pb_gltf_value *o, const char *key, double dflt, double lo, int lo_open,
                        double hi, int hi_open, const char *range, double *out) {
  const pb_gltf_value *v = pb_gltf_value_get(o, key);
  *out = dflt;
  if (!v) return PB_OK;
  if (v->type != PB_GLTF_NUMBER) return type_error(r, key, "a number");
  double x = v->number;
  if (!isfinite(x))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s: %g is not a finite number", r->path, r->where, key, x);
  if (x < lo || (lo_open && x == lo) || x > hi || (hi_open && x == hi))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s: %.9g is not %s", r->path, r->where, key, x, range);
  *out = x;
  return PB_OK;
}

static pb_result boolean(const rd *r, const pb_gltf_value *o, const char *key, int dflt, int *out) {
  const pb_gltf_value *v = pb_gltf_value_get(o, key);
  *out = dflt;
  if (!v) return PB_OK;
  if (v->type != PB_GLTF_BOOL) return type_error(r, key, "true or false");
  *out = v->boolean;
  return PB_OK;
}

/* An optional string, NULL when absent. */
static pb_result string(const rd *r, const pb_gltf_value *o, const char *key, const char **out) {
  const pb_gltf_value *v = pb_gltf_value_get(o, key);
  *out = NULL;
  if (!v) return PB_OK;
  if (v->type != PB_GLTF_STRING) return type_error(r, key, "a string");
  *out = v->string;
  return PB_OK;
}

/* An optional array of n finite numbers (>= 0 when non_negative). */
static pb_result vector(const rd *r, const pb_gltf_value *o, const char *key, int n, int non_negative,
                        const double *dflt, double *out) {
  const pb_gltf_value *v = pb_gltf_value_get(o, key);
  for (int k = 0; k < n; ++k) out[k] = dflt[k];
  if (!v) return PB_OK;
  if (v->type != PB_GLTF_ARRAY || v->count < (size_t)n) {
    char want[48];
    snprintf(want, sizeof want, "an array of %d numbers", n);
    return type_error(r, key, want);
  }
  for (int k = 0; k < n; ++k) {
    const pb_gltf_value *x = &v->items[k];
    if (x->type != PB_GLTF_NUMBER)
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s[%d]: not a number", r->path, r->where, key, k);
    if (!isfinite(x->number) || (non_negative && x->number < 0))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s[%d]: %.9g is not a %sfinite number", r->path, r->where, key, k,
                     x->number, non_negative ? "non-negative " : "");
    out[k] = x->number;
  }
  return PB_OK;
}

/* An optional member that must be an object. */
static pb_result object(const rd *r, const pb_gltf_value *o, const char *key, const pb_gltf_value **out) {
  const pb_gltf_value *v = pb_gltf_value_get(o, key);
  *out = NULL;
  if (!v) return PB_OK;
  if (v->type != PB_GLTF_OBJECT) return type_error(r, key, "an object");
  *out = v;
  return PB_OK;
}

/* ---- lights -------------------------------------------------------------- */

pb_result pb_blender_read_light(const char *path, int node, const char *node_name, const pb_gltf_value *ext,
                                const mat4 *M, pb_light *out, int *has_light) {
  *has_light = 0;
  char where[96];
  snprintf(where, sizeof where, "nodes[%d].extensions", node);
  rd r = {path, where};
  if (ext->type != PB_GLTF_OBJECT) return type_error(&r, "PHOTONBRIDGE_blender", "an object");
  snprintf(where, sizeof where, "nodes[%d].extensions.PHOTONBRIDGE_blender", node);
  const pb_gltf_value *lo;
  pb_result e = object(&r, ext, "light", &lo);
  if (e != PB_OK || !lo) return e;
  snprintf(where, sizeof where, "nodes[%d].extensions.PHOTONBRIDGE_blender.light", node);

  const char *type, *name, *shape = NULL, *model = NULL;
  if ((e = string(&r, lo, "type", &type)) != PB_OK) return e;
  pb_light l;
  memset(&l, 0, sizeof l);
  char known[64];
  int kind_known = pb_light_kind_parse(type, 1, &l.type, known, sizeof known);
  if (!type) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.type: missing (%s)", path, where, known);
  if (!kind_known) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.type: '%s' is not %s", path, where, type, known);
  if ((e = string(&r, lo, "name", &name)) != PB_OK) return e;
  snprintf(l.name, PB_NAME_MAX, "%s", node_name && node_name[0] ? node_name : (name ? name : ""));
  if (!l.name[0]) snprintf(l.name, PB_NAME_MAX, "nodes[%d]", node);

  static const double white[3] = {1, 1, 1};
  double color[3], power, strength, radius, spot_size, spot_blend, angle, size, size_y, spread, exposure;
  int cast, mis, soft_falloff;
  if ((e = vector(&r, lo, "color", 3, 1, white, color)) != PB_OK) return e;
  if ((e = number(&r, lo, "power", DEF_POWER, 0, 0, HUGE_VAL, 0, "a non-negative number of watts", &power)) != PB_OK ||
      (e = number(&r, lo, "strength", 1.0, 0, 0, HUGE_VAL, 0, "a non-negative irradiance (W/m^2)", &strength)) != PB_OK ||
      (e = number(&r, lo, "radius", DEF_RADIUS, 0, 0, HUGE_VAL, 0, "a non-negative radius (m)", &radius)) != PB_OK ||
      (e = number(&r, lo, "spotSize", DEF_SPOT_SIZE, 0, 1, PI_F32, 0, "in (0, pi] radians", &spot_size)) != PB_OK ||
      (e = number(&r, lo, "spotBlend", DEF_SPOT_BLEND, 0, 0, 1, 0, "in [0, 1]", &spot_blend)) != PB_OK ||
      (e = number(&r, lo, "angle", DEF_SUN_ANGLE, 0, 0, PI, 1, "in [0, pi) radians", &angle)) != PB_OK ||
      (e = number(&r, lo, "size", DEF_AREA_SIZE, 0, 0, HUGE_VAL, 0, "a non-negative size (m)", &size)) != PB_OK ||
      (e = number(&r, lo, "sizeY", DEF_AREA_SIZE, 0, 0, HUGE_VAL, 0, "a non-negative size (m)", &size_y)) != PB_OK ||
      (e = number(&r, lo, "spread", PI, 0, 1, PI_F32, 0, "in (0, pi] radians", &spread)) != PB_OK ||
      (e = number(&r, lo, "exposure", 0, -32, 0, 32, 0, "in [-32, 32] stops", &exposure)) != PB_OK ||
      (e = boolean(&r, lo, "castShadow", 1, &cast)) != PB_OK || (e = boolean(&r, lo, "useMIS", 1, &mis)) != PB_OK ||
      (e = boolean(&r, lo, "softFalloff", 1, &soft_falloff)) != PB_OK ||
      (e = string(&r, lo, "shape", &shape)) != PB_OK || (e = string(&r, lo, "model", &model)) != PB_OK)
    return e;
  /* Which Cycles' light model: 3.4's (no member: files written before 4.0
   * existed), or 4.x's area radiance and spot falloff (scene.h). */
  l.blender_exposure = (float)exposure; /* folded into power/strength by the writer */
  int cycles4 = 0;
  if (model && strcmp(model, "cycles4") == 0) cycles4 = 1;
  else if (model && strcmp(model, "cycles3") != 0)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.model: '%s' is not cycles3 or cycles4", path, where, model);

  /* Position, direction and an area light's axes (Blender's size and size_y
   * run along the node's X and Y). */
  if ((e = pb_light_place(&l, M, path, node, 1)) != PB_OK) return e;

  /* Blender's value and the members the kind has (scene/light.h): a sun's
   * strength is its irradiance; the others' power is spread over the
   * sphere (4 pi) or, for a surface, over Cycles' area term. */
  const uint32_t kind = pb_light_kind_of(l.type)->flags;
  const int by_strength = (kind & PB_LIGHT_DISTANT) != 0;
  double k = by_strength ? strength : power / (4.0 * PI);
  l.file_intensity = (float)(by_strength ? strength : power);
  if (kind & PB_LIGHT_RADIUS) l.radius = (float)radius;
  if (kind & PB_LIGHT_ANGLE) l.angle = (float)angle;
  if (kind & PB_LIGHT_CONE) {
    l.spot_model = cycles4 ? PB_SPOT_CYCLES4 : PB_SPOT_CYCLES;
    spot_size = fmin(spot_size, PI);
    l.outer_cone = (float)(0.5 * spot_size);
    l.spot_blend = (float)spot_blend;
    l.inner_cone = (float)(0.5 * spot_size * (1.0 - spot_blend)); /* for info and POV-Ray's cone */
  }
  if (kind & PB_LIGHT_SURFACE) {
    int ellipse;
    if (!shape || strcmp(shape, "SQUARE") == 0) ellipse = 0, size_y = size;
    else if (strcmp(shape, "RECTANGLE") == 0) ellipse = 0;
    else if (strcmp(shape, "DISK") == 0) ellipse = 1, size_y = size;
    else if (strcmp(shape, "ELLIPSE") == 0) ellipse = 1;
    else return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.shape: '%s' is not SQUARE, RECTANGLE, DISK or ELLIPSE", path, where, shape);
    double area = size * size_y * (ellipse ? 0.25 * PI : 1.0);
    if (!(area > 0) || !fits_float(area))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: size %g x %g m: a light of zero area emits nothing", path, where,
                     size, size_y);
    l.shape = ellipse ? PB_AREA_ELLIPSE : PB_AREA_RECTANGLE;
    l.size[0] = (float)size;
    l.size[1] = (float)size_y;
    l.spread = (float)fmin(spread, PI);
    k = power / ((cycles4 ? PI : 4.0) * area); /* Cycles eval_fac: 3.4 1/(4 A), 4.x 1/(pi A) */
  }
  if (!fits_float(k))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s: %g gives an intensity of %g, out of float range", path, where,
                   by_strength ? "strength" : "power", by_strength ? strength : power, k);
  l.intensity = (float)k;
  for (int c = 0; c < 3; ++c) l.color[c] = (float)color[c];
  l.no_shadow = !cast;
  l.sphere = (kind & PB_LIGHT_RADIUS) && !soft_falloff && l.radius > 0.0f;
  l.no_mis = !mis;
  l.from_blender = 1;
  *out = l;
  *has_light = 1;
  return PB_OK;
}

/* ---- world --------------------------------------------------------------- */

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), m = strlen(suffix);
  if (n < m) return 0;
  for (size_t i = 0; i < m; ++i)
    if ((s[n - m + i] | 0x20) != suffix[i]) return 0;
  return 1;
}

/* Reads the map at `uri` into w->env (RGB float, top row first, linear). */
static pb_result load_map(const char *path, const char *dir, const char *where, const char *uri, const pb_load_desc *desc, pb_world *w) {
  char *file = NULL;
  pb_result e = pb_gltf_resolve_uri(path, dir, uri, desc->allow_external_files, where, &file);
  if (e != PB_OK) return e;
  uint32_t W = 0, H = 0;
  float *rgb = NULL;
  char why[160] = "";
  if (ends_with(uri, ".exr")) {
    pb_exr_read_limits lim = {desc->max_image_dim, desc->max_image_pixels, 0};
    pb_image im;
    e = pb_exr_read(file, &lim, &im);
    if (e != PB_OK) {
      snprintf(why, sizeof why, "%s", pb_error_message());
      pb_error_clear();
    } else {
      int ch[3] = {pb_image_find_channel(&im, "R"), pb_image_find_channel(&im, "G"), pb_image_find_channel(&im, "B")};
      int y = pb_image_find_channel(&im, "Y");
      if (ch[0] < 0 || ch[1] < 0 || ch[2] < 0) ch[0] = ch[1] = ch[2] = y;
      if (ch[0] < 0) {
        e = PB_ERR_IMAGE;
        snprintf(why, sizeof why, "no R, G, B or Y channel");
      } else if (!(rgb = malloc((size_t)im.width * im.height * 3 * sizeof *rgb))) {
        e = PB_ERR_NOMEM;
        snprintf(why, sizeof why, "out of memory");
      } else {
        W = im.width, H = im.height;
        for (size_t i = 0; i < (size_t)W * H; ++i)
          for (int c = 0; c < 3; ++c) rgb[3 * i + c] = im.pixels[i * im.channel_count + (size_t)ch[c]];
      }
      pb_image_destroy(&im);
    }
  } else {
    uint8_t *bytes = NULL;
    size_t size = 0;
    e = pb_read_file(file, desc->max_file_bytes, &bytes, &size);
    if (e != PB_OK) {
      snprintf(why, sizeof why, "%s", pb_error_message());
      pb_error_clear();
    } else if (ends_with(uri, ".hdr") || ends_with(uri, ".pic")) {
      e = pb_hdr_decode(bytes, size, desc->max_image_dim, desc->max_image_pixels, &rgb, &W, &H, why, sizeof why);
    } else if (ends_with(uri, ".png") || ends_with(uri, ".jpg") || ends_with(uri, ".jpeg")) {
      /* 8-bit images through the texture decoder (PNG or JPEG by signature),
       * the declared size checked from the header before any pixel memory
       * is allocated (image/decode.h). */
      const pb_decode_limits lim = {.max_dim = desc->max_image_dim, .max_pixels = desc->max_image_pixels};
      pb_decoded dec;
      pb_decode_status st = pb_decode_image_rgba8(bytes, size, &lim, &dec);
      if (st == PB_DECODE_TOO_LARGE) {
        e = PB_ERR_LIMIT;
        snprintf(why, sizeof why, "%u x %u pixels exceeds the limit", dec.width, dec.height);
      } else if (st == PB_DECODE_UNKNOWN) {
        e = PB_ERR_SCENE_UNSUPPORTED; /* as a texture's (load_texture.c) */
        snprintf(why, sizeof why, "not a PNG or JPEG file");
      } else if (st == PB_DECODE_NOMEM) {
        e = PB_ERR_NOMEM;
        snprintf(why, sizeof why, "out of memory decoding it");
      } else if (st != PB_DECODE_OK) {
        e = PB_ERR_IMAGE;
        snprintf(why, sizeof why, "%s", dec.why[0] ? dec.why : "cannot decode");
      } else if (!(rgb = malloc((size_t)dec.width * dec.height * 3 * sizeof *rgb))) {
        e = PB_ERR_NOMEM;
        snprintf(why, sizeof why, "out of memory");
      } else {
        /* Blender reads 8-bit PNG and JPEG files as sRGB (the Image's default
         * colour space), and the writer copies such files as they are. */
        W = dec.width, H = dec.height;
        for (size_t i = 0; i < (size_t)W * H; ++i)
          for (int c = 0; c < 3; ++c) rgb[3 * i + c] = pb_srgb_to_linear(dec.rgba[4 * i + c] * (1.0f / 255.0f));
      }
      free(dec.rgba);
    } else {
      e = PB_ERR_SCENE_UNSUPPORTED;
      snprintf(why, sizeof why, "not a .hdr, .exr, .png or .jpg file");
    }
    free(bytes);
  }
  free(file);
  if (e == PB_OK && (W == 0 || H == 0)) {
    e = PB_ERR_IMAGE;
    snprintf(why, sizeof why, "%u x %u pixels (an environment map needs at least one)", W, H);
  }
  if (e != PB_OK) {
    free(rgb);
    return pb_fail(e, "%s: %s: '%s': %s", path, where, uri, why);
  }
  for (size_t i = 0; i < (size_t)W * H * 3; ++i)
    if (!isfinite(rgb[i]) || rgb[i] < 0) rgb[i] = 0.0f; /* negative or non-finite texels emit nothing */
  w->env = rgb;
  w->env_width = W;
  w->env_height = H;
  const char *base = strrchr(uri, '/');
  snprintf(w->env_name, PB_NAME_MAX, "%s", base ? base + 1 : uri);
  return PB_OK;
}

static pb_result read_world(const char *path, const char *dir, const pb_gltf_value *wo, const pb_load_desc *desc, pb_world *w) {
  rd r = {path, "extensions.PHOTONBRIDGE_blender.world"};
  static const double grey[3] = {DEF_WORLD_COLOR, DEF_WORLD_COLOR, DEF_WORLD_COLOR}, zero[3] = {0, 0, 0};
  double color[3], strength;
  int visible;
  const pb_gltf_value *env;
  pb_result e;
  if ((e = vector(&r, wo, "color", 3, 1, grey, color)) != PB_OK ||
      (e = number(&r, wo, "strength", 1.0, 0, 0, HUGE_VAL, 0, "a non-negative number", &strength)) != PB_OK ||
      (e = boolean(&r, wo, "visibleToCamera", 1, &visible)) != PB_OK || (e = object(&r, wo, "environment", &env)) != PB_OK)
    return e;
  memset(w, 0, sizeof *w);
  w->present = 1;
  w->hidden_from_camera = !visible;
  for (int c = 0; c < 3; ++c) {
    double x = color[c] * strength;
    if (!fits_float(x))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: colour x strength %g is out of float range", path, r.where, x);
    w->color[c] = (float)x;
  }
  double rot[3] = {0, 0, 0};
  pb_world_set_rotation(w, rot);
  if (env) {
    rd re = {path, "extensions.PHOTONBRIDGE_blender.world.environment"};
    const char *uri, *proj;
    double es;
    if ((e = string(&re, env, "uri", &uri)) != PB_OK || (e = string(&re, env, "projection", &proj)) != PB_OK ||
        (e = vector(&re, env, "rotation", 3, 0, zero, rot)) != PB_OK ||
        (e = number(&re, env, "strength", 1.0, 0, 0, HUGE_VAL, 0, "a non-negative number", &es)) != PB_OK)
      return e;
    if (!uri) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.uri: missing", path, re.where);
    if (proj && strcmp(proj, "EQUIRECTANGULAR") != 0)
      return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: %s.projection: '%s' (only EQUIRECTANGULAR)", path, re.where, proj);
    if (!fits_float(es * strength))
      return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.strength: %g x %g is out of float range", path, re.where, es, strength);
    if ((e = load_map(path, dir, "extensions.PHOTONBRIDGE_blender.world.environment.uri", uri, desc, w)) != PB_OK) return e;
    w->env_scale = (float)(es * strength);
    pb_world_set_rotation(w, rot);
  }
  pb_world_update_integral(w);
  if (!(w->integral[0] > 0) && !(w->integral[1] > 0) && !(w->integral[2] > 0)) {
    /* A black world is no light; free the map. */
    free(w->env);
    memset(w, 0, sizeof *w);
  }
  return PB_OK;
}

/* ---- colour management ---------------------------------------------------- */

/* An optional string of at most size - 1 bytes into buf ("" when absent). */
static pb_result bounded(const rd *r, const pb_gltf_value *o, const char *key, char *buf, size_t size,
                         const char *what) {
  const char *v;
  pb_result e = string(r, o, key, &v);
  buf[0] = 0;
  if (e != PB_OK || !v) return e;
  size_t n = strlen(v);
  if (n >= size)
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.%s: a %s of %zu bytes (at most %zu)", r->path, r->where, key, what, n,
                   size - 1);
  memcpy(buf, v, n + 1);
  return PB_OK;
}

/* An optional name of at most PB_SCENE_VIEW_NAME - 1 bytes into buf ("" when
 * absent). */
static pb_result name(const rd *r, const pb_gltf_value *o, const char *key, char *buf) {
  return bounded(r, o, key, buf, PB_SCENE_VIEW_NAME, "name");
}

/* colorManagement: Blender's display device, view transform, look ("None"
 * is no look), exposure and gamma, in the ranges of Blender's RNA, and the
 * OCIO config Blender used ("ocioConfig", a path on the writing machine)
 * (rna_color.c: exposure -32..32 stops, gamma 0..5; gamma 0 is taken as
 * Blender does not allow it, so it must be > 0). Missing members keep
 * Blender 3.4's defaults: sRGB / Filmic, no look, 0, 1. Whether the OCIO
 * config has those names is checked where a display image is made. */
static pb_result read_view(const char *path, const pb_gltf_value *cm, pb_scene_view *v) {
  rd r = {path, "extensions.PHOTONBRIDGE_blender.colorManagement"};
  pb_result e;
  if ((e = name(&r, cm, "display", v->display)) != PB_OK || (e = name(&r, cm, "view", v->view)) != PB_OK ||
      (e = name(&r, cm, "look", v->look)) != PB_OK ||
      (e = bounded(&r, cm, "ocioConfig", v->config, sizeof v->config, "path")) != PB_OK ||
      (e = number(&r, cm, "exposure", 0, -32, 0, 32, 0, "in [-32, 32]", &v->exposure)) != PB_OK ||
      (e = number(&r, cm, "gamma", 1, 0, 1, 5, 0, "in (0, 5]", &v->gamma)) != PB_OK)
    return e;
  if (!v->display[0]) snprintf(v->display, sizeof v->display, "sRGB");
  if (!v->view[0]) snprintf(v->view, sizeof v->view, "Filmic");
  if (!strcmp(v->look, "None")) v->look[0] = 0;
  v->set = 1;
  return PB_OK;
}

pb_result pb_blender_read_root(const char *path, const char *dir, const pb_gltf_value *root, const pb_load_desc *desc, pb_scene *s) {
  rd r = {path, "extensions"};
  if (root->type != PB_GLTF_OBJECT) return type_error(&r, "PHOTONBRIDGE_blender", "an object");
  r.where = "extensions.PHOTONBRIDGE_blender";
  const pb_gltf_value *v = pb_gltf_value_get(root, "version");
  if (!v) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s.version: missing", path, r.where);
  if (v->type != PB_GLTF_NUMBER || !v->is_integer) return type_error(&r, "version", "an integer");
  if (v->number != 1)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: %s.version: %g (this photonbridge reads version 1)", path, r.where,
                   v->number);
  const pb_gltf_value *render, *world, *cm;
  pb_result e;
  if ((e = object(&r, root, "render", &render)) != PB_OK || (e = object(&r, root, "world", &world)) != PB_OK ||
      (e = object(&r, root, "colorManagement", &cm)) != PB_OK)
    return e;
  if (cm && (e = read_view(path, cm, &s->view)) != PB_OK) return e;
  int transparent = 0;
  if (render) {
    rd rr = {path, "extensions.PHOTONBRIDGE_blender.render"};
    if ((e = boolean(&rr, render, "filmTransparent", 0, &transparent)) != PB_OK) return e;
  }
  s->film_opaque = !transparent;
  if (world && (e = read_world(path, dir, world, desc, &s->world)) != PB_OK) return e;
  return PB_OK;
}
