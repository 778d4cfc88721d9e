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
//     smooth step, 1 for point lights), dOmega = (1 + X^2 + Y^2)^(-3/2) dA;
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
  float f = 1.0;
  if (L.type == PB_GPU_LIGHT_SPOT) {
    float c = dot(d, axis);
    if (L.cos_inner - L.cos_outer <= 1e-7) f = c >= L.cos_outer ? 1.0 : 0.0;
    else f = pb_smoothstep01((c - L.cos_outer) / (L.cos_inner - L.cos_outer));
  }
  float q = 1.0 + X * X + Y * Y;
  dens = L.power * (f / (q * sqrt(q)));
}
