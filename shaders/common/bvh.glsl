// BVH traversal against the layout of shaders/shared/pb_gpu.h.
// The includer declares   vec4 bvh_nodes4[];  vec4 bvh_tris4[];   (the
// pb_gpu_bvh_node and pb_gpu_tri arrays seen as vec4s) in storage buffers
// before including this file.
//
// Ray-triangle: watertight test of Woop, Benthin and Wald, "Watertight
// Ray/Triangle Intersection", JCGT 2(1), 2013: the ray is sheared so that it
// runs along +z through the origin, the edge functions are evaluated in that
// 2-D frame, so a point on a shared edge is inside exactly one of the two
// triangles (or both, never neither). Hits are accepted in (tmin, tmax);
// back faces count (no culling), as in Embree.
//
// Boxes: slab test with the reciprocal direction and tmax scaled by
// 1 + 2 gamma(3) (Ize, "Robust BVH Ray Traversal", JCGT 2(2), 2013), so that
// rounding never culls a box the ray touches.
//
// With PB_RAY_QUERY (the _rq builds of shaders.cmake, loaded on a device with
// VK_KHR_ray_query) pb_trace is cast through rayQueryEXT instead, against the
// scene's acceleration structure (src/gpu/accel.c); the includer then
// declares  accelerationStructureEXT pb_tlas  at the binding where the BVH
// nodes are, and no BVH buffer.
#ifndef PB_BVH_GLSL
#define PB_BVH_GLSL

#define PB_INF uintBitsToFloat(0x7f800000u)

#ifdef PB_RAY_QUERY
// The same contract as the BVH's pb_trace below: the closest hit in
// (tmin, tmax) (any hit with any_hit), primitive id = the scene's triangle
// index (the structure holds the scene's triangles in order, one opaque
// geometry, no face culling: back faces count, as in the BVH and Embree),
// u, v the barycentrics of p1 and p2 (Embree's and the BVH's), t_hit = tmax
// on a miss. Differences by design: the query's interval is closed and the
// hardware's triangle test is its own (watertight on NVIDIA, AMD, Intel and
// lavapipe), without the BVH's test that rejects an origin lying on the
// triangle's plane within rounding; rays start off surfaces by
// pb_offset_ray as before. A ray the query may not take (a non-finite or
// zero direction, a non-finite origin, NaN bounds: undefined behaviour for
// rayQueryInitializeEXT) misses, as every BVH test fails for it.
uint pb_trace(vec3 org, vec3 dir, float tmin, float tmax, bool any_hit,
              out float t_hit, out float u_hit, out float v_hit) {
  u_hit = 0.0;
  v_hit = 0.0;
  t_hit = tmax;
  float t1 = min(tmax, 3.0e38); // +inf and beyond: a finite bound
  bool ok = !(any(isnan(org)) || any(isinf(org)) || any(isnan(dir)) || any(isinf(dir)) || all(equal(dir, vec3(0.0))));
  if (!ok || !(tmin >= 0.0) || !(t1 > tmin)) return PB_GPU_MISS;
  uint flags = gl_RayFlagsOpaqueEXT | (any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : 0u);
  rayQueryEXT q;
  rayQueryInitializeEXT(q, pb_tlas, flags, 0xffu, org, tmin, dir, t1);
  while (rayQueryProceedEXT(q)) {
  }
  if (rayQueryGetIntersectionTypeEXT(q, true) != gl_RayQueryCommittedIntersectionTriangleEXT) return PB_GPU_MISS;
  vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, true);
  t_hit = rayQueryGetIntersectionTEXT(q, true);
  u_hit = b.x;
  v_hit = b.y;
  return uint(rayQueryGetIntersectionPrimitiveIndexEXT(q, true));
}
#else

struct pb_ray_prep {
  vec3 org;
  vec3 dir;
  vec3 inv_dir;
  int kx, ky, kz;
  vec3 shear; // Sx, Sy, Sz
};

pb_ray_prep pb_prepare_ray(vec3 org, vec3 dir) {
  pb_ray_prep r;
  r.org = org;
  r.dir = dir;
  // Division by a zero component gives +-inf, which the slab test handles;
  // 1/-0 = -inf is what we want for a direction of -0.
  r.inv_dir = vec3(1.0) / dir;
  vec3 a = abs(dir);
  r.kz = (a.x > a.y) ? ((a.x > a.z) ? 0 : 2) : ((a.y > a.z) ? 1 : 2);
  r.kx = (r.kz + 1) % 3;
  r.ky = (r.kx + 1) % 3;
  // Keep the winding: swap kx, ky when dir[kz] is negative.
  if (dir[r.kz] < 0.0) {
    int t = r.kx;
    r.kx = r.ky;
    r.ky = t;
  }
  r.shear = vec3(dir[r.kx] / dir[r.kz], dir[r.ky] / dir[r.kz], 1.0 / dir[r.kz]);
  return r;
}

// Returns true and updates t, u, v (Embree barycentrics) for a hit closer
// than t and beyond tmin.
bool pb_intersect_tri(in pb_ray_prep r, vec3 p0, vec3 p1, vec3 p2, float tmin,
                      inout float t, out float u, out float v) {
  u = 0.0;
  v = 0.0;
  vec3 A = p0 - r.org, B = p1 - r.org, C = p2 - r.org;
  float Ax = A[r.kx] - r.shear.x * A[r.kz];
  float Ay = A[r.ky] - r.shear.y * A[r.kz];
  float Bx = B[r.kx] - r.shear.x * B[r.kz];
  float By = B[r.ky] - r.shear.y * B[r.kz];
  float Cx = C[r.kx] - r.shear.x * C[r.kz];
  float Cy = C[r.ky] - r.shear.y * C[r.kz];
  // precise: the edge functions must be evaluated exactly as written (no
  // contraction into FMA differently for the two triangles of an edge).
  precise float U = Cx * By - Cy * Bx;
  precise float V = Ax * Cy - Ay * Cx;
  precise float W = Bx * Ay - By * Ax;
  if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0))
    return false;
  precise float det = U + V + W;
  if (det == 0.0) return false;
  // Distance from the triangle's plane (as Embree does), better conditioned
  // for grazing rays than the sheared-space numerator; the inside test
  // above stays the watertight one.
  vec3 e1 = p1 - p0, e2 = p2 - p0;
  vec3 N = cross(e1, e2);
  float den = dot(r.dir, N);
  if (den == 0.0) return false;
  float num = dot(A, N);
  // An origin on the plane within the rounding of num is no hit (as pbrt-v4
  // rejects t <= deltaT): N from the float edges errs by ~eps |e1||e2| per
  // component, so the plane distance errs by ~eps |A| / sin(angle), which
  // beats the 256-ulp offset of pb_offset_ray on slivers and on triangles
  // much larger than the hit point's coordinates (tests/unit/hard_rays.h).
  // First-order bound 8 eps dot(|A|, M) (eps = 2^-24; M: the magnitudes of
  // the cross product's terms; rounding of e1, e2, N, A and the dot), with
  // a margin: 12 eps.
  vec3 a1 = abs(e1), a2 = abs(e2);
  vec3 M = vec3(a1.y * a2.z + a1.z * a2.y, a1.z * a2.x + a1.x * a2.z, a1.x * a2.y + a1.y * a2.x);
  if (abs(num) <= 7.1525574e-7 * dot(abs(A), M)) return false;
  float tt = num / den;
  if (!(tt > tmin) || !(tt < t)) return false;
  float inv_det = 1.0 / det;
  t = tt;
  u = V * inv_det;
  v = W * inv_det;
  return true;
}

// Entry distance of the ray into a box, or +inf when it misses (t0, t1).
float pb_box_entry(in pb_ray_prep r, vec3 lo, vec3 hi, float t0, float t1) {
  vec3 a = (lo - r.org) * r.inv_dir;
  vec3 b = (hi - r.org) * r.inv_dir;
  vec3 tn = min(a, b), tf = max(a, b);
  // NaN (0 * inf when the origin lies on a slab with a zero direction
  // component) must not cull: max/min return the other operand for NaN in
  // GLSL only by implementation, so replace NaN explicitly.
  tn = mix(tn, vec3(-PB_INF), isnan(tn));
  tf = mix(tf, vec3(PB_INF), isnan(tf));
  float enter = max(max(tn.x, tn.y), max(tn.z, t0));
  float leave = min(min(tf.x, tf.y), min(tf.z, t1)) * 1.0000003576; // 1 + 2 gamma(3)
  return enter <= leave ? enter : PB_INF;
}

// Node and triangle fetches. The includer declares the BVH buffers as vec4
// arrays (two per pb_gpu_bvh_node: lo + first, hi + count; three per
// pb_gpu_tri: p0 + prim, p1, p2), the std430 layout of pb_gpu.h: one vec4
// load per 16 bytes. llvmpipe turns every load whose address differs between
// lanes into a loop over the lanes, so fewer, wider loads are what makes
// divergent traversal cheaper there.
//
// Traversal state: a node is carried as its packed (first << 3) | count
// (count <= PB_BVH_MAX_LEAF < 8; the builder keeps first < 2^29), read from
// the parent's fetch of both children, so a node is never fetched twice.

// Closest hit in (tmin, tmax) when any_hit is false; with any_hit, stops at
// the first hit found (occlusion). Returns the primitive id or PB_GPU_MISS.
//
// 4-wide nodes (PB_BVH_WIDTH): the four child slots are fetched together
// (eight vec4 loads) and box-tested. Closest hit: the children hit are
// sorted by entry distance (a 5-comparator network), the nearest is entered
// and the others pushed farthest first, each with its entry distance; a
// popped node entered beyond the closest hit so far is skipped. Any hit: no
// sorting (any hit ends the query).
uint pb_trace(vec3 org, vec3 dir, float tmin, float tmax, bool any_hit,
              out float t_hit, out float u_hit, out float v_hit) {
  pb_ray_prep r = pb_prepare_ray(org, dir);
  uvec2 stack[(PB_BVH_WIDTH - 1u) * PB_BVH_MAX_DEPTH];
  int sp = 0;
  float t = tmax;
  uint prim = PB_GPU_MISS;
  u_hit = 0.0;
  v_hit = 0.0;
  vec4 ra = bvh_nodes4[0], rb = bvh_nodes4[1];
  if (pb_box_entry(r, ra.xyz, rb.xyz, tmin, t) == PB_INF) {
    t_hit = t;
    return PB_GPU_MISS;
  }
  uint node = (floatBitsToUint(ra.w) << 3u) | floatBitsToUint(rb.w);
  for (;;) {
    uint first = node >> 3u, count = node & 7u;
    if (count > 0u) {
      for (uint i = 0u; i < count; ++i) {
        uint k = 3u * (first + i);
        vec4 a = bvh_tris4[k], b = bvh_tris4[k + 1u], c = bvh_tris4[k + 2u];
        float u, v;
        if (pb_intersect_tri(r, a.xyz, b.xyz, c.xyz, tmin, t, u, v)) {
          prim = floatBitsToUint(a.w);
          u_hit = u;
          v_hit = v;
          if (any_hit) {
            t_hit = t;
            return prim;
          }
        }
      }
    } else {
      uint k = 2u * first;
      float e[4];
      uint n[4];
      for (uint j = 0u; j < 4u; ++j) {
        vec4 a = bvh_nodes4[k + 2u * j], b = bvh_nodes4[k + 2u * j + 1u];
        n[j] = (floatBitsToUint(a.w) << 3u) | floatBitsToUint(b.w);
        e[j] = n[j] == 0u ? PB_INF : pb_box_entry(r, a.xyz, b.xyz, tmin, t);
      }
      if (!any_hit) {
#define PB_CSWAP(i, j) if (e[j] < e[i]) { float te = e[i]; e[i] = e[j]; e[j] = te; uint tn = n[i]; n[i] = n[j]; n[j] = tn; }
        PB_CSWAP(0, 1) PB_CSWAP(2, 3) PB_CSWAP(0, 2) PB_CSWAP(1, 3) PB_CSWAP(1, 2)
#undef PB_CSWAP
      }
      // Walk from the farthest: every child hit but the nearest is pushed
      // (farthest first), the nearest is entered.
      uint next = 0u;
      float next_e = PB_INF;
      for (int j = 3; j >= 0; --j) {
        if (e[j] == PB_INF) continue;
        if (next != 0u) stack[sp++] = uvec2(next, floatBitsToUint(next_e));
        next = n[j];
        next_e = e[j];
      }
      if (next != 0u) {
        node = next;
        continue;
      }
    }
    // Pop, skipping nodes entered beyond the closest hit so far.
    bool found = false;
    while (sp > 0) {
      uvec2 s = stack[--sp];
      if (uintBitsToFloat(s.y) <= t * 1.0000003576) { // the box test's own slack
        node = s.x;
        found = true;
        break;
      }
    }
    if (!found) break;
  }
  t_hit = t;
  return prim;
}

#endif // PB_RAY_QUERY

#endif
