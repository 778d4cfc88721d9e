/* Embree 3 scene for the reference renderer: one triangle geometry built from
 * pb_scene's flat world-space arrays, robust traversal, high-quality BVH. */
#include <stdio.h>
#include <string.h>

#include "ref/accel.h"
#include "ref/bsdf.h"

/* Embree reports errors through a callback; keep the first message of this
 * thread for pb_fail. */
static _Thread_local char embree_msg[256];

static void on_embree_error(void *user, enum RTCError code, const char *str) {
  (void)user;
  if (!embree_msg[0])
    snprintf(embree_msg, sizeof embree_msg, "Embree error %d: %s", (int)code,
             str ? str : "");
}

/* Embree's robust intersector computes the distance to the triangle's plane
 * in float, from the float cross product of the edges: its error scales with
 * the triangle (and with 1/sin of its smallest angle), not with the hit
 * point, so a ray spawned with pb_offset_ray (256 ulps of the point's own
 * coordinates) can re-hit its own triangle when the triangle is much larger
 * than the point's coordinates (tests/unit/hard_rays.h: about 4 in 10^3 rays
 * on triangles 1000 across around the origin). This filter redoes the side
 * test in double (differences of floats and their products exact, so the
 * sign is right unless the origin lies within ~1e-16 relative of the plane)
 * and rejects hits whose exact t is not positive. Called only for candidate
 * hits. The user pointer is the geometry itself. Embree's ray and hit
 * arrays are structures of N-wide arrays (rtcore_ray.h: org_x, org_y, org_z,
 * tnear, dir_x, dir_y, dir_z; hit primID at 5 N). */
static void exact_side_filter(const struct RTCFilterFunctionNArguments *args) {
  RTCGeometry g = (RTCGeometry)args->geometryUserPtr;
  const float *vb = rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_VERTEX, 0);
  const uint32_t *ib = rtcGetGeometryBufferData(g, RTC_BUFFER_TYPE_INDEX, 0);
  const float *ray = (const float *)args->ray;
  const unsigned *hit = (const unsigned *)args->hit;
  unsigned n = args->N;
  for (unsigned i = 0; i < n; ++i) {
    if (args->valid[i] != -1) continue;
    const uint32_t *t = ib + 3 * (size_t)hit[5 * n + i];
    const float *p0 = vb + 3 * (size_t)t[0], *p1 = vb + 3 * (size_t)t[1], *p2 = vb + 3 * (size_t)t[2];
    double e1[3], e2[3], a[3], d[3];
    for (unsigned k = 0; k < 3; ++k) {
      e1[k] = (double)p1[k] - p0[k];
      e2[k] = (double)p2[k] - p0[k];
      a[k] = (double)p0[k] - ray[k * n + i];
      d[k] = ray[(4 + k) * n + i];
    }
    double nx = e1[1] * e2[2] - e1[2] * e2[1], ny = e1[2] * e2[0] - e1[0] * e2[2],
           nz = e1[0] * e2[1] - e1[1] * e2[0];
    double num = a[0] * nx + a[1] * ny + a[2] * nz, den = d[0] * nx + d[1] * ny + d[2] * nz;
    if (!(num * den > 0.0)) args->valid[i] = 0; /* exact t = num / den <= 0 */
  }
}

void pb_ref_accel_destroy(pb_ref_accel *a) {
  if (!a) return;
  if (a->scene) rtcReleaseScene(a->scene);
  if (a->device) rtcReleaseDevice(a->device);
  a->scene = NULL;
  a->device = NULL;
}

pb_result pb_ref_accel_create(const pb_scene *s, pb_ref_accel *a) {
  memset(a, 0, sizeof *a);
  embree_msg[0] = 0;
  /* Indices were checked by ref.c's check_scene before anything read them. */
  a->device = rtcNewDevice("verbose=0");
  if (!a->device)
    return pb_fail(PB_ERR_INTERNAL, "Embree: rtcNewDevice failed (error %d)",
                   (int)rtcGetDeviceError(NULL));
  rtcSetDeviceErrorFunction(a->device, on_embree_error, NULL);

  a->scene = rtcNewScene(a->device);
  RTCGeometry g = rtcNewGeometry(a->device, RTC_GEOMETRY_TYPE_TRIANGLE);
  /* Embree-owned buffers: Embree reads vertices with 16-byte loads, so the
   * buffer needs padding past the last vertex that pb_scene's does not have. */
  float *vb = g ? rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                          RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                          s->vertex_count)
                : NULL;
  uint32_t *ib = g ? rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0,
                                             RTC_FORMAT_UINT3, 3 * sizeof(uint32_t),
                                             s->triangle_count)
                   : NULL;
  if (!a->scene || !g || !vb || !ib) {
    if (g) rtcReleaseGeometry(g);
    pb_ref_accel_destroy(a);
    if (embree_msg[0]) return pb_fail(PB_ERR_NOMEM, "%s", embree_msg);
    return pb_fail(PB_ERR_NOMEM, "Embree: cannot allocate the scene");
  }
  memcpy(vb, s->positions, (size_t)s->vertex_count * 3 * sizeof(float));
  memcpy(ib, s->triangles, (size_t)s->triangle_count * 3 * sizeof(uint32_t));
  rtcSetGeometryUserData(g, g);
  rtcSetGeometryIntersectFilterFunction(g, exact_side_filter);
  rtcSetGeometryOccludedFilterFunction(g, exact_side_filter);
  rtcCommitGeometry(g);
  rtcAttachGeometry(a->scene, g);
  rtcReleaseGeometry(g);
  /* ROBUST: watertight traversal, no rays slipping through shared edges
   * (the reference must not leak light). HIGH: SAH build with spatial splits;
   * the build is a small part of a reference render. */
  rtcSetSceneFlags(a->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(a->scene, RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(a->scene);
  enum RTCError e = rtcGetDeviceError(a->device);
  if (e != RTC_ERROR_NONE || embree_msg[0]) {
    pb_ref_accel_destroy(a);
    return pb_fail(e == RTC_ERROR_OUT_OF_MEMORY ? PB_ERR_NOMEM : PB_ERR_INTERNAL,
                   "%s", embree_msg[0] ? embree_msg : "Embree: scene build failed");
  }
  return PB_OK;
}

int pb_ref_intersect(const pb_ref_accel *a, v3 o, v3 d, float tmax, pb_ref_hit *hit) {
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  struct RTCRayHit rh;
  rh.ray.org_x = o.x;
  rh.ray.org_y = o.y;
  rh.ray.org_z = o.z;
  rh.ray.tnear = 0.0f;
  rh.ray.dir_x = d.x;
  rh.ray.dir_y = d.y;
  rh.ray.dir_z = d.z;
  rh.ray.time = 0.0f;
  rh.ray.tfar = tmax;
  rh.ray.mask = 0xffffffffu;
  rh.ray.id = 0;
  rh.ray.flags = 0;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  rh.hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
  rtcIntersect1(a->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return 0;
  hit->t = rh.ray.tfar;
  hit->prim = rh.hit.primID;
  hit->u = rh.hit.u;
  hit->v = rh.hit.v;
  return 1;
}

int pb_ref_occluded(const pb_ref_accel *a, v3 o, v3 d, float tmax) {
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  struct RTCRay r;
  r.org_x = o.x;
  r.org_y = o.y;
  r.org_z = o.z;
  r.tnear = 0.0f;
  r.dir_x = d.x;
  r.dir_y = d.y;
  r.dir_z = d.z;
  r.time = 0.0f;
  r.tfar = tmax;
  r.mask = 0xffffffffu;
  r.id = 0;
  r.flags = 0;
  rtcOccluded1(a->scene, &ctx, &r);
  return r.tfar < 0.0f; /* Embree sets tfar to -inf on occlusion */
}

/* One coordinate: p moved by `ulps` units in the last place away from zero
 * for ulps > 0 along +n (toward zero for the other sign), or by a small
 * absolute step near the origin. Unsigned bit arithmetic: no signed
 * overflow even for -0 (whose bits are INT_MIN). */
static inline float offset1(float p, float n, float origin, float float_scale,
                            float int_scale) {
  if (fabsf(p) < origin) return p + float_scale * n;
  int32_t of = (int32_t)(int_scale * n);
  uint32_t bits;
  memcpy(&bits, &p, sizeof bits);
  bits += (uint32_t)(p < 0 ? -of : of);
  float q;
  memcpy(&q, &bits, sizeof q);
  return q;
}

v3 pb_offset_ray(v3 p, v3 n) {
  /* The constants of Waechter & Binder's listing 6-1: origin() = 1/32,
   * float_scale() = 1/65536, int_scale() = 256. */
  const float origin = 1.0f / 32.0f, float_scale = 1.0f / 65536.0f,
              int_scale = 256.0f;
  return (v3){offset1(p.x, n.x, origin, float_scale, int_scale),
              offset1(p.y, n.y, origin, float_scale, int_scale),
              offset1(p.z, n.z, origin, float_scale, int_scale)};
}

void pb_surface_from_hit(const pb_scene *s, const pb_ref_hit *h, v3 ray_dir,
                         pb_surface *o) {
  const uint32_t *tri = s->triangles[h->prim];
  v3 p0 = v3_load(s->positions[tri[0]]), p1 = v3_load(s->positions[tri[1]]),
     p2 = v3_load(s->positions[tri[2]]);
  float w = 1.0f - h->u - h->v;
  o->prim = h->prim;
  o->p = v3_add(v3_add(v3_scale(p0, w), v3_scale(p1, h->u)), v3_scale(p2, h->v));
  v3 ng = v3_norm(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0)));
  o->front = v3_dot(ng, ray_dir) < 0.0f;
  if (!o->front) ng = v3_neg(ng);
  o->ng = ng;
  v3 ns = ng;
  if (s->normals) {
    v3 n0 = v3_load(s->normals[tri[0]]), n1 = v3_load(s->normals[tri[1]]),
       n2 = v3_load(s->normals[tri[2]]);
    v3 n = v3_add(v3_add(v3_scale(n0, w), v3_scale(n1, h->u)), v3_scale(n2, h->v));
    float l = v3_len(n);
    if (l > 1e-12f && isfinite(l)) {
      n = v3_scale(n, 1.0f / l);
      /* Vertex normals may disagree with the winding; keep them on the side
       * of the geometric normal that faces the ray. */
      ns = v3_dot(n, ng) < 0.0f ? v3_neg(n) : n;
    }
  }
  o->ns = o->ni = o->nc = ns;
  if (s->uvs) {
    o->uv[0] = s->uvs[tri[0]][0] * w + s->uvs[tri[1]][0] * h->u + s->uvs[tri[2]][0] * h->v;
    o->uv[1] = s->uvs[tri[0]][1] * w + s->uvs[tri[1]][1] * h->u + s->uvs[tri[2]][1] * h->v;
  } else {
    o->uv[0] = o->uv[1] = 0.0f;
  }
  for (int k = 0; k < 2; ++k)
    o->uv1[k] = s->uvs1 ? s->uvs1[tri[0]][k] * w + s->uvs1[tri[1]][k] * h->u + s->uvs1[tri[2]][k] * h->v : 0.0f;
  for (int k = 0; k < 4; ++k)
    o->color[k] = s->colors ? s->colors[tri[0]][k] * w + s->colors[tri[1]][k] * h->u + s->colors[tri[2]][k] * h->v : 1.0f;
  o->mat = &s->materials[s->triangle_material[h->prim]];
  o->tangent = v3_make(0.0f, 0.0f, 0.0f);
  if (s->tangents) {
    v3 t = v3_add(v3_add(v3_scale(v3_load(s->tangents[tri[0]]), w), v3_scale(v3_load(s->tangents[tri[1]]), h->u)),
                  v3_scale(v3_load(s->tangents[tri[2]]), h->v));
    float l = v3_len(t);
    if (l > 1e-12f && isfinite(l)) o->tangent = v3_scale(t, 1.0f / l);
  }
  pb_apply_normal_map(s, h, o);
}

/* The normal of texture `tex` (tangent space, glTF scale `scale`, Blender's
 * Normal Map strength `st`) in the frame t, b, n; 0 where it degenerates. */
static int map_normal(const pb_scene *s, const pb_surface *o, int32_t tex, float scale, float st, int cycles4, v3 t,
                      v3 b, v3 n, v3 *out) {
  float c[4];
  pb_texture_lookup(&s->textures[tex], o->uv, o->uv1, c);
  float cx = (c[0] * 2.0f - 1.0f) * scale, cy = (c[1] * 2.0f - 1.0f) * scale;
  float cz = c[2] * 2.0f - 1.0f;
  /* Blender's Normal Map node, strength s (svm_node_normal_map): Cycles 4.0
   * and later scale the tangent-space vector, xy s and z mix(1, z,
   * saturate(s)), before the frame; 3.x blend the mapped normal from the
   * interpolated one after it, normalize(n + (nm - n) s). */
  if (cycles4 && st != 1.0f) {
    cx *= st, cy *= st;
    float sat = fminf(fmaxf(st, 0.0f), 1.0f);
    cz = 1.0f + (cz - 1.0f) * sat;
  }
  v3 nm = v3_add(v3_add(v3_scale(t, cx), v3_scale(b, cy)), v3_scale(n, cz));
  float ml = v3_len(nm);
  if (!(ml > 1e-12f) || !isfinite(ml)) return 0;
  nm = v3_scale(nm, 1.0f / ml);
  if (!cycles4 && st != 1.0f) {
    v3 bl = v3_add(n, v3_scale(v3_sub(nm, n), fmaxf(st, 0.0f)));
    float bl_len = v3_len(bl);
    if (!(bl_len > 1e-12f) || !isfinite(bl_len)) return 0;
    nm = v3_scale(bl, 1.0f / bl_len);
  }
  *out = nm;
  return 1;
}

/* Normal mapping, the same computation as shaders/common/scene.glsl's
 * pb_apply_normal_map (glTF 2.0 normalTexture): in the frame of the
 * interpolated vertex normal N, the interpolated tangent T (Gram-Schmidt
 * against N) and B = cross(N, T) w,
 *   n_s = normalize(T t.x + B t.y + N t.z),  t = (2 rgb - 1) (scale, scale, 1),
 * linear texels, oriented like o->ns. The reference shades with it at every
 * vertex of every path (path tracer and photons alike); o->ng stays the
 * geometric normal for offsets and side tests. The guards are pbrt's
 * (pbrt-v3 BSDF::f): pb_bsdf_setup falls back to ng when wo is below n_s,
 * and pb_bsdf_eval / _sample_dir give no reflection unless wi is above both
 * ng and n_s (bsdf.c), so light never leaks through the geometric surface.
 * The Principled BSDF's Coat Normal map goes into o->nc the same way
 * (Cycles 4.5 svm/closure.h: the coat, its tint and the sheen's blend toward
 * it use coat_normal, which is sd->N when the socket is unlinked). */
void pb_apply_normal_map(const pb_scene *s, const pb_ref_hit *h, pb_surface *o) {
  const pb_material *m = o->mat;
  int blender = m->blender.model != PB_MODEL_GLTF;
  int main_map = m->normal_tex >= 0 && (uint32_t)m->normal_tex < s->texture_count;
  int coat_map = blender && m->blender.coat_normal_tex >= 0 && (uint32_t)m->blender.coat_normal_tex < s->texture_count;
  if (!s->tangents || !s->uvs || (!main_map && !coat_map)) return;
  const uint32_t *tri = s->triangles[h->prim];
  float w = 1.0f - h->u - h->v;
  v3 p0 = v3_load(s->positions[tri[0]]), p1 = v3_load(s->positions[tri[1]]),
     p2 = v3_load(s->positions[tri[2]]);
  v3 n = v3_norm(v3_cross(v3_sub(p1, p0), v3_sub(p2, p0))); /* as stored */
  if (s->normals) {
    v3 vn = v3_add(v3_add(v3_scale(v3_load(s->normals[tri[0]]), w), v3_scale(v3_load(s->normals[tri[1]]), h->u)),
                   v3_scale(v3_load(s->normals[tri[2]]), h->v));
    float l = v3_len(vn);
    if (l > 1e-12f && isfinite(l)) n = v3_scale(vn, 1.0f / l);
  }
  float t4[4];
  for (int k = 0; k < 4; ++k)
    t4[k] = s->tangents[tri[0]][k] * w + s->tangents[tri[1]][k] * h->u + s->tangents[tri[2]][k] * h->v;
  v3 t = v3_make(t4[0], t4[1], t4[2]);
  t = v3_sub(t, v3_scale(n, v3_dot(n, t)));
  float tl = v3_len(t);
  v3 b;
  if (tl > 1e-12f && isfinite(tl)) {
    t = v3_scale(t, 1.0f / tl);
    b = v3_scale(v3_cross(n, t), t4[3] < 0.0f ? -1.0f : 1.0f);
  } else {
    v3_basis(n, &t, &b);
  }
  int cycles4 = blender && m->blender.normal_map_cycles4;
  int flip = v3_dot(n, o->ng) < 0.0f;
  v3 nm;
  if (main_map && map_normal(s, o, m->normal_tex, m->normal_scale, blender ? m->blender.normal_strength : 1.0f,
                             cycles4, t, b, n, &nm))
    o->ns = flip ? v3_neg(nm) : nm;
  if (coat_map && map_normal(s, o, m->blender.coat_normal_tex, 1.0f, m->blender.coat_normal_strength, cycles4, t, b,
                             n, &nm))
    o->nc = flip ? v3_neg(nm) : nm;
}
