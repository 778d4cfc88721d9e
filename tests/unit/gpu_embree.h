/* Test and benchmark helper: an Embree scene of a pb_scene and random rays,
 * so the GPU's ray queries can be compared with rtcIntersect1/rtcOccluded1
 * on exactly the same rays. Header-only (static functions). */
#ifndef PB_TEST_GPU_EMBREE_H
#define PB_TEST_GPU_EMBREE_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <embree3/rtcore.h>

#include "scene/scene.h"
#include "shared/pb_gpu.h"

typedef struct pbt_embree {
  RTCDevice dev;
  RTCScene scene;
} pbt_embree;

static inline void pbt_embree_destroy(pbt_embree *e) {
  if (e->scene) rtcReleaseScene(e->scene);
  if (e->dev) rtcReleaseDevice(e->dev);
  memset(e, 0, sizeof *e);
}

/* ROBUST (watertight) traversal, like the reference renderer. threads: 0 = all. */
static inline int pbt_embree_create(const pb_scene *s, uint32_t threads, pbt_embree *e) {
  memset(e, 0, sizeof *e);
  char cfg[64];
  snprintf(cfg, sizeof cfg, "verbose=0,threads=%u", threads);
  e->dev = rtcNewDevice(cfg);
  if (!e->dev) return 0;
  e->scene = rtcNewScene(e->dev);
  RTCGeometry g = rtcNewGeometry(e->dev, RTC_GEOMETRY_TYPE_TRIANGLE);
  float *vb = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, s->vertex_count);
  uint32_t *ib = rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, s->triangle_count);
  if (!vb || !ib) {
    rtcReleaseGeometry(g);
    pbt_embree_destroy(e);
    return 0;
  }
  memcpy(vb, s->positions, (size_t)s->vertex_count * 12);
  memcpy(ib, s->triangles, (size_t)s->triangle_count * 12);
  rtcCommitGeometry(g);
  rtcAttachGeometry(e->scene, g);
  rtcReleaseGeometry(g);
  rtcSetSceneFlags(e->scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(e->scene, RTC_BUILD_QUALITY_HIGH);
  rtcCommitScene(e->scene);
  return rtcGetDeviceError(e->dev) == RTC_ERROR_NONE;
}

static inline void pbt_embree_trace(const pbt_embree *e, const pb_gpu_ray *r, int any_hit, pb_gpu_hit *h) {
  struct RTCIntersectContext ctx;
  rtcInitIntersectContext(&ctx);
  struct RTCRayHit rh;
  memset(&rh, 0, sizeof rh);
  rh.ray.org_x = r->org[0];
  rh.ray.org_y = r->org[1];
  rh.ray.org_z = r->org[2];
  rh.ray.dir_x = r->dir[0];
  rh.ray.dir_y = r->dir[1];
  rh.ray.dir_z = r->dir[2];
  rh.ray.tnear = r->tmin;
  rh.ray.tfar = r->tmax;
  rh.ray.mask = 0xffffffffu;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  if (any_hit) {
    rtcOccluded1(e->scene, &ctx, &rh.ray);
    h->prim = rh.ray.tfar < 0.0f ? 0u : PB_GPU_MISS;
    h->t = r->tmax;
    h->u = h->v = 0.0f;
    return;
  }
  rtcIntersect1(e->scene, &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) {
    h->prim = PB_GPU_MISS;
    h->t = r->tmax;
    h->u = h->v = 0.0f;
    return;
  }
  h->prim = rh.hit.primID;
  h->t = rh.ray.tfar;
  h->u = rh.hit.u;
  h->v = rh.hit.v;
}

/* splitmix64-based uniform floats. */
static inline double pbt_rand(uint64_t *st) {
  uint64_t z = (*st += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  return (double)(z >> 11) * (1.0 / 9007199254740992.0);
}

/* Random rays: origins uniform in the scene box grown by 10 %; half of the
 * directions uniform on the sphere, half aimed at a random point of a random
 * triangle (so most of those hit). tmin 0, tmax inf. */
static inline void pbt_random_rays(const pb_scene *s, uint64_t seed, pb_gpu_ray *rays, uint32_t n) {
  uint64_t st = seed;
  float lo[3], ext[3];
  for (int k = 0; k < 3; ++k) {
    float e = s->bounds_max[k] - s->bounds_min[k];
    lo[k] = s->bounds_min[k] - 0.05f * e;
    ext[k] = 1.1f * e;
  }
  for (uint32_t i = 0; i < n; ++i) {
    pb_gpu_ray *r = &rays[i];
    memset(r, 0, sizeof *r);
    for (int k = 0; k < 3; ++k) r->org[k] = lo[k] + ext[k] * (float)pbt_rand(&st);
    double d[3];
    if (i & 1) {
      uint32_t t = (uint32_t)(pbt_rand(&st) * s->triangle_count) % s->triangle_count;
      double a = pbt_rand(&st), b = pbt_rand(&st);
      if (a + b > 1) {
        a = 1 - a;
        b = 1 - b;
      }
      const float *p0 = s->positions[s->triangles[t][0]], *p1 = s->positions[s->triangles[t][1]],
                  *p2 = s->positions[s->triangles[t][2]];
      for (int k = 0; k < 3; ++k) d[k] = p0[k] + a * (p1[k] - p0[k]) + b * (p2[k] - p0[k]) - r->org[k];
    } else {
      double z = 2 * pbt_rand(&st) - 1, phi = 2 * M_PI * pbt_rand(&st), q = sqrt(fmax(0, 1 - z * z));
      d[0] = q * cos(phi);
      d[1] = q * sin(phi);
      d[2] = z;
    }
    double l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(l > 0)) {
      d[0] = 0, d[1] = 1, d[2] = 0, l = 1;
    }
    for (int k = 0; k < 3; ++k) r->dir[k] = (float)(d[k] / l);
    r->tmin = 0.0f;
    r->tmax = INFINITY;
  }
}

#endif
