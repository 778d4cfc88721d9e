/* Texture decoding (src/image/decode.h) and images in glTF data URIs.
 *
 *   test_image_decode [SEED_DIR]   (default: $PB_IMAGE_SEEDS)
 *
 * SEED_DIR holds tests/fuzz/make_image_seeds.py's textures (ctest makes them
 * first): every one must decode to the same pixels as stb_image gives (PNG
 * exactly; JPEG within the rounding of two IDCTs), and every truncation of it
 * must either decode or fail with a one-line reason. Then the contract on
 * crafted input: limits from the header alone, CRC and scan-count errors,
 * the fuzzing finding's file, and data-URI images equal to the same image
 * from a file. */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "pbtest.h"
#include "gltf_test.h"

#include "core/fs.h"
#include "core/log.h"
#include "core/result.h"
#include "image/decode.h"
#include "scene/scene.h"

/* stb_image as the reference decoder of valid files (its 2022 snapshot; the
 * files here are written by us, Pillow and Blender). */
#define STBI_ONLY_PNG
#define STBI_ONLY_JPEG
#define STBI_NO_STDIO
#define STB_IMAGE_STATIC
#define STB_IMAGE_IMPLEMENTATION
#pragma GCC diagnostic ignored "-Wunused-function"
#pragma GCC diagnostic ignored "-Wunused-but-set-variable"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wstrict-prototypes"
#include <stb/stb_image.h>

static const pb_decode_limits big = {.max_dim = 16384, .max_pixels = 64ull << 20};

static int ends_with(const char *s, const char *suffix) {
  size_t n = strlen(s), k = strlen(suffix);
  return n >= k && strcmp(s + n - k, suffix) == 0;
}

static uint8_t *slurp(const char *path, size_t *n) {
  uint8_t *d = NULL;
  if (pb_read_file(path, 1u << 30, &d, n) != PB_OK) {
    fprintf(stderr, "cannot read %s: %s\n", path, pb_error_message());
    pb_error_clear();
    return NULL;
  }
  return d;
}

static int one_line(const char *s) { return s[0] && !strchr(s, '\n') && !strchr(s, '\r'); }

/* A failure's contract: no pixels, no size, a one-line reason. */
static int clean_failure(pb_decode_status st, const pb_decoded *d) {
  return st == PB_DECODE_BAD && !d->rgba && !d->width && !d->height && one_line(d->why);
}

static int jpeg_checked, png_checked, truncations;

static void check_file(const char *dir, const char *name) {
  char path[1024];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  size_t n = 0;
  uint8_t *bytes = slurp(path, &n);
  CHECK(bytes != NULL);
  if (!bytes) return;
  int jpeg = ends_with(name, ".jpg");
  pb_decoded d;
  pb_decode_status st = pb_decode_image_rgba8(bytes, n, &big, &d);
  if (st != PB_DECODE_OK) fprintf(stderr, "%s: status %d: %s\n", name, (int)st, d.why);
  CHECK_EQ_INT(st, PB_DECODE_OK);
  int w = 0, h = 0, c = 0;
  uint8_t *ref = stbi_load_from_memory(bytes, (int)n, &w, &h, &c, 4);
  CHECK(ref != NULL);
  if (st == PB_DECODE_OK && ref) {
    CHECK_EQ_INT(d.width, w);
    CHECK_EQ_INT(d.height, h);
    size_t count = (size_t)w * h * 4, differ = 0;
    double sum = 0;
    int worst = 0;
    for (size_t i = 0; i < count && d.width == (uint32_t)w && d.height == (uint32_t)h; ++i) {
      int e = abs((int)d.rgba[i] - (int)ref[i]);
      differ += e != 0;
      sum += e;
      if (e > worst) worst = e;
    }
    if (jpeg) {
      /* libjpeg-turbo's accurate integer IDCT and fancy upsampling against
       * stb_image's own IDCT and upsampler: measured mean <= 0.16, worst 7
       * (4:2:2 chroma; PB_TEST_VERBOSE=1 prints them). A wrong colour
       * conversion, channel order or row stride gives tens. */
      if (getenv("PB_TEST_VERBOSE") || sum / count > 0.5 || worst > 16)
        fprintf(stderr, "%s: mean |diff| %.3f, worst %d\n", name, sum / count, worst);
      CHECK(sum / count <= 0.5);
      CHECK(worst <= 16);
      jpeg_checked++;
    } else {
      if (differ) fprintf(stderr, "%s: %zu of %zu bytes differ from stb_image (worst %d)\n", name, differ, count, worst);
      CHECK_EQ_INT(differ, 0);
      png_checked++;
    }
  }
  stbi_image_free(ref);
  free(d.rgba);
  /* Truncations: the header only, half the file, all but the last byte. */
  const size_t cuts[] = {n > 33 ? 33 : n / 2, n / 2, n - 1};
  for (size_t k = 0; k < sizeof cuts / sizeof *cuts; ++k) {
    pb_decoded t;
    pb_decode_status ts = pb_decode_image_rgba8(bytes, cuts[k], &big, &t);
    if (ts == PB_DECODE_OK) {
      CHECK(t.rgba != NULL);
      free(t.rgba);
    } else {
      CHECK(clean_failure(ts, &t));
    }
    truncations++;
  }
  free(bytes);
}

static int cmp_names(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

static void test_seed_dir(const char *dir) {
  DIR *dp = opendir(dir);
  CHECK(dp != NULL);
  if (!dp) return;
  char *names[512];
  size_t count = 0;
  for (struct dirent *e; (e = readdir(dp)) && count < 512;)
    if (ends_with(e->d_name, ".png") || ends_with(e->d_name, ".jpg")) names[count++] = strdup(e->d_name);
  closedir(dp);
  qsort(names, count, sizeof *names, cmp_names);
  for (size_t i = 0; i < count; ++i) {
    check_file(dir, names[i]);
    free(names[i]);
  }
  printf("seeds: %d PNG and %d JPEG files against stb_image, %d truncations\n", png_checked, jpeg_checked,
         truncations);
  /* make_image_seeds.py writes 52 PNG and 12 JPEG files (Blender adds 4 and 2). */
  CHECK(png_checked >= 52);
  CHECK(jpeg_checked >= 12);
}

/* ---- crafted input -------------------------------------------------------- */

/* CRC-32 of PNG chunks (ISO/IEC 15948 annex D), bitwise. */
static uint32_t crc32_png(const uint8_t *p, size_t n) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < n; ++i) {
    c ^= p[i];
    for (int k = 0; k < 8; ++k) c = c & 1 ? 0xEDB88320u ^ (c >> 1) : c >> 1;
  }
  return c ^ 0xFFFFFFFFu;
}

static void put_be32(uint8_t *p, uint32_t v) {
  p[0] = (uint8_t)(v >> 24), p[1] = (uint8_t)(v >> 16), p[2] = (uint8_t)(v >> 8), p[3] = (uint8_t)v;
}

static void test_limits(const char *dir) {
  const char *files[] = {"rgba8_256.png", "baseline_420.jpg"};
  for (int f = 0; f < 2; ++f) {
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, files[f]);
    size_t n = 0;
    uint8_t *bytes = slurp(path, &n);
    CHECK(bytes != NULL);
    if (!bytes) continue;
    pb_decoded d;
    CHECK_EQ_INT(pb_decode_image_rgba8(bytes, n, &big, &d), PB_DECODE_OK);
    uint32_t w = d.width, h = d.height;
    free(d.rgba);
    const pb_decode_limits side = {.max_dim = w - 1, .max_pixels = 1u << 30};
    const pb_decode_limits area = {.max_dim = 1u << 14, .max_pixels = (uint64_t)w * h - 1};
    const pb_decode_limits exact = {.max_dim = w > h ? w : h, .max_pixels = (uint64_t)w * h};
    CHECK_EQ_INT(pb_decode_image_rgba8(bytes, n, &side, &d), PB_DECODE_TOO_LARGE);
    CHECK(!d.rgba && d.width == w && d.height == h);
    CHECK_EQ_INT(pb_decode_image_rgba8(bytes, n, &area, &d), PB_DECODE_TOO_LARGE);
    CHECK(!d.rgba && d.width == w && d.height == h);
    CHECK_EQ_INT(pb_decode_image_rgba8(bytes, n, &exact, &d), PB_DECODE_OK);
    free(d.rgba);
    free(bytes);
  }
  /* A PNG header declaring 100000 x 100000 (30 GB decoded) and nothing
   * else: refused from IHDR, before any pixel memory. */
  uint8_t hdr[33] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n', 0, 0, 0, 13, 'I', 'H', 'D', 'R'};
  put_be32(hdr + 16, 100000);
  put_be32(hdr + 20, 100000);
  hdr[24] = 8, hdr[25] = 2;
  put_be32(hdr + 29, crc32_png(hdr + 12, 17));
  pb_decoded d;
  CHECK_EQ_INT(pb_decode_png_rgba8(hdr, sizeof hdr, &big, &d), PB_DECODE_TOO_LARGE);
  CHECK(d.width == 100000 && d.height == 100000 && !d.rgba);
  /* Neither PNG nor JPEG. */
  static const uint8_t gif[] = "GIF89a\x02\x00\x02\x00\x80\x00\x00";
  CHECK_EQ_INT(pb_decode_image_rgba8(gif, sizeof gif, &big, &d), PB_DECODE_UNKNOWN);
  CHECK_EQ_INT(pb_decode_image_rgba8(gif, 0, &big, &d), PB_DECODE_UNKNOWN);
  CHECK(clean_failure(pb_decode_png_rgba8(gif, sizeof gif, &big, &d), &d));
  CHECK(clean_failure(pb_decode_jpeg_rgba8(gif, sizeof gif, &big, &d), &d));
  CHECK(clean_failure(pb_decode_jpeg_rgba8(gif, 0, &big, &d), &d));
}

/* A wrong CRC on IHDR is refused (stb_image never checks CRCs; libspng does
 * for the chunks it reads whole, but not always for the image data's last
 * IDAT); a flipped bit inside the compressed data is a stream error. */
static void test_png_crc(const char *dir) {
  char path[1024];
  snprintf(path, sizeof path, "%s/rgb8.png", dir);
  size_t n = 0;
  uint8_t *bytes = slurp(path, &n);
  CHECK(bytes != NULL && n > 33);
  if (!bytes || n <= 33) {
    free(bytes);
    return;
  }
  pb_decoded d;
  bytes[29] ^= 0x01; /* IHDR's CRC */
  CHECK(clean_failure(pb_decode_image_rgba8(bytes, n, &big, &d), &d));
  CHECK(strstr(d.why, "invalid chunk checksum") != NULL);
  printf("IHDR CRC: %s\n", d.why);
  bytes[29] ^= 0x01;
  uint8_t *idat = memmem(bytes, n, "IDAT", 4);
  CHECK(idat != NULL && idat - bytes >= 4);
  if (!idat || idat - bytes < 4) {
    free(bytes);
    return;
  }
  uint32_t len = (uint32_t)idat[-4] << 24 | (uint32_t)idat[-3] << 16 | (uint32_t)idat[-2] << 8 | idat[-1];
  CHECK((size_t)(idat - bytes) + 8 + len <= n);
  idat[4 + len / 2] ^= 0x10; /* inside the zlib stream */
  CHECK(clean_failure(pb_decode_image_rgba8(bytes, n, &big, &d), &d));
  CHECK(strstr(d.why, "PNG data") != NULL);
  printf("IDAT data: %s\n", d.why);
  free(bytes);
}

/* A progressive JPEG whose first scan is repeated 600 times: libjpeg only
 * warns about the bogus progression, so the scan bound must stop it. */
static void test_jpeg_scan_bound(const char *dir) {
  char path[1024];
  snprintf(path, sizeof path, "%s/grey_progressive.jpg", dir);
  size_t n = 0;
  uint8_t *bytes = slurp(path, &n);
  CHECK(bytes != NULL);
  if (!bytes) return;
  /* The first scan: from its SOS marker to the next marker (0xFF followed
   * by neither 0x00 stuffing nor a restart marker). */
  size_t sos = 0, end = 0;
  for (size_t i = 2; i + 1 < n && !sos; ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] == 0xDA) sos = i;
  for (size_t i = sos + 2; sos && i + 1 < n && !end; ++i)
    if (bytes[i] == 0xFF && bytes[i + 1] != 0x00 && (bytes[i + 1] < 0xD0 || bytes[i + 1] > 0xD7)) end = i;
  CHECK(sos > 0 && end > sos);
  if (!(sos > 0 && end > sos)) {
    free(bytes);
    return;
  }
  size_t scan = end - sos, reps = 600;
  uint8_t *bomb = malloc(n + scan * reps);
  memcpy(bomb, bytes, end);
  for (size_t r = 0; r < reps; ++r) memcpy(bomb + end + r * scan, bytes + sos, scan);
  memcpy(bomb + end + reps * scan, bytes + end, n - end);
  pb_decoded d;
  pb_decode_status st = pb_decode_image_rgba8(bomb, n + scan * reps, &big, &d);
  CHECK(clean_failure(st, &d));
  CHECK(strstr(d.why, "more than 500 progressive scans") != NULL);
  free(bomb);
  free(bytes);
}

/* ---- through the loader ----------------------------------------------------- */

/* The fuzzing finding: a GLB whose PNG made stb_image add an offset to a
 * null pointer. Now a clean PB_ERR_IMAGE naming the image. */
static void test_finding(void) {
  const char *path = "tests/fuzz/regressions/gltf/stb_png_idat_null.glb";
  pb_scene s;
  pb_error_clear();
  CHECK_EQ_INT(pb_scene_load(path, NULL, &s), PB_ERR_IMAGE);
  const char *msg = pb_error_message();
  printf("finding: %s\n", msg);
  CHECK(strstr(msg, path) != NULL);
  CHECK(strstr(msg, "images[0]: cannot decode: PNG") != NULL);
  CHECK(one_line(msg));
  pb_error_clear();
}

static const char *tmpdir(void) {
  static char dir[256];
  if (!dir[0]) {
    snprintf(dir, sizeof dir, "/tmp/pb_test_image_decode.XXXXXX");
    if (!mkdtemp(dir)) return NULL;
  }
  return dir;
}

/* One textured quad; the image is `image_json` (a uri or bufferView object). */
static int write_scene(const char *path, const char *image_json) {
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
          "{\"asset\":{\"version\":\"2.0\"},\"scene\":0,\"scenes\":[{\"nodes\":[0]}],\"nodes\":[{\"mesh\":0}],"
          "\"meshes\":[{\"primitives\":[{\"attributes\":{\"POSITION\":0,\"TEXCOORD_0\":1},\"indices\":2,"
          "\"material\":0}]}],\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}],"
          "\"textures\":[{\"source\":0}],\"images\":[%s],"
          "\"accessors\":[{\"bufferView\":0,\"componentType\":5126,\"count\":4,\"type\":\"VEC3\","
          "\"min\":[-1,-1,0],\"max\":[1,1,0]},{\"bufferView\":1,\"componentType\":5126,\"count\":4,"
          "\"type\":\"VEC2\"},{\"bufferView\":2,\"componentType\":5123,\"count\":6,\"type\":\"SCALAR\"}],"
          "\"bufferViews\":[{\"buffer\":0,\"byteOffset\":0,\"byteLength\":48},{\"buffer\":0,\"byteOffset\":48,"
          "\"byteLength\":32},{\"buffer\":0,\"byteOffset\":80,\"byteLength\":12}],"
          "\"buffers\":[{\"byteLength\":%zu,\"uri\":\"data:application/octet-stream;base64,%s\"}]}\n",
          image_json, sizeof bin, b64);
  free(b64);
  return fclose(f) == 0;
}

static void test_data_uri(const char *seeds) {
  const char *dir = tmpdir();
  CHECK(dir != NULL);
  if (!dir) return;
  const char *files[] = {"rgba8_adam7.png", "palette4_trns.png", "progressive_420.jpg", "cmyk_adobe.jpg"};
  const char *mimes[] = {"image/png", "image/png", "image/jpeg", "image/jpeg"};
  for (int k = 0; k < 4; ++k) {
    char src[1024], copy[512], a[512], b[512];
    snprintf(src, sizeof src, "%s/%s", seeds, files[k]);
    size_t n = 0;
    uint8_t *bytes = slurp(src, &n);
    CHECK(bytes != NULL);
    if (!bytes) continue;
    snprintf(copy, sizeof copy, "%s/%s", dir, files[k]);
    FILE *f = fopen(copy, "wb");
    CHECK(f && fwrite(bytes, 1, n, f) == n);
    if (f) fclose(f);
    char *b64 = pbt_b64(bytes, n);
    size_t jn = strlen(b64) + 128;
    char *json = malloc(jn);
    snprintf(json, jn, "{\"uri\":\"data:%s;base64,%s\"}", mimes[k], b64);
    snprintf(a, sizeof a, "%s/data_uri.gltf", dir);
    CHECK(write_scene(a, json));
    snprintf(json, jn, "{\"uri\":\"%s\"}", files[k]);
    snprintf(b, sizeof b, "%s/file_uri.gltf", dir);
    CHECK(write_scene(b, json));
    pb_scene sa, sb;
    CHECK_EQ_INT(pb_scene_load(a, NULL, &sa), PB_OK);
    CHECK_EQ_INT(pb_scene_load(b, NULL, &sb), PB_OK);
    CHECK_EQ_INT(sa.texture_count, 1);
    CHECK_EQ_INT(sb.texture_count, 1);
    if (sa.texture_count == 1 && sb.texture_count == 1) {
      CHECK_EQ_INT(sa.textures[0].width, sb.textures[0].width);
      CHECK_EQ_INT(sa.textures[0].height, sb.textures[0].height);
      CHECK(memcmp(sa.textures[0].rgba8, sb.textures[0].rgba8,
                   (size_t)sb.textures[0].width * sb.textures[0].height * 4) == 0);
    }
    pb_scene_destroy(&sa);
    pb_scene_destroy(&sb);
    /* The same data URI over the size limit: refused from the header. */
    pb_load_desc small = {.max_image_dim = 8};
    snprintf(json, jn, "{\"uri\":\"data:%s;base64,%s\"}", mimes[k], b64);
    CHECK(write_scene(a, json));
    pb_error_clear();
    CHECK_EQ_INT(pb_scene_load(a, &small, &sa), PB_ERR_LIMIT);
    CHECK(strstr(pb_error_message(), "images[0]: 64x64 is over the image size limit") != NULL);
    pb_error_clear();
    unlink(a), unlink(b), unlink(copy);
    free(json);
    free(b64);
    free(bytes);
  }
  /* Bad data URIs: exact codes and the JSON path. */
  const struct {
    const char *uri;
    pb_result code;
    const char *msg;
  } bad[] = {
      {"data:image/png;base64,iVBORw0KGgo*AAAA", PB_ERR_SCENE_PARSE, "images[0].uri: malformed base64 data"},
      {"data:image/png;base64,iVBORw0KGgoAAA", PB_ERR_SCENE_PARSE, "images[0].uri: malformed base64 data"},
      {"data:image/webp;base64,UklGRg==", PB_ERR_SCENE_UNSUPPORTED, "images[0].uri: data URI of media type 'image/webp'"},
      {"data:text/plain;base64,aGVsbG8=", PB_ERR_SCENE_UNSUPPORTED, "media type 'text/plain'"},
      {"data:image/png,%89PNG", PB_ERR_SCENE_INVALID, "images[0].uri: data URI is not base64"},
      {"data:image/png;base64,", PB_ERR_IMAGE, "images[0].uri: data URI holds no image bytes"},
      {"data:image/jpeg;base64,R0lGODlhAQABAAAAACw=", PB_ERR_SCENE_UNSUPPORTED, "images[0] (used by"},
      {"data:image/png;base64,iVBORw0KGgoAAAANSUhEUg==", PB_ERR_IMAGE, "images[0]: cannot decode: PNG"},
  };
  for (size_t k = 0; k < sizeof bad / sizeof *bad; ++k) {
    char a[512], json[256];
    snprintf(a, sizeof a, "%s/bad_uri.gltf", dir);
    snprintf(json, sizeof json, "{\"uri\":\"%s\"}", bad[k].uri);
    CHECK(write_scene(a, json));
    pb_scene s;
    pb_error_clear();
    pb_result r = pb_scene_load(a, NULL, &s);
    if (r != bad[k].code || !strstr(pb_error_message(), bad[k].msg))
      fprintf(stderr, "%s: got %d: %s\n", bad[k].uri, (int)r, pb_error_message());
    CHECK_EQ_INT(r, bad[k].code);
    CHECK(strstr(pb_error_message(), bad[k].msg) != NULL);
    CHECK(strstr(pb_error_message(), a) != NULL);
    pb_error_clear();
    unlink(a);
  }
  rmdir(dir);
}

/* Every colour space, uv set and KHR_texture_transform of an image is a
 * copy of its pixels: the scene's texels are bounded by 16 images at the
 * size limit. The 64x64 seed under a 4096-pixel limit: 16 materials, each
 * with its own transform of it, load; a 17th is refused, naming it. */
static void test_texel_budget(const char *seeds) {
  const char *dir = tmpdir();
  CHECK(dir != NULL);
  if (!dir) return;
  mkdir(dir, 0700); /* test_data_uri removes it when done */
  char src[1024], copy[512], path[512];
  snprintf(src, sizeof src, "%s/rgba8_adam7.png", seeds);
  size_t n = 0;
  uint8_t *bytes = slurp(src, &n);
  CHECK(bytes != NULL);
  if (!bytes) return;
  snprintf(copy, sizeof copy, "%s/tex.png", dir);
  FILE *f = fopen(copy, "wb");
  CHECK(f && fwrite(bytes, 1, n, f) == n);
  if (f) fclose(f);
  free(bytes);
  snprintf(path, sizeof path, "%s/copies.gltf", dir);
  for (int count = 16; count <= 17; ++count) {
    /* write_scene's quad; its one material replaced by `count` of them. */
    CHECK(write_scene(path, "{\"uri\":\"tex.png\"}"));
    size_t len = 0;
    char *text = (char *)slurp(path, &len);
    CHECK(text != NULL);
    if (!text) return;
    const char *mat = "\"materials\":[{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0}}}]";
    char *at = strstr(text, mat);
    CHECK(at != NULL);
    if (!at) return;
    f = fopen(path, "w");
    fprintf(f, "%.*s\"extensionsUsed\":[\"KHR_texture_transform\"],\"materials\":[", (int)(at - text), text);
    for (int k = 0; k < count; ++k)
      fprintf(f, "%s{\"pbrMetallicRoughness\":{\"baseColorTexture\":{\"index\":0,\"extensions\":"
                 "{\"KHR_texture_transform\":{\"offset\":[%d,0]}}}}}", k ? "," : "", k);
    fprintf(f, "]%s", at + strlen(mat));
    fclose(f);
    free(text);
    pb_load_desc small = {.max_image_pixels = 64 * 64};
    pb_scene s;
    pb_error_clear();
    pb_result r = pb_scene_load(path, &small, &s);
    if (count == 16) {
      CHECK_EQ_INT(r, PB_OK);
      if (r == PB_OK) CHECK_EQ_INT(s.texture_count, 16);
      if (r == PB_OK) pb_scene_destroy(&s);
    } else {
      CHECK_EQ_INT(r, PB_ERR_LIMIT);
      CHECK(strstr(pb_error_message(), "materials[16].pbrMetallicRoughness.baseColorTexture: textures[0] (images[0], 64x64) "
                                       "takes the scene's textures over 65536 texels") != NULL);
      CHECK(one_line(pb_error_message()));
      if (r == PB_OK) pb_scene_destroy(&s);
    }
    pb_error_clear();
  }
  unlink(path), unlink(copy);
  rmdir(dir);
}

int main(int argc, char **argv) {
  pb_log_set_level(PB_LOG_QUIET);
  const char *dir = argc > 1 ? argv[1] : getenv("PB_IMAGE_SEEDS");
  if (!dir) {
    fprintf(stderr, "usage: test_image_decode SEED_DIR (or PB_IMAGE_SEEDS)\n");
    return 2;
  }
  test_seed_dir(dir);
  test_limits(dir);
  test_png_crc(dir);
  test_jpeg_scan_bound(dir);
  test_finding();
  test_data_uri(dir);
  test_texel_budget(dir);
  return pbt_done();
}
