/* The scene BVH, checked structurally on every sample scene and on small
 * code-built scenes (GPU-free): every node reached once from the root, no
 * inner node with fewer than two children (empty slots of the 4-wide layout
 * excepted), each parent box the union of its children's, each leaf
 * box its triangles' bounds, every triangle in exactly one leaf. */
#include <stdlib.h>
#include <string.h>

#include "render/scene/bvh.h"
#include "pbtest.h"

static const char *const samples[] = {"cornell_box", "cornell_caustics", "ring", "spot_room", "sun_atrium"};

static void check_scene(const pb_scene *s, const char *label) {
  pb_bvh b;
  pb_result r = pb_bvh_build(s, &b);
  CHECK_EQ_INT(r, PB_OK);
  if (r != PB_OK) {
    fprintf(stderr, "%s: %s\n", label, pb_error_message());
    pb_error_clear();
    return;
  }
  char why[256] = "";
  int ok = pb_bvh_check(&b, why, sizeof why);
  if (!ok) fprintf(stderr, "%s: BVH check failed: %s\n", label, why);
  CHECK(ok);
  CHECK_EQ_INT(b.tri_count, s->triangle_count);
  /* Inner nodes have 2..PB_BVH_WIDTH children, each PB_BVH_WIDTH slots. */
  CHECK(b.node_count >= b.leaf_count && b.node_count <= 1 + PB_BVH_WIDTH * (b.leaf_count > 1 ? b.leaf_count - 1 : 0));
  /* Each scene triangle appears once. */
  uint8_t *seen = calloc(s->triangle_count, 1);
  int dup = 0;
  for (uint32_t i = 0; i < b.tri_count; ++i) {
    if (b.tris[i].prim >= s->triangle_count || seen[b.tris[i].prim]) dup++;
    else seen[b.tris[i].prim] = 1;
  }
  CHECK_EQ_INT(dup, 0);
  free(seen);
  printf("%-18s %7u triangles  %7u nodes  depth %2u  %.1f ms\n", label, b.tri_count, b.node_count, b.depth,
         b.build_s * 1e3);
  /* The checker itself catches a broken parent box and a shared child. */
  if (b.node_count > 2) {
    b.nodes[0].hi[0] += 1.0f;
    CHECK(!pb_bvh_check(&b, why, sizeof why));
    b.nodes[0].hi[0] -= 1.0f;
    uint32_t first = b.nodes[0].first;
    b.nodes[0].first = 0; /* points at itself */
    CHECK(!pb_bvh_check(&b, why, sizeof why));
    b.nodes[0].first = first;
    CHECK(pb_bvh_check(&b, why, sizeof why));
  }
  pb_bvh_destroy(&b);
}

static void one_triangle(void) {
  float pos[3][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  uint32_t tri[1][3] = {{0, 1, 2}};
  uint32_t mat[1] = {0};
  pb_scene s;
  memset(&s, 0, sizeof s);
  s.positions = pos;
  s.vertex_count = 3;
  s.triangles = tri;
  s.triangle_material = mat;
  s.triangle_count = 1;
  check_scene(&s, "one triangle");
  /* Empty and out-of-range scenes are refused with exact codes. */
  pb_bvh b;
  s.triangle_count = 0;
  CHECK_EQ_INT(pb_bvh_build(&s, &b), PB_ERR_SCENE_EMPTY);
  s.triangle_count = 1;
  tri[0][2] = 7;
  CHECK_EQ_INT(pb_bvh_build(&s, &b), PB_ERR_SCENE_INVALID);
  pb_error_clear();
}

int main(void) {
  one_triangle();
  for (size_t i = 0; i < sizeof samples / sizeof *samples; ++i) {
    char path[256];
    snprintf(path, sizeof path, "samples/%s/%s.gltf", samples[i], samples[i]);
    pb_scene s;
    pb_load_desc d = {0};
    pb_result r = pb_scene_load(path, &d, &s);
    CHECK_EQ_INT(r, PB_OK);
    if (r != PB_OK) {
      fprintf(stderr, "%s\n", pb_error_message());
      pb_error_clear();
      continue;
    }
    check_scene(&s, samples[i]);
    pb_scene_destroy(&s);
  }
  return pbt_done();
}
