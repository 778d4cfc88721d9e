/* Skins and shape keys against Blender's own deformation: the scene of
 * tests/data/deform (make_deform.py: a cylinder skinned to a bending chain
 * of three bones, a cube with two animated shape keys) exported by Blender's
 * glTF exporter with skins, morph targets and sampled animation, and again
 * at frames 0, 12 and 24 with Blender's armature and shape keys applied.
 * photonbridge poses the first at t = frame / 24 s: every vertex must be
 * where Blender put it, within 1e-5 of the scene's size, with the same
 * triangles. Normals follow glTF (the skin matrix's inverse transpose, the
 * targets' NORMAL deltas blended linearly), where Blender recomputes them
 * from the deformed faces: equal at rest (checked), they differ where the
 * mesh bends or the shapes mix (printed; docs/benchmarks.md). The pictures are compared
 * by test_gpu_deform, in both renderers. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pbtest.h"
#include "scene/scene.h"

static const int frames[3] = {0, 12, 24};

static int load(const char *path, pb_scene *s) {
  pb_result r = pb_scene_load(path, NULL, s);
  if (r != PB_OK) fprintf(stderr, "%s\n", pb_error_message());
  CHECK_EQ_INT(r, PB_OK);
  return r == PB_OK;
}

static double scene_size(const pb_scene *s) {
  double d = 0;
  for (int k = 0; k < 3; ++k) d += ((double)s->bounds_max[k] - s->bounds_min[k]) * (s->bounds_max[k] - s->bounds_min[k]);
  return sqrt(d);
}

int main(void) {
  pb_scene anim;
  if (!load("tests/data/deform/deform.gltf", &anim)) return pbt_done();
  CHECK(anim.features & PB_FEATURE_SKINNING);
  CHECK(anim.features & PB_FEATURE_MORPH_TARGETS);
  CHECK(anim.posed_vertex_count > 300);
  double size = scene_size(&anim);
  for (int f = 0; f < 3; ++f) {
    char path[128];
    snprintf(path, sizeof path, "tests/data/deform/deform_baked_f%02d.gltf", frames[f]);
    pb_scene baked;
    if (!load(path, &baked)) continue;
    CHECK_EQ_INT(pb_scene_set_time(&anim, frames[f] / 24.0), PB_OK);
    CHECK_EQ_INT(anim.vertex_count, baked.vertex_count);
    CHECK_EQ_INT(anim.triangle_count, baked.triangle_count);
    double dp = 0, dn = 0;
    uint32_t worst = 0;
    for (uint32_t v = 0; v < anim.vertex_count && v < baked.vertex_count; ++v) {
      double e = 0, c = 0;
      for (int k = 0; k < 3; ++k) {
        e = fmax(e, fabs((double)anim.positions[v][k] - baked.positions[v][k]));
        c += (double)anim.normals[v][k] * baked.normals[v][k];
      }
      if (e > dp) dp = e, worst = v;
      dn = fmax(dn, 1 - c);
    }
    int same_topology = anim.triangle_count == baked.triangle_count &&
                        memcmp(anim.triangles, baked.triangles, (size_t)anim.triangle_count * sizeof *anim.triangles) == 0;
    printf("frame %2d: %u vertices, max |photonbridge - Blender| %.3g m (%.2g of the scene's %.3g m; worst vertex %u), "
           "normals (glTF's against Blender's recomputed ones) max 1 - cos %.2g, same triangles %s\n",
           frames[f], anim.vertex_count, dp, dp / size, size, worst, dn, same_topology ? "yes" : "no");
    CHECK(dp <= 1e-5 * size);
    if (frames[f] == 0) CHECK(dn <= 1e-6);
    CHECK(same_topology);
    pb_scene_destroy(&baked);
  }
  pb_scene_destroy(&anim);
  return pbt_done();
}
