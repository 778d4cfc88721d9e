// A point of a reflective-shadow-map texel (seed 001 24.2.1), shared by
// photon_rsm.comp (texel centres and corners, when the map is rendered) and
// photon_trace.comp (a uniformly jittered point of the texel a photon
// picked). Included after scene.glsl (lights[], pb_basis, pb_smoothstep01).
//
// Texel `local` of light entry rl covers [x0, x1] x [y0, y1] of its face in
// [-1, 1]^2 coordinates; jit in [0, 1]^2 places the point inside it ((0.5,
// 0.5): the centre). Out: the ray (o, d) from the light through that point,
// `measure`: the texel's measure (face-plane area for point and spot lights,
// area for directional ones), and `dens`: the light's flux per unit of that
// measure at the point, so that flux = integral of dens over the texel and a
// uniformly placed photon of the texel carries dens x measure:
//   point, spot: I f(d) (1 + X^2 + Y^2)^(-3/2), (X, Y) the point on the face
//     plane at distance 1 (s = tan(outer) scales a spot's plane; f the spot's
//     falloff, pb_spot_factor, 1 for point lights), dOmega = (1 + X^2 + Y^2)^(-3/2) dA;
//   directional: E, over the square around the scene's bounding disc.
void pb_rsm_texel_point(pb_gpu_rsm_light rl, uint local, vec2 jit, vec3 center, float radius, out vec3 o,
                        out vec3 d, out vec3 dens, out float measure) {
  uint res = rl.res;
  uint face = local / (res * res), pix = local % (res * res);
  uint ix = pix % res, iy = pix / res;
  float inv = 1.0 / float(res);
  float x = 2.0 * (float(ix) + jit.x) * inv - 1.0, y = 2.0 * (float(iy) + jit.y) * inv - 1.0;
  pb_gpu_light L = lights[rl.light];
  if (L.type == PB_GPU_LIGHT_DIRECTIONAL) {
    d = normalize(L.direction);
    vec3 t, b;
    pb_basis(d, t, b);
    o = center + t * (radius * x) + b * (radius * y) - d * (1.01 * radius);
    measure = (2.0 * radius * inv) * (2.0 * radius * inv);
    dens = L.power;
    return;
  }
  vec3 axis, t, b;
  float s;
  if (L.type == PB_GPU_LIGHT_SPOT) {
    axis = normalize(L.direction);
    pb_basis(axis, t, b);
    s = rl.tan_half;
  } else {
    uint ax = face >> 1u;
    float sg = (face & 1u) != 0u ? -1.0 : 1.0;
    vec3 e[3] = vec3[3](vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0), vec3(0.0, 0.0, 1.0));
    axis = sg * e[ax];
    t = e[(ax + 1u) % 3u];
    b = e[(ax + 2u) % 3u];
    s = 1.0;
  }
  float X = s * x, Y = s * y;
  d = normalize(axis + t * X + b * Y);
  o = L.position;
  measure = (2.0 * s * inv) * (2.0 * s * inv);
  float f = L.type == PB_GPU_LIGHT_SPOT ? pb_spot_factor(L, dot(d, axis)) : 1.0;
  float q = 1.0 + X * X + Y * Y;
  dens = L.power * (f / (q * sqrt(q)));
}

// ---- the weight pyramid (hierarchical warp) --------------------------------
// Level 0 is the texels' weights; level l = 1 .. rl.levels holds, per face,
// (res >> l)^2 nodes, each the sum of its 2 x 2 children; the top of a face
// (level rl.levels) is one node. Node k of a light's pyramid (levels 1 and
// up, face-major within a level) is stored in the `pyramid` float of texel
// record first + k: a map of F faces has F res^2 texels but fewer than
// F res^2 / 3 nodes.
uint pb_rsm_node(pb_gpu_rsm_light rl, uint level, uint face, uint x, uint y) {
  uint off = 0u;
  for (uint l = 1u; l < level; ++l) off += rl.faces * ((rl.res >> l) * (rl.res >> l));
  uint side = rl.res >> level;
  return off + face * side * side + y * side + x;
}

// Weight of node (x, y) of `face` at `level` (0: the texel). Needs the
// including shader's rtexels[] buffer.
float pb_rsm_weight(pb_gpu_rsm_light rl, uint level, uint face, uint x, uint y) {
  if (level == 0u) return rtexels[rl.first + face * rl.res * rl.res + y * rl.res + x].weight;
  return rtexels[rl.first + pb_rsm_node(rl, level, face, x, y)].pyramid;
}

// Picks `*c` among weights a, b with probability a / (a + b) from u in [0, 1),
// and rescales u to [0, 1) within the chosen part (the warp keeps u's
// remaining bits). A zero side is never picked.
uint pb_rsm_split(float a, float b, inout float u) {
  float s = a + b;
  if (!(s > 0.0)) return 0u;
  float x = u * s;
  if ((x < a && a > 0.0) || !(b > 0.0)) {
    u = clamp(x / a, 0.0, 0.99999994);
    return 0u;
  }
  u = clamp((x - a) / b, 0.0, 0.99999994);
  return 1u;
}

// Hierarchical warp (seed 001 24.2.1's mip warp): the point (u, v) of the
// unit square picks a face in proportion to its weight (by u), then at every
// level below its top a column of the 2 x 2 children (by u) and a row within
// it (by v), so the texel is chosen with probability weight / total and
// stratified points stay stratified over the map. Returns the texel's index
// within the light's map and leaves (u, v) as the point within the texel.
uint pb_rsm_warp(pb_gpu_rsm_light rl, inout float u, inout float v) {
  uint face = 0u;
  float x = u * rl.total, acc = 0.0;
  for (uint f = 0u; f < rl.faces; ++f) {
    float w = pb_rsm_weight(rl, rl.levels, f, 0u, 0u);
    face = f;
    if (w > 0.0 && (x < acc + w || f + 1u == rl.faces)) {
      u = clamp((x - acc) / w, 0.0, 0.99999994);
      break;
    }
    acc += w;
  }
  uint px = 0u, py = 0u;
  for (uint l = rl.levels; l > 0u; --l) {
    uint lv = l - 1u, x0 = 2u * px, y0 = 2u * py;
    float w00 = pb_rsm_weight(rl, lv, face, x0, y0), w10 = pb_rsm_weight(rl, lv, face, x0 + 1u, y0);
    float w01 = pb_rsm_weight(rl, lv, face, x0, y0 + 1u), w11 = pb_rsm_weight(rl, lv, face, x0 + 1u, y0 + 1u);
    uint cx = pb_rsm_split(w00 + w01, w10 + w11, u);
    uint cy = cx == 0u ? pb_rsm_split(w00, w01, v) : pb_rsm_split(w10, w11, v);
    px = x0 + cx;
    py = y0 + cy;
  }
  return face * rl.res * rl.res + py * rl.res + px;
}
