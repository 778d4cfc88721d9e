/* Textures of more than 8 bits a channel (image/decode.h
 * pb_decode_image_float, scene.h pb_texture.rgbah): half conversions, the
 * three float decoders on files made here (a 16-bit PNG through libspng's
 * encoder, EXRs through pb_exr_write, a flat Radiance file), the loader's
 * float textures (a 16-bit PNG in an sRGB slot keeps 16 bits; an EXR named
 * by textures[i].extensions.PHOTONBRIDGE_blender.source replaces the 8-bit
 * fallback and keeps values over 1) and its one-line errors. */
#include <spng.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/srgb.h"
#include "pbtest.h"
#include "gltf_test.h"

#include "core/fs.h"
#include "core/half.h"
#include "core/log.h"
#include "core/result.h"
#include "image/decode.h"
#include "image/image.h"
#include "scene/scene.h"

static const pb_decode_limits LIM = {.max_dim = 4096, .max_pixels = 1u << 24};

static void test_half(void) {
  CHECK_EQ_INT(pb_float_to_half(1.0f), 0x3c00);
  CHECK_EQ_INT(pb_float_to_half(-2.0f), 0xc000);
  CHECK_EQ_INT(pb_float_to_half(65504.0f), 0x7bff);
  CHECK_EQ_INT(pb_float_to_half(65520.0f), 0x7c00); /* rounds up to infinity */
  CHECK_EQ_INT(pb_float_to_half(0.1f), 0x2e66);
  CHECK_EQ_INT(pb_float_to_half(5.9604645e-8f), 0x0001); /* 2^-24, the smallest subnormal */
  CHECK_EQ_INT(pb_float_to_half(2.9802322e-8f), 0x0000); /* half of it: to even (0) */
  CHECK_EQ_INT(pb_float_to_half(6.1035156e-5f), 0x0400); /* the smallest normal */
  CHECK_EQ_INT(pb_float_to_half(1.0f + 1.0f / 2048.0f), 0x3c00); /* halfway: to even */
  CHECK_EQ_INT(pb_float_to_half(1.0f + 3.0f / 2048.0f), 0x3c02);
  /* Every half survives half -> float -> half. */
  int bad = 0;
  for (uint32_t h = 0; h < 0x10000u; ++h) {
    if ((h & 0x7c00u) == 0x7c00u && (h & 0x3ffu)) continue; /* NaN payloads */
    if (pb_float_to_half(pb_half_to_float((uint16_t)h)) != h) ++bad;
  }
  CHECK_EQ_INT(bad, 0);
  CHECK_NEAR(pb_half_to_float(0x3555), 0.33325195, 1e-8);
}

/* A 3x1 16-bit RGBA PNG through libspng's encoder (libspng 0.7.3 takes
 * SPNG_FMT_PNG's 16-bit samples in host byte order: measured, a PNG written
 * by Python's zlib decodes to the same values). */
static uint8_t *png16(size_t *n, const uint16_t v[12]) {
  spng_ctx *ctx = spng_ctx_new(SPNG_CTX_ENCODER);
  struct spng_ihdr ih = {.width = 3, .height = 1, .bit_depth = 16, .color_type = SPNG_COLOR_TYPE_TRUECOLOR_ALPHA};
  uint16_t raw[12];
  memcpy(raw, v, sizeof raw);
  int e = spng_set_option(ctx, SPNG_ENCODE_TO_BUFFER, 1);
  if (!e) e = spng_set_ihdr(ctx, &ih);
  if (!e) e = spng_encode_image(ctx, raw, sizeof raw, SPNG_FMT_PNG, SPNG_ENCODE_FINALIZE);
  uint8_t *out = NULL;
  if (!e) out = spng_get_png_buffer(ctx, n, &e);
  spng_ctx_free(ctx);
  return e ? NULL : out;
}

static uint8_t *slurp(const char *path, size_t *n) {
  uint8_t *b = NULL;
  if (pb_read_file(path, 1u << 26, &b, n) != PB_OK) return NULL;
  return b;
}

/* An RGBA EXR of w x 1 pixels. */
static int exr_file(const char *path, const float *px, uint32_t w, pb_exr_pixel type) {
  pb_image_layer l = {.name = "", .channels = 4, .pixels = px};
  pb_exr_desc d = {.width = w, .height = 1, .layers = &l, .layer_count = 1, .pixel_type = type};
  return pb_exr_write(path, &d) == PB_OK;
}

static void test_decoders(const char *dir) {
  const uint16_t v[12] = {0, 1000, 65535, 65535, 32768, 1, 2, 3, 40000, 50000, 60000, 7};
  size_t n = 0;
  uint8_t *png = png16(&n, v);
  CHECK(png != NULL);
  CHECK(pb_decode_is_float_image(png, n));
  pb_decoded_float df;
  CHECK_EQ_INT(pb_decode_image_float(png, n, &LIM, &df), PB_DECODE_OK);
  CHECK_EQ_INT(df.width, 3);
  CHECK_EQ_INT(df.linear, 0);
  int exact = df.rgba != NULL;
  for (int k = 0; k < 12 && df.rgba; ++k) exact &= df.rgba[k] == (float)v[k] * (1.0f / 65535.0f);
  CHECK(exact); /* host byte order, every sample */
  free(df.rgba);
  pb_decoded_float small;
  const pb_decode_limits tiny = {.max_dim = 2, .max_pixels = 4};
  CHECK_EQ_INT(pb_decode_image_float(png, n, &tiny, &small), PB_DECODE_TOO_LARGE);
  CHECK_EQ_INT(small.width, 3);
  CHECK(small.rgba == NULL);
  free(png);

  const float px[8] = {4.0f, 2.0f, 1.0f, 0.5f, 0.25f, 1e-3f, 300.0f, 1.0f};
  char path[512];
  for (int type = 0; type < 2; ++type) {
    snprintf(path, sizeof path, "%s/f%d.exr", dir, type);
    CHECK(exr_file(path, px, 2, (pb_exr_pixel)type));
    uint8_t *b = slurp(path, &n);
    CHECK(b && pb_decode_is_float_image(b, n));
    CHECK_EQ_INT(pb_decode_image_float(b, n, &LIM, &df), PB_DECODE_OK);
    CHECK_EQ_INT(df.linear, 1);
    for (int k = 0; k < 8 && df.rgba; ++k) CHECK_NEAR(df.rgba[k], px[k], type ? px[k] * 1e-3 : 0);
    free(df.rgba);
    /* Every truncation fails with a reason, never a crash. */
    int ok = 1;
    for (size_t cut = 0; b && cut < n; cut += 7) {
      pb_decoded_float t;
      pb_decode_status st = pb_decode_image_float(b, cut, &LIM, &t);
      if (st == PB_DECODE_OK) free(t.rgba);
      else if (st != PB_DECODE_UNKNOWN && !t.why[0]) ok = 0;
    }
    CHECK(ok);
    free(b);
  }
  /* Radiance, flat: (128, 64, 32, e 129) is (1, 0.5, 0.25) x (m + 0.5) / 256 x 2^(129 - 128) / ... */
  const char hdr_head[] = "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 1 +X 2\n";
  uint8_t hdr[sizeof hdr_head - 1 + 8];
  memcpy(hdr, hdr_head, sizeof hdr_head - 1);
  const uint8_t pix[8] = {128, 64, 32, 129, 255, 0, 0, 136};
  memcpy(hdr + sizeof hdr_head - 1, pix, 8);
  CHECK(pb_decode_is_float_image(hdr, sizeof hdr));
  CHECK_EQ_INT(pb_decode_image_float(hdr, sizeof hdr, &LIM, &df), PB_DECODE_OK);
  if (df.rgba) {
    CHECK_NEAR(df.rgba[0], 128.5 / 256 * 2, 1e-6);
    CHECK_NEAR(df.rgba[1], 64.5 / 256 * 2, 1e-6);
    CHECK_NEAR(df.rgba[3], 1.0, 0);
    CHECK_NEAR(df.rgba[4], 255.5, 1e-3);
  }
  free(df.rgba);
  /* 8-bit PNGs and JPEGs are not the float decoder's. */
  const uint8_t png8[29] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R',
                            0, 0, 0, 1, 0, 0, 0, 1, 8, 6, 0, 0, 0};
  CHECK(!pb_decode_is_float_image(png8, sizeof png8));
  CHECK_EQ_INT(pb_decode_image_float(png8, sizeof png8, &LIM, &df), PB_DECODE_UNKNOWN);
}

/* A unit quad whose base colour reads `textures` (JSON) over `images`. */
static int write_scene(const char *path, const char *textures, const char *images) {
  static const float pos[] = {-1, -1, 0, 1, -1, 0, 1, 1, 0, -1, 1, 0};
  static const float uv[] = {0, 1, 1, 1, 1, 0, 0, 0};
  static const uint16_t idx[] = {0, 1, 2, 0, 2, 3};
  uint8_t bin[48 + 32 + 12];
  memcpy(bin, pos, 48), memcpy(bin + 48, uv, 32), memcpy(bin + 80, idx, 12);
  char *b64 = pbt_b64(bin, sizeof bin);
  FILE *f = fopen(path, "w");
  if (!f || !b64) {
    free(b64);
    if (f) fclose(f);
    return 0;
  }
  fprintf(f,
          "{\"asset\":{\"version\":\"2.0\"},\"extensionsUsed\":[\"PHOTONBRIDGE_blender\"],\"scene\":0,"
          "\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,"
          "\"material\":0}]}],\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
          "\"textures\":[%s],\"images\":[%s],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
          "\"min\":[-1,-1,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":4,"
          "\"type\":\"VEC2\"},{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,\"byteLength\":32},"
          "{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12}],"
          "\"buffers\":[{\"byteLength\":92,\"uri\":\"data:application/octet-stream;base64,%s\"}]}",
          textures, images, b64);
  free(b64);
  return fclose(f) == 0;
}

static int one_line(const char *m) { return m && m[0] && !strchr(m, '\n'); }

static void test_loader(const char *dir) {
  char path[512], file[512];
  /* A 16-bit PNG in the sRGB base colour slot: 1000 / 65535 keeps its 16
   * bits (its high byte alone, 3 / 255, would be 23 % low). */
  const uint16_t v[12] = {1000, 1000, 1000, 65535, 1000, 1000, 1000, 65535, 1000, 1000, 1000, 65535};
  size_t n = 0;
  uint8_t *png = png16(&n, v);
  snprintf(file, sizeof file, "%s/p16.png", dir);
  FILE *f = fopen(file, "wb");
  CHECK(png && f && fwrite(png, 1, n, f) == n);
  if (f) fclose(f);
  free(png);
  snprintf(path, sizeof path, "%s/p16.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0}", "{\"uri\":\"p16.png\"}"));
  pb_scene s;
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_OK);
  if (s.texture_count == 1) {
    CHECK(s.textures[0].rgbah != NULL && s.textures[0].rgba8 == NULL);
    float c[4];
    pb_texture_sample(&s.textures[0], 0.5f, 0.5f, c);
    float want = pb_srgb_to_linear(1000.0f / 65535.0f);
    CHECK_NEAR(c[0], want, want * 1e-3);
    CHECK_NEAR(c[3], 1.0, 0);
    pb_scene_destroy(&s);
  }

  /* The float image through the extension: the 8-bit source is a fallback. */
  const float px[8] = {4.0f, 2.0f, 1.0f, 1.0f, 4.0f, 2.0f, 1.0f, 1.0f};
  snprintf(file, sizeof file, "%s/e.exr", dir);
  CHECK(exr_file(file, px, 2, PB_EXR_HALF));
  snprintf(file, sizeof file, "%s/fallback.png", dir);
  png = png16(&n, v); /* any PNG: it must not be read */
  f = fopen(file, "wb");
  CHECK(png && f && fwrite(png, 1, n, f) == n);
  if (f) fclose(f);
  free(png);
  snprintf(path, sizeof path, "%s/ext.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0,\"extensions\":{\"PHOTONBRIDGE_blender\":{\"source\":1}}}",
                    "{\"uri\":\"fallback.png\"},{\"uri\":\"e.exr\"}"));
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_OK);
  if (s.texture_count == 1) {
    float c[4];
    pb_texture_sample(&s.textures[0], 0.5f, 0.5f, c);
    CHECK_NEAR(c[0], 4.0, 0); /* linear: no sRGB decode although the slot is sRGB */
    CHECK_NEAR(c[1], 2.0, 0);
    CHECK_NEAR(c[2], 1.0, 0);
    pb_scene_destroy(&s);
  }
  /* An EXR straight in images[] is read too (by its signature). */
  snprintf(path, sizeof path, "%s/direct.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0}", "{\"uri\":\"e.exr\"}"));
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_OK);
  if (s.texture_count == 1) pb_scene_destroy(&s);

  /* Out-of-range values: NaN and negative to 0, over 65504 to 65504, a warning. */
  const float odd[8] = {NAN, -1.0f, 1e6f, 1.0f, 0.5f, 0.5f, 0.5f, 1.0f};
  snprintf(file, sizeof file, "%s/odd.exr", dir);
  CHECK(exr_file(file, odd, 2, PB_EXR_FLOAT));
  snprintf(path, sizeof path, "%s/odd.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0}", "{\"uri\":\"odd.exr\"}"));
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_OK);
  if (s.texture_count == 1) {
    CHECK_EQ_INT(s.textures[0].rgbah[0], 0);
    CHECK_EQ_INT(s.textures[0].rgbah[1], 0);
    CHECK_EQ_INT(s.textures[0].rgbah[2], 0x7bff);
    pb_scene_destroy(&s);
  }

  /* Errors: one line naming the file and the element. */
  snprintf(path, sizeof path, "%s/badext.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0,\"extensions\":{\"PHOTONBRIDGE_blender\":{\"source\":5}}}",
                    "{\"uri\":\"fallback.png\"}"));
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_ERR_SCENE_INVALID);
  CHECK(strstr(pb_error_message(), "textures[0].extensions.PHOTONBRIDGE_blender.source") != NULL);
  CHECK(strstr(pb_error_message(), path) != NULL && one_line(pb_error_message()));
  pb_error_clear();
  CHECK(write_scene(path, "{\"source\":0,\"extensions\":{\"PHOTONBRIDGE_blender\":{\"source\":\"e.exr\"}}}",
                    "{\"uri\":\"fallback.png\"}"));
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_ERR_SCENE_INVALID);
  pb_error_clear();
  size_t en = 0;
  uint8_t *e = slurp(file, &en);
  snprintf(file, sizeof file, "%s/cut.exr", dir);
  f = fopen(file, "wb");
  CHECK(e && f && fwrite(e, 1, en / 2, f) == en / 2);
  if (f) fclose(f);
  free(e);
  snprintf(path, sizeof path, "%s/cut.gltf", dir);
  CHECK(write_scene(path, "{\"source\":0}", "{\"uri\":\"cut.exr\"}"));
  pb_result r = pb_scene_load(path, NULL, &s);
  CHECK_EQ_INT(r, PB_ERR_IMAGE);
  CHECK(strstr(pb_error_message(), "images[0]") != NULL && one_line(pb_error_message()));
  pb_error_clear();
}

int main(void) {
  pb_log_set_level(PB_LOG_QUIET);
  char dir[] = "/tmp/pb_float_texture_XXXXXX";
  if (!mkdtemp(dir)) return 2;
  test_half();
  test_decoders(dir);
  test_loader(dir);
  char cmd[600];
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return pbt_done();
}
