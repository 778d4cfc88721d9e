/* pb_gpu_scene_update: an animated scene posed at t0 goes to the
 * GPU, is posed at t1 and updated by refit and by rebuild; the ray-query
 * kernel's hits must equal those of a GPU scene made fresh from the t1 pose.
 * The host BVH passes pb_bvh_check after each update (also without a device:
 * those checks run before it is opened). */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "pbtest.h"
#include "gltf_test.h"
#include "gpu_test.h"
#include "gpu_embree.h"
#include "ref/accel.h"
#include "ref/bsdf.h"
#include "render/render.h"

static char dir[] = "/tmp/pbtest_gpu_anim_XXXXXX";


enum { GRID = 12, NODES = 24 };

/* A GRID x GRID quad grid (2 GRID^2 triangles, normals +Z) instanced on NODES
 * nodes in a ring; every other node spins about its own Y axis and flies
 * across the ring between 0 and 1 s; an emissive material on the odd ones
 * (the emitter table moves too) and a point light on an animated node. */
static pb_result load_scene(pb_scene *s) {
  enum { NV = (GRID + 1) * (GRID + 1), NI = GRID * GRID * 6 };
  static float buf[NV * 6 + 2 + 2 * 4 + 2 * 3 * NODES];
  static uint32_t idx[NI];
  size_t n = 0;
  for (int y = 0; y <= GRID; ++y)
    for (int x = 0; x <= GRID; ++x) buf[n++] = (float)x / GRID - 0.5f, buf[n++] = (float)y / GRID - 0.5f, buf[n++] = 0;
  for (int i = 0; i < NV; ++i) buf[n++] = 0, buf[n++] = 0, buf[n++] = 1;
  size_t times = n;
  buf[n++] = 0, buf[n++] = 1;
  size_t rot = n;
  const float h = 0.70710678f;
  buf[n++] = 0, buf[n++] = 0, buf[n++] = 0, buf[n++] = 1, buf[n++] = 0, buf[n++] = h, buf[n++] = 0, buf[n++] = h;
  size_t tr = n;
  for (int k = 0; k < NODES; ++k) {
    double a = 2 * M_PI * k / NODES, b = a + M_PI * 0.8;
    buf[n++] = (float)(3 * cos(a)), buf[n++] = (float)(3 * sin(a)), buf[n++] = (float)(0.1 * k);
    buf[n++] = (float)(3 * cos(b)), buf[n++] = (float)(3 * sin(b)), buf[n++] = (float)(-0.1 * k);
  }
  size_t ni = 0;
  for (int y = 0; y < GRID; ++y)
    for (int x = 0; x < GRID; ++x) {
      uint32_t v = (uint32_t)(y * (GRID + 1) + x);
      idx[ni++] = v, idx[ni++] = v + 1, idx[ni++] = v + GRID + 2;
      idx[ni++] = v, idx[ni++] = v + GRID + 2, idx[ni++] = v + GRID + 1;
    }
  size_t fbytes = n * 4, ibytes = ni * 4;
  uint8_t *all = malloc(fbytes + ibytes);
  memcpy(all, buf, fbytes);
  memcpy(all + fbytes, idx, ibytes);
  char *data = pbt_b64(all, fbytes + ibytes);
  free(all);
  char path[256];
  snprintf(path, sizeof path, "%s/g.gltf", dir);
  FILE *f = fopen(path, "w");
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},"
          "\"buffers\":[{\"uri\":\"data:application/octet-stream;base64,%s\",\"byteLength\":%zu}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":%zu},{\"buffer\":0,\"byteOffset\":%zu,\"byteLength\":%zu}],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\",\"min\":[-0.5,-0.5,0],\"max\":[0.5,0.5,0]},"
          "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":%d,\"type\":\"VEC3\"},"
          "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":2,\"type\":\"SCALAR\"},"
          "{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":2,\"type\":\"VEC4\"},"
          "{\"bufferView\":1,\"componentType\":5125,\"count\":%d,\"type\":\"SCALAR\"}",
          data, fbytes + ibytes, fbytes, fbytes, ibytes, NV, (size_t)NV * 12, NV, times * 4, rot * 4, NI);
  for (int k = 0; k < NODES; ++k)
    fprintf(f, ",{\"bufferView\":0,\"byteOffset\":%zu,\"componentType\":5126,\"count\":2,\"type\":\"VEC3\"}", (tr + 6 * (size_t)k) * 4);
  fprintf(f, "],\"materials\":[{\"pbrMetallicRoughness\":{\"metallicFactor\":0}},"
             "{\"emissiveFactor\":[1,1,1],\"pbrMetallicRoughness\":{\"metallicFactor\":0}}],"
             "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":4,\"material\":0}]},"
             "{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"NORMAL\":1},\"indices\":4,\"material\":1}]}],\"nodes\":[");
  for (int k = 0; k < NODES; ++k) {
    double a = 2 * M_PI * k / NODES;
    fprintf(f, "%s{\"mesh\":%d,\"translation\":[%g,%g,%g]}", k ? "," : "", k & 1, 3 * cos(a), 3 * sin(a), 0.1 * k);
  }
  fprintf(f, ",{\"extensions\":{\"KHR_lights_punctual\":{\"light\":0}},\"translation\":[0,0,4]}");
  fprintf(f, "],\"scenes\":[{\"nodes\":[");
  for (int k = 0; k <= NODES; ++k) fprintf(f, "%s%d", k ? "," : "", k);
  fprintf(f, "]}],\"scene\":0,\"extensionsUsed\":[\"KHR_lights_punctual\"],"
             "\"extensions\":{\"KHR_lights_punctual\":{\"lights\":[{\"type\":\"point\",\"intensity\":100}]}},"
             "\"animations\":[{\"samplers\":[{\"input\":2,\"output\":3}");
  for (int k = 0; k < NODES; k += 2) fprintf(f, ",{\"input\":2,\"output\":%d}", 5 + k);
  fprintf(f, "],\"channels\":[{\"sampler\":1,\"target\":{\"node\":%d,\"path\":\"translation\"}}", NODES);
  for (int k = 0; k < NODES; k += 2)
    fprintf(f, ",{\"sampler\":0,\"target\":{\"node\":%d,\"path\":\"rotation\"}},{\"sampler\":%d,\"target\":{\"node\":%d,\"path\":\"translation\"}}",
            k, 1 + k / 2, k);
  fprintf(f, "]}]}");
  fclose(f);
  free(data);
  pb_result r = pb_scene_load(path, NULL, s);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  unlink(path);
  return r;
}

enum { NRAYS = 20000 };

static pb_result trace(pb_gpu *g, const pb_gpu_scene *gs, const pb_gpu_ray *rays, pb_gpu_hit *hits) {
  pb_raycast_pass rc;
  pb_result r = pb_raycast_create(g, gs, NRAYS, &rc);
  if (r == PB_OK) r = pb_raycast_run(g, &rc, rays, NRAYS, 0, hits, NULL);
  pb_raycast_destroy(g, &rc);
  return r;
}

/* Hits equal: same primitive and distance; `ties` counts rays whose
 * primitive differs at the same distance (two triangles at one t). */
static int same_hits(const pb_gpu_hit *a, const pb_gpu_hit *b, uint32_t *ties) {
  int bad = 0;
  *ties = 0;
  for (uint32_t i = 0; i < NRAYS; ++i) {
    if (a[i].prim == b[i].prim && (a[i].prim == PB_GPU_MISS || a[i].t == b[i].t)) continue;
    if (a[i].prim != PB_GPU_MISS && b[i].prim != PB_GPU_MISS && a[i].t == b[i].t) {
      (*ties)++;
      continue;
    }
    if (bad++ < 5) fprintf(stderr, "ray %u: prim %u t %.9g vs prim %u t %.9g\n", i, a[i].prim, a[i].t, b[i].prim, b[i].t);
  }
  return bad == 0;
}

int main(void) {
  if (!mkdtemp(dir)) return 1;
  pb_scene s;
  if (load_scene(&s) != PB_OK) {
    CHECK(0);
    rmdir(dir);
    return pbt_done();
  }
  rmdir(dir);
  CHECK(s.anim != NULL);
  CHECK_EQ_INT(s.triangle_count, NODES * GRID * GRID * 2);
  const double t0 = 0.1, t1 = 0.9;
  char why[256];

  /* Host BVH: refit to the t1 pose is sound and bounds the moved triangles. */
  CHECK_EQ_INT(pb_scene_set_time(&s, t0), PB_OK);
  pb_bvh b;
  CHECK_EQ_INT(pb_bvh_build(&s, &b), PB_OK);
  double sah0 = pb_bvh_sah_cost(&b);
  CHECK_EQ_INT(pb_scene_set_time(&s, t1), PB_OK);
  CHECK_EQ_INT(pb_bvh_refit(&s, &b), PB_OK);
  CHECK(pb_bvh_check(&b, why, sizeof why) || (fprintf(stderr, "refit: %s\n", why), 0));
  double sah1 = pb_bvh_sah_cost(&b);
  printf("SAH cost: built at t0 %.2f, refitted to t1 %.2f\n", sah0, sah1);
  CHECK(sah1 > sah0); /* objects flew apart: the refitted tree is worse */
  pb_bvh_destroy(&b);

  PBT_GPU_OPEN(g);
  pb_gpu_ray *rays = malloc(NRAYS * sizeof *rays);
  pb_gpu_hit *fresh = malloc(NRAYS * sizeof *fresh), *got = malloc(NRAYS * sizeof *got);
  pb_gpu_scene gs, gf;
  memset(&gf, 0, sizeof gf);
  CHECK_EQ_INT(pb_scene_set_time(&s, t0), PB_OK);
  CHECK_EQ_INT(r = pb_gpu_scene_create(g, &s, &gs), PB_OK);
  uint32_t em0 = gs.emitter_count;
  CHECK(em0 > 0);
  CHECK_EQ_INT(pb_scene_set_time(&s, t1), PB_OK);
  pbt_random_rays(&s, 77, rays, NRAYS);
  CHECK_EQ_INT(pb_gpu_scene_create(g, &s, &gf), PB_OK);
  CHECK_EQ_INT(trace(g, &gf, rays, fresh), PB_OK);
  uint32_t hits = 0, ties = 0;
  for (uint32_t i = 0; i < NRAYS; ++i) hits += fresh[i].prim != PB_GPU_MISS;
  printf("%u of %u rays hit the t1 pose\n", hits, NRAYS);
  CHECK(hits > NRAYS / 10);

  /* The Embree reference takes the posed scene as it is (its accel is made
   * from the arrays on each call, nothing cached): its hits at t1 are the
   * GPU's, and an accel made at t0 is not. */
  pb_ref_accel acc0, acc1;
  CHECK_EQ_INT(pb_scene_set_time(&s, t0), PB_OK);
  CHECK_EQ_INT(pb_ref_accel_create(&s, &acc0), PB_OK);
  CHECK_EQ_INT(pb_scene_set_time(&s, t1), PB_OK);
  CHECK_EQ_INT(pb_ref_accel_create(&s, &acc1), PB_OK);
  uint32_t ref_agree = 0, stale_agree = 0;
  for (uint32_t i = 0; i < NRAYS; ++i) {
    pb_ref_hit h;
    v3 o = v3_load(rays[i].org), d = v3_load(rays[i].dir);
    uint32_t p1 = pb_ref_intersect(&acc1, o, d, rays[i].tmax, &h) ? h.prim : PB_GPU_MISS;
    uint32_t p0 = pb_ref_intersect(&acc0, o, d, rays[i].tmax, &h) ? h.prim : PB_GPU_MISS;
    ref_agree += p1 == fresh[i].prim;
    stale_agree += p0 == fresh[i].prim;
  }
  printf("Embree reference: %u of %u rays agree at t1 (accel made at t0: %u)\n", ref_agree, NRAYS, stale_agree);
  CHECK(ref_agree >= NRAYS - NRAYS / 1000);
  CHECK(stale_agree < NRAYS - NRAYS / 20);
  pb_ref_accel_destroy(&acc0);
  pb_ref_accel_destroy(&acc1);

  /* The t0 GPU scene, updated to t1: hits of the fresh one. Before the
   * update they differ (the test can fail). */
  CHECK_EQ_INT(trace(g, &gs, rays, got), PB_OK);
  uint32_t differ = 0;
  for (uint32_t i = 0; i < NRAYS; ++i) differ += got[i].prim != fresh[i].prim;
  printf("%u rays differ before the update\n", differ);
  CHECK(differ > NRAYS / 20);
  double ms = -1;
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_REFIT, &ms), PB_OK);
  CHECK(ms >= 0);
  CHECK(pb_bvh_check(&gs.bvh, why, sizeof why) || (fprintf(stderr, "refit: %s\n", why), 0));
  CHECK_EQ_INT(gs.refits, 1);
  CHECK_EQ_INT(trace(g, &gs, rays, got), PB_OK);
  CHECK(same_hits(got, fresh, &ties));
  printf("refit (%.2f ms): hits equal (%u ties at equal t)\n", ms, ties);
  CHECK_EQ_INT(gs.emitter_count, gf.emitter_count);
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_REBUILD, &ms), PB_OK);
  CHECK_EQ_INT(gs.refits, 0);
  CHECK(pb_bvh_check(&gs.bvh, why, sizeof why) || (fprintf(stderr, "rebuild: %s\n", why), 0));
  CHECK_EQ_INT(trace(g, &gs, rays, got), PB_OK);
  CHECK(same_hits(got, fresh, &ties));
  printf("rebuild (%.2f ms): hits equal (%u ties at equal t)\n", ms, ties);
  /* The uploaded arrays are the posed scene's. */
  float *pos = malloc((size_t)s.vertex_count * 12);
  pb_gpu_emitter *em = malloc((size_t)gs.emitter_count * sizeof *em + 16), *emf = malloc((size_t)gf.emitter_count * sizeof *emf + 16);
  pb_gpu_light lt;
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &gs.positions, 0, pos, (uint64_t)s.vertex_count * 12), PB_OK);
  CHECK(memcmp(pos, s.positions, (size_t)s.vertex_count * 12) == 0);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &gs.normals, 0, pos, (uint64_t)s.vertex_count * 12), PB_OK);
  CHECK(memcmp(pos, s.normals, (size_t)s.vertex_count * 12) == 0);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &gs.lights, 0, &lt, sizeof lt), PB_OK);
  CHECK_NEAR(lt.position[0], s.lights[0].position[0], 0);
  CHECK_NEAR(lt.position[1], s.lights[0].position[1], 0);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &gs.emitters, 0, em, (uint64_t)gs.emitter_count * sizeof *em), PB_OK);
  CHECK_EQ_INT(pb_gpu_buffer_download(g, &gf.emitters, 0, emf, (uint64_t)gf.emitter_count * sizeof *emf), PB_OK);
  CHECK(memcmp(em, emf, (size_t)gf.emitter_count * sizeof *em) == 0);
  /* AUTO: back to t0 then t1 again; whichever it picks, hits are right. */
  CHECK_EQ_INT(pb_scene_set_time(&s, t0), PB_OK);
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_AUTO, &ms), PB_OK);
  CHECK_EQ_INT(pb_scene_set_time(&s, t1), PB_OK);
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, PB_BVH_UPDATE_AUTO, &ms), PB_OK);
  CHECK_EQ_INT(trace(g, &gs, rays, got), PB_OK);
  CHECK(same_hits(got, fresh, &ties));
  CHECK_EQ_INT(pb_gpu_scene_update(g, &s, &gs, 7, NULL), PB_ERR_USAGE);
  free(pos);
  free(em);
  free(emf);
  free(rays);
  free(fresh);
  free(got);
  pb_gpu_scene_destroy(g, &gs);
  pb_gpu_scene_destroy(g, &gf);
  pb_gpu_destroy(g);
  pb_scene_destroy(&s);
  return pbt_done();
}
