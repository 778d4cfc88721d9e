/* JPEG textures through libjpeg-turbo's libjpeg API (decode.h).
 *
 * libjpeg reports errors through error_exit, which must not return: it
 * longjmps back here. Everything that lives across the setjmp and is changed
 * after it is volatile (C11 7.13.2.1). */
#include <setjmp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <jpeglib.h>
#include <jerror.h>

#include "image/decode.h"

/* libjpeg-turbo's TurboJPEG API bounds progressive files to 500 scans
 * (TJFLAG_LIMITSCANS, turbojpeg.c's progress monitor): every scan re-reads the
 * whole coefficient buffer, so a small file of tiny scans would otherwise cost
 * minutes. Real progressive JPEGs have 6-12 scans. */
#define JPEG_MAX_SCANS 500

typedef struct jpeg_guard {
  struct jpeg_error_mgr err;
  struct jpeg_progress_mgr progress;
  jmp_buf jump;
  int too_many_scans;
} jpeg_guard;

static void on_error(j_common_ptr c) { longjmp(((jpeg_guard *)(void *)c->err)->jump, 1); }

/* Warnings (corrupt data libjpeg recovers from) would go to stderr: the
 * library's recovery is the result, so they are dropped. */
static void on_message(j_common_ptr c, int level) { (void)c, (void)level; }

static void on_progress(j_common_ptr c) {
  j_decompress_ptr d = (j_decompress_ptr)c;
  if (d->progressive_mode && d->input_scan_number > JPEG_MAX_SCANS) {
    ((jpeg_guard *)(void *)c->err)->too_many_scans = 1;
    longjmp(((jpeg_guard *)(void *)c->err)->jump, 1);
  }
}

/* x * y / 255 rounded, the product of two 8-bit fractions. */
static uint8_t mul255(unsigned x, unsigned y) {
  unsigned t = x * y + 128;
  return (uint8_t)((t + (t >> 8)) >> 8);
}

pb_decode_status pb_decode_jpeg_rgba8(const uint8_t *bytes, size_t size, const pb_decode_limits *lim,
                                      pb_decoded *out) {
  memset(out, 0, sizeof *out);
  struct jpeg_decompress_struct ci;
  jpeg_guard g;
  memset(&ci, 0, sizeof ci);
  memset(&g, 0, sizeof g);
  uint8_t *volatile px = NULL;
  uint8_t *volatile row = NULL;
  volatile pb_decode_status st = PB_DECODE_OK;
  ci.err = jpeg_std_error(&g.err);
  g.err.error_exit = on_error;
  g.err.emit_message = on_message;
  g.progress.progress_monitor = on_progress;
  if (setjmp(g.jump)) {
    if (g.too_many_scans) {
      snprintf(out->why, sizeof out->why, "JPEG: more than %d progressive scans", JPEG_MAX_SCANS);
      st = PB_DECODE_BAD;
    } else if (g.err.msg_code == JERR_OUT_OF_MEMORY) {
      st = PB_DECODE_NOMEM;
    } else {
      char msg[JMSG_LENGTH_MAX];
      g.err.format_message((j_common_ptr)&ci, msg);
      snprintf(out->why, sizeof out->why, "JPEG: %.150s", msg);
      st = PB_DECODE_BAD;
    }
    goto done;
  }
  jpeg_create_decompress(&ci);
  ci.progress = &g.progress;
  jpeg_mem_src(&ci, bytes, (unsigned long)size);
  jpeg_read_header(&ci, TRUE);
  out->width = ci.image_width;
  out->height = ci.image_height;
  if (ci.image_width > lim->max_dim || ci.image_height > lim->max_dim ||
      (uint64_t)ci.image_width * ci.image_height > lim->max_pixels) {
    st = PB_DECODE_TOO_LARGE;
    goto done;
  }
  /* libjpeg-turbo converts grey, YCbCr and RGB straight to RGBA; CMYK and
   * YCCK come out as CMYK (YCCK's YCC part converted) and are multiplied
   * out below. */
  int cmyk = ci.jpeg_color_space == JCS_CMYK || ci.jpeg_color_space == JCS_YCCK;
  ci.out_color_space = cmyk ? JCS_CMYK : JCS_EXT_RGBA;
  jpeg_start_decompress(&ci); /* a progressive file's scans are all read here */
  size_t stride = (size_t)ci.output_width * 4;
  if (ci.output_width != ci.image_width || ci.output_height != ci.image_height || ci.output_components != 4) {
    snprintf(out->why, sizeof out->why, "JPEG: decoder gave %ux%u x %d", ci.output_width, ci.output_height,
             ci.output_components);
    st = PB_DECODE_BAD;
    goto done;
  }
  px = malloc(stride * ci.output_height);
  if (cmyk) row = malloc(stride);
  if (!px || (cmyk && !row)) {
    st = PB_DECODE_NOMEM;
    goto done;
  }
  /* Adobe's CMYK JPEGs (Photoshop, and the only common writer) store inverted
   * ink, so a sample is the fraction of light let through: R = C * K. Without
   * the Adobe marker the samples are ink amounts (libjpeg's install.txt,
   * "CMYK files"; stb_image assumes Adobe's convention throughout). */
  int inverted = ci.saw_Adobe_marker;
  while (ci.output_scanline < ci.output_height) {
    uint8_t *dst = px + stride * ci.output_scanline;
    JSAMPROW r = cmyk ? row : dst;
    if (jpeg_read_scanlines(&ci, &r, 1) != 1) {
      snprintf(out->why, sizeof out->why, "JPEG: no data for row %u", ci.output_scanline);
      st = PB_DECODE_BAD;
      goto done;
    }
    if (!cmyk) continue;
    for (uint32_t x = 0; x < ci.output_width; ++x) {
      const uint8_t *s = row + 4 * x;
      unsigned c = s[0], m = s[1], y = s[2], k = s[3];
      if (!inverted) c = 255 - c, m = 255 - m, y = 255 - y, k = 255 - k;
      dst[4 * x + 0] = mul255(c, k);
      dst[4 * x + 1] = mul255(m, k);
      dst[4 * x + 2] = mul255(y, k);
      dst[4 * x + 3] = 255;
    }
  }
  out->rgba = px;
  px = NULL;
done:
  /* Aborts a decompression in progress; the rest of the file (after the last
   * row we need) is never read. */
  jpeg_destroy_decompress(&ci);
  free(px);
  free(row);
  if (st != PB_DECODE_OK && st != PB_DECODE_TOO_LARGE) out->width = out->height = 0;
  return st;
}
