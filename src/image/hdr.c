/* Radiance RGBE decoder (hdr.h). Written from the format's description in
 * Ward's "Real Pixels" and Radiance's header conventions; pixel values follow
 * Radiance's colr_color, (m + 1/2) 2^(e - 136), which is also what Blender
 * 3.4's own reader (imbuf radiance_hdr.c) gives Cycles (checked here: a
 * texel written as mantissa 64, exponent byte 120 reads back as 64.5 / 65536
 * in Blender). */
#include "image/hdr.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct reader {
  const uint8_t *p, *end;
  char *why;
  size_t why_size;
} reader;

static pb_result bad(reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static pb_result bad(reader *r, const char *fmt, ...) {
  if (r->why && r->why_size) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(r->why, r->why_size, fmt, ap);
    va_end(ap);
  }
  return PB_ERR_IMAGE;
}

/* Next header line (without its '\n') into buf; 0 at the end of the data. */
static int read_line(reader *r, char *buf, size_t cap) {
  if (r->p >= r->end) return 0;
  size_t n = 0;
  while (r->p < r->end && *r->p != '\n') {
    if (n + 1 < cap) buf[n++] = (char)*r->p;
    r->p++;
  }
  if (r->p < r->end) r->p++; /* the '\n' */
  buf[n] = '\0';
  return 1;
}

static void rgbe_to_float(const uint8_t *c, float *out) {
  if (c[3] == 0) {
    out[0] = out[1] = out[2] = 0.0f;
    return;
  }
  float f = ldexpf(1.0f, (int)c[3] - 136);
  for (int k = 0; k < 3; ++k) out[k] = ((float)c[k] + 0.5f) * f;
}

/* One scanline of w RGBE pixels into line (4 w bytes). */
static pb_result read_scanline(reader *r, uint32_t w, uint8_t *line, uint32_t y) {
  size_t left = (size_t)(r->end - r->p);
  if (w >= 8 && w < 0x8000 && left >= 4 && r->p[0] == 2 && r->p[1] == 2 && !(r->p[2] & 0x80)) {
    uint32_t lw = (uint32_t)r->p[2] << 8 | r->p[3];
    if (lw != w) return bad(r, "scanline %u: run-length line of width %u in an image %u wide", y, lw, w);
    r->p += 4;
    for (int c = 0; c < 4; ++c) {
      uint32_t x = 0;
      while (x < w) {
        if (r->p >= r->end) return bad(r, "scanline %u: data ends inside the line", y);
        uint32_t n = *r->p++;
        if (n > 128) { /* a run of n - 128 copies of the next byte */
          n -= 128;
          if (n > w - x) return bad(r, "scanline %u: run of %u bytes passes the line's end", y, n);
          if (r->p >= r->end) return bad(r, "scanline %u: data ends inside the line", y);
          uint8_t v = *r->p++;
          for (uint32_t k = 0; k < n; ++k) line[4 * (x + k) + c] = v;
        } else {           /* n literal bytes */
          if (n == 0) return bad(r, "scanline %u: literal count 0", y);
          if (n > w - x) return bad(r, "scanline %u: %u literal bytes pass the line's end", y, n);
          if ((size_t)(r->end - r->p) < n) return bad(r, "scanline %u: data ends inside the line", y);
          for (uint32_t k = 0; k < n; ++k) line[4 * (x + k) + c] = r->p[k];
          r->p += n;
        }
        x += n;
      }
    }
    return PB_OK;
  }
  /* Flat pixels, with old-style runs (1 1 1 n: the previous pixel repeated
   * n << shift times; consecutive runs shift by 8 more). */
  uint32_t x = 0, shift = 0;
  while (x < w) {
    if ((size_t)(r->end - r->p) < 4) return bad(r, "scanline %u: data ends after %u of %u pixels", y, x, w);
    const uint8_t *q = r->p;
    r->p += 4;
    if (q[0] == 1 && q[1] == 1 && q[2] == 1) {
      if (x == 0) return bad(r, "scanline %u: a run before any pixel", y);
      if (shift > 24) return bad(r, "scanline %u: run length overflows", y);
      uint64_t n = (uint64_t)q[3] << shift;
      if (n > w - x) return bad(r, "scanline %u: run of %llu pixels passes the line's end", y, (unsigned long long)n);
      for (uint64_t k = 0; k < n; ++k) memcpy(line + 4 * (x + k), line + 4 * (x - 1), 4);
      x += (uint32_t)n;
      shift += 8;
    } else {
      memcpy(line + 4 * x, q, 4);
      x++;
      shift = 0;
    }
  }
  return PB_OK;
}

pb_result pb_hdr_decode(const uint8_t *bytes, size_t size, uint32_t max_dim, uint64_t max_pixels, float **rgb,
                        uint32_t *w_out, uint32_t *h_out, char *why, size_t why_size) {
  *rgb = NULL;
  *w_out = *h_out = 0;
  reader r = {bytes, bytes + size, why, why_size};
  char line[256];
  if (!read_line(&r, line, sizeof line) || (strncmp(line, "#?RADIANCE", 10) != 0 && strncmp(line, "#?RGBE", 6) != 0))
    return bad(&r, "not a Radiance HDR file (no #?RADIANCE or #?RGBE line)");
  int ended = 0;
  while (read_line(&r, line, sizeof line)) {
    if (line[0] == '\0') {
      ended = 1;
      break;
    }
    if (strncmp(line, "FORMAT=", 7) == 0 && strcmp(line + 7, "32-bit_rle_rgbe") != 0)
      return bad(&r, "FORMAT=%.40s is not supported (only 32-bit_rle_rgbe)", line + 7);
  }
  if (!ended) return bad(&r, "the header has no end (empty line)");
  if (!read_line(&r, line, sizeof line)) return bad(&r, "no resolution line");
  char ys;
  long hh = 0, ww = 0;
  int used = 0;
  if (sscanf(line, "%cY %ld +X %ld%n", &ys, &hh, &ww, &used) != 3 || (ys != '-' && ys != '+') ||
      line[used] != '\0')
    return bad(&r, "resolution line '%.40s' is not '-Y H +X W' or '+Y H +X W'", line);
  if (hh <= 0 || ww <= 0) return bad(&r, "image is %ld x %ld pixels", ww, hh);
  if ((uint64_t)ww > max_dim || (uint64_t)hh > max_dim || (uint64_t)ww * (uint64_t)hh > max_pixels) {
    *w_out = (uint32_t)(ww > (long)UINT32_MAX ? UINT32_MAX : ww);
    *h_out = (uint32_t)(hh > (long)UINT32_MAX ? UINT32_MAX : hh);
    snprintf(why, why_size, "%ld x %ld pixels exceeds the limit (%u per side, %llu pixels)", ww, hh, max_dim,
             (unsigned long long)max_pixels);
    return PB_ERR_LIMIT;
  }
  uint32_t w = (uint32_t)ww, h = (uint32_t)hh;
  float *out = malloc((size_t)w * h * 3 * sizeof *out);
  uint8_t *scan = malloc((size_t)w * 4);
  if (!out || !scan) {
    free(out);
    free(scan);
    snprintf(why, why_size, "out of memory for %u x %u pixels", w, h);
    return PB_ERR_NOMEM;
  }
  for (uint32_t y = 0; y < h; ++y) {
    pb_result e = read_scanline(&r, w, scan, y);
    if (e != PB_OK) {
      free(out);
      free(scan);
      return e;
    }
    uint32_t row = ys == '-' ? y : h - 1 - y; /* +Y: the file's first line is the bottom row */
    for (uint32_t x = 0; x < w; ++x) rgbe_to_float(scan + 4 * x, out + 3 * ((size_t)row * w + x));
  }
  free(scan);
  *rgb = out;
  *w_out = w;
  *h_out = h;
  return PB_OK;
}
