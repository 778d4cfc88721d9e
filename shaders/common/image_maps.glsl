// Ray-map intersection of the image-space photon tracer (seed 003, Yao et
// al. 2010, section 5), against the cube maps of shared/pb_image_maps.h.
// The includer declares
//   im_info (pb_gpu_image_maps_info), im_maps[] (pb_gpu_image_map),
//   im_texels[] (pb_gpu_image_texel)
// (one buffer for the first two), and defines PB_INF (common/bvh.glsl).
// A host port of pb_image_classify and of the whole search lives in
// src/render/photon/image_maps.c (pb_image_classify, pb_image_maps_intersect_host)
// and is tested on constructed rays (test_image_maps_classify).
#ifndef PB_IMAGE_MAPS_GLSL
#define PB_IMAGE_MAPS_GLSL

// Outcomes of one map (section 5.2, Figure 7) and of a whole search.
const uint PB_IMAGE_TYPE_A = 0u;  // no crossing: the ray leaves what the map sees
const uint PB_IMAGE_TYPE_B = 1u;  // a point of the surface, not on the ray (e > epsilon)
const uint PB_IMAGE_TYPE_D = 3u;  // accepted (C or D: the nearest over the maps is D)

// Texel of direction w (not necessarily unit) in a cube of res^2 per face:
// the layout of shared/pb_image_maps.h.
uint pb_cube_texel(vec3 w, uint res) {
  vec3 a = abs(w);
  uint ax = (a.x >= a.y && a.x >= a.z) ? 0u : (a.y >= a.z ? 1u : 2u);
  float m = max(a[ax], 1e-30);
  uint face = 2u * ax + (w[ax] < 0.0 ? 1u : 0u);
  float s = w[(ax + 1u) % 3u] / m, t = w[(ax + 2u) % 3u] / m;
  float fr = float(res);
  uint i = uint(clamp(floor((s * 0.5 + 0.5) * fr), 0.0, fr - 1.0));
  uint j = uint(clamp(floor((t * 0.5 + 0.5) * fr), 0.0, fr - 1.0));
  return (face * res + j) * res + i;
}

// Direction (unit) through the centre of texel idx.
vec3 pb_cube_dir(uint idx, uint res) {
  uint i = idx % res, j = (idx / res) % res, face = idx / (res * res);
  uint ax = face / 2u;
  float sg = (face % 2u) == 0u ? 1.0 : -1.0;
  float s = (float(i) + 0.5) / float(res) * 2.0 - 1.0, t = (float(j) + 0.5) / float(res) * 2.0 - 1.0;
  vec3 w = vec3(0.0);
  w[ax] = sg;
  w[(ax + 1u) % 3u] = s;
  w[(ax + 2u) % 3u] = t;
  return normalize(w);
}

// Eq. 2: the angular error of a point p found for the ray (x, r):
// e = 1 - (p - x).r / |p - x| ~ theta^2 / 2. Accepted (type C or D) when
// e <= epsilon and p lies ahead of x; else type B.
uint pb_image_classify(vec3 x, vec3 r, vec3 p, float epsilon) {
  vec3 q = p - x;
  float l = length(q);
  if (!(l > 0.0)) return PB_IMAGE_TYPE_B;
  float e = 1.0 - dot(q, r) / l;
  return e <= epsilon ? PB_IMAGE_TYPE_D : PB_IMAGE_TYPE_B;
}

// f(d) = |P(d) - c| - D(P(d) - c), P(d) = x + d r, D the map's distance
// along that direction (infinite where the texel saw nothing): negative
// where P is in front of the surface the map sees, positive behind it.
float pb_image_f(uint m, vec3 c, vec3 x, vec3 r, float d, out uint texel) {
  vec3 w = x + d * r - c;
  texel = im_maps[m].first + pb_cube_texel(w, im_info.resolution);
  pb_gpu_image_texel tx = im_texels[texel];
  if (tx.prim == PB_GPU_MISS) return -PB_INF;
  return length(w) - length(tx.position - c);
}

// Ray parameter of the i-th of n samples of the ray's projection in map m
// (section 5.1's marching): equal steps of the angle phi under which the
// centre c sees the point, phi from the foot of the perpendicular from c to
// the line (distance h): P = F + h tan(phi) r. Equal angles are equal
// texel counts on the cube, so the march crosses the map's texels evenly
// wherever the ray runs; a ray through c (h ~ 0) steps evenly in d.
float pb_image_march_d(float s_x, float h, float phi0, float phi1, float d0, float d1, uint i, uint n) {
  float a = float(i) / float(n);
  if (!(h > 1e-6 * (abs(s_x) + abs(d1) + 1e-6))) return mix(d0, d1, a);
  float phi = mix(phi0, phi1, a);
  return clamp(h * tan(phi) - s_x, d0, d1);
}

// One map (section 5.1): the march finds the first bracket [lo, hi] where
// f changes sign (in front (< 0) to behind (>= 0), or behind to in front of
// a surface the map saw); false position (the method
// of [SKALP05], im_info.secant_steps iterations) narrows it, keeping one
// under- and one overshoot; the point read at the end (the texel's surface
// point at the last overshoot) is classified by eq. 2. A type B point
// (a depth discontinuity of the map: Figure 6 (a)) does not end the search:
// the march goes on for a later bracket on the same ray. Returns the type;
// for D, t_out (distance along r to the point) and texel.
uint pb_image_map_intersect(uint m, vec3 x, vec3 r, float d0, float d1, out float t_out, out uint texel_out,
                            inout uint type_b) {
  vec3 c = im_maps[m].center;
  vec3 q = x - c;
  float s_x = dot(q, r);
  float h = length(q - s_x * r);
  float phi0 = atan(s_x + d0, h), phi1 = atan(s_x + d1, h);
  uint n = max(im_info.march_steps, 1u);
  uint tex;
  float d_prev = d0;
  float f_prev = pb_image_f(m, c, x, r, d0, tex);
  t_out = 0.0;
  texel_out = 0u;
  for (uint i = 1u; i <= n; ++i) {
    float d = pb_image_march_d(s_x, h, phi0, phi1, d0, d1, i, n);
    uint tex_hi;
    float f = pb_image_f(m, c, x, r, d, tex_hi);
    // A zero of f either way (5.1: "finding a zero of ... f(x + d r) = 0"):
    // in front -> behind, the ray meets the surface the map sees; behind ->
    // in front (not into -inf, where the map saw nothing: a silhouette), the
    // ray comes out through a surface the map sees from its other side (a
    // ray from outside a closed room, a sun photon through a roof: without
    // this it passed through and lit the room from inside).
    if ((f_prev < 0.0 && f >= 0.0) || (f_prev >= 0.0 && f < 0.0 && !isinf(f))) {
      float lo = d_prev, hi = d, f_lo = f_prev, f_hi = f;
      for (uint k = 0u; k < im_info.secant_steps; ++k) {
        // False position; a bound at -inf (that end saw nothing) falls back
        // to bisection.
        float dm = (isinf(f_lo) || isinf(f_hi) || !(abs(f_hi - f_lo) > 0.0))
                       ? 0.5 * (lo + hi)
                       : lo + (hi - lo) * (-f_lo / (f_hi - f_lo));
        uint tm;
        float fm = pb_image_f(m, c, x, r, dm, tm);
        if ((fm < 0.0) == (f_lo < 0.0)) {
          lo = dm;
          f_lo = fm;
        } else {
          hi = dm;
          f_hi = fm;
          tex_hi = tm;
        }
      }
      vec3 p = im_texels[tex_hi].position;
      if (pb_image_classify(x, r, p, im_info.epsilon) == PB_IMAGE_TYPE_D) {
        // The root on the ray, not the texel's centre point: that one lies
        // off the ray by up to half a texel's footprint, which at grazing
        // incidence is a long way along it (measured: the 95th percentile of
        // the distance error against the BVH on cornell_box, 8 maps of
        // 128^2, 1.3e-2 R with the texel's point).
        t_out = hi;
        texel_out = tex_hi;
        return PB_IMAGE_TYPE_D;
      }
      type_b++;
    }
    d_prev = d;
    f_prev = f;
  }
  return type_b > 0u ? PB_IMAGE_TYPE_B : PB_IMAGE_TYPE_A;
}

// The whole search (section 5.2): every map, the nearest accepted point
// (a farther accepted one is type C). Returns the outcome (A: every map saw
// the ray leave, B: only rejected points, D: texel_out holds the hit at
// distance t_out); nb, nc: the type B and C points met.
uint pb_image_intersect(vec3 x, vec3 r, out float t_out, out uint texel_out, out uint nb, out uint nc) {
  t_out = PB_INF;
  texel_out = 0u;
  nb = 0u;
  nc = 0u;
  // Clip to the scene's box (rays from directional lights start outside).
  vec3 inv = 1.0 / r;
  vec3 ta = (im_info.bounds_min - x) * inv, tb = (im_info.bounds_max - x) * inv;
  vec3 tn = min(ta, tb), tf = max(ta, tb);
  float d0 = max(max(max(tn.x, tn.y), tn.z), im_info.start_offset);
  float d1 = min(min(tf.x, tf.y), tf.z);
  if (!(d1 > d0)) return PB_IMAGE_TYPE_A;
  uint found = 0u;
  for (uint m = 0u; m < im_info.count; ++m) {
    float t;
    uint tex, b = 0u;
    // A point beyond the nearest accepted so far cannot be the first
    // intersection (type C at best): later maps march only up to it (its
    // distance along the ray plus 1 % for the texel's depth error).
    float dm = found > 0u ? min(d1, 1.01 * t_out + im_info.start_offset) : d1;
    if (!(dm > d0)) continue;
    uint ty = pb_image_map_intersect(m, x, r, d0, dm, t, tex, b);
    nb += b;
    if (ty == PB_IMAGE_TYPE_D) {
      found++;
      if (t < t_out) {
        t_out = t;
        texel_out = tex;
      }
    }
  }
  if (found > 0u) {
    nc = found - 1u;
    return PB_IMAGE_TYPE_D;
  }
  return nb > 0u ? PB_IMAGE_TYPE_B : PB_IMAGE_TYPE_A;
}

#endif
