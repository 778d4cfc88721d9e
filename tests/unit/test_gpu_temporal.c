/* The temporal filter (render/filter/temporal.h, seed 001 24.4.1) and the motion
 * vectors it reprojects with (render/scene/motion.h), on a code-built scene whose
 * G-buffer is known analytically: a wall facing the camera at depth 5 and a
 * small card in front of it at depth 2.5.
 *  - pan: the camera moves sideways by exactly 3 of the wall's pixel widths;
 *    motion vectors are (3, 0) on the wall and (6, 0) on the card; an image
 *    fixed to the world reprojects exactly where nothing is disoccluded, and
 *    the disoccluded pixels (behind the card before) start afresh;
 *  - moving object: the card moves, the camera stays; pixels the card
 *    uncovered reset (no ghost of the card), the rest keep their history;
 *  - still: successive still frames give their exact running mean
 *    (progressive rendering);
 *  - constant: a constant irradiance stays constant through temporal +
 *    A-Trous (filters.h). */
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pbtest.h"
#include "gpu_test.h"
#include "render/filter/filters.h"
#include "render/scene/motion.h"
#include "render/render.h"
#include "render/filter/temporal.h"

enum { W = 64, H = 48, N = W * H };
static const float WALL_Z = -5.0f, CARD_Z = -2.5f;

typedef struct fixture {
  float pos[8][3], nrm[8][3], uv[8][2];
  uint32_t tri[4][3], tm[4];
  pb_material mat;
  pb_camera cam;
  pb_scene s;
} fixture;

static void set_card(fixture *f, float cx) {
  const float c[4][2] = {{-0.45f, -0.37f}, {0.45f, -0.37f}, {0.45f, 0.41f}, {-0.45f, 0.41f}};
  for (int i = 0; i < 4; ++i) {
    f->pos[4 + i][0] = c[i][0] + cx;
    f->pos[4 + i][1] = c[i][1];
    f->pos[4 + i][2] = CARD_Z;
  }
}

static void build(fixture *f) {
  memset(f, 0, sizeof *f);
  const float wq[4][2] = {{-40, -40}, {40, -40}, {40, 40}, {-40, 40}};
  for (int i = 0; i < 4; ++i) f->pos[i][0] = wq[i][0], f->pos[i][1] = wq[i][1], f->pos[i][2] = WALL_Z;
  set_card(f, 0.0f);
  for (int i = 0; i < 8; ++i) f->nrm[i][2] = 1.0f;
  uint32_t t[4][3] = {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}};
  memcpy(f->tri, t, sizeof t);
  f->mat.base_color[0] = f->mat.base_color[1] = f->mat.base_color[2] = 0.5f;
  f->mat.base_color[3] = 1;
  f->mat.base_color_tex = f->mat.metallic_roughness_tex = f->mat.emissive_tex = f->mat.normal_tex = PB_NO_TEXTURE;
  f->mat.roughness = 1;
  f->mat.ior = 1.5f;
  f->cam.forward[2] = -1;
  f->cam.up[1] = 1;
  f->cam.right[0] = 1;
  f->cam.yfov = 0.8f;
  f->cam.aspect = (float)W / H;
  pb_scene *s = &f->s;
  s->positions = f->pos;
  s->normals = f->nrm;
  s->uvs = f->uv;
  s->vertex_count = 8;
  s->triangles = f->tri;
  s->triangle_material = f->tm;
  s->triangle_count = 4;
  s->materials = &f->mat;
  s->material_count = 1;
  s->cameras = &f->cam;
  s->camera_count = 1;
  pb_scene_finalize(s);
}

/* The G-buffer of the fixture, analytically: depth, normal (+z), albedo,
 * and the world point each pixel centre sees. */
static void gbuffer(const fixture *f, float *depth, float *normal, float *albedo, float (*world)[3]) {
  const pb_camera *c = &f->cam;
  float ty = tanf(0.5f * c->yfov), tx = ty * W / H;
  for (int p = 0; p < N; ++p) {
    float sx = (2.0f * ((float)(p % W) + 0.5f) / W - 1.0f) * tx, sy = (1.0f - 2.0f * ((float)(p / W) + 0.5f) / H) * ty;
    float d[3] = {sx, sy, -1.0f}; /* right = x, up = y, forward = -z */
    float t = (CARD_Z - c->position[2]) / d[2];
    float x = c->position[0] + t * d[0], y = c->position[1] + t * d[1];
    if (!(x >= f->pos[4][0] && x <= f->pos[5][0] && y >= f->pos[4][1] && y <= f->pos[6][1]))
      t = (WALL_Z - c->position[2]) / d[2];
    depth[p] = t; /* |d . forward| = 1 */
    for (int k = 0; k < 3; ++k) {
      world[p][k] = c->position[k] + t * d[k];
      normal[3 * p + k] = k == 2 ? 1.0f : 0.0f;
      albedo[3 * p + k] = 0.5f;
    }
  }
}

/* An irradiance fixed to the world with detail at the pixel scale, times the
 * albedo (the indirect radiance the filter demodulates). */
static void pattern(const float (*world)[3], float *indirect) {
  for (int p = 0; p < N; ++p) {
    float e = 1.0f + 0.5f * sinf(world[p][0] * 17.0f) * cosf(world[p][1] * 13.0f) + (world[p][2] > -3 ? 1.0f : 0.0f);
    for (int k = 0; k < 3; ++k) indirect[3 * p + k] = 0.5f * e * (1.0f + 0.25f * (float)k);
  }
}

typedef struct frame {
  float depth[N], normal[3 * N], albedo[3 * N], world[N][3], indirect[3 * N], motion[4 * N], hist[N];
} frame;

static void pan(pb_gpu *g) {
  fixture f;
  build(&f);
  static frame a, b;
  gbuffer(&f, a.depth, a.normal, a.albedo, a.world);
  pattern(a.world, a.indirect);
  pb_temporal *t = NULL;
  CHECK_EQ_INT(pb_temporal_create(g, W, H, NULL, &t), PB_OK);
  if (!t) return;
  CHECK_EQ_INT(pb_temporal_apply(g, t, a.normal, a.depth, a.albedo, NULL, 1, a.indirect, a.hist, NULL), PB_OK);
  /* Pan: 3 wall pixels to the right. */
  pb_camera prev = f.cam;
  float pw = 2.0f * -WALL_Z * tanf(0.5f * f.cam.yfov) * W / H / W;
  f.cam.position[0] += 3.0f * pw;
  gbuffer(&f, b.depth, b.normal, b.albedo, b.world);
  pattern(b.world, b.indirect);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &f.s, &gs), PB_OK);
  CHECK_EQ_INT(pb_motion_vectors(g, &f.s, &gs, NULL, &f.cam, &prev, W, H, b.motion, NULL), PB_OK);
  pb_gpu_scene_destroy(g, &gs);
  static float want[3 * N];
  memcpy(want, b.indirect, sizeof want);
  pb_temporal_stats ts;
  CHECK_EQ_INT(pb_temporal_apply(g, t, b.normal, b.depth, b.albedo, b.motion, 0, b.indirect, b.hist, &ts), PB_OK);
  int kept = 0, reset = 0, bad_mv = 0, bad_keep = 0, bad_reset = 0, bad_proj = 0;
  double max_err = 0;
  for (int p = 0; p < N; ++p) {
    int x = p % W, on_card = b.depth[p] < 3.0f;
    float *mv = &b.motion[4 * p];
    float want_dx = on_card ? 6.0f : 3.0f;
    if (mv[3] != 1.0f || fabsf(mv[0] - want_dx) > 1e-3f || fabsf(mv[1]) > 1e-3f ||
        fabsf(mv[2] - b.depth[p]) > 1e-4f * b.depth[p])
      ++bad_mv;
    /* The same against the host's projection of the analytic point. */
    float hx, hy, hz;
    if (!pb_camera_project(&prev, W, H, b.world[p], &hx, &hy, &hz) ||
        fabsf(mv[0] - (hx - ((float)x + 0.5f))) > 1e-3f || fabsf(mv[1] - (hy - ((float)(p / W) + 0.5f))) > 1e-3f)
      ++bad_proj;
    /* Where was this point in frame a: pixel x + dx, same row. Visible
     * there (same depth) and on screen: reprojected; else disoccluded. */
    int qx = x + (int)want_dx;
    int visible = qx < W && fabsf(a.depth[p - x + qx] - b.depth[p]) < 1e-3f;
    if (visible) {
      ++kept;
      if (!(b.hist[p] > 1.5f)) ++bad_keep;
      for (int k = 0; k < 3; ++k) {
        double e = fabs(b.indirect[3 * p + k] - want[3 * p + k]) / want[3 * p + k];
        if (e > max_err) max_err = e;
      }
    } else {
      ++reset;
      if (b.hist[p] != 1.0f) ++bad_reset;
      for (int k = 0; k < 3; ++k)
        if (fabsf(b.indirect[3 * p + k] - want[3 * p + k]) > 1e-6f * want[3 * p + k]) ++bad_reset;
    }
  }
  printf("pan: %d pixels reprojected (max relative difference %.2e), %d reset (disoccluded or off-screen); "
         "pass %.3f ms\n", kept, max_err, reset, ts.gpu_ms);
  CHECK_EQ_INT(bad_mv, 0);
  CHECK_EQ_INT(bad_proj, 0);
  CHECK(kept > N / 2);
  CHECK(reset >= 3 * H + 10); /* the entering columns plus the card's trail */
  CHECK_EQ_INT(bad_keep, 0);
  CHECK_EQ_INT(bad_reset, 0);
  CHECK(max_err < 1e-4);
  CHECK_EQ_INT((int)ts.reset_pixels, reset);
  pb_temporal_destroy(g, t);
}

static void moving_object(pb_gpu *g) {
  fixture f;
  build(&f);
  static frame a, b;
  pb_temporal *t = NULL;
  CHECK_EQ_INT(pb_temporal_create(g, W, H, NULL, &t), PB_OK);
  if (!t) return;
  gbuffer(&f, a.depth, a.normal, a.albedo, a.world);
  /* Irradiance 1 on the wall, 3 on the card: a ghost of the card would
   * show as values above 1 on the wall it uncovers. */
  for (int frame_i = 0; frame_i < 3; ++frame_i) {
    for (int p = 0; p < N; ++p)
      for (int k = 0; k < 3; ++k) a.indirect[3 * p + k] = 0.5f * (a.depth[p] < 3.0f ? 3.0f : 1.0f);
    CHECK_EQ_INT(pb_temporal_apply(g, t, a.normal, a.depth, a.albedo, NULL, 1, a.indirect, a.hist, NULL), PB_OK);
  }
  float prev_pos[8][3];
  memcpy(prev_pos, f.pos, sizeof prev_pos);
  set_card(&f, 0.3f); /* 0.3 m at depth 2.5: about 5.5 pixels */
  pb_scene_finalize(&f.s);
  gbuffer(&f, b.depth, b.normal, b.albedo, b.world);
  for (int p = 0; p < N; ++p)
    for (int k = 0; k < 3; ++k) b.indirect[3 * p + k] = 0.5f * (b.depth[p] < 3.0f ? 3.0f : 1.0f);
  pb_gpu_scene gs;
  CHECK_EQ_INT(pb_gpu_scene_create(g, &f.s, &gs), PB_OK);
  CHECK_EQ_INT(pb_motion_vectors(g, &f.s, &gs, (const float(*)[3])prev_pos, &f.cam, &f.cam, W, H, b.motion, NULL),
               PB_OK);
  pb_gpu_scene_destroy(g, &gs);
  CHECK_EQ_INT(pb_temporal_apply(g, t, b.normal, b.depth, b.albedo, b.motion, 0, b.indirect, b.hist, NULL), PB_OK);
  int uncovered = 0, ghost = 0, lost = 0;
  double worst = 0;
  for (int p = 0; p < N; ++p) {
    int was_card = a.depth[p] < 3.0f, is_card = b.depth[p] < 3.0f;
    double want = 0.5 * (is_card ? 3.0 : 1.0), err = fabs(b.indirect[3 * p] - want) / want;
    if (err > worst) worst = err;
    if (was_card && !is_card) {
      ++uncovered;
      if (b.hist[p] != 1.0f || err > 1e-6) ++ghost;
    } else if (b.hist[p] < 1.0001f) {
      ++lost; /* history that should have been kept (a tap on the card's
                 edge may lower its weight, never to nothing) */
    }
  }
  printf("moving card: %d pixels uncovered, %d with a ghost; %d kept pixels lost their history; worst relative "
         "error %.2e\n", uncovered, ghost, lost, worst);
  CHECK(uncovered >= 40);
  CHECK_EQ_INT(ghost, 0);
  CHECK_EQ_INT(lost, 0);
  CHECK(worst < 1e-4);
  pb_temporal_destroy(g, t);
}

/* Successive still frames give their exact running mean. edge = 0: random
 * radiance, 40 frames (past 0.95's 20-frame window: a still view keeps
 * averaging), the history length the frame count. edge = 1: pixels that
 * straddle two materials: the jittered samples of successive frames meet
 * albedo 0.8 and 0.1 in turn (as at an edge), so the radiance is e * a_i
 * with a_i changing every frame. The result is the running mean of the
 * radiance itself, sum(e_i a_i) / i, not the mean irradiance times the last
 * frame's albedo (which never converges there: it swings by the ratio of
 * the albedos from frame to frame). edge = 2: a silhouette against the
 * world: every fifth pixel's sample misses every surface on even frames
 * (depth 0, no indirect light), so its mean goes on with a zero there and
 * converges to the box-filtered pixel, where a reset at each miss kept it
 * at one frame's noise. */
static void still_run(pb_gpu *g, int edge) {
  fixture f;
  build(&f);
  static frame a;
  static double sum[3 * N];
  memset(sum, 0, sizeof sum);
  gbuffer(&f, a.depth, a.normal, a.albedo, a.world);
  pb_temporal *t = NULL;
  CHECK_EQ_INT(pb_temporal_create(g, W, H, NULL, &t), PB_OK);
  if (!t) return;
  srand(edge ? 11 + edge : 7);
  float depth0[N];
  memcpy(depth0, a.depth, sizeof depth0);
  double worst = 0, worst_rel = 0;
  int bad_len = 0;
  const int frames = edge == 1 ? 12 : edge == 2 ? 20 : 40;
  int missed = 0;
  for (int i = 1; i <= frames; ++i) {
    float alb = (i & 1) ? 0.8f : 0.1f;
    for (int p = 0; p < N; ++p) a.depth[p] = edge == 2 && !(i & 1) && p % 5 == 0 ? 0.0f : depth0[p];
    for (int p = 0; p < 3 * N; ++p) {
      if (edge == 1) a.albedo[p] = alb;
      float r = (float)rand() / (float)RAND_MAX;
      a.indirect[p] = edge == 1 ? alb * (0.2f + 0.6f * r) : 0.5f * r;
      if (!(a.depth[p / 3] > 0)) a.indirect[p] = 0.0f, missed += p % 3 == 0;
      sum[p] += a.indirect[p];
    }
    CHECK_EQ_INT(pb_temporal_apply(g, t, a.normal, a.depth, a.albedo, NULL, 1, a.indirect, a.hist, NULL), PB_OK);
    for (int p = 0; p < N; ++p) {
      if (fabsf(a.hist[p] - (float)i) > 1e-3f * i) ++bad_len;
      if (edge == 1 && !(a.depth[p] > 0)) continue;
      for (int k = 0; k < 3; ++k) {
        double e = fabs(a.indirect[3 * p + k] - sum[3 * p + k] / i);
        if (e > worst) worst = e;
        if (sum[3 * p + k] > 0 && e / (sum[3 * p + k] / i) > worst_rel) worst_rel = e / (sum[3 * p + k] / i);
      }
    }
  }
  printf("still%s: %d frames, largest difference from the running mean %.2e (relative %.2e)\n",
         edge == 1 ? " edge (alternating albedo)" : edge == 2 ? " silhouette (samples missing every surface)" : "",
         frames, worst, worst_rel);
  if (edge == 2) CHECK(missed > 0 && depth0[0] > 0);
  if (edge == 1) {
    CHECK(worst_rel < 1e-5);
  } else {
    CHECK(worst < 2e-5);
    CHECK_EQ_INT(bad_len, 0);
  }
  pb_temporal_destroy(g, t);
}

static void constant(pb_gpu *g) {
  fixture f;
  build(&f);
  static frame a;
  pb_temporal *t = NULL;
  CHECK_EQ_INT(pb_temporal_create(g, W, H, NULL, &t), PB_OK);
  if (!t) return;
  pb_render_result res;
  memset(&res, 0, sizeof res);
  res.width = W, res.height = H;
  static float beauty[4 * N];
  res.beauty = beauty, res.normal = a.normal, res.depth = a.depth, res.albedo = a.albedo, res.indirect = a.indirect;
  pb_camera prev = f.cam;
  double worst = 0;
  for (int i = 0; i < 4; ++i) {
    gbuffer(&f, a.depth, a.normal, a.albedo, a.world);
    for (int p = 0; p < 3 * N; ++p) a.indirect[p] = 0.35f;
    pb_filter_desc fd = {.atrous_iterations = 4, .temporal = t, .still = i == 0};
    if (i > 0) {
      pb_gpu_scene gs;
      CHECK_EQ_INT(pb_gpu_scene_create(g, &f.s, &gs), PB_OK);
      CHECK_EQ_INT(pb_motion_vectors(g, &f.s, &gs, NULL, &f.cam, &prev, W, H, a.motion, NULL), PB_OK);
      pb_gpu_scene_destroy(g, &gs);
      fd.motion = a.motion;
    }
    CHECK_EQ_INT(pb_filter_indirect(g, &res, &fd), PB_OK);
    for (int p = 0; p < 3 * N; ++p) {
      double e = fabs(a.indirect[p] - 0.35) / 0.35;
      if (e > worst) worst = e;
    }
    prev = f.cam;
    f.cam.position[0] += 0.037f * (float)(i + 1); /* sub-pixel and multi-pixel pans */
    f.cam.position[1] -= 0.021f;
  }
  printf("constant: temporal + 4 A-Trous passes over 4 panning frames, worst relative change %.2e\n", worst);
  CHECK(worst < 1e-5);
  pb_temporal_destroy(g, t);
}

int main(void) {
  PBT_GPU_OPEN(g);
  pan(g);
  moving_object(g);
  still_run(g, 0);
  still_run(g, 1);
  still_run(g, 2);
  constant(g);
  pb_gpu_destroy(g);
  return pbt_done();
}
