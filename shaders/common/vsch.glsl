// The view-sample cluster hierarchy (seed 004; layout in shared/pb_vsch.h):
// the data buffer, node accessors, the view frame, fixed-point sums and the
// photon traversal shared by vsch_count.comp and vsch_fill.comp.
// Include after shared/pb_gpu.h, pb_photon.h, pb_vsch.h and, for the shading
// kernels, common/scene.glsl (which then provides `frame`); define
// PB_VSCH_DATA_BINDING first.
#ifndef PB_VSCH_GLSL
#define PB_VSCH_GLSL

#ifndef PB_SCENE_GLSL
layout(std430, set = 0, binding = PB_VSCH_BIND_FRAME) readonly buffer FrameBuf { pb_gpu_frame frame; };
uint pb_gid() { return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP; }
#endif
layout(std430, set = 0, binding = PB_VSCH_DATA_BINDING) buffer VschData { uint vd[]; };
layout(push_constant) uniform VschPush { pb_gpu_vsch_push vp; };

const float PB_VSCH_PI = 3.14159265358979323846;

uint pb_ord(float f) {
  uint b = floatBitsToUint(f);
  return (b & 0x80000000u) != 0u ? ~b : (b | 0x80000000u);
}
float pb_unord(uint o) { return uintBitsToFloat((o & 0x80000000u) != 0u ? (o & 0x7fffffffu) : ~o); }

uint pb_node_word(uint g, uint w) { return vp.node_off + g * PB_VSCH_NODE_WORDS + w; }
vec3 pb_node_lo(uint g) {
  uint b = pb_node_word(g, 0u);
  return vec3(pb_unord(vd[b]), pb_unord(vd[b + 1u]), pb_unord(vd[b + 2u]));
}
vec3 pb_node_hi(uint g) {
  uint b = pb_node_word(g, 3u);
  return vec3(pb_unord(vd[b]), pb_unord(vd[b + 1u]), pb_unord(vd[b + 2u]));
}
// The unit cone axis of node g of `level` (clusters keep an integer sum).
vec3 pb_node_axis(uint g, uint level) {
  uint b = pb_node_word(g, 8u);
  if (level == 0u) {
    vec3 s = vec3(ivec3(int(vd[b]), int(vd[b + 1u]), int(vd[b + 2u])));
    float l = length(s);
    return l > 0.0 ? s / l : vec3(0.0, 0.0, 1.0);
  }
  return vec3(uintBitsToFloat(vd[b]), uintBitsToFloat(vd[b + 1u]), uintBitsToFloat(vd[b + 2u]));
}
float pb_node_alpha(uint g) { return uintBitsToFloat(vd[pb_node_word(g, 11u)]); }

// The camera's orthonormal view frame: right, up, forward (the grid and
// the boxes live in it, seed 004 4.3: "bounding boxes in view-space
// coordinates").
void pb_view_frame(out vec3 r, out vec3 u, out vec3 f) {
  precise vec3 f0 = normalize(frame.cam.forward);
  f = f0;
  r = normalize(frame.cam.right - f * dot(frame.cam.right, f));
  u = cross(r, f);
  if (dot(u, frame.cam.up) < 0.0) u = -u;
}
vec3 pb_to_view(vec3 p) {
  precise vec3 r, u, f;
  pb_view_frame(r, u, f);
  precise vec3 d = p - frame.cam.position;
  precise vec3 v = vec3(dot(d, r), dot(d, u), dot(d, f));
  return v;
}

// Global id of node (x, y) of level L >= 1.
uint pb_level_node(uint L, uint x, uint y) { return vp.level_base[L] + y * vd[PB_VSCH_H_NX + L] + x; }

// 64-bit unsigned add of v at words w (low), w + 1 (high) with 32-bit
// atomics: the add that wraps the low word carries.
void pb_add64(uint w, uint v) {
  if (v == 0u) return;
  uint old = atomicAdd(vd[w], v);
  if (old + v < old) atomicAdd(vd[w + 1u], 1u);
}
float pb_read64(uint w) { return float(vd[w + 1u]) * 4294967296.0 + float(vd[w]); }
uint pb_fixed(float e, float emax) {
  float q = emax > 0.0 ? e / emax * float(PB_VSCH_FIXED_ONE) : 0.0;
  return q > 0.0 && !isinf(q) ? uint(min(q, 4.0 * float(PB_VSCH_FIXED_ONE)) + 0.5) : 0u;
}

// Photons of the map: min(counts.stored, capacity) or the host's count.
#ifdef PB_VSCH_PHOTON_COUNT
uint pb_vsch_photons() { return vp.count_from_map != 0u ? min(mcounts.stored, vp.capacity) : min(vp.host_count, vp.capacity); }
#endif

float pb_photon_radius(pb_gpu_photon p) {
  return vp.radius > 0.0 ? vp.radius : p.radius * (vp.footprint_scale > 0.0 ? vp.footprint_scale : 1.0);
}

// How far the edges of a sample's face are looked for (common/
// kernel_edges.glsl): twice the largest photon radius of the map, as the
// cluster-trivial acceptance needs every edge within 2 r of a sample known
// (vsch_traverse.glsl); 0 (no edge tests) under PB_VSCH_NO_EDGES.
float pb_vsch_edge_reach() {
  return (vp.flags & PB_VSCH_NO_EDGES) != 0u ? 0.0 : 2.0 * uintBitsToFloat(vd[PB_VSCH_H_RMAX]);
}

// Octant of a view-space direction, and its centre (seed 004 4.7).
uint pb_octant(vec3 d) { return (d.x > 0.0 ? 1u : 0u) | (d.y > 0.0 ? 2u : 0u) | (d.z > 0.0 ? 4u : 0u); }
vec3 pb_octant_dir(uint o) {
  return vec3((o & 1u) != 0u ? 1.0 : -1.0, (o & 2u) != 0u ? 1.0 : -1.0, (o & 4u) != 0u ? 1.0 : -1.0) * 0.57735026919;
}

#endif
