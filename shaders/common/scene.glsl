// Bindings shared by the render passes (gbuffer.comp, direct.comp), the
// specialization constants that compile a scene's features in or out, and
// surface reconstruction from a hit. Mirrors src/ref (accel.c
// pb_surface_from_hit, bsdf.c pb_bsdf_setup/eval, lights.c) so that the GPU
// and the reference render the same scene model the same way.
#ifndef PB_SCENE_GLSL
#define PB_SCENE_GLSL

layout(std430, set = 0, binding = PB_BIND_FRAME) readonly buffer FrameBuf { pb_gpu_frame frame; };
#ifdef PB_RAY_QUERY
layout(set = 0, binding = PB_BIND_NODES) uniform accelerationStructureEXT pb_tlas; // the scene's (gpu/accel.c)
#else
layout(std430, set = 0, binding = PB_BIND_NODES) readonly buffer Nodes { vec4 bvh_nodes4[]; };   // pb_gpu_bvh_node[], 2 each
layout(std430, set = 0, binding = PB_BIND_TRIS) readonly buffer Tris { vec4 bvh_tris4[]; };     // pb_gpu_tri[], 3 each
#endif
layout(std430, set = 0, binding = PB_BIND_INDICES) readonly buffer Indices { uint indices[]; };
layout(std430, set = 0, binding = PB_BIND_NORMALS) readonly buffer Normals { float normals[]; };
layout(std430, set = 0, binding = PB_BIND_UVS) readonly buffer Uvs { float uvs[]; };
layout(std430, set = 0, binding = PB_BIND_TRI_MATERIAL) readonly buffer TriMat { uint tri_material[]; };
layout(std430, set = 0, binding = PB_BIND_MATERIALS) readonly buffer Materials { pb_gpu_material materials[]; };
layout(std430, set = 0, binding = PB_BIND_TEXTURES) readonly buffer Textures { pb_gpu_texture textures[]; };
layout(std430, set = 0, binding = PB_BIND_TEXELS) readonly buffer Texels { uint texels[]; };
layout(std430, set = 0, binding = PB_BIND_LIGHTS) readonly buffer Lights { pb_gpu_light lights[]; };
// Bindings 11, 12 and the push constants belong to the render passes; a pass
// with other buffers there (the photon tracer) defines PB_SCENE_OWN_PASS_IO
// and declares its own.
#ifndef PB_SCENE_OWN_PASS_IO
layout(std430, set = 0, binding = PB_BIND_GBUFFER) buffer GBuf { pb_gpu_gbuffer gbuffer[]; };
layout(std430, set = 0, binding = PB_BIND_ACCUM) buffer Accum { pb_gpu_accum accum[]; };
#endif
layout(std430, set = 0, binding = PB_BIND_POSITIONS) readonly buffer Positions { float positions[]; };
layout(std430, set = 0, binding = PB_BIND_EMITTERS) readonly buffer Emitters { pb_gpu_emitter emitters[]; };
#ifndef PB_SCENE_OWN_PASS_IO
layout(push_constant) uniform PassPush { pb_gpu_pass_push pass; };
#endif

// Specialization constants (src/render/frame/frame.c sets them from the scene's
// plan, src/render/scene/scene_plan.c): code for a feature the scene lacks is compiled out.
layout(constant_id = PB_SPEC_HAS_NORMALS) const bool SC_HAS_NORMALS = true;
layout(constant_id = PB_SPEC_TEXTURES) const bool SC_TEXTURES = true;
layout(constant_id = PB_SPEC_SPECULAR) const bool SC_SPECULAR = true;   // delta lobes: eye chains
layout(constant_id = PB_SPEC_EMISSIVE) const bool SC_EMISSIVE = true;  // emissive triangles or unlit surfaces
// SC_TRANSMISSION and SC_NORMAL_MAPS belong to the photon tracer and the
// gather. Soft lights (sphere, area, soft sun) and the world light, for the
// passes that include common/lights.glsl.
layout(constant_id = PB_SPEC_SOFT_LIGHTS) const bool SC_SOFT_LIGHTS = true;
layout(constant_id = PB_SPEC_WORLD) const bool SC_WORLD = true;
// Blender materials (principled.glsl) exist only in the PB_BLENDER build of
// a pass (shaders.cmake); the other build has them compiled out entirely.
#ifdef PB_BLENDER
const bool SC_BLENDER = true;
layout(constant_id = PB_SPEC_ALPHA) const bool SC_ALPHA = true;      // Alpha < 1: transparent shadows
layout(constant_id = PB_SPEC_PRINCIPLED2) const bool SC_PRINCIPLED2 = true; // a Principled v2 material
layout(constant_id = PB_SPEC_CLOSURES) const uint SC_CLOSURES = PB_CLOSURES_ALL; // the closures it may make
#else
const bool SC_BLENDER = false;
const bool SC_ALPHA = false;
const bool SC_PRINCIPLED2 = false;
const uint SC_CLOSURES = 0u;
#endif

// [[dont_unroll]] on the loops that must stay loops (texture lookups).
#extension GL_EXT_control_flow_attributes : require

#include "common/bvh.glsl"

const float PB_PI = 3.14159265358979323846;
const float PB_INV_PI = 0.31830988618379067154;
const float PB_SPECULAR_ROUGHNESS = 0.02;

// Linear pixel index of this invocation within the band (2-D dispatch fold,
// see pb_gpu_dispatch).
uint pb_gid() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * PB_GPU_WORKGROUP;
}

// ---- random numbers: a counter-based hash per (seed, pixel, sample, dim) --

uint pb_hash(uint x) { // lowbias32 (Wellons)
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}
float pb_rand(uint pixel, uint s, uint dim) {
  uint h = pb_hash(frame.seed_lo ^ pb_hash(pixel ^ pb_hash(s * 0x9e3779b9u ^ pb_hash(dim ^ frame.seed_hi))));
  return float(h >> 8) * (1.0 / 16777216.0);
}

// Seed of a small per-evaluation stream (principled.glsl's Multiscatter GGX
// walk) for one pixel sample and purpose; pixel is the random-number key
// (pb_pixel_key).
uint pb_walk_seed(uint pixel, uint s, uint purpose) {
  return pb_hash(frame.seed_lo ^ pb_hash(pixel ^ pb_hash(s * 0x9e3779b9u ^ pb_hash(purpose ^ 0x632be5abu))));
}

// The random-number key of pixel `pixel` of this image: its index in the
// full frame (frame.key_*), so a crop draws the full frame's numbers.
uint pb_pixel_key(uint pixel) {
  if (frame.key_width == 0u) return pixel;
  return (pixel / frame.width + frame.key_y0) * frame.key_width + pixel % frame.width + frame.key_x0;
}

// ---- textures: pb_texture_sample semantics (scene.c) ----------------------

float pb_srgb_to_linear(float v) {
  return v <= 0.04045 ? v / 12.92 : pow((v + 0.055) / 1.055, 2.4);
}
int pb_wrap(int i, int n, uint mode) {
  if (mode == 1u) return clamp(i, 0, n - 1);
  if (mode == 2u) {
    int p = 2 * n;
    int m = ((i % p) + p) % p;
    return m < n ? m : p - 1 - m;
  }
  return ((i % n) + n) % n;
}
vec4 pb_texel(pb_gpu_texture t, int x, int y) {
  if ((t.flags & PB_GPU_TEX_HALF) != 0u) { // scene.h pb_texture.rgbah
    uint i = t.offset + 2u * (uint(y) * t.width + uint(x));
    return vec4(unpackHalf2x16(texels[i]), unpackHalf2x16(texels[i + 1u]));
  }
  uint w = texels[t.offset + uint(y) * t.width + uint(x)];
  vec4 c = vec4(float(w & 255u), float((w >> 8) & 255u), float((w >> 16) & 255u), float(w >> 24)) * (1.0 / 255.0);
  if ((t.flags & PB_GPU_TEX_SRGB) != 0u)
    c.rgb = vec3(pb_srgb_to_linear(c.r), pb_srgb_to_linear(c.g), pb_srgb_to_linear(c.b));
  return c;
}
// The texels are read in a loop kept as a loop ([[dont_unroll]],
// principled.glsl): a lookup is inlined at every use of a texture, and four
// inlined texel decodes (each with three sRGB pow) per site made the
// shading passes of textured scenes slow to compile on lavapipe. Same
// arithmetic as four separate reads.
vec4 pb_texture_sample(uint index, vec2 uv) {
  pb_gpu_texture t = textures[index];
  float u = uv.x, v = uv.y;
  if (isnan(u) || isinf(u)) u = 0.0;
  if (isnan(v) || isinf(v)) v = 0.0;
  u = u - 65536.0 * trunc(u / 65536.0); // fmodf
  v = v - 65536.0 * trunc(v / 65536.0);
  int W = int(t.width), H = int(t.height);
  float fx = u * float(W) - 0.5, fy = v * float(H) - 0.5;
  bool nearest = (t.flags & PB_GPU_TEX_NEAREST) != 0u;
  int xa, xb, ya, yb;
  float ax = 0.0, ay = 0.0;
  if (nearest) {
    xa = xb = pb_wrap(int(floor(fx + 0.5)), W, t.wrap_s);
    ya = yb = pb_wrap(int(floor(fy + 0.5)), H, t.wrap_t);
  } else {
    float x0f = floor(fx), y0f = floor(fy);
    ax = fx - x0f;
    ay = fy - y0f;
    int x0 = int(x0f), y0 = int(y0f);
    xa = pb_wrap(x0, W, t.wrap_s);
    xb = pb_wrap(x0 + 1, W, t.wrap_s);
    ya = pb_wrap(y0, H, t.wrap_t);
    yb = pb_wrap(y0 + 1, H, t.wrap_t);
  }
  vec4 q[4];
  uint n = nearest ? 1u : 4u;
  [[dont_unroll]] for (uint k = 0u; k < n; ++k) q[k] = pb_texel(t, (k & 1u) != 0u ? xb : xa, (k & 2u) != 0u ? yb : ya);
  if (nearest) return q[0];
  return (q[0] * (1.0 - ax) + q[1] * ax) * (1.0 - ay) + (q[2] * (1.0 - ax) + q[3] * ax) * ay;
}

// ---- surfaces -------------------------------------------------------------

struct pb_surface {
  vec3 p;      // from barycentrics
  vec3 ng;     // unit, facing the incoming ray
  vec3 ns;     // unit, same hemisphere as ng
  vec3 ni;     // the interpolated normal: ns before a normal map (the reference's pb_surface.ni)
  vec3 nc;     // the Principled BSDF's coat normal: its Coat Normal's map, else ni (Cycles' sd->N)
  bool front;
  vec2 uv;     // TEXCOORD_0
  vec2 uv1;    // TEXCOORD_1 (0 when the scene has none)
  vec4 color;  // COLOR_0 (white when the scene has none)
  uint mat;
};

vec3 pb_position(uint i) { return vec3(positions[3u * i], positions[3u * i + 1u], positions[3u * i + 2u]); }

pb_surface pb_surface_from_hit(uint prim, float u, float v, vec3 ray_dir) {
  pb_surface s;
  float w = 1.0 - u - v;
  uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
  vec3 p0 = pb_position(i0), p1 = pb_position(i1), p2 = pb_position(i2);
  s.p = p0 * w + p1 * u + p2 * v;
  vec3 ng = normalize(cross(p1 - p0, p2 - p0));
  s.front = dot(ng, ray_dir) < 0.0;
  if (!s.front) ng = -ng;
  s.ng = ng;
  s.ns = ng;
  if (SC_HAS_NORMALS) {
    vec3 n0 = vec3(normals[3u * i0], normals[3u * i0 + 1u], normals[3u * i0 + 2u]);
    vec3 n1 = vec3(normals[3u * i1], normals[3u * i1 + 1u], normals[3u * i1 + 2u]);
    vec3 n2 = vec3(normals[3u * i2], normals[3u * i2 + 1u], normals[3u * i2 + 2u]);
    vec3 n = n0 * w + n1 * u + n2 * v;
    float l = length(n);
    if (l > 1e-12 && !isinf(l) && !isnan(l)) {
      n /= l;
      s.ns = dot(n, ng) < 0.0 ? -n : n;
    }
  }
  s.ni = s.nc = s.ns;
  s.uv = vec2(0.0);
  s.uv1 = vec2(0.0);
  if (SC_TEXTURES || frame.tangent_base != 0u) { // textures, or a normal map alone
    vec2 t0 = vec2(uvs[2u * i0], uvs[2u * i0 + 1u]);
    vec2 t1 = vec2(uvs[2u * i1], uvs[2u * i1 + 1u]);
    vec2 t2 = vec2(uvs[2u * i2], uvs[2u * i2 + 1u]);
    s.uv = t0 * w + t1 * u + t2 * v;
    uint b1 = frame.uv1_base;
    if (b1 != 0u)
      s.uv1 = vec2(uvs[b1 + 2u * i0], uvs[b1 + 2u * i0 + 1u]) * w + vec2(uvs[b1 + 2u * i1], uvs[b1 + 2u * i1 + 1u]) * u +
              vec2(uvs[b1 + 2u * i2], uvs[b1 + 2u * i2 + 1u]) * v;
  }
  s.color = vec4(1.0);
  uint bc = frame.color_base;
  if (bc != 0u)
    s.color = vec4(uvs[bc + 4u * i0], uvs[bc + 4u * i0 + 1u], uvs[bc + 4u * i0 + 2u], uvs[bc + 4u * i0 + 3u]) * w +
              vec4(uvs[bc + 4u * i1], uvs[bc + 4u * i1 + 1u], uvs[bc + 4u * i1 + 2u], uvs[bc + 4u * i1 + 3u]) * u +
              vec4(uvs[bc + 4u * i2], uvs[bc + 4u * i2 + 1u], uvs[bc + 4u * i2 + 2u], uvs[bc + 4u * i2 + 3u]) * v;
  s.mat = tri_material[prim];
  return s;
}

// A material's texture at the surface: its uv set through its transform
// (pb_texture_lookup, scene.c).
vec4 pb_texture_lookup(uint index, pb_surface s) {
  pb_gpu_texture t = textures[index];
  vec3 uv = vec3(t.texcoord == 1u ? s.uv1 : s.uv, 1.0);
  return pb_texture_sample(index, vec2(dot(t.xform_u.xyz, uv), dot(t.xform_v.xyz, uv)));
}

// The material's inputs at the surface, as pb_material_base_color /
// _metal_rough (scene.c): base colour = factor x texture x COLOR_0 (RGBA,
// clamped to [0, 1]); metallic, roughness = factors x texture B, G.
vec4 pb_surface_base_color(pb_surface s) {
  pb_gpu_material m = materials[s.mat];
  vec4 t = vec4(1.0);
  if (SC_TEXTURES && m.base_color_tex != PB_GPU_NO_TEXTURE) t = pb_texture_lookup(m.base_color_tex, s);
  return clamp(m.base_color * t * s.color, 0.0, 1.0);
}
vec2 pb_surface_metal_rough(pb_surface s) {
  pb_gpu_material m = materials[s.mat];
  vec2 mr = vec2(m.metallic, m.roughness);
  if (SC_TEXTURES && m.metallic_roughness_tex != PB_GPU_NO_TEXTURE) mr *= pb_texture_lookup(m.metallic_roughness_tex, s).bg;
  return mr;
}

// Waechter & Binder, Ray Tracing Gems ch. 6 (the reference's pb_offset_ray).
vec3 pb_offset_ray(vec3 p, vec3 n) {
  const float origin = 1.0 / 32.0, float_scale = 1.0 / 65536.0, int_scale = 256.0;
  ivec3 of = ivec3(int_scale * n);
  vec3 pi = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of.x : of.x)),
                 intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of.y : of.y)),
                 intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of.z : of.z)));
  return vec3(abs(p.x) < origin ? p.x + float_scale * n.x : pi.x,
              abs(p.y) < origin ? p.y + float_scale * n.y : pi.y,
              abs(p.z) < origin ? p.z + float_scale * n.z : pi.z);
}

// Tangent at a hit for anisotropic lobes: the interpolated vertex tangent
// of normal-mapped scenes (pb_scene.tangents), else 0 (principled.glsl then
// takes an arbitrary frame, as the reference does).
vec3 pb_surface_tangent(uint prim, float u, float v) {
  if (frame.tangent_base == 0u) return vec3(0.0);
  float w = 1.0 - u - v;
  uint tb = frame.tangent_base;
  uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
  vec3 t = vec3(normals[tb + 4u * i0], normals[tb + 4u * i0 + 1u], normals[tb + 4u * i0 + 2u]) * w +
           vec3(normals[tb + 4u * i1], normals[tb + 4u * i1 + 1u], normals[tb + 4u * i1 + 2u]) * u +
           vec3(normals[tb + 4u * i2], normals[tb + 4u * i2 + 1u], normals[tb + 4u * i2 + 2u]) * v;
  float l = length(t);
  return l > 1e-12 && !isinf(l) ? t / l : vec3(0.0);
}

// Beer-Lambert along a segment of length t in a medium of absorption
// sigma [1/m] (KHR_materials_volume), and the medium after a refraction
// (src/ref/ref_internal.h pb_medium_after: entering a front face takes the
// material's, leaving a back face clears it; media are not nested). t may
// be infinite (a ray that leaves the scene): 1 where sigma is 0, else 0.
vec3 pb_medium_transmittance(vec3 sigma, float t) {
  return mix(exp(-sigma * t), vec3(1.0), equal(sigma, vec3(0.0)));
}
vec3 pb_medium_after(vec3 sigma, pb_surface s, bool transmit) {
  if (!transmit) return sigma;
  return s.front ? materials[s.mat].attenuation : vec3(0.0);
}

#include "common/bsdf.glsl"

// Emitted radiance toward the ray (pb_surface_emission, src/ref/bsdf.c):
// the material's, from the front only unless double-sided (Blender
// materials are: Cycles' emission leaves both sides), a Principled BSDF's
// times its Alpha (the Transparent BSDF Cycles mixes in takes the rest). An
// unlit surface's base colour counts on camera paths only; the passes that
// call this for other paths (direct.comp's emitter samples) never meet one,
// since the emitter table holds emissive materials only.
vec3 pb_emission(pb_surface s) {
  if (!SC_EMISSIVE) return vec3(0.0);
  pb_gpu_material m = materials[s.mat];
  if (!s.front && (m.flags & PB_GPU_MAT_DOUBLE_SIDED) == 0u) return vec3(0.0);
  if ((m.flags & PB_GPU_MAT_UNLIT) != 0u) return pb_surface_base_color(s).rgb;
  vec3 e = m.emissive;
  if (SC_TEXTURES && m.emissive_tex != PB_GPU_NO_TEXTURE) e *= pb_texture_lookup(m.emissive_tex, s).rgb;
  if (SC_BLENDER && m.model == PB_GPU_MODEL_PRINCIPLED) e *= pb_blender_alpha(s);
  return e;
}
// The same toward wo: a Principled v2 material's emission lies under its
// sheen and coat (principled.glsl pb2_emission_weight), so it depends on
// the direction. The photon tracer's emitters keep pb_emission (alpha only).
vec3 pb_emission_toward(pb_surface s, vec3 wo) {
  if (SC_PRINCIPLED2 && materials[s.mat].model == PB_GPU_MODEL_PRINCIPLED && materials[s.mat].principled_v2 != 0u) {
    vec3 e = pb_emission(s);
    if (all(equal(e, vec3(0.0)))) return e;
    return e / max(pb_blender_alpha(s), 1e-30) * pb2_emission_weight(s, wo);
  }
  return pb_emission(s);
}
// The normal of texture `tex` (tangent space, glTF scale `scale`, Blender's
// Normal Map strength `st`: Cycles 4.0+ on the tangent-space vector, 3.x on
// the mapped normal) in the frame t, bb, n; false where it degenerates.
bool pb_map_normal(pb_surface s, uint tex, float scale, float st, bool cycles4, vec3 t, vec3 bb, vec3 n,
                   out vec3 nm) {
  vec3 c = pb_texture_lookup(tex, s).rgb * 2.0 - 1.0;
  c.xy *= scale;
  if (cycles4 && st != 1.0) {
    c.xy *= st;
    c.z = mix(1.0, c.z, clamp(st, 0.0, 1.0));
  }
  nm = t * c.x + bb * c.y + n * c.z;
  float ml = length(nm);
  if (!(ml > 1e-12) || isinf(ml)) return false;
  nm /= ml;
  if (!cycles4 && st != 1.0) {
    vec3 bl = n + (nm - n) * max(st, 0.0);
    float bll = length(bl);
    if (!(bll > 1e-12) || isinf(bll)) return false;
    nm = bl / bll;
  }
  return true;
}
// Normal mapping (glTF 2.0, material.normalTexture): in the tangent frame of
// the interpolated vertex normal N, tangent T (Gram-Schmidt against N at the
// hit) and bitangent B = cross(N, T) w (glTF TANGENT's handedness),
//   n_s = normalize(T t.x + B t.y + N t.z),  t = (2 rgb - 1) (scale, scale, 1)
// with linear (not sRGB) texels. Oriented like s.ns (flipped with it when
// the hit is on the side opposite the vertex normal). s.ng is untouched: it
// stays the normal for ray offsets and side tests, and pb_bsdf_setup /
// pb_bsdf_eval keep their guards (n_s replaced by ng when wo is below it;
// no reflection unless wi is above both ng and n_s). Identical to the
// reference's pb_apply_normal_map (src/ref/accel.c). The eye passes (gbuffer,
// direct) and the gather's n_s accumulator call it; the photon tracer does
// not (photon_trace.comp).
// The Principled BSDF's Coat Normal map goes into s.nc the same way (the
// reference's; Cycles 4.5 svm/closure.h: an unlinked Coat Normal is sd->N).
void pb_apply_normal_map(inout pb_surface s, uint prim, float u, float v) {
  if (frame.tangent_base == 0u) return;
  pb_gpu_material m = materials[s.mat];
  bool blender = SC_BLENDER && m.model != PB_GPU_MODEL_GLTF;
  bool coat_map = blender && m.coat_normal_tex != PB_GPU_NO_TEXTURE;
  if (m.normal_tex == PB_GPU_NO_TEXTURE && !coat_map) return;
  float w = 1.0 - u - v;
  uint i0 = indices[3u * prim], i1 = indices[3u * prim + 1u], i2 = indices[3u * prim + 2u];
  vec3 p0 = pb_position(i0), p1 = pb_position(i1), p2 = pb_position(i2);
  vec3 n = normalize(cross(p1 - p0, p2 - p0)); // as stored (not facing the ray)
  if (SC_HAS_NORMALS) {
    vec3 vn = vec3(normals[3u * i0], normals[3u * i0 + 1u], normals[3u * i0 + 2u]) * w +
              vec3(normals[3u * i1], normals[3u * i1 + 1u], normals[3u * i1 + 2u]) * u +
              vec3(normals[3u * i2], normals[3u * i2 + 1u], normals[3u * i2 + 2u]) * v;
    float l = length(vn);
    if (l > 1e-12 && !isinf(l) && !isnan(l)) n = vn / l;
  }
  uint tb = frame.tangent_base;
  vec4 t4 = vec4(normals[tb + 4u * i0], normals[tb + 4u * i0 + 1u], normals[tb + 4u * i0 + 2u],
                 normals[tb + 4u * i0 + 3u]) * w +
            vec4(normals[tb + 4u * i1], normals[tb + 4u * i1 + 1u], normals[tb + 4u * i1 + 2u],
                 normals[tb + 4u * i1 + 3u]) * u +
            vec4(normals[tb + 4u * i2], normals[tb + 4u * i2 + 1u], normals[tb + 4u * i2 + 2u],
                 normals[tb + 4u * i2 + 3u]) * v;
  vec3 t = t4.xyz - n * dot(n, t4.xyz);
  float tl = length(t);
  vec3 bb;
  if (tl > 1e-12 && !isinf(tl) && !isnan(tl)) {
    t /= tl;
    bb = cross(n, t) * (t4.w < 0.0 ? -1.0 : 1.0);
  } else {
    pb_basis(n, t, bb);
  }
  bool cycles4 = blender && (m.flags & PB_GPU_MAT_NORMAL_MAP_CYCLES4) != 0u;
  float flip = dot(n, s.ng) < 0.0 ? -1.0 : 1.0;
  vec3 nm;
  if (m.normal_tex != PB_GPU_NO_TEXTURE &&
      pb_map_normal(s, m.normal_tex, m.normal_scale, blender ? m.normal_strength : 1.0, cycles4, t, bb, n, nm))
    s.ns = flip * nm;
  if (coat_map && pb_map_normal(s, m.coat_normal_tex, 1.0, m.coat_normal_strength, cycles4, t, bb, n, nm))
    s.nc = flip * nm;
}

#endif
