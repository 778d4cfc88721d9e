/* src/image: EXR write/read round trips (float, half, layers, attributes),
 * exact error codes for unwritable paths, malformed desc, limits, truncated
 * and corrupted files, reading tiled / offset / uint files made with the raw
 * OpenEXR API, and PNG previews decoded back with stb_image. */
#ifndef _GNU_SOURCE
#define _GNU_SOURCE /* mkdtemp */
#endif
#include <dirent.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <openexr.h>

#include "core/result.h"
#include "image/image.h"
#include "pbtest.h"

#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wimplicit-fallthrough"
#define STBI_ONLY_PNG
#define STB_IMAGE_IMPLEMENTATION
#include <stb/stb_image.h>
#pragma GCC diagnostic pop

static char tmpdir[64];

static const char *tpath(const char *name) {
  static char buf[4][256];
  static int next;
  char *p = buf[next++ & 3];
  snprintf(p, 256, "%s/%s", tmpdir, name);
  return p;
}

static int file_exists(const char *p) {
  struct stat st;
  return stat(p, &st) == 0;
}

/* Names in the temporary directory other than `keep` (NULL: any). */
static int stray_files(const char *keep) {
  DIR *d = opendir(tmpdir);
  if (!d) return -1;
  int n = 0;
  struct dirent *e;
  while ((e = readdir(d)))
    if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..") &&
        (!keep || strcmp(e->d_name, keep)))
      ++n;
  closedir(d);
  return n;
}

static void clean_dir(const char *dir) {
  DIR *d = opendir(dir);
  if (!d) return;
  struct dirent *e;
  while ((e = readdir(d))) {
    if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, "..")) continue;
    char p[512];
    snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
    struct stat st;
    if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode)) {
      clean_dir(p);
      rmdir(p);
    } else {
      unlink(p);
    }
  }
  closedir(d);
}

static uint8_t *slurp(const char *p, size_t *n) {
  FILE *f = fopen(p, "rb");
  if (!f) return NULL;
  fseek(f, 0, SEEK_END);
  long len = ftell(f);
  fseek(f, 0, SEEK_SET);
  uint8_t *b = malloc((size_t)len + 1);
  *n = fread(b, 1, (size_t)len, f);
  fclose(f);
  return b;
}

static void spill(const char *p, const uint8_t *b, size_t n) {
  FILE *f = fopen(p, "wb");
  if (!f) return;
  fwrite(b, 1, n, f);
  fclose(f);
}

/* The error contract: the failing call's code is recorded, and its message
 * is one line that starts with the path. */
static int error_is(pb_result got, pb_result want, const char *path) {
  const char *m = pb_error_message();
  int ok = got == want && pb_error_result() == want &&
           strncmp(m, path, strlen(path)) == 0 && !strchr(m, '\n');
  if (!ok)
    fprintf(stderr, "  expected %s for %s, got %s: \"%s\"\n",
            pb_result_name(want), path, pb_result_name(got), m);
  pb_error_clear();
  return ok;
}

/* ---- round trips -------------------------------------------------------- */

static void test_roundtrip_float(void) {
  enum { W = 37, H = 23 };
  float *px = malloc(sizeof(float) * W * H * 4);
  for (int i = 0; i < W * H * 4; ++i)
    px[i] = (float)(i % 101) * 0.37f - 9.0f + (float)(i / 4) * 1e-3f;
  px[5] = 1e30f;
  px[6] = -1e-30f;
  pb_image_layer layer = {"", 4, px, NULL};
  uint64_t nonfinite = 99, clamped = 99;
  pb_exr_desc d = {.width = W, .height = H, .layers = &layer,
                   .layer_count = 1, .nonfinite_count = &nonfinite,
                   .half_clamped_count = &clamped};
  const char *p = tpath("float.exr");
  CHECK_EQ_INT(pb_exr_write(p, &d), PB_OK);
  CHECK_EQ_INT(nonfinite, 0);
  CHECK_EQ_INT(clamped, 0);
  CHECK_EQ_INT(stray_files("float.exr"), 0); /* the temporary is gone */

  pb_image img;
  CHECK_EQ_INT(pb_exr_read(p, NULL, &img), PB_OK);
  CHECK_EQ_INT(img.width, W);
  CHECK_EQ_INT(img.height, H);
  CHECK_EQ_INT(img.channel_count, 4);
  CHECK_EQ_INT(img.data_x, 0);
  CHECK_EQ_INT(img.data_y, 0);
  if (img.channel_count == 4) {
    /* Sorted order in the file: A, B, G, R. */
    CHECK(!strcmp(img.channel_names[0], "A"));
    CHECK(!strcmp(img.channel_names[1], "B"));
    CHECK(!strcmp(img.channel_names[2], "G"));
    CHECK(!strcmp(img.channel_names[3], "R"));
    const char *names[4] = {"R", "G", "B", "A"};
    int bad = 0;
    for (int c = 0; c < 4; ++c) {
      int k = pb_image_find_channel(&img, names[c]);
      for (int i = 0; i < W * H; ++i)
        bad += img.pixels[(size_t)i * 4 + (size_t)k] != px[i * 4 + c];
    }
    CHECK_EQ_INT(bad, 0); /* float is exact */
  }
  CHECK_EQ_INT(pb_image_find_channel(&img, "Z"), -1);
  pb_image_destroy(&img);
  CHECK(img.pixels == NULL && img.channel_names == NULL);
  pb_image_destroy(NULL);
  free(px);
}

static void test_roundtrip_half(void) {
  enum { W = 19, H = 40 }; /* 40 rows: three ZIP chunks, the last short */
  float *px = malloc(sizeof(float) * W * H * 3);
  for (int i = 0; i < W * H * 3; ++i)
    px[i] = powf(10.0f, (float)(i % 97) / 16.0f - 3.0f) * ((i & 1) ? 1 : -1);
  px[0] = NAN;
  px[1] = INFINITY;
  px[2] = -INFINITY;
  px[3] = 1e6f;
  px[4] = -70000.0f;
  px[5] = 65504.0f; /* the largest half: kept, not counted */
  pb_image_layer layer = {NULL, 3, px, NULL};
  uint64_t nonfinite = 0, clamped = 0;
  pb_exr_desc d = {.width = W, .height = H, .layers = &layer,
                   .layer_count = 1, .pixel_type = PB_EXR_HALF,
                   .nonfinite_count = &nonfinite,
                   .half_clamped_count = &clamped};
  const char *p = tpath("half.exr");
  CHECK_EQ_INT(pb_exr_write(p, &d), PB_OK);
  CHECK_EQ_INT(nonfinite, 3);
  CHECK_EQ_INT(clamped, 2);

  pb_image img;
  CHECK_EQ_INT(pb_exr_read(p, NULL, &img), PB_OK);
  CHECK_EQ_INT(img.channel_count, 3);
  if (img.channel_count == 3) {
    int r = pb_image_find_channel(&img, "R"), g = pb_image_find_channel(&img, "G"),
        b = pb_image_find_channel(&img, "B");
    CHECK(r >= 0 && g >= 0 && b >= 0);
    CHECK_NEAR(img.pixels[r], 0.0f, 0.0);
    CHECK_NEAR(img.pixels[g], 0.0f, 0.0);
    CHECK_NEAR(img.pixels[b], 0.0f, 0.0);
    CHECK_NEAR(img.pixels[3 + r], 65504.0f, 0.0);
    CHECK_NEAR(img.pixels[3 + g], -65504.0f, 0.0);
    CHECK_NEAR(img.pixels[3 + b], 65504.0f, 0.0);
    /* Half keeps 11 significant bits: relative error <= 2^-11 for normal
     * values (>= 2^-14), absolute <= 2^-25 below. */
    int bad = 0;
    const int idx[3] = {r, g, b};
    for (int i = 6; i < W * H * 3; ++i) {
      float want = px[i], got = img.pixels[(size_t)(i / 3) * 3 + (size_t)idx[i % 3]];
      float tol = fmaxf(fabsf(want) * (1.0f / 2048.0f), 1.0f / 33554432.0f);
      if (!(fabsf(got - want) <= tol)) {
        if (bad < 3) fprintf(stderr, "  half: %d: %g vs %g\n", i, got, want);
        ++bad;
      }
    }
    CHECK_EQ_INT(bad, 0);
  }
  pb_image_destroy(&img);
  free(px);
}

/* OpenEXR 3.1.5's ZIP encoder kept a zlib stream exactly as long as the
 * packed chunk, which every reader then takes for raw pixels (exr.c
 * zip_guard): this 2 x 1 RGBA half image came back as (1.3e-4, 4.4e-5, ...).
 * Then small images of smooth and repeated values, half and float, each
 * read back exactly (half: the values are halfs), so that any chunk size
 * that lands on the equality is caught. */
static void test_zip_equal_size(void) {
  const float a[8] = {4.0f, 2.0f, 1.0f, 1.0f, 4.0f, 2.0f, 1.0f, 1.0f};
  pb_image_layer layer = {NULL, 4, a, NULL};
  pb_exr_desc d = {.width = 2, .height = 1, .layers = &layer, .layer_count = 1, .pixel_type = PB_EXR_HALF};
  const char *p = tpath("zip_equal.exr");
  CHECK_EQ_INT(pb_exr_write(p, &d), PB_OK);
  pb_image img;
  CHECK_EQ_INT(pb_exr_read(p, NULL, &img), PB_OK);
  int same = img.channel_count == 4;
  for (uint32_t i = 0; same && i < 2; ++i) {
    same &= img.pixels[i * 4 + (uint32_t)pb_image_find_channel(&img, "R")] == 4.0f;
    same &= img.pixels[i * 4 + (uint32_t)pb_image_find_channel(&img, "G")] == 2.0f;
    same &= img.pixels[i * 4 + (uint32_t)pb_image_find_channel(&img, "A")] == 1.0f;
  }
  CHECK(same);
  pb_image_destroy(&img);
  uint32_t bad = 0, seed = 12345;
  float px[4 * 24 * 3];
  for (int t = 0; t < 400; ++t) {
    uint32_t w = 1 + (uint32_t)t % 24, h = 1 + (uint32_t)(t / 24) % 3;
    for (uint32_t k = 0; k < 4 * w * h; ++k) {
      seed = seed * 1664525u + 1013904223u;
      /* a few distinct values, some runs: partly compressible */
      px[k] = (float)((seed >> 28) % (1u + (uint32_t)t % 7)) * 0.25f;
    }
    for (int half = 0; half < 2; ++half) {
      pb_image_layer l = {NULL, 4, px, NULL};
      pb_exr_desc e = {.width = w, .height = h, .layers = &l, .layer_count = 1,
                       .pixel_type = half ? PB_EXR_HALF : PB_EXR_FLOAT};
      if (pb_exr_write(p, &e) != PB_OK || pb_exr_read(p, NULL, &img) != PB_OK) {
        ++bad;
        continue;
      }
      const char *names[4] = {"R", "G", "B", "A"};
      for (uint32_t k = 0; k < w * h; ++k)
        for (int c = 0; c < 4; ++c)
          if (img.pixels[k * 4 + (uint32_t)pb_image_find_channel(&img, names[c])] != px[k * 4 + (uint32_t)c]) {
            ++bad;
            k = w * h;
            break;
          }
      pb_image_destroy(&img);
    }
  }
  CHECK_EQ_INT(bad, 0);
}

static void test_layers(void) {
  enum { W = 13, H = 17, N = W * H };
  /* Every sample is unique: 1000 * layer + 100 * component + pixel / 4. */
  static const struct { const char *name; uint32_t ch; } L[] = {
      {"", 4}, {"albedo", 3}, {"depth", 1}, {"normal", 3}, {"mask", 1},
      {"custom", 2}, {"a_layer_name_well_past_the_31_byte_short_name_limit", 3}};
  enum { NL = sizeof L / sizeof L[0] };
  static const char *const custom_names[2] = {"foo.a", "foo.b"};
  static const char *const expect[NL][4] = {
      {"R", "G", "B", "A"},
      {"albedo.R", "albedo.G", "albedo.B"},
      {"depth.Z"},
      {"normal.X", "normal.Y", "normal.Z"},
      {"mask.V"},
      {"foo.a", "foo.b"},
      {"a_layer_name_well_past_the_31_byte_short_name_limit.R",
       "a_layer_name_well_past_the_31_byte_short_name_limit.G",
       "a_layer_name_well_past_the_31_byte_short_name_limit.B"}};
  float *px[NL];
  pb_image_layer layers[NL];
  for (int l = 0; l < NL; ++l) {
    px[l] = malloc(sizeof(float) * N * L[l].ch);
    for (int i = 0; i < N; ++i)
      for (uint32_t c = 0; c < L[l].ch; ++c)
        px[l][(size_t)i * L[l].ch + c] =
            1000.0f * (float)l + 100.0f * (float)c + (float)i * 0.25f;
    layers[l] = (pb_image_layer){L[l].name, L[l].ch, px[l],
                                 l == 5 ? custom_names : NULL};
  }
  pb_exr_desc d = {.width = W, .height = H, .layers = layers,
                   .layer_count = NL};
  const char *p = tpath("layers.exr");
  CHECK_EQ_INT(pb_exr_write(p, &d), PB_OK);

  pb_image img;
  CHECK_EQ_INT(pb_exr_read(p, NULL, &img), PB_OK);
  CHECK_EQ_INT(img.channel_count, 4 + 3 + 1 + 3 + 1 + 2 + 3);
  /* Stored in EXR's sorted order. */
  for (uint32_t k = 1; k < img.channel_count; ++k)
    CHECK(strcmp(img.channel_names[k - 1], img.channel_names[k]) < 0);
  for (int l = 0; l < NL; ++l)
    for (uint32_t c = 0; c < L[l].ch; ++c) {
      int k = pb_image_find_channel(&img, expect[l][c]);
      CHECK(k >= 0);
      if (k < 0) {
        fprintf(stderr, "  missing channel %s\n", expect[l][c]);
        continue;
      }
      int bad = 0;
      for (int i = 0; i < N; ++i)
        bad += img.pixels[(size_t)i * img.channel_count + (size_t)k] !=
               px[l][(size_t)i * L[l].ch + c];
      if (bad) fprintf(stderr, "  channel %s: %d wrong\n", expect[l][c], bad);
      CHECK_EQ_INT(bad, 0);
    }
  pb_image_destroy(&img);
  for (int l = 0; l < NL; ++l) free(px[l]);
}

static void test_header_attributes(void) {
  float px[2 * 2 * 3] = {0};
  pb_image_layer layer = {"", 3, px, NULL};
  const char *names[2] = {"photonbridge/renderer",
                          "photonbridge/reference_samples_per_pixel"};
  const char *values[2] = {"reference", "4096"};
  pb_exr_desc d = {.width = 2, .height = 2, .layers = &layer,
                   .layer_count = 1, .attr_names = names,
                   .attr_values = values, .attr_count = 2};
  const char *p = tpath("attrs.exr");
  CHECK_EQ_INT(pb_exr_write(p, &d), PB_OK);

  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  CHECK_EQ_INT(exr_start_read(&ctx, p, &init), EXR_ERR_SUCCESS);
  if (!ctx) return;
  exr_attr_chromaticities_t c;
  CHECK_EQ_INT(exr_attr_get_chromaticities(ctx, 0, "chromaticities", &c),
               EXR_ERR_SUCCESS);
  CHECK_NEAR(c.red_x, 0.64, 1e-6);
  CHECK_NEAR(c.red_y, 0.33, 1e-6);
  CHECK_NEAR(c.green_x, 0.30, 1e-6);
  CHECK_NEAR(c.green_y, 0.60, 1e-6);
  CHECK_NEAR(c.blue_x, 0.15, 1e-6);
  CHECK_NEAR(c.blue_y, 0.06, 1e-6);
  CHECK_NEAR(c.white_x, 0.3127, 1e-6);
  CHECK_NEAR(c.white_y, 0.3290, 1e-6);
  for (int i = 0; i < 2; ++i) {
    int32_t len = 0;
    const char *s = NULL;
    CHECK_EQ_INT(exr_attr_get_string(ctx, 0, names[i], &len, &s),
                 EXR_ERR_SUCCESS);
    CHECK(s && len == (int32_t)strlen(values[i]) &&
          !memcmp(s, values[i], (size_t)len));
  }
  exr_compression_t comp;
  CHECK_EQ_INT(exr_get_compression(ctx, 0, &comp), EXR_ERR_SUCCESS);
  CHECK_EQ_INT(comp, EXR_COMPRESSION_ZIP);
  exr_storage_t st;
  CHECK_EQ_INT(exr_get_storage(ctx, 0, &st), EXR_ERR_SUCCESS);
  CHECK_EQ_INT(st, EXR_STORAGE_SCANLINE);
  const exr_attr_chlist_t *cl = NULL;
  CHECK_EQ_INT(exr_get_channels(ctx, 0, &cl), EXR_ERR_SUCCESS);
  CHECK(cl && cl->num_channels == 3 && cl->entries[0].pixel_type == EXR_PIXEL_FLOAT);
  exr_finish(&ctx);

  /* An attribute name the format reserves for another type is refused. */
  const char *bad_names[1] = {"dataWindow"};
  const char *bad_values[1] = {"x"};
  d.attr_names = bad_names;
  d.attr_values = bad_values;
  d.attr_count = 1;
  const char *q = tpath("badattr.exr");
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  CHECK(!file_exists(q));
}

/* ---- write failures ----------------------------------------------------- */

static void test_write_errors(void) {
  float px[4 * 4 * 4] = {0};
  pb_image_layer layer = {"", 3, px, NULL};
  pb_exr_desc d = {.width = 4, .height = 4, .layers = &layer,
                   .layer_count = 1};
  int before = stray_files(NULL);

  const char *p = "/nonexistent/dir/x.exr";
  CHECK(error_is(pb_exr_write(p, &d), PB_ERR_IO, p));
  CHECK(!file_exists(p));
  CHECK(error_is(pb_png_write_srgb(p, 4, 4, 3, px, 0.0f), PB_ERR_IO, p));

  /* The temporary can be made but the rename fails (the target is a
   * non-empty directory): no temporary is left behind. */
  const char *dir = tpath("occupied");
  mkdir(dir, 0700);
  char inner[300];
  snprintf(inner, sizeof inner, "%s/keep", dir);
  spill(inner, (const uint8_t *)"x", 1);
  CHECK(error_is(pb_exr_write(dir, &d), PB_ERR_IO, dir));
  CHECK(error_is(pb_png_write_srgb(dir, 4, 4, 3, px, 0.0f), PB_ERR_IO, dir));
  CHECK_EQ_INT(stray_files(NULL), before + 1);

  const char *q = tpath("bad.exr");
  d.width = 0;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  d.width = 40000;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_LIMIT, q));
  d.width = 4;
  layer.channels = 2; /* no default names for 2 channels */
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  layer.channels = 3;
  pb_image_layer twice[2] = {{"a", 3, px, NULL}, {"a", 1, px, NULL}};
  const char *const dup_names[1] = {"a.R"};
  twice[1].channel_names = dup_names;
  d.layers = twice;
  d.layer_count = 2;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  char longname[80];
  memset(longname, 'x', 70);
  longname[70] = 0;
  twice[1].name = longname;
  twice[1].channel_names = NULL;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_LIMIT, q));
  d.layers = &layer;
  d.layer_count = 1;
  d.pixel_type = (pb_exr_pixel)7;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  d.pixel_type = PB_EXR_FLOAT;
  CHECK(!file_exists(q));
  CHECK_EQ_INT(stray_files(NULL), before + 1);

  /* A failed write leaves an existing file as it was. */
  CHECK_EQ_INT(pb_exr_write(q, &d), PB_OK);
  size_t n0 = 0, n1 = 0;
  uint8_t *b0 = slurp(q, &n0);
  d.height = 0;
  CHECK(error_is(pb_exr_write(q, &d), PB_ERR_IMAGE, q));
  uint8_t *b1 = slurp(q, &n1);
  CHECK(b0 && b1 && n0 == n1 && !memcmp(b0, b1, n0));
  free(b0);
  free(b1);
  unlink(q);
}

/* ---- read failures ------------------------------------------------------ */

static int write_small(const char *p) {
  enum { W = 21, H = 35 };
  static float px[W * H * 4];
  for (int i = 0; i < W * H * 4; ++i) px[i] = (float)(i % 13) * 0.1f;
  pb_image_layer layers[2] = {{"", 4, px, NULL}, {"depth", 1, px, NULL}};
  pb_exr_desc d = {.width = W, .height = H, .layers = layers,
                   .layer_count = 2};
  return pb_exr_write(p, &d) == PB_OK;
}

static void test_read_errors(void) {
  pb_image img;
  const char *missing = tpath("missing.exr");
  CHECK(error_is(pb_exr_read(missing, NULL, &img), PB_ERR_IO, missing));
  CHECK(img.pixels == NULL && img.width == 0);
  CHECK(error_is(pb_exr_read(tmpdir, NULL, &img), PB_ERR_IO, tmpdir));

  const char *empty = tpath("empty.exr");
  spill(empty, (const uint8_t *)"", 0);
  CHECK(error_is(pb_exr_read(empty, NULL, &img), PB_ERR_IMAGE, empty));
  const char *text = tpath("text.exr");
  const char *junk = "this is not an EXR file, just some text\n";
  spill(text, (const uint8_t *)junk, strlen(junk));
  CHECK(error_is(pb_exr_read(text, NULL, &img), PB_ERR_IMAGE, text));

  const char *good = tpath("good.exr");
  CHECK(write_small(good));
  pb_exr_read_limits lim = {.max_dim = 30};
  CHECK(error_is(pb_exr_read(good, &lim, &img), PB_ERR_LIMIT, good));
  lim = (pb_exr_read_limits){.max_pixels = 21 * 35 - 1};
  CHECK(error_is(pb_exr_read(good, &lim, &img), PB_ERR_LIMIT, good));
  lim = (pb_exr_read_limits){.max_channels = 4};
  CHECK(error_is(pb_exr_read(good, &lim, &img), PB_ERR_LIMIT, good));
  lim = (pb_exr_read_limits){.max_dim = 35, .max_pixels = 21 * 35,
                             .max_channels = 5};
  CHECK_EQ_INT(pb_exr_read(good, &lim, &img), PB_OK);
  pb_image_destroy(&img);

  size_t n = 0;
  uint8_t *bytes = slurp(good, &n);
  CHECK(bytes && n > 100);
  if (!bytes) return;
  const char *bad = tpath("bad.exr");

  /* Truncated anywhere (header, offset table, chunk data, last byte): a
   * malformed file, never a crash and never a partial image. */
  int trunc_tested = 0, trunc_ok = 0;
  for (size_t len = 0; len < n; len += (len < 400 ? 1 : 37)) {
    spill(bad, bytes, len);
    trunc_ok += error_is(pb_exr_read(bad, NULL, &img), PB_ERR_IMAGE, bad);
    ++trunc_tested;
  }
  spill(bad, bytes, n - 1);
  trunc_ok += error_is(pb_exr_read(bad, NULL, &img), PB_ERR_IMAGE, bad);
  ++trunc_tested;
  CHECK_EQ_INT(trunc_ok, trunc_tested);

  /* Each of the first bytes (header and offset table) set to several values:
   * a clean result or an image/limit error, whatever the byte. */
  static const int vals[] = {0x00, 0xff, 0x7f, 0x80, -1 /* flip bit 0 */};
  size_t span = n < 700 ? n : 700;
  int corrupt_tested = 0, corrupt_ok = 0, corrupt_rejected = 0;
  for (size_t i = 0; i < span; ++i)
    for (size_t v = 0; v < sizeof vals / sizeof vals[0]; ++v) {
      uint8_t saved = bytes[i];
      bytes[i] = vals[v] < 0 ? (uint8_t)(saved ^ 1) : (uint8_t)vals[v];
      if (bytes[i] == saved) continue;
      spill(bad, bytes, n);
      bytes[i] = saved;
      pb_result r = pb_exr_read(bad, NULL, &img);
      int fine = r == PB_OK || r == PB_ERR_IMAGE || r == PB_ERR_LIMIT;
      if (r != PB_OK) {
        const char *m = pb_error_message();
        fine = fine && !strncmp(m, bad, strlen(bad)) && !strchr(m, '\n');
        ++corrupt_rejected;
      } else {
        fine = fine && img.pixels && img.width > 0 && img.channel_count > 0;
      }
      if (!fine)
        fprintf(stderr, "  corrupt byte %zu: %s \"%s\"\n", i,
                pb_result_name(r), pb_error_message());
      pb_image_destroy(&img);
      pb_error_clear();
      corrupt_ok += fine;
      ++corrupt_tested;
    }
  CHECK_EQ_INT(corrupt_ok, corrupt_tested);
  CHECK(corrupt_rejected > corrupt_tested / 4);

  /* Specific damage that must be refused. */
  uint8_t *copy = malloc(n);
  memcpy(copy, bytes, n);
  copy[0] = 0x77; /* magic number */
  spill(bad, copy, n);
  CHECK(error_is(pb_exr_read(bad, NULL, &img), PB_ERR_IMAGE, bad));
  memcpy(copy, bytes, n);
  copy[4] = 9; /* file format version */
  spill(bad, copy, n);
  CHECK(error_is(pb_exr_read(bad, NULL, &img), PB_ERR_IMAGE, bad));
  /* Zeroed chunk data (past the header and offset table): ZIP cannot
   * inflate it. */
  memcpy(copy, bytes, n);
  memset(copy + n - 64, 0, 64);
  spill(bad, copy, n);
  CHECK(error_is(pb_exr_read(bad, NULL, &img), PB_ERR_IMAGE, bad));
  free(copy);
  free(bytes);
  unlink(bad);
}

/* ---- files made with the raw library: tiles, windows, uint -------------- */

/* Channels "R" (half), "Z" (float), "id" (uint) over data window `dw`, with
 * R = ((3x + y) mod 97) / 2, Z = x - y / 4, id = 1000 x + y in absolute
 * pixel coordinates; tiled with 16x16 tiles when `tiled`. */
static float raw_r(int x, int y) { return (float)(((3 * x + y) % 97 + 97) % 97) * 0.5f; }
static float raw_z(int x, int y) { return (float)x - (float)y * 0.25f; }
static uint32_t raw_id(int x, int y) { return (uint32_t)(1000 * x + y); }

static exr_attr_box2i_t box(int x0, int y0, int x1, int y1) {
  exr_attr_box2i_t b;
  b.min.x = x0;
  b.min.y = y0;
  b.max.x = x1;
  b.max.y = y1;
  return b;
}

static int write_raw(const char *p, exr_attr_box2i_t dw, int tiled,
                     exr_compression_t comp) {
  exr_context_t ctx = NULL;
  exr_context_initializer_t init = EXR_DEFAULT_CONTEXT_INITIALIZER;
  if (exr_start_write(&ctx, p, EXR_WRITE_FILE_DIRECTLY, &init)) return 0;
  int part = 0, ok = 0;
  exr_attr_v2f_t center;
  center.x = center.y = 0.0f;
  exr_attr_box2i_t disp = box(0, 0, 63, 63);
  if (exr_add_part(ctx, NULL, tiled ? EXR_STORAGE_TILED : EXR_STORAGE_SCANLINE,
                   &part) ||
      exr_initialize_required_attr(ctx, part, &disp, &dw, 1.0f, &center, 1.0f,
                                   EXR_LINEORDER_INCREASING_Y, comp))
    goto out;
  if (tiled && exr_set_tile_descriptor(ctx, part, 16, 16, EXR_TILE_ONE_LEVEL,
                                       EXR_TILE_ROUND_DOWN))
    goto out;
  if (exr_add_channel(ctx, part, "R", EXR_PIXEL_HALF, EXR_PERCEPTUALLY_LOGARITHMIC, 1, 1) ||
      exr_add_channel(ctx, part, "Z", EXR_PIXEL_FLOAT, EXR_PERCEPTUALLY_LINEAR, 1, 1) ||
      exr_add_channel(ctx, part, "id", EXR_PIXEL_UINT, EXR_PERCEPTUALLY_LINEAR, 1, 1) ||
      exr_write_header(ctx))
    goto out;
  int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  float *rbuf = malloc(sizeof(float) * (size_t)(w * h));
  float *zbuf = malloc(sizeof(float) * (size_t)(w * h));
  uint32_t *ibuf = malloc(sizeof(uint32_t) * (size_t)(w * h));
  exr_encode_pipeline_t enc = EXR_ENCODE_PIPELINE_INITIALIZER;
  int live = 0, failed = 0;
  int32_t lines = 1;
  if (!tiled) exr_get_scanlines_per_chunk(ctx, part, &lines);
  int ntx = tiled ? (w + 15) / 16 : 1, nty = tiled ? (h + 15) / 16 : (h + lines - 1) / lines;
  for (int ty = 0; ty < nty && !failed; ++ty)
    for (int tx = 0; tx < ntx && !failed; ++tx) {
      exr_chunk_info_t ci;
      int x0 = tiled ? tx * 16 : 0, y0 = tiled ? ty * 16 : ty * lines;
      if (tiled ? exr_write_tile_chunk_info(ctx, part, tx, ty, 0, 0, &ci)
                : exr_write_scanline_chunk_info(ctx, part, dw.min.y + y0, &ci)) {
        failed = 1;
        break;
      }
      for (int yy = 0; yy < ci.height; ++yy)
        for (int xx = 0; xx < ci.width; ++xx) {
          int ax = dw.min.x + x0 + xx, ay = dw.min.y + y0 + yy;
          size_t i = (size_t)(yy * ci.width + xx);
          rbuf[i] = raw_r(ax, ay);
          zbuf[i] = raw_z(ax, ay);
          ibuf[i] = raw_id(ax, ay);
        }
      if (live ? exr_encoding_update(ctx, part, &ci, &enc)
               : exr_encoding_initialize(ctx, part, &ci, &enc)) {
        failed = 1;
        break;
      }
      live = 1;
      for (int c = 0; c < enc.channel_count; ++c) {
        exr_coding_channel_info_t *ch = &enc.channels[c];
        const char *nm = ch->channel_name;
        ch->encode_from_ptr = !strcmp(nm, "R")   ? (const uint8_t *)rbuf
                              : !strcmp(nm, "Z") ? (const uint8_t *)zbuf
                                                 : (const uint8_t *)ibuf;
        ch->user_pixel_stride = 4;
        ch->user_line_stride = 4 * ci.width;
        ch->user_bytes_per_element = 4;
        ch->user_data_type = !strcmp(nm, "id") ? EXR_PIXEL_UINT : EXR_PIXEL_FLOAT;
      }
      if (exr_encoding_choose_default_routines(ctx, part, &enc) ||
          exr_encoding_run(ctx, part, &enc))
        failed = 1;
    }
  if (live) exr_encoding_destroy(ctx, &enc);
  free(rbuf);
  free(zbuf);
  free(ibuf);
  ok = !failed;
out:
  if (exr_finish(&ctx)) ok = 0;
  return ok;
}

static void check_raw(const char *p, exr_attr_box2i_t dw) {
  pb_image img;
  CHECK_EQ_INT(pb_exr_read(p, NULL, &img), PB_OK);
  int w = dw.max.x - dw.min.x + 1, h = dw.max.y - dw.min.y + 1;
  CHECK_EQ_INT(img.width, w);
  CHECK_EQ_INT(img.height, h);
  CHECK_EQ_INT(img.data_x, dw.min.x);
  CHECK_EQ_INT(img.data_y, dw.min.y);
  CHECK_EQ_INT(img.channel_count, 3);
  int r = pb_image_find_channel(&img, "R"), z = pb_image_find_channel(&img, "Z"),
      id = pb_image_find_channel(&img, "id");
  CHECK(r >= 0 && z >= 0 && id >= 0);
  if (img.pixels && r >= 0 && z >= 0 && id >= 0) {
    int bad = 0;
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) {
        const float *q = img.pixels + ((size_t)y * (size_t)w + (size_t)x) * 3;
        int ax = dw.min.x + x, ay = dw.min.y + y;
        bad += q[r] != raw_r(ax, ay) || q[z] != raw_z(ax, ay) ||
               q[id] != (float)raw_id(ax, ay);
      }
    if (bad) fprintf(stderr, "  %s: %d wrong pixels\n", p, bad);
    CHECK_EQ_INT(bad, 0);
  }
  pb_image_destroy(&img);
}

static void test_raw_files(void) {
  exr_attr_box2i_t dw1 = box(10, 20, 49, 49); /* 40x30: partial tiles */
  const char *t = tpath("tiled.exr");
  CHECK(write_raw(t, dw1, 1, EXR_COMPRESSION_ZIP));
  check_raw(t, dw1);
  exr_attr_box2i_t dw2 = box(-5, 7, 17, 27); /* negative origin */
  const char *s = tpath("window.exr");
  CHECK(write_raw(s, dw2, 0, EXR_COMPRESSION_NONE));
  check_raw(s, dw2);
  const char *s2 = tpath("rle.exr");
  CHECK(write_raw(s2, dw2, 0, EXR_COMPRESSION_RLE));
  check_raw(s2, dw2);
  const char *s3 = tpath("piz.exr");
  CHECK(write_raw(s3, dw1, 1, EXR_COMPRESSION_PIZ));
  check_raw(s3, dw1);
}

/* ---- PNG ---------------------------------------------------------------- */

static void test_png(void) {
  /* Linear 0, 0.18, 1, 2 (grey) and NaN, -1: sRGB 0, 118, 255, 255, 0, 0. */
  const float lin[6] = {0.0f, 0.18f, 1.0f, 2.0f, NAN, -1.0f};
  const int want[6] = {0, 118, 255, 255, 0, 0};
  float rgb[6 * 3], rgba[6 * 4];
  for (int i = 0; i < 6; ++i) {
    for (int c = 0; c < 3; ++c) rgb[i * 3 + c] = rgba[i * 4 + c] = lin[i];
    rgba[i * 4 + 3] = (float)i * 0.25f - 0.25f; /* -0.25 .. 1.0 */
  }
  const char *p = tpath("prev.png");
  CHECK_EQ_INT(pb_png_write_srgb(p, 3, 2, 3, rgb, 0.0f), PB_OK);
  int w = 0, h = 0, n = 0;
  unsigned char *dec = stbi_load(p, &w, &h, &n, 0);
  CHECK(dec != NULL);
  CHECK_EQ_INT(w, 3);
  CHECK_EQ_INT(h, 2);
  CHECK_EQ_INT(n, 3);
  if (dec && n == 3 && w * h == 6)
    for (int i = 0; i < 6; ++i)
      for (int c = 0; c < 3; ++c) CHECK_EQ_INT(dec[i * 3 + c], want[i]);
  stbi_image_free(dec);

  /* Exposure +1 doubles: 0.09 -> 0.18 -> 118. Alpha is linear, no exposure. */
  float half[6 * 4];
  for (int i = 0; i < 6 * 4; ++i) half[i] = (i % 4 == 3) ? rgba[i] : rgba[i] * 0.5f;
  const char *q = tpath("prev4.png");
  CHECK_EQ_INT(pb_png_write_srgb(q, 6, 1, 4, half, 1.0f), PB_OK);
  dec = stbi_load(q, &w, &h, &n, 0);
  CHECK(dec && w == 6 && h == 1 && n == 4);
  if (dec && n == 4 && w == 6) {
    for (int i = 0; i < 6; ++i) CHECK_EQ_INT(dec[i * 4 + 1], want[i]);
    const int alpha[6] = {0, 0, 64, 128, 191, 255};
    for (int i = 0; i < 6; ++i) CHECK_EQ_INT(dec[i * 4 + 3], alpha[i]);
  }
  stbi_image_free(dec);

  const char *r = tpath("never.png");
  CHECK(error_is(pb_png_write_srgb(r, 0, 2, 3, rgb, 0.0f), PB_ERR_IMAGE, r));
  CHECK(error_is(pb_png_write_srgb(r, 3, 2, 2, rgb, 0.0f), PB_ERR_IMAGE, r));
  CHECK(error_is(pb_png_write_srgb(r, 3, 2, 3, rgb, NAN), PB_ERR_USAGE, r));
  CHECK(error_is(pb_png_write_srgb(r, 40000, 2, 3, rgb, 0.0f), PB_ERR_LIMIT, r));
  CHECK(!file_exists(r));
}

int main(void) {
  snprintf(tmpdir, sizeof tmpdir, "/tmp/pb_test_image.XXXXXX");
  if (!mkdtemp(tmpdir)) {
    perror("mkdtemp");
    return 1;
  }
  test_roundtrip_float();
  test_roundtrip_half();
  test_zip_equal_size();
  test_layers();
  test_header_attributes();
  test_write_errors();
  test_read_errors();
  test_raw_files();
  test_png();
  clean_dir(tmpdir);
  rmdir(tmpdir);
  return pbt_done();
}
