#version 450
// Pass 2 of a sample: direct light at the G-buffer's surface, with the
// reference's BSDF (smooth lobes):
//  - every point, spot and directional light: one shadow ray (any hit) each;
//  - emissive triangles (SC_EMISSIVE, frame.emitter_count > 0): one emitter
//    picked by power from the host's table (pb_gpu_emitter), a uniform point
//    on it (Shirley's map, as the reference), the solid-angle pdf
//    pick / area * d^2 / cos_l and one shadow ray between the two points,
//    both moved off their surfaces (the reference's segment).
//  - soft lights (SC_SOFT_LIGHTS): one light sample each (common/lights.glsl,
//    the reference's strategies), a shadow ray unless the light casts none;
//  - the world (SC_WORLD): a direction drawn from the BSDF (a Blender
//    material's closures; a cosine-weighted one for glTF's lobes) and, for a
//    map, PB_WORLD_MAP_SAMPLES directions from its table, combined by the
//    power heuristic (a constant world: the BSDF direction alone, weight 1),
//    each with a shadow ray to infinity; the map and soft-light samples are
//    stratified over the pixel's samples (pb_ld2).
// Added to beauty, and to the direct AOV when the surface is the first hit
// (one scattering event).
//
// Soft lights and the reference: the reference also reaches them by its
// BSDF-sampled continuation, MIS-weighted; light sampling alone has the same
// expectation wherever the light's pdf is positive where it emits, which
// holds for every strategy here (the emitter argument below). The world's two
// strategies are combined here as there, with other BSDF pdfs.
//
// Emitters and the reference: src/ref/pathtrace.c combines this light sample
// with the BSDF-sampled continuation that hits an emitter (power heuristic).
// The MIS weights of the two strategies sum to 1 wherever both pdfs are
// positive, and where the BSDF pdf is 0 the light sample's weight is 1, so
// the reference's expectation of once-scattered emitter light is the plain
// integral of f Le |cos| over the emitters' solid angle: exactly what pure
// light sampling estimates here (weight 1, every emitter point with
// Le > 0 has a positive pdf). Only the variance differs. The BSDF-sampled
// continuation is not traced on the GPU, so an emitter hit after a smooth
// bounce is never counted twice (the G-buffer pass counts emission only along
// delta chains, where the reference's weight is 1 too). Blender materials
// split the same way by closure: the G-buffer pass follows their smoother
// glossy closures and counts the emitters those reach (their BSDF sampling
// alone, and the soft lights and the world by a light sample there,
// MIS-weighted against that continuation: pb_lights_mis), this pass lights
// only the closures it was left (gbuffer.lobes: those that stop,
// pb_blender_split, or all at the end of the eye path), so each path is
// counted once; direct.comp and the G-buffer's glossy vertices share
// common/direct_light.glsl.
#extension GL_GOOGLE_include_directive : require
#include "shared/pb_gpu.h"

layout(local_size_x = PB_GPU_WORKGROUP) in;

#define PB_WORLD_BINDING PB_BIND_WORLD
#include "common/scene.glsl"
#include "common/lights.glsl"

#include "common/direct_light.glsl"

void main() {
  uint gid = pb_gid();
  if (gid >= frame.pixel_count) return;
  pb_gpu_gbuffer g = gbuffer[gid];
  if (g.prim == PB_GPU_MISS) return;
  pb_surface surf = pb_surface_from_hit(g.prim, g.u, g.v, -g.wo);
  // Normal map: the BSDF (and its |cos| below) use n_s; shadow-ray offsets
  // and side tests keep surf.ng.
  pb_apply_normal_map(surf, g.prim, g.u, g.v);
  pb_bsdf b = pb_bsdf_setup_t(surf, g.wo, pb_surface_tangent(g.prim, g.u, g.v));
  // A Blender material's vertex lights the closures the G-buffer pass left
  // to it (those that stop, or all at the end of its eye path).
  if (SC_BLENDER && g.lobes != 0u) {
    b.mask = g.lobes;
    pb_blender_split(b, frame.glossy_path_alpha2);
  }
  // Random numbers keyed by the pixel's index in the full frame (a crop
  // draws the full frame's samples).
  uint key = pb_pixel_key(frame.pixel_base + gid);
  uint rng = pb_walk_seed(key, pass.sample_index, 1u);
  vec3 sum = pb_delta_lights(surf, b, g.wo, rng);
  if (SC_EMISSIVE && frame.emitter_count > 0u) sum += pb_emitter_light(surf, b, g.wo, key, pass.sample_index, rng);
  if (SC_SOFT_LIGHTS) sum += pb_soft_direct(surf, b, g.wo, key, pass.sample_index, rng);
  if (SC_WORLD) sum += pb_world_direct(surf, b, g.wo, key, pass.sample_index, rng);
  vec3 c = g.throughput * sum;
  pb_gpu_accum acc = accum[gid];
  acc.beauty.rgb += c;
  if (g.chain == 0u) acc.direct += c;
  accum[gid] = acc;
}
