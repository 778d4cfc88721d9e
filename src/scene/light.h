/* The host's one light module: every host-side decision that depends on a
 * light's kind (point, spot, directional, area) reads the kind's row of one
 * table (light.c): its names, what its intensity means, its emitted power,
 * which of its axes a transform turns, its GPU packing and `info`'s
 * description. The kind's value is the GPU's (shared/pb_gpu.h
 * PB_GPU_LIGHT_*), so no translation exists between the two.
 *
 * The renderers evaluate and sample lights on their own (the reference in
 * src/ref/lights.c, soft_lights.c and photons.c; the GPU in
 * shaders/common/lights.glsl and the photon kernels), so that one checks the
 * other; they share the kinds and their names only. scene.h's pb_light says
 * what each member means. */
#ifndef PB_SCENE_LIGHT_H
#define PB_SCENE_LIGHT_H

#include <stdint.h>
#include <stdio.h>

#include "core/result.h"
#include "shared/pb_gpu.h"

/* A light's kind: the GPU's value (pb_gpu_light.type). */
typedef enum pb_light_type {
  PB_LIGHT_POINT = PB_GPU_LIGHT_POINT,
  PB_LIGHT_SPOT = PB_GPU_LIGHT_SPOT,
  PB_LIGHT_DIRECTIONAL = PB_GPU_LIGHT_DIRECTIONAL,
  PB_LIGHT_AREA = PB_GPU_LIGHT_AREA,
  PB_LIGHT_KIND_COUNT
} pb_light_type;

typedef struct pb_light pb_light; /* scene.h */
typedef struct pb_json pb_json;   /* core/json.h */
typedef struct mat4 mat4;         /* scene/xform.h */

/* What a kind is, for the code that branches on it (pb_light_kind.flags). */
enum {
  PB_LIGHT_AIMED = 1u << 0,    /* has a direction (the node's -Z); else (0, 0, -1) */
  PB_LIGHT_OMNI = 1u << 1,     /* emits into every direction from a point */
  PB_LIGHT_CONE = 1u << 2,     /* emits into a cone of half-angle outer_cone */
  PB_LIGHT_DISTANT = 1u << 3,  /* at infinity: direction only, no position */
  PB_LIGHT_SURFACE = 1u << 4,  /* a shape of axes axis_u, axis_v that turn with its node */
  PB_LIGHT_RADIUS = 1u << 5,   /* soft with radius > 0 (else a delta light) */
  PB_LIGHT_ANGLE = 1u << 6,    /* soft with angle > 0 (else a delta light) */
};

/* The directions a kind's photons leave in and the flux they carry per unit
 * intensity (the GPU photon tracer's emission, src/render/photon/photon_trace.c):
 * solid angle `omega` of the directions (for ray differentials), `scale` the
 * flux per unit of intensity x colour, `cos_max` the cosine bounding the
 * directions about the axis (-1: the sphere, 1: parallel). */
typedef struct pb_light_emission {
  double omega, scale;
  float cos_max;
} pb_light_emission;

typedef struct pb_light_kind {
  const char *name;          /* "point", "spot", ...: info, JSON, messages */
  const char *gltf_type;     /* KHR_lights_punctual's "type"; NULL: none */
  const char *blender_type;  /* PHOTONBRIDGE_blender's light "type" */
  uint32_t flags;            /* PB_LIGHT_* above */
  /* What `intensity` is, for info: its symbol, unit and JSON member. */
  const char *symbol, *unit, *json_intensity;
  /* The file's value: glTF's unit and JSON member; Blender's JSON member,
   * and info's words before the number and its unit ("strength ", "W/m^2"). */
  const char *gltf_unit, *json_gltf, *json_blender, *blender_label, *blender_unit;
  /* Emitted power [W] per unit of colour; directional lights over the
   * scene's bounding disc of radius scene_radius. */
  float (*power)(const pb_light *l, float scene_radius);
  /* The kind's own members of pb_gpu_light (the common ones are set). */
  void (*pack)(const pb_light *l, pb_gpu_light *o);
  /* info's text after the intensity and colour (pb_light_describe). */
  void (*describe)(const pb_light *l, FILE *f);
  void (*json)(const pb_light *l, pb_json *j);
  void (*emission)(const pb_light *l, double scene_radius, pb_light_emission *e);
} pb_light_kind;

/* The kind's row; NULL for a value that is no kind. */
const pb_light_kind *pb_light_kind_of(pb_light_type t);
/* The kind's name, "unknown" for a value that is no kind. */
const char *pb_light_kind_name(pb_light_type t);
/* The kind of KHR_lights_punctual's `type` (gltf) or PHOTONBRIDGE_blender's
 * (blender = 1); 0 when none has it, and `known` (when not NULL) lists the
 * types that exist, for the message ("point, spot or directional"). */
int pb_light_kind_parse(const char *type, int blender, pb_light_type *out, char *known, size_t known_size);

/* 1 when the light is a delta light (point/spot of radius 0, directional of
 * angle 0): only next-event estimation or photons reach it. Area lights
 * never are. */
int pb_light_is_delta(const pb_light *l);
/* Area of an area light's shape [m^2] (0 for other kinds). */
float pb_light_area(const pb_light *l);
/* Total emitted power [W] of a light per channel, used to split photon
 * budgets; directional lights use the area of the scene's bounding disc. */
void pb_light_power(const pb_light *l, float scene_radius, float power[3]);

/* The member that makes a light of this kind soft ("radius", "angle") and
 * its value; NULL for a kind that has none (area lights are always soft). */
const char *pb_light_softness(const pb_light *l, float *value);

/* Places a light (its type set) by its node's world transform M: position
 * (the node's origin), direction (its -Z; (0, 0, -1) for a kind that is not
 * aimed) and a surface's axes. Errors name path and nodes[node]
 * (PB_ERR_SCENE_INVALID): a position out of float range, a degenerate
 * transform where a direction is needed (always when require_direction). */
pb_result pb_light_place(pb_light *l, const mat4 *M, const char *path, int node, int require_direction);
/* At another pose (animation): the same, except that a degenerate pose
 * keeps direction `keep_dir` and the last axes; 0 when the position is out
 * of float range (l unchanged). */
int pb_light_pose(pb_light *l, const mat4 *M, const float keep_dir[3]);

/* The light as the GPU sees it (shared/pb_gpu.h pb_gpu_light). */
void pb_light_pack_gpu(const pb_light *l, pb_gpu_light *o);

/* info's line for a light after its name and kind: the value as typed
 * (Blender's watts or W/m^2, glTF's cd or lx, or unitless), then as
 * rendered, and the kind's own members. */
void pb_light_describe(const pb_light *l, int gltf_unitless, FILE *f);
/* info --json's members of a light (inside its object). */
void pb_light_write_json(const pb_light *l, pb_json *j);

#endif
