// Soft lights and the world light on the GPU: the reference's models and
// strategies, function for function (src/ref/soft_lights.c for sphere
// lights, area lights and the soft sun; src/scene/world.c for the world's
// radiance and its sampling table), so that both renderers draw the same
// estimators. Included after scene.glsl by the passes that light or emit:
// they define PB_WORLD_BINDING, the binding of the world's buffer
// (pb_gpu_world and its data, src/render/scene/scene_gpu.c).
#ifndef PB_LIGHTS_GLSL
#define PB_LIGHTS_GLSL

layout(std430, set = 0, binding = PB_WORLD_BINDING) readonly buffer WorldBuf {
  pb_gpu_world world;
  float world_data[];
};

// Rectangles below this solid angle are sampled by area (soft_lights.c).
const float PB_RECT_MIN_SOLID_ANGLE = 1e-3;

bool pb_light_is_soft(pb_gpu_light l) {
  return l.type == PB_GPU_LIGHT_AREA || l.radius > 0.0;
}

// Uniform point of the unit disc (polar map).
vec2 pb_unit_disc(float u1, float u2) {
  float r = sqrt(u1), phi = 2.0 * PB_PI * u2;
  return r * vec2(cos(phi), sin(phi));
}

// Cycles 3.4's spread profile for the cosine of the angle to the normal.
float pb_spread_factor(pb_gpu_light l, float cos_t) {
  if (!(cos_t > 0.0)) return 0.0;
  if (!(l.tan_spread > 0.0)) return 1.0;
  float tan_t = sqrt(max(0.0, 1.0 - cos_t * cos_t)) / cos_t;
  return max((1.0 - l.tan_spread * tan_t) * l.norm_spread, 0.0);
}

struct pb_rect {
  vec3 c, u, v;
  float lu, lv;
};

// The part of area light l that its spread lets light p (rect_for).
bool pb_rect_for(pb_gpu_light l, vec3 p, out pb_rect r) {
  r.c = l.position;
  r.u = l.axis_u;
  r.v = l.axis_v;
  r.lu = l.size_u;
  r.lv = l.size_v;
  if (l.tan_spread > 0.0) {
    vec3 n = l.direction;
    float t = dot(p - r.c, n);
    vec3 foot = p - n * t;
    float rad = abs(t) / l.tan_spread;
    float cu = dot(foot - r.c, r.u), cv = dot(foot - r.c, r.v);
    float u0 = max(cu - rad, -0.5 * r.lu), u1 = min(cu + rad, 0.5 * r.lu);
    float v0 = max(cv - rad, -0.5 * r.lv), v1 = min(cv + rad, 0.5 * r.lv);
    if (!(u0 < u1) || !(v0 < v1)) return false;
    r.c += r.u * (0.5 * (u0 + u1)) + r.v * (0.5 * (v0 + v1));
    r.lu = u1 - u0;
    r.lv = v1 - v0;
  }
  return true;
}

float pb_acos_clamped(float x) { return acos(clamp(x, -1.0, 1.0)); }

// Urena et al. 2013, algorithm 1 (spherical_rect in soft_lights.c).
float pb_spherical_rect(pb_rect r, vec3 o, bool smp, float s, float t, out vec3 q) {
  q = vec3(0.0);
  vec3 x = r.u, y = r.v, z = cross(x, y);
  vec3 corner = r.c - x * (0.5 * r.lu) - y * (0.5 * r.lv);
  vec3 d = corner - o;
  float z0 = dot(d, z);
  if (z0 > 0.0) {
    z = -z;
    z0 = -z0;
  }
  float x0 = dot(d, x), y0 = dot(d, y), x1 = x0 + r.lu, y1 = y0 + r.lv;
  if (!(z0 < 0.0)) return 0.0;
  vec3 v00 = vec3(x0, y0, z0), v10 = vec3(x1, y0, z0), v11 = vec3(x1, y1, z0), v01 = vec3(x0, y1, z0);
  vec3 n0 = normalize(cross(v00, v10)), n1 = normalize(cross(v10, v11));
  vec3 n2 = normalize(cross(v11, v01)), n3 = normalize(cross(v01, v00));
  float g0 = pb_acos_clamped(-dot(n0, n1)), g1 = pb_acos_clamped(-dot(n1, n2));
  float g2 = pb_acos_clamped(-dot(n2, n3)), g3 = pb_acos_clamped(-dot(n3, n0));
  float b0 = n0.z, b1 = n2.z, k = 2.0 * PB_PI - g2 - g3;
  float S = g0 + g1 - k;
  if (!smp || !(S > 0.0)) return S;
  float au = s * S + k;
  float fu = (cos(au) * b0 - b1) / sin(au);
  float cu = (fu >= 0.0 ? 1.0 : -1.0) / sqrt(fu * fu + b0 * b0);
  cu = clamp(cu, -1.0, 1.0);
  float xu = -(cu * z0) / max(sqrt(1.0 - cu * cu), 1e-7);
  xu = clamp(xu, x0, x1);
  float dd = sqrt(xu * xu + z0 * z0);
  float h0 = y0 / sqrt(dd * dd + y0 * y0), h1 = y1 / sqrt(dd * dd + y1 * y1);
  float hv = h0 + t * (h1 - h0), hv2 = hv * hv;
  float yv = hv2 < 1.0 - 1e-6 ? hv * dd / sqrt(1.0 - hv2) : y1;
  q = o + x * xu + y * yv + z * z0;
  return S;
}

float pb_light_area(pb_gpu_light l) {
  float a = l.size_u * l.size_v;
  return (l.flags & PB_GPU_LIGHT_ELLIPSE) != 0u ? 0.25 * PB_PI * a : a;
}

vec3 pb_sphere_radiance(pb_gpu_light l, vec3 w) {
  float k = 1.0 / (PB_PI * l.radius * l.radius);
  if (l.type == PB_GPU_LIGHT_SPOT) k *= pb_spot_factor(l, dot(l.direction, w));
  return l.power * k;
}

// Cycles 4.x's sphere light (PB_GPU_LIGHT_SPHERE; src/ref/soft_lights.c
// sphere_light_sample / _hit): the cone the sphere subtends, uniform in solid
// angle, from outside; the whole sphere of directions from inside; a spot's
// falloff outside only. 1 - cos of the cone's half-angle without cancellation.
float pb_sphere_one_minus_cos(float r2, float d2) {
  float s2 = r2 / d2;
  return s2 / (1.0 + sqrt(max(0.0, 1.0 - s2)));
}

vec3 pb_sphere_light_radiance(pb_gpu_light l, vec3 w, bool inside) {
  float k = 1.0 / (PB_PI * l.radius * l.radius);
  if (l.type == PB_GPU_LIGHT_SPOT && !inside) k *= pb_spot_factor(l, dot(l.direction, w));
  return l.power * k;
}

bool pb_sphere_light_sample(pb_gpu_light l, vec3 p, float u1, float u2, out vec3 wi, out float dist, out vec3 L,
                            out float pdf) {
  vec3 axis = l.position - p;
  float d2 = dot(axis, axis), r2 = l.radius * l.radius, d = sqrt(d2);
  bool inside = !(d2 > r2);
  float cos_t;
  if (!inside) {
    axis /= d;
    float omc = pb_sphere_one_minus_cos(r2, d2), x = u1 * omc;
    cos_t = 1.0 - x;
    float sin_t = sqrt(max(0.0, x * (2.0 - x))), phi = 2.0 * PB_PI * u2;
    vec3 t, b;
    pb_basis(axis, t, b);
    wi = normalize(axis * cos_t + t * (sin_t * cos(phi)) + b * (sin_t * sin(phi)));
    pdf = 1.0 / (2.0 * PB_PI * omc);
  } else {
    float z = 1.0 - 2.0 * u1, s = sqrt(max(0.0, 1.0 - z * z)), phi = 2.0 * PB_PI * u2;
    wi = vec3(s * cos(phi), s * sin(phi), z);
    cos_t = d > 0.0 ? dot(wi, axis / d) : 0.0;
    pdf = 1.0 / (4.0 * PB_PI);
  }
  float h = sqrt(max(0.0, r2 - d2 + d2 * cos_t * cos_t));
  dist = inside ? d * cos_t + h : d * cos_t - h;
  L = pb_sphere_light_radiance(l, -wi, inside);
  return dist > 0.0 && pdf > 0.0 && !isinf(pdf) && any(notEqual(L, vec3(0.0)));
}

bool pb_sphere_light_hit(pb_gpu_light l, vec3 o, vec3 d, float tmax, out float t, out vec3 L, out float pdf) {
  t = 0.0;
  L = vec3(0.0);
  pdf = 0.0;
  vec3 oc = o - l.position;
  float r2 = l.radius * l.radius, b = dot(oc, d), d2 = dot(oc, oc), cc = d2 - r2;
  float disc = b * b - cc;
  if (!(disc >= 0.0)) return false;
  float sq = sqrt(disc);
  bool inside = !(cc > 0.0);
  if (!inside) {
    if (!(b < 0.0)) return false;
    t = cc / (sq - b);
    pdf = 1.0 / (2.0 * PB_PI * pb_sphere_one_minus_cos(r2, d2));
  } else {
    t = sq - b;
    pdf = 1.0 / (4.0 * PB_PI);
  }
  if (!(t > 0.0) || !(t < tmax)) return false;
  L = pb_sphere_light_radiance(l, -d, inside);
  return !isinf(pdf) && any(notEqual(L, vec3(0.0)));
}

// pb_soft_light_sample: direction wi toward the light, distance, radiance
// along -wi, solid-angle pdf.
bool pb_soft_light_sample(pb_gpu_light l, vec3 p, float u1, float u2, out vec3 wi, out float dist, out vec3 L,
                          out float pdf) {
  wi = vec3(0.0);
  dist = 0.0;
  L = vec3(0.0);
  pdf = 0.0;
  if (l.type == PB_GPU_LIGHT_DIRECTIONAL) {
    vec3 axis = -l.direction, t, b;
    pb_basis(axis, t, b);
    vec2 xy = pb_unit_disc(u1, u2) * l.radius;
    wi = normalize(axis + t * xy.x + b * xy.y);
    float c = dot(wi, axis);
    pdf = 1.0 / (PB_PI * l.radius * l.radius * c * c * c);
    dist = PB_INF;
    L = l.power * pdf;
    return pdf > 0.0 && !isinf(pdf);
  }
  if (l.type == PB_GPU_LIGHT_AREA) {
    vec3 n = l.direction, c = l.position;
    if (!(dot(p - c, n) > 0.0)) return false;
    vec3 q;
    float pa = 0.0; // > 0: an area density, converted below
    if ((l.flags & PB_GPU_LIGHT_ELLIPSE) == 0u) {
      pb_rect r;
      if (!pb_rect_for(l, p, r)) return false;
      float S = pb_spherical_rect(r, p, false, 0.0, 0.0, q);
      if (S >= PB_RECT_MIN_SOLID_ANGLE) {
        pb_spherical_rect(r, p, true, u1, u2, q);
        pdf = 1.0 / S;
      } else {
        q = r.c + r.u * ((u1 - 0.5) * r.lu) + r.v * ((u2 - 0.5) * r.lv);
        pa = 1.0 / (r.lu * r.lv);
      }
    } else {
      vec2 xy = pb_unit_disc(u1, u2);
      q = c + l.axis_u * (0.5 * l.size_u * xy.x) + l.axis_v * (0.5 * l.size_v * xy.y);
      pa = 1.0 / pb_light_area(l);
    }
    vec3 d = q - p;
    float d2 = dot(d, d);
    if (!(d2 > 0.0)) return false;
    dist = sqrt(d2);
    wi = d / dist;
    float cos_l = -dot(wi, n);
    if (!(cos_l > 0.0)) return false;
    if (pa > 0.0) pdf = pa * d2 / cos_l;
    float f = pb_spread_factor(l, cos_l);
    if (!(f > 0.0)) return false;
    L = l.power * f;
    return pdf > 0.0 && !isinf(pdf);
  }
  if ((l.flags & PB_GPU_LIGHT_SPHERE) != 0u) return pb_sphere_light_sample(l, p, u1, u2, wi, dist, L, pdf);
  // Soft light (3.4's, 4.x's Soft Falloff): uniform on the disc facing p.
  vec3 nl = p - l.position;
  float dc = length(nl);
  if (!(dc > 0.0)) return false;
  nl /= dc;
  vec3 t, b;
  pb_basis(nl, t, b);
  vec2 xy = pb_unit_disc(u1, u2) * l.radius;
  vec3 d = l.position + t * xy.x + b * xy.y - p;
  float d2 = dot(d, d);
  if (!(d2 > 0.0)) return false;
  dist = sqrt(d2);
  wi = d / dist;
  float cos_l = -dot(wi, nl);
  if (!(cos_l > 0.0)) return false;
  pdf = d2 / (cos_l * PB_PI * l.radius * l.radius);
  L = pb_sphere_radiance(l, -wi);
  return pdf > 0.0 && !isinf(pdf) && any(notEqual(L, vec3(0.0)));
}

// pb_soft_light_hit: the ray (o, d) meets soft light l in (0, tmax) (the
// sun only for tmax = inf). t, radiance toward o, light-sampling pdf.
bool pb_soft_light_hit(pb_gpu_light l, vec3 o, vec3 d, float tmax, out float t, out vec3 L, out float pdf) {
  t = 0.0;
  L = vec3(0.0);
  pdf = 0.0;
  if (l.type == PB_GPU_LIGHT_DIRECTIONAL) {
    if (!isinf(tmax)) return false;
    float c = dot(d, -l.direction);
    if (!(c >= l.cos_half) || !(c > 0.0)) return false;
    pdf = 1.0 / (PB_PI * l.radius * l.radius * c * c * c);
    L = l.power * pdf;
    t = PB_INF;
    return !isinf(pdf);
  }
  if (l.type == PB_GPU_LIGHT_AREA) {
    vec3 n = l.direction;
    float dn = dot(d, n);
    if (!(dn < 0.0)) return false;
    t = dot(l.position - o, n) / dn;
    if (!(t > 0.0) || !(t < tmax)) return false;
    vec3 rq = o + d * t - l.position;
    float x = dot(rq, l.axis_u) / (0.5 * l.size_u), y = dot(rq, l.axis_v) / (0.5 * l.size_v);
    bool ellipse = (l.flags & PB_GPU_LIGHT_ELLIPSE) != 0u;
    if (ellipse ? (x * x + y * y > 1.0) : (abs(x) > 1.0 || abs(y) > 1.0)) return false;
    float cos_l = -dn, f = pb_spread_factor(l, cos_l);
    if (!(f > 0.0)) return false;
    if (!ellipse) {
      pb_rect r;
      if (!pb_rect_for(l, o, r)) return false;
      vec3 q;
      float S = pb_spherical_rect(r, o, false, 0.0, 0.0, q);
      pdf = S >= PB_RECT_MIN_SOLID_ANGLE ? 1.0 / S : t * t / (cos_l * r.lu * r.lv);
    } else {
      pdf = t * t / (cos_l * pb_light_area(l));
    }
    L = l.power * f;
    return pdf > 0.0 && !isinf(pdf);
  }
  if ((l.flags & PB_GPU_LIGHT_SPHERE) != 0u) return pb_sphere_light_hit(l, o, d, tmax, t, L, pdf);
  vec3 nl = o - l.position;
  float dc = length(nl);
  if (!(dc > 0.0)) return false;
  nl /= dc;
  float dn = dot(d, nl);
  if (!(dn < 0.0)) return false;
  t = -dc / dn;
  if (!(t > 0.0) || !(t < tmax)) return false;
  vec3 rq = o + d * t - l.position;
  if (dot(rq, rq) > l.radius * l.radius) return false;
  L = pb_sphere_radiance(l, -d);
  pdf = t * t / (-dn * PB_PI * l.radius * l.radius);
  return pdf > 0.0 && !isinf(pdf) && any(notEqual(L, vec3(0.0)));
}

// Photon emission (src/ref/soft_lights.c pb_area_light_emit,
// pb_sphere_light_origin).
bool pb_area_light_emit(pb_gpu_light l, float u1, float u2, float u3, float u4, out vec3 o, out vec3 d,
                        out float weight) {
  vec2 xy = (l.flags & PB_GPU_LIGHT_ELLIPSE) != 0u ? 0.5 * pb_unit_disc(u1, u2) : vec2(u1 - 0.5, u2 - 0.5);
  o = l.position + l.axis_u * (xy.x * l.size_u) + l.axis_v * (xy.y * l.size_v);
  float s2max = l.tan_spread > 0.0 ? 1.0 / (1.0 + l.tan_spread * l.tan_spread) : 1.0;
  float s2 = u3 * s2max, ct = sqrt(max(0.0, 1.0 - s2)), st = sqrt(s2), phi = 2.0 * PB_PI * u4;
  d = normalize(l.direction * ct + l.axis_u * (st * cos(phi)) + l.axis_v * (st * sin(phi)));
  weight = pb_light_area(l) * PB_PI * s2max * pb_spread_factor(l, ct);
  return weight > 0.0;
}

vec3 pb_sphere_light_origin(pb_gpu_light l, vec3 d, float u1, float u2) {
  vec3 t, b;
  pb_basis(d, t, b);
  vec2 xy = pb_unit_disc(u1, u2);
  float h = sqrt(max(0.0, 1.0 - dot(xy, xy)));
  return l.position + (t * xy.x + b * xy.y + d * h) * l.radius;
}

// ---- the world (scene/world.c) ---------------------------------------------

vec3 pb_world_texel(int x, int y) {
  int W = int(world.width), H = int(world.height);
  x = ((x % W) + W) % W;
  y = clamp(y, 0, H - 1);
  uint i = 4u * (uint(y) * world.width + uint(x));
  return vec3(world_data[i], world_data[i + 1u], world_data[i + 2u]);
}

// (u, v from the top row, sin theta) of a scene direction.
vec3 pb_world_dir_to_uv(vec3 dir) {
  vec3 m = vec3(dot(world.map_to0.xyz, dir), dot(world.map_to1.xyz, dir), dot(world.map_to2.xyz, dir));
  float l = length(m);
  float cz = l > 0.0 ? clamp(m.z / l, -1.0, 1.0) : 1.0;
  float u = 0.5 - atan(m.y, m.x) * (0.5 / PB_PI);
  u -= floor(u);
  if (!(u < 1.0)) u = 0.0;
  return vec3(u, acos(cz) / PB_PI, sqrt(max(0.0, 1.0 - cz * cz)));
}

vec3 pb_world_uv_to_dir(float u, float v) {
  float phi = PB_PI * (1.0 - 2.0 * u), theta = PB_PI * v, st = sin(theta);
  vec3 m = vec3(st * cos(phi), st * sin(phi), cos(theta));
  return world.map_to0.xyz * m.x + world.map_to1.xyz * m.y + world.map_to2.xyz * m.z;
}

vec3 pb_world_radiance(vec3 dir) {
  if ((world.flags & PB_GPU_WORLD_PRESENT) == 0u) return vec3(0.0);
  if ((world.flags & PB_GPU_WORLD_MAP) == 0u) return world.color;
  vec3 uv = pb_world_dir_to_uv(dir);
  float fx = uv.x * float(world.width) - 0.5, fy = uv.y * float(world.height) - 0.5;
  float x0f = floor(fx), y0f = floor(fy), ax = fx - x0f, ay = fy - y0f;
  int x0 = int(x0f), y0 = int(y0f);
  vec3 a = pb_world_texel(x0, y0), b = pb_world_texel(x0 + 1, y0), c = pb_world_texel(x0, y0 + 1),
       d = pb_world_texel(x0 + 1, y0 + 1);
  return world.scale * ((a * (1.0 - ax) + b * ax) * (1.0 - ay) + (c * (1.0 - ax) + d * ax) * ay);
}

// Conditional CDF of row y at cell x (x == width: 1).
float pb_world_cond(uint y, uint x) {
  return x >= world.width ? 1.0 : world_data[4u * (y * world.width + x) + 3u];
}
float pb_world_marg(uint y) { return world_data[world.marg_offset + y]; }

bool pb_world_sample(float u1, float u2, out vec3 dir, out float pdf) {
  if ((world.flags & PB_GPU_WORLD_SAMPLED) == 0u) { // uniform sphere
    float z = 1.0 - 2.0 * u1, r = sqrt(max(0.0, 1.0 - z * z)), phi = 2.0 * PB_PI * u2;
    dir = vec3(r * cos(phi), r * sin(phi), z);
    pdf = 0.25 / PB_PI;
    return true;
  }
  uint W = world.width, H = world.height;
  uint lo = 0u, hi = H;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1u;
    if (pb_world_marg(mid) <= u1) lo = mid;
    else hi = mid;
  }
  uint y = lo;
  float py = pb_world_marg(y + 1u) - pb_world_marg(y);
  lo = 0u;
  hi = W;
  while (hi - lo > 1u) {
    uint mid = (lo + hi) >> 1u;
    if (pb_world_cond(y, mid) <= u2) lo = mid;
    else hi = mid;
  }
  uint x = lo;
  float px = pb_world_cond(y, x + 1u) - pb_world_cond(y, x);
  dir = vec3(0.0, 0.0, 1.0);
  pdf = 0.0;
  if (!(py > 0.0) || !(px > 0.0)) return false;
  float fy = clamp((u1 - pb_world_marg(y)) / py, 0.0, 0.99999994);
  float fx = clamp((u2 - pb_world_cond(y, x)) / px, 0.0, 0.99999994);
  float u = (float(x) + fx) / float(W), v = (float(y) + fy) / float(H);
  dir = pb_world_uv_to_dir(u, v);
  float st = sin(PB_PI * v);
  if (!(st > 0.0)) return false;
  pdf = px * py * float(W) * float(H) / (2.0 * PB_PI * PB_PI * st);
  return true;
}

float pb_world_pdf(vec3 dir) {
  if ((world.flags & PB_GPU_WORLD_SAMPLED) == 0u) return 0.25 / PB_PI;
  vec3 uv = pb_world_dir_to_uv(dir);
  if (!(uv.z > 0.0)) return 0.0;
  uint W = world.width, H = world.height;
  uint x = min(uint(uv.x * float(W)), W - 1u), y = min(uint(uv.y * float(H)), H - 1u);
  float py = pb_world_marg(y + 1u) - pb_world_marg(y);
  float px = pb_world_cond(y, x + 1u) - pb_world_cond(y, x);
  return px * py * float(W) * float(H) / (2.0 * PB_PI * PB_PI * uv.z);
}

#endif
