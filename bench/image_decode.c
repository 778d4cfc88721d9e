/* Texture decode speed: photonbridge's decoders (libspng, libjpeg-turbo;
 * src/image/decode.h) against stb_image on the same files, and whether they
 * give the same pixels. The measurement behind the choice in docs/scenes.md,
 * "Texture decoding"; not a test.
 *
 *   pb_bench_image_decode DIR...     every .png / .jpg in each DIR
 *
 * Per file: the best of 5 timed decodes (after one warm-up) of each decoder,
 * from memory to RGBA8, single thread; MB/s of decoded RGBA. Files are
 * made by tests/fuzz/make_image_seeds.py (bench/README.md). */
#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "core/fs.h"
#include "core/result.h"
#include "image/decode.h"

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

static double now(void) {
  struct timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int ends_with(const char *s, const char *x) {
  size_t n = strlen(s), k = strlen(x);
  return n >= k && strcmp(s + n - k, x) == 0;
}

static const pb_decode_limits lim = {.max_dim = 16384, .max_pixels = 1ull << 28};

/* Best of 5 seconds per decode; 0 when the decoder fails. */
static double time_ours(const uint8_t *b, size_t n, uint8_t **keep) {
  double best = 1e30;
  for (int r = 0; r < 6; ++r) {
    pb_decoded d;
    double t0 = now();
    if (pb_decode_image_rgba8(b, n, &lim, &d) != PB_DECODE_OK) return 0;
    double t = now() - t0;
    if (r > 0 && t < best) best = t;
    if (r == 5) *keep = d.rgba;
    else free(d.rgba);
  }
  return best;
}

static double time_stb(const uint8_t *b, size_t n, uint8_t **keep) {
  double best = 1e30;
  for (int r = 0; r < 6; ++r) {
    int w, h, c;
    double t0 = now();
    uint8_t *p = stbi_load_from_memory(b, (int)n, &w, &h, &c, 4);
    double t = now() - t0;
    if (!p) return 0;
    if (r > 0 && t < best) best = t;
    if (r == 5) *keep = p;
    else stbi_image_free(p);
  }
  return best;
}

static int cmp(const void *a, const void *b) { return strcmp(*(char *const *)a, *(char *const *)b); }

int main(int argc, char **argv) {
  if (argc < 2) {
    fprintf(stderr, "usage: pb_bench_image_decode DIR...\n");
    return 2;
  }
  printf("%-28s %9s %10s %9s %9s %8s %8s %6s\n", "file", "bytes", "pixels", "ours MB/s", "stb MB/s", "ours/stb",
         "mean|d|", "max|d|");
  double sum_ours[2] = {0, 0}, sum_stb[2] = {0, 0}, mb[2] = {0, 0};
  for (int a = 1; a < argc; ++a) {
    DIR *dp = opendir(argv[a]);
    if (!dp) {
      fprintf(stderr, "cannot open %s\n", argv[a]);
      return 3;
    }
    char *names[1024];
    int count = 0;
    for (struct dirent *e; (e = readdir(dp)) && count < 1024;)
      if (ends_with(e->d_name, ".png") || ends_with(e->d_name, ".jpg")) names[count++] = strdup(e->d_name);
    closedir(dp);
    qsort(names, (size_t)count, sizeof *names, cmp);
    for (int i = 0; i < count; ++i) {
      char path[2048];
      snprintf(path, sizeof path, "%s/%s", argv[a], names[i]);
      uint8_t *b = NULL;
      size_t n = 0;
      if (pb_read_file(path, 1u << 30, &b, &n) != PB_OK) {
        fprintf(stderr, "%s\n", pb_error_message());
        return 3;
      }
      uint8_t *po = NULL, *ps = NULL;
      double to = time_ours(b, n, &po), ts = time_stb(b, n, &ps);
      pb_decoded info;
      const pb_decode_limits none = {0, 0};
      pb_decode_image_rgba8(b, n, &none, &info); /* TOO_LARGE: the size from the header */
      double px = (double)info.width * info.height, bytes = px * 4 / 1e6;
      double mean = 0;
      int worst = 0;
      if (po && ps) {
        for (size_t k = 0; k < (size_t)px * 4; ++k) {
          int e = abs((int)po[k] - (int)ps[k]);
          mean += e;
          worst = e > worst ? e : worst;
        }
        mean /= px * 4;
      }
      printf("%-28s %9zu %10.0f %9.1f %9.1f %8.2f %8.3f %6d\n", names[i], n, px, to > 0 ? bytes / to : 0,
             ts > 0 ? bytes / ts : 0, to > 0 && ts > 0 ? ts / to : 0, mean, worst);
      int jpeg = ends_with(names[i], ".jpg");
      if (to > 0 && ts > 0) sum_ours[jpeg] += to, sum_stb[jpeg] += ts, mb[jpeg] += bytes;
      free(po);
      stbi_image_free(ps);
      free(b);
      free(names[i]);
    }
  }
  for (int j = 0; j < 2; ++j)
    if (mb[j] > 0)
      printf("all %s: ours %.1f MB/s, stb_image %.1f MB/s (%.2fx), %.1f MB of RGBA\n", j ? "JPEG" : "PNG",
             mb[j] / sum_ours[j], mb[j] / sum_stb[j], sum_stb[j] / sum_ours[j], mb[j]);
  return 0;
}
