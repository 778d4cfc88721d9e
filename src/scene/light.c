/* The light kinds' table and the host's operations on a light (light.h). A
 * new kind is a PB_GPU_LIGHT_* value (shared/pb_gpu.h), its name in
 * light.h's pb_light_type and a row here; then the renderers' own
 * evaluation and sampling (docs/architecture.md, "Adding a light kind"). */
#include "scene/light.h"

#include <math.h>
#include <string.h>

#include "core/json.h"
#include "scene/scene.h"
#include "scene/xform.h"

_Static_assert(PB_LIGHT_KIND_COUNT == PB_GPU_LIGHT_AREA + 1, "every GPU light kind has a row in the table");

/* ---- per kind ------------------------------------------------------------ */

static void json_vec3(pb_json *j, const char *key, const float v[3]) {
  pb_json_begin_array(j, key);
  for (int k = 0; k < 3; ++k) pb_json_number(j, NULL, v[k]);
  pb_json_end_array(j);
}

static float power_point(const pb_light *l, float scene_radius) { return 4.0f * (float)M_PI * l->intensity; }

static float power_spot(const pb_light *l, float scene_radius) {
  /* Solid angle of the cone, with the smooth-step band counted at half
   * weight: 2 pi (1 - cos) at the mean of the two cone angles. Cycles'
   * falloff (its cos factor, its band inside the outer cone) is within the
   * same estimate's error: the split only needs a rough power. */
  float inner = l->spot_model != PB_SPOT_SMOOTHSTEP ? l->outer_cone * (1.0f - l->spot_blend) : l->inner_cone;
  float a = 0.5f * (inner + l->outer_cone);
  return 2.0f * (float)M_PI * (1.0f - cosf(a)) * l->intensity;
}

static float power_directional(const pb_light *l, float scene_radius) {
  return (float)M_PI * scene_radius * scene_radius * l->intensity;
}

/* pi A L: the Lambertian exitance; the spread profile keeps it. */
static float power_area(const pb_light *l, float scene_radius) {
  return (float)M_PI * pb_light_area(l) * l->intensity;
}

static void pack_punctual(const pb_light *l, pb_gpu_light *o) { o->radius = l->radius; }

static void pack_directional(const pb_light *l, pb_gpu_light *o) {
  /* The soft sun: its disc's radius at unit distance (0: a delta light). */
  o->radius = l->angle > 0.0f ? tanf(0.5f * l->angle) : 0.0f;
  o->cos_half = cosf(0.5f * l->angle);
}

static void pack_area(const pb_light *l, pb_gpu_light *o) {
  if (l->shape == PB_AREA_ELLIPSE) o->flags |= PB_GPU_LIGHT_ELLIPSE;
  o->size_u = l->size[0];
  o->size_v = l->size[1];
  /* The spread profile (scene.h; src/ref/soft_lights.c spread_params). */
  float sp = l->spread > 0.0f ? l->spread : (float)M_PI;
  float a = 0.5f * ((float)M_PI - fmaxf(sp, (float)M_PI / 180.0f));
  o->tan_spread = tanf(a);
  o->norm_spread = 2.0f / (2.0f + (2.0f * a - (float)M_PI) * o->tan_spread);
}

static const char *spot_falloff_name(const pb_light *l) {
  return l->spot_model == PB_SPOT_CYCLES ? "cycles" : l->spot_model == PB_SPOT_CYCLES4 ? "cycles4" : "smoothstep";
}

static void describe_emits(const pb_light *l, const char *into, FILE *f) {
  float power[3];
  pb_light_power(l, 0, power);
  fprintf(f, ", at (%.4g %.4g %.4g), emits %.4g W%s", l->position[0], l->position[1], l->position[2],
          (power[0] + power[1] + power[2]) / 3, into);
}

static void describe_point(const pb_light *l, FILE *f) {
  describe_emits(l, "", f);
  if (l->radius > 0) fprintf(f, ", radius %.4g m (soft)", l->radius);
}

static void describe_spot(const pb_light *l, FILE *f) {
  describe_emits(l, " into its cone", f);
  fprintf(f, ", cone %.2f..%.2f deg%s", l->inner_cone * 180.0 / M_PI, l->outer_cone * 180.0 / M_PI,
          l->spot_model == PB_SPOT_CYCLES    ? " (Cycles 3.4 falloff)"
          : l->spot_model == PB_SPOT_CYCLES4 ? " (Cycles 4 falloff)"
                                             : "");
  if (l->radius > 0) fprintf(f, ", radius %.4g m (soft)", l->radius);
}

static void describe_directional(const pb_light *l, FILE *f) {
  fprintf(f, ", direction (%.3f %.3f %.3f)", l->direction[0], l->direction[1], l->direction[2]);
  if (l->angle > 0) fprintf(f, ", angle %.3g deg (soft)", l->angle * 180.0 / M_PI);
}

static void describe_area(const pb_light *l, FILE *f) {
  fprintf(f, ", %s %.4g x %.4g m at (%.4g %.4g %.4g), facing (%.3f %.3f %.3f), spread %.3g deg",
          l->shape == PB_AREA_ELLIPSE ? "ellipse" : "rectangle", l->size[0], l->size[1], l->position[0],
          l->position[1], l->position[2], l->direction[0], l->direction[1], l->direction[2],
          (l->spread > 0 ? l->spread : M_PI) * 180.0 / M_PI);
}

static void json_point(const pb_light *l, pb_json *j) { pb_json_number(j, "radius", l->radius); }

static void json_spot(const pb_light *l, pb_json *j) {
  pb_json_number(j, "inner_cone", l->inner_cone);
  pb_json_number(j, "outer_cone", l->outer_cone);
  pb_json_string(j, "spot_falloff", spot_falloff_name(l));
  pb_json_number(j, "radius", l->radius);
}

static void json_directional(const pb_light *l, pb_json *j) { pb_json_number(j, "angle", l->angle); }

static void json_area(const pb_light *l, pb_json *j) {
  pb_json_string(j, "shape", l->shape == PB_AREA_ELLIPSE ? "ellipse" : "rectangle");
  pb_json_number(j, "size_u", l->size[0]);
  pb_json_number(j, "size_v", l->size[1]);
  json_vec3(j, "axis_u", l->axis_u);
  json_vec3(j, "axis_v", l->axis_v);
  pb_json_number(j, "spread", l->spread > 0 ? l->spread : M_PI);
}

static void emit_point(const pb_light *l, double scene_radius, pb_light_emission *e) {
  e->omega = e->scale = 4.0 * M_PI;
  e->cos_max = -1.0f;
}

static void emit_spot(const pb_light *l, double scene_radius, pb_light_emission *e) {
  float co = cosf(fmaxf(l->outer_cone, 0.0f));
  e->omega = e->scale = 2.0 * M_PI * (1.0 - co);
  e->cos_max = co;
}

/* Parallel rays over the bounding disc (a soft sun's directions vary per
 * photon; the spacing is the disc's). */
static void emit_directional(const pb_light *l, double scene_radius, pb_light_emission *e) {
  e->omega = M_PI * scene_radius * scene_radius; /* disc area */
  e->scale = e->omega;
  e->cos_max = 1.0f;
}

/* pb_area_light_emit: flux L A pi cos^2 a x the spread profile; the
 * directions fill a cone of half-angle pi/2 - a, whose solid angle stands in
 * the differentials (as a point light's would). */
static void emit_area(const pb_light *l, double scene_radius, pb_light_emission *e) {
  double ta = 0.0;
  if (l->spread > 0.0f && l->spread < (float)M_PI) ta = tan(0.5 * (M_PI - fmax(l->spread, M_PI / 180.0)));
  double c2 = 1.0 / (1.0 + ta * ta); /* cos^2 a */
  e->scale = pb_light_area(l) * M_PI * c2;
  e->omega = 2.0 * M_PI * (1.0 - sqrt(1.0 - c2)); /* 1 - cos(pi/2 - a) = 1 - sin a */
  e->cos_max = 0.0f;
}

/* Indexed by pb_light_type: the GPU's values, so the order is theirs. */
static const pb_light_kind kinds[PB_LIGHT_KIND_COUNT] = {
    [PB_LIGHT_POINT] = {.name = "point", .gltf_type = "point", .blender_type = "POINT",
                        .flags = PB_LIGHT_OMNI | PB_LIGHT_RADIUS,
                        .symbol = "I", .unit = "W/sr", .json_intensity = "intensity_w_sr",
                        .gltf_unit = "cd", .json_gltf = "file_candela", .json_blender = "file_watts",
                        .blender_label = "", .blender_unit = "W",
                        .power = power_point, .pack = pack_punctual, .describe = describe_point,
                        .json = json_point, .emission = emit_point},
    [PB_LIGHT_SPOT] = {.name = "spot", .gltf_type = "spot", .blender_type = "SPOT",
                       .flags = PB_LIGHT_AIMED | PB_LIGHT_CONE | PB_LIGHT_RADIUS,
                       .symbol = "I", .unit = "W/sr", .json_intensity = "intensity_w_sr",
                       .gltf_unit = "cd", .json_gltf = "file_candela", .json_blender = "file_watts",
                       .blender_label = "", .blender_unit = "W",
                       .power = power_spot, .pack = pack_punctual, .describe = describe_spot,
                       .json = json_spot, .emission = emit_spot},
    [PB_LIGHT_DIRECTIONAL] = {.name = "directional", .gltf_type = "directional", .blender_type = "SUN",
                              .flags = PB_LIGHT_AIMED | PB_LIGHT_DISTANT | PB_LIGHT_ANGLE,
                              .symbol = "E", .unit = "W/m^2", .json_intensity = "irradiance_w_m2",
                              .gltf_unit = "lx", .json_gltf = "file_lux", .json_blender = "file_w_m2",
                              .blender_label = "strength ", .blender_unit = "W/m^2",
                              .power = power_directional, .pack = pack_directional, .describe = describe_directional,
                              .json = json_directional, .emission = emit_directional},
    /* Not in KHR_lights_punctual: glTF's unit and member are those a
     * code-built scene's area light has always reported. */
    [PB_LIGHT_AREA] = {.name = "area", .gltf_type = NULL, .blender_type = "AREA",
                       .flags = PB_LIGHT_AIMED | PB_LIGHT_SURFACE,
                       .symbol = "L", .unit = "W/(m^2 sr)", .json_intensity = "radiance_w_m2_sr",
                       .gltf_unit = "cd", .json_gltf = "file_candela", .json_blender = "file_watts",
                       .blender_label = "", .blender_unit = "W",
                       .power = power_area, .pack = pack_area, .describe = describe_area,
                       .json = json_area, .emission = emit_area},
};

/* ---- the table's users --------------------------------------------------- */

const pb_light_kind *pb_light_kind_of(pb_light_type t) {
  return (unsigned)t < PB_LIGHT_KIND_COUNT ? &kinds[t] : NULL;
}

const char *pb_light_kind_name(pb_light_type t) {
  const pb_light_kind *k = pb_light_kind_of(t);
  return k ? k->name : "unknown";
}

int pb_light_kind_parse(const char *type, int blender, pb_light_type *out, char *known, size_t known_size) {
  int found = 0, n = 0, names = 0;
  for (int t = 0; t < PB_LIGHT_KIND_COUNT; ++t)
    if (blender ? kinds[t].blender_type != NULL : kinds[t].gltf_type != NULL) names++;
  if (known && known_size) known[0] = 0;
  for (int t = 0; t < PB_LIGHT_KIND_COUNT; ++t) {
    const char *name = blender ? kinds[t].blender_type : kinds[t].gltf_type;
    if (!name) continue;
    if (!found && type && strcmp(type, name) == 0) *out = (pb_light_type)t, found = 1;
    if (known && known_size) {
      size_t used = strlen(known);
      snprintf(known + used, known_size - used, "%s%s", n == 0 ? "" : n == names - 1 ? " or " : ", ", name);
    }
    n++;
  }
  return found;
}

int pb_light_is_delta(const pb_light *l) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  if (!k) return 0;
  if (k->flags & PB_LIGHT_RADIUS) return !(l->radius > 0.0f);
  if (k->flags & PB_LIGHT_ANGLE) return !(l->angle > 0.0f);
  return 0;
}

const char *pb_light_softness(const pb_light *l, float *value) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  uint32_t f = k ? k->flags : 0;
  *value = f & PB_LIGHT_RADIUS ? l->radius : f & PB_LIGHT_ANGLE ? l->angle : 0.0f;
  return f & PB_LIGHT_RADIUS ? "radius" : f & PB_LIGHT_ANGLE ? "angle" : NULL;
}

float pb_light_area(const pb_light *l) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  if (!k || !(k->flags & PB_LIGHT_SURFACE)) return 0.0f;
  float a = l->size[0] * l->size[1];
  return l->shape == PB_AREA_ELLIPSE ? 0.25f * (float)M_PI * a : a;
}

void pb_light_power(const pb_light *l, float scene_radius, float power[3]) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  float p = k ? k->power(l, scene_radius) : 0.0f;
  for (int c = 0; c < 3; ++c) power[c] = p * l->color[c];
}

/* A surface light's axes from its node's world transform M and unit
 * emission direction: the node's local X and Y made orthonormal to the
 * direction (Gram-Schmidt). 0 when M collapses them. */
static int surface_axes(const mat4 *M, const double dir[3], float axis_u[3], float axis_v[3]) {
  double ux[3] = {1, 0, 0}, vy[3] = {0, 1, 0}, u[3], v[3];
  xform_dir(M, ux, u);
  xform_dir(M, vy, v);
  double du = u[0] * dir[0] + u[1] * dir[1] + u[2] * dir[2];
  for (int c = 0; c < 3; ++c) u[c] -= du * dir[c];
  if (!normalize3(u)) return 0;
  double dv = v[0] * dir[0] + v[1] * dir[1] + v[2] * dir[2], uv = v[0] * u[0] + v[1] * u[1] + v[2] * u[2];
  for (int c = 0; c < 3; ++c) v[c] -= dv * dir[c] + uv * u[c];
  if (!normalize3(v)) return 0;
  for (int c = 0; c < 3; ++c) axis_u[c] = (float)u[c], axis_v[c] = (float)v[c];
  return 1;
}

pb_result pb_light_place(pb_light *l, const mat4 *M, const char *path, int node, int require_direction) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  uint32_t f = k ? k->flags : 0;
  double o[3] = {0, 0, 0}, pos[3], dir[3], fz[3] = {0, 0, -1};
  xform_point(M, o, pos);
  xform_dir(M, fz, dir);
  if (!fits_float3(pos))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: light position is out of float range", path, node);
  if ((require_direction || (f & PB_LIGHT_AIMED)) && !normalize3(dir))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: light transform is degenerate", path, node);
  for (int c = 0; c < 3; ++c) {
    l->position[c] = (float)pos[c];
    l->direction[c] = f & PB_LIGHT_AIMED ? (float)dir[c] : (c == 2 ? -1.0f : 0.0f);
  }
  if ((f & PB_LIGHT_SURFACE) && !surface_axes(M, dir, l->axis_u, l->axis_v))
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: nodes[%d]: light transform is degenerate", path, node);
  return PB_OK;
}

int pb_light_pose(pb_light *l, const mat4 *M, const float keep_dir[3]) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  uint32_t f = k ? k->flags : 0;
  double o[3] = {0, 0, 0}, pos[3], dir[3], fz[3] = {0, 0, -1};
  xform_point(M, o, pos);
  xform_dir(M, fz, dir);
  if (!fits_float3(pos)) return 0;
  for (int c = 0; c < 3; ++c) l->position[c] = (float)pos[c];
  if (!(f & PB_LIGHT_AIMED)) return 1; /* direction stays (0, 0, -1), as loaded */
  if (normalize3(dir)) {
    for (int c = 0; c < 3; ++c) l->direction[c] = (float)dir[c];
    /* A surface turns with its node (a degenerate pose keeps the last axes). */
    if (f & PB_LIGHT_SURFACE) surface_axes(M, dir, l->axis_u, l->axis_v);
  } else {
    memcpy(l->direction, keep_dir, sizeof l->direction);
  }
  return 1;
}

void pb_light_pack_gpu(const pb_light *l, pb_gpu_light *o) {
  memset(o, 0, sizeof *o);
  memcpy(o->position, l->position, sizeof o->position);
  float d[3] = {l->direction[0], l->direction[1], l->direction[2]};
  float len = sqrtf(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
  for (int k = 0; k < 3; ++k) {
    o->direction[k] = len > 0 ? d[k] / len : 0.0f;
    o->power[k] = l->color[k] * l->intensity;
    o->axis_u[k] = l->axis_u[k];
    o->axis_v[k] = l->axis_v[k];
  }
  o->type = (uint32_t)l->type; /* the GPU's value */
  o->cos_outer = cosf(l->outer_cone);
  o->cos_inner = cosf(l->inner_cone);
  o->spot_blend = l->spot_blend;
  if (l->spot_model == PB_SPOT_CYCLES) o->flags |= PB_GPU_LIGHT_CYCLES_SPOT;
  if (l->spot_model == PB_SPOT_CYCLES4) o->flags |= PB_GPU_LIGHT_CYCLES4_SPOT;
  if (l->no_shadow) o->flags |= PB_GPU_LIGHT_NO_SHADOW;
  if (l->sphere && l->radius > 0.0f) o->flags |= PB_GPU_LIGHT_SPHERE;
  if (l->no_mis) o->flags |= PB_GPU_LIGHT_NO_MIS;
  const pb_light_kind *k = pb_light_kind_of(l->type);
  if (k) k->pack(l, o);
}

void pb_light_describe(const pb_light *l, int gltf_unitless, FILE *f) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  if (!k) {
    fprintf(f, "of unknown kind %d", (int)l->type);
    return;
  }
  if (l->from_blender && l->blender_exposure != 0) /* Blender 4.x: the value typed times 2^Exposure */
    fprintf(f, "%s%.4g %s at exposure %+g in Blender", k->blender_label, l->file_intensity / exp2(l->blender_exposure),
            k->blender_unit, l->blender_exposure);
  else if (l->from_blender)
    fprintf(f, "%s%.4g %s in Blender", k->blender_label, l->file_intensity, k->blender_unit);
  else if (gltf_unitless)
    fprintf(f, "intensity %.4g in glTF (unitless)", l->file_intensity);
  else
    fprintf(f, "%.4g %s in glTF", l->file_intensity, k->gltf_unit);
  fprintf(f, " (%s = %.4g %s) x colour (%.3g %.3g %.3g)", k->symbol, l->intensity, k->unit, l->color[0], l->color[1],
          l->color[2]);
  k->describe(l, f);
  if (l->no_shadow) fprintf(f, ", casts no shadow");
  if (l->no_mis) fprintf(f, ", no MIS");
}

void pb_light_write_json(const pb_light *l, pb_json *j) {
  const pb_light_kind *k = pb_light_kind_of(l->type);
  pb_json_string(j, "name", l->name);
  pb_json_string(j, "type", pb_light_kind_name(l->type));
  if (k) {
    pb_json_number(j, k->json_intensity, l->intensity);
    pb_json_number(j, l->from_blender ? k->json_blender : k->json_gltf, l->file_intensity);
  }
  json_vec3(j, "color", l->color);
  json_vec3(j, "position", l->position);
  json_vec3(j, "direction", l->direction);
  if (k) k->json(l, j);
  pb_json_bool(j, "cast_shadow", !l->no_shadow);
  pb_json_bool(j, "use_mis", !l->no_mis);
  pb_json_bool(j, "blender_units", l->from_blender);
}
