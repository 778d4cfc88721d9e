/* photonbridge compare TEST.exr REFERENCE.exr: the src/metrics numbers
 * (RMSE and relMSE on scene-linear RGB, PSNR and SSIM on the display image
 * through the shared OCIO view, HDR-FLIP on scene-linear RGB), an optional
 * heat map PNG of the per-pixel error and --json. Images of different sizes, or without R, G, B channels
 * in the compared layer, are PB_ERR_IMAGE_MISMATCH naming both files. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/color_opts.h"
#include "core/json.h"
#include "core/log.h"
#include "image/image.h"
#include "metrics/flip.h"
#include "metrics/metrics.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_compare) return &pb_commands[i];
  return NULL;
}

/* relative and absolute are pb_heatmap_metric values; flip is FLIP's own map. */
enum { HEAT_FLIP = 2 };
static const char *const heat_names[] = {"relative", "absolute", "flip", NULL};

/* Finds the three colour channels of `layer` ("" = the main image):
 * R,G,B, or X,Y,Z (the normal layer); a single-channel layer (depth.Z,
 * N.V, N.Y; Z or Y in the main image) is compared as grey, its channel
 * taken three times. Returns 0 when absent. */
static int find_rgb(const pb_image *img, const char *layer, int idx[3]) {
  static const char *const sets[5][3] = {
      {"R", "G", "B"}, {"X", "Y", "Z"}, {"Z", "Z", "Z"}, {"V", "V", "V"}, {"Y", "Y", "Y"}};
  for (int s = 0; s < 5; ++s) {
    int ok = 1;
    for (int c = 0; c < 3; ++c) {
      char name[160];
      if (layer[0]) snprintf(name, sizeof name, "%s.%s", layer, sets[s][c]);
      else snprintf(name, sizeof name, "%s", sets[s][c]);
      idx[c] = pb_image_find_channel(img, name);
      if (idx[c] < 0) ok = 0;
    }
    if (ok) return 1;
  }
  return 0;
}

static float *extract_rgb(const pb_image *img, const int idx[3]) {
  size_t n = (size_t)img->width * img->height;
  float *p = malloc(3 * n * sizeof *p);
  if (!p) return NULL;
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c)
      p[3 * i + (size_t)c] = img->pixels[i * img->channel_count + (size_t)idx[c]];
  return p;
}

static pb_result display_view(void *user, float *rgb, uint32_t w, uint32_t h) {
  return pb_color_apply_display(user, rgb, w, h, 3);
}

static void json_number_or_null(pb_json *j, const char *key, double v) {
  if (isfinite(v)) pb_json_number(j, key, v);
  else pb_json_null(j, key); /* PSNR of identical images is +inf */
}

int pb_cmd_compare(int argc, char **argv) {
  const pb_command *cmd = self();
  const char *json = NULL, *heatmap = NULL, *layer = "";
  int heat_metric = 0, quiet = 0;
  double heat_max = 0;
  pb_color_opts co = PB_COLOR_OPTS_INIT;
  const pb_opt opts[] = {
      {"layer", 0, PB_OPT_STRING, &layer, "NAME",
       "compare this layer (direct, indirect, albedo, normal, depth...; default: the "
       "main RGB image); one-channel layers are compared as grey", NULL, 0, 0, "Comparison", 0},
      {"heatmap", 0, PB_OPT_STRING, &heatmap, "FILE.png",
       "write the per-pixel error as a heat map PNG (viridis; FLIP's magma for flip)",
       NULL, 0, 0, "Output", 0},
      {"heatmap-metric", 0, PB_OPT_CHOICE, &heat_metric, "M",
       "relative: sqrt(mean over RGB of (t-r)^2/(r^2+0.01)); absolute: per-pixel RMSE; "
       "flip: HDR-FLIP's error map in FLIP's magma colours, 0 black .. 1 light yellow, "
       "not rescaled", heat_names, 0, 0, "Output", 0},
      {"heatmap-max", 0, PB_OPT_FLOAT, &heat_max, "V",
       "error at the bright end of the heat map (default: the 99th percentile; "
       "not used by flip, whose scale is 0 .. 1)", NULL, 0, 1e30, "Output", 0},
      {"json", 0, PB_OPT_STRING, &json, "FILE",
       "write the numbers as JSON to FILE ('-' for stdout)", NULL, 0, 0, "Reporting", 0},
      {"quiet", 'q', PB_OPT_FLAG, &quiet, NULL, "print nothing but errors", NULL, 0, 0, "Reporting", 0},
      PB_COLOR_OPTS(&co),
  };
  const size_t nopts = sizeof opts / sizeof *opts;
  const char *pos[2];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, nopts, pos, 2, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(
        stdout, help, cmd, opts, nopts,
        "RMSE and relMSE (mean of (t-r)^2/(r^2+0.01), r = REFERENCE) on scene-linear\n"
        "RGB; PSNR (peak 1) and SSIM (Wang et al. 2004, 11x11 Gaussian window,\n"
        "sigma 1.5, K1 0.01, K2 0.03, mean of R, G, B) on the display image through\n"
        "the OCIO view (default: the built-in config's sRGB Standard view); HDR-FLIP\n"
        "(NVIDIA FLIP 1.7: Andersson et al. 2020, 2021) on scene-linear Rec.709 RGB,\n"
        "not through the OCIO view: the mean over pixels of the largest LDR-FLIP over\n"
        "exposures from 2^start to 2^stop, both images through FLIP's ACES tone mapper,\n"
        "start and stop from REFERENCE (its largest and its median luminance),\n"
        "ceil(stop - start) exposures (at least 2), 67 pixels per degree; 0 = the same,\n"
        "1 = maximal. Negative and NaN/Inf values are taken as 0 for FLIP; a reference\n"
        "that is black everywhere has no FLIP (n/a, JSON null).\n"
        "JSON keys: rmse, relmse, psnr_db, ssim, ssim_rgb, mse_display, max_abs_error,\n"
        "nonfinite_values; hdr_flip (the mean), hdr_flip_start_exposure and\n"
        "hdr_flip_stop_exposure (log2 scales), hdr_flip_exposures (how many),\n"
        "hdr_flip_zeroed_pixels (pixels with a negative or NaN/Inf value taken as 0).");
    return 0;
  }
  if (npos != 2)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "compare: expected TEST.exr and "
                                                  "REFERENCE.exr (see 'photonbridge compare --help')"));
  if (quiet) pb_log_set_level(PB_LOG_QUIET);
  const char *tpath = pos[0], *rpath = pos[1];
  pb_image ti, ri;
  memset(&ti, 0, sizeof ti);
  memset(&ri, 0, sizeof ri);
  float *t = NULL, *rf = NULL;
  pb_color *color = NULL;
  float *flip_map = NULL;
  pb_metrics m;
  memset(&m, 0, sizeof m);
  pb_flip_result fl;
  memset(&fl, 0, sizeof fl);
  r = pb_exr_read(tpath, NULL, &ti);
  if (r != PB_OK) goto done;
  r = pb_exr_read(rpath, NULL, &ri);
  if (r != PB_OK) goto done;
  if (ti.width != ri.width || ti.height != ri.height) {
    r = pb_fail(PB_ERR_IMAGE_MISMATCH, "%s is %ux%u but %s is %ux%u", tpath, ti.width,
                ti.height, rpath, ri.width, ri.height);
    goto done;
  }
  int ti_idx[3], ri_idx[3];
  int th = find_rgb(&ti, layer, ti_idx), rh = find_rgb(&ri, layer, ri_idx);
  if (!th || !rh) {
    char what[96];
    if (layer[0]) snprintf(what, sizeof what, "layer '%s' (%s.R/G/B)", layer, layer);
    else snprintf(what, sizeof what, "channels R, G, B");
    if (!th && !rh)
      r = pb_fail(PB_ERR_IMAGE_MISMATCH, "neither %s nor %s has %s", tpath, rpath, what);
    else
      r = pb_fail(PB_ERR_IMAGE_MISMATCH, "%s has no %s but %s has", th ? rpath : tpath,
                  what, th ? tpath : rpath);
    goto done;
  }
  t = extract_rgb(&ti, ti_idx);
  rf = extract_rgb(&ri, ri_idx);
  if (!t || !rf) {
    r = pb_fail(PB_ERR_NOMEM, "compare: out of memory for %ux%u images", ti.width, ti.height);
    goto done;
  }
  r = pb_color_opts_open_for(&co, PB_COLOR_METRICS, &color);
  if (r != PB_OK) goto done;
  pb_metrics_desc md = {display_view, color};
  r = pb_metrics_compute(t, rf, ti.width, ti.height, 3, &md, &m);
  if (r != PB_OK) goto done;
  if (heatmap && heat_metric == HEAT_FLIP) {
    flip_map = malloc((size_t)ti.width * ti.height * sizeof *flip_map);
    if (!flip_map) {
      r = pb_fail(PB_ERR_NOMEM, "compare: out of memory for the FLIP map");
      goto done;
    }
  }
  r = pb_flip_hdr(t, rf, ti.width, ti.height, 3, flip_map, &fl);
  if (r != PB_OK) goto done;
  float heat_scale = 0;
  if (heatmap && heat_metric == HEAT_FLIP) {
    if (!fl.defined) {
      r = pb_fail(PB_ERR_USAGE, "compare: %s is black everywhere, so HDR-FLIP (which takes "
                  "its exposures from the reference) is undefined and %s was not written; "
                  "use --heatmap-metric relative or absolute", rpath, heatmap);
      goto done;
    }
    r = pb_flip_write_heatmap(heatmap, flip_map, ti.width, ti.height);
    if (r != PB_OK) goto done;
    heat_scale = 1.0f;
  } else if (heatmap) {
    r = pb_metrics_write_heatmap(heatmap, t, rf, ti.width, ti.height, 3,
                                 (pb_heatmap_metric)heat_metric, (float)heat_max, &heat_scale);
    if (r != PB_OK) goto done;
  }
  char view[256];
  snprintf(view, sizeof view, "%s / %s%s%s (%s)", pb_color_display(color),
           pb_color_view(color), pb_color_look(color)[0] ? " / " : "",
           pb_color_look(color), pb_color_config_name(color));
  if (json) {
    pb_json j;
    char *tmp;
    r = pb_json_open(&j, json, &tmp);
    if (r != PB_OK) goto done;
    pb_json_begin_object(&j, NULL);
    pb_json_string(&j, "test", tpath);
    pb_json_string(&j, "reference", rpath);
    pb_json_string(&j, "layer", layer);
    pb_json_int(&j, "width", m.width);
    pb_json_int(&j, "height", m.height);
    pb_json_number(&j, "rmse", m.rmse);
    pb_json_number(&j, "relmse", m.relmse);
    json_number_or_null(&j, "psnr_db", m.psnr);
    pb_json_number(&j, "ssim", m.ssim);
    pb_json_begin_array(&j, "ssim_rgb");
    for (int c = 0; c < 3; ++c) pb_json_number(&j, NULL, m.ssim_rgb[c]);
    pb_json_end_array(&j);
    pb_json_number(&j, "mse_display", m.mse_display);
    pb_json_number(&j, "max_abs_error", m.max_abs);
    pb_json_int(&j, "nonfinite_values", (int64_t)m.nonfinite);
    if (fl.defined) {
      pb_json_number(&j, "hdr_flip", fl.mean);
      pb_json_number(&j, "hdr_flip_start_exposure", fl.start_exposure);
      pb_json_number(&j, "hdr_flip_stop_exposure", fl.stop_exposure);
      pb_json_int(&j, "hdr_flip_exposures", fl.exposures);
    } else {
      pb_json_null(&j, "hdr_flip");
      pb_json_null(&j, "hdr_flip_start_exposure");
      pb_json_null(&j, "hdr_flip_stop_exposure");
      pb_json_null(&j, "hdr_flip_exposures");
    }
    pb_json_int(&j, "hdr_flip_zeroed_pixels", (int64_t)fl.zeroed_pixels);
    pb_json_string(&j, "display", view);
    if (heatmap) {
      pb_json_begin_object(&j, "heatmap");
      pb_json_string(&j, "file", heatmap);
      pb_json_string(&j, "metric", heat_names[heat_metric]);
      pb_json_number(&j, "scale_max", heat_scale);
      pb_json_end_object(&j);
    }
    pb_json_end_object(&j);
    r = pb_json_close(&j, json, tmp);
    if (r != PB_OK) goto done;
  }
  if (!quiet && !(json && strcmp(json, "-") == 0)) {
    printf("test       %s\nreference  %s%s%s\nsize       %ux%u\n", tpath, rpath,
           layer[0] ? "\nlayer      " : "", layer, m.width, m.height);
    printf("RMSE       %.6g  (scene-linear RGB)\n", m.rmse);
    printf("relMSE     %.6g\n", m.relmse);
    if (isfinite(m.psnr)) printf("PSNR       %.3f dB  (display: %s)\n", m.psnr, view);
    else printf("PSNR       inf  (identical display images: %s)\n", view);
    printf("SSIM       %.6f  (R %.4f, G %.4f, B %.4f)\n", m.ssim, m.ssim_rgb[0],
           m.ssim_rgb[1], m.ssim_rgb[2]);
    if (fl.defined)
      printf("FLIP       %.6f  (HDR-FLIP, %d exposures %.3f .. %.3f)\n", fl.mean, fl.exposures,
             (double)fl.start_exposure, (double)fl.stop_exposure);
    else
      printf("FLIP       n/a  (the reference is black: HDR-FLIP has no exposure range)\n");
    if (m.nonfinite)
      printf("warning    %llu NaN/Inf values, compared as 0\n", (unsigned long long)m.nonfinite);
    if (fl.zeroed_pixels)
      printf("warning    %llu pixels with negative or NaN/Inf values, taken as 0 for FLIP\n",
             (unsigned long long)fl.zeroed_pixels);
    if (heatmap)
      printf("heat map   %s (%s error, 0 .. %.4g)\n", heatmap, heat_names[heat_metric],
             (double)heat_scale);
  }

done:
  free(flip_map);
  free(t);
  free(rf);
  pb_color_destroy(color);
  pb_image_destroy(&ti);
  pb_image_destroy(&ri);
  return pb_cli_exit(cmd, r);
}
