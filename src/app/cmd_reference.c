/* photonbridge reference SCENE -o OUT.exr: the CPU reference (src/ref),
 * Embree path tracing with next-event estimation and MIS, plus progressive
 * caustic photon mapping (SPPM) where path tracing cannot reach. Writes a
 * multi-layer EXR (RGBA beauty, direct, indirect, albedo, normal, depth), an
 * optional PNG preview through the OCIO view and --json statistics; each
 * output atomically, and a failure after the first removes the earlier ones. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <strings.h>
#include <unistd.h>

#include "app/cli.h"
#include "app/commands.h"
#include "app/color_opts.h"
#include "core/fs.h"
#include "core/json.h"
#include "core/log.h"
#include "image/image.h"
#include "metrics/metrics.h"
#include "ref/ref.h"

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_reference) return &pb_commands[i];
  return NULL;
}

static const char *const mode_names[] = {"auto", "pt", "sppm", NULL};

typedef struct ref_opts {
  uint32_t spp, max_bounces, threads, photons;
  double time_limit, photon_radius, photon_alpha;
  int mode, caustics, estimate_noise;
  const char *png;
} ref_opts;

static void on_progress(void *user, uint64_t done, uint64_t total) {
  pb_progress *p = user;
  if (p->total != total) p->total = total;
  pb_progress_update(p, done);
}

static pb_result display_view(void *user, float *rgb, uint32_t w, uint32_t h) {
  return pb_color_apply_display(user, rgb, w, h, 3);
}

static pb_result write_json(const char *path, const pb_scene *s, const char *camera,
                            const pb_ref_result *res, const ref_opts *o,
                            const pb_ref_desc *d, uint64_t seed) {
  pb_json j;
  char *tmp;
  pb_result r = pb_json_open(&j, path, &tmp);
  if (r != PB_OK) return r;
  const pb_ref_stats *st = &res->stats;
  double rays_s = st->time_s > 0 ? (double)st->rays / st->time_s : 0.0;
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "renderer", "reference");
  pb_json_string(&j, "scene", s->path);
  pb_json_string(&j, "camera", camera);
  pb_json_int(&j, "width", res->width);
  pb_json_int(&j, "height", res->height);
  pb_json_string(&j, "mode", pb_ref_mode_name(st->mode));
  pb_json_int(&j, "spp", st->spp);
  pb_json_int(&j, "seed", (int64_t)seed);
  pb_json_int(&j, "max_bounces", d->max_bounces == PB_REF_BOUNCES_ZERO ? 0
                                 : d->max_bounces ? d->max_bounces : PB_REF_BOUNCE_CAP);
  pb_json_number(&j, "time_limit_s", o->time_limit);
  pb_json_int(&j, "threads", st->threads);
  pb_json_number(&j, "time_s", st->time_s);
  pb_json_number(&j, "bvh_build_s", st->build_s);
  pb_json_int(&j, "rays", (int64_t)st->rays);
  pb_json_number(&j, "rays_per_s", rays_s);
  pb_json_number(&j, "rays_per_s_per_core", st->threads ? rays_s / st->threads : 0.0);
  pb_json_number(&j, "cpu_s", st->cpu_s);
  pb_json_number(&j, "rays_per_cpu_s", st->cpu_s > 0 ? (double)st->rays / st->cpu_s : 0.0);
  pb_json_int(&j, "camera_samples", (int64_t)st->camera_samples);
  pb_json_int(&j, "guarded_samples", (int64_t)st->guarded_samples);
  if (st->mode == PB_REF_MODE_SPPM) {
    pb_json_begin_object(&j, "photons");
    pb_json_int(&j, "paths", (int64_t)st->photon_paths);
    pb_json_int(&j, "stored", (int64_t)st->photons_stored);
    pb_json_number(&j, "radius_first", st->photon_radius_first);
    pb_json_number(&j, "radius_last", st->photon_radius_last);
    pb_json_number(&j, "alpha", o->photon_alpha > 0 ? o->photon_alpha : 2.0 / 3.0);
    pb_json_end_object(&j);
  }
  if (st->noise_rmse >= 0) {
    pb_json_begin_object(&j, "noise");
    pb_json_number(&j, "rmse", st->noise_rmse);
    pb_json_number(&j, "relmse", st->noise_relmse);
    pb_json_number(&j, "psnr_db", st->noise_psnr);
    pb_json_string(&j, "method", "two independent halves (even/odd samples): "
                                 "Var(mean) = E[(A-B)^2]/4; variance only, no bias");
    pb_json_end_object(&j);
  } else {
    pb_json_null(&j, "noise");
  }
  pb_json_end_object(&j);
  return pb_json_close(&j, path, tmp);
}

int pb_cmd_reference(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_core_opts c = {0};
  pb_color_opts co = PB_COLOR_OPTS_INIT;
  ref_opts o = {.max_bounces = UINT32_MAX};
  pb_pose_opts pose = {NAN, 0};
  const pb_opt opts[] = {
      PB_RENDER_OPTS_OUT(&c, "output file (.exr: scene-linear, with its AOVs)"),
      PB_POSE_OPTS(&pose),
      {"spp", 0, PB_OPT_U32, &o.spp, "N",
       "samples per pixel (default 64; with only --time-limit: until the time is up)",
       NULL, 1, 1 << 24, "Sampling", 0},
      {"time-limit", 0, PB_OPT_FLOAT, &o.time_limit, "S",
       "stop after the first whole pass (1 spp each) ending past S seconds; "
       "the spp reached is reported", NULL, 0, 1e9, "Sampling", 0},
      {"max-bounces", 0, PB_OPT_U32, &o.max_bounces, "N",
       "scattering events per path, direct light = 1 (default: unbounded, paths end by Russian "
       "roulette, with a safety cap of 1024; Blender's Max Bounces B is B + 1; 0: emitters only)",
       NULL, 0, 4096, "Sampling", 0},
      {"threads", 0, PB_OPT_U32, &o.threads, "N",
       "worker threads (default: every core; the image does not depend on it)", NULL,
       1, 1024, "Device", 0},
      {"mode", 0, PB_OPT_CHOICE, &o.mode, "MODE",
       "pt: path tracing; sppm: plus progressive caustic photon mapping for delta "
       "light -> specular -> diffuse paths; auto: sppm when the scene has both "
       "specular surfaces and point/spot/directional lights",
       mode_names, 0, 0, "Sampling", 0},
      {"caustics", 0, PB_OPT_FLAG, &o.caustics, NULL, "same as --mode sppm", NULL, 0, 0, "Sampling", 0},
      {"photons", 0, PB_OPT_U32, &o.photons, "N",
       "SPPM photon paths per pass (default width x height, at least 16384)", NULL, 1,
       1 << 26, "Photons", PB_OPT_ADVANCED},
      {"photon-radius", 0, PB_OPT_FLOAT, &o.photon_radius, "R",
       "SPPM first gather radius, scene units (default: 2 pixel footprints at the "
       "scene's centre)", NULL, 0, 1e30, "Photons", PB_OPT_ADVANCED},
      {"photon-alpha", 0, PB_OPT_FLOAT, &o.photon_alpha, "A",
       "SPPM radius reduction r^2 *= (i + A) / (i + 1) (default 2/3)", NULL, 0.01, 0.99, "Photons", PB_OPT_ADVANCED},
      {"estimate-noise", 0, PB_OPT_FLAG, &o.estimate_noise, NULL,
       "render even and odd samples as two independent halves and report the "
       "image's own noise (RMSE, relMSE, PSNR); rounds spp up to even", NULL, 0, 0, "Reporting", 0},
      {"png", 0, PB_OPT_STRING, &o.png, "FILE",
       "also write a PNG preview through the OCIO view", NULL, 0, 0, "Output", 0},
      PB_COLOR_OPTS(&co),
  };
  const size_t nopts = sizeof opts / sizeof *opts;
  const char *pos[1];
  size_t npos;
  int help;
  pb_result r = pb_cli_parse(cmd, argc, argv, opts, nopts, pos, 1, &npos, &help);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  if (help) {
    pb_cli_print_help(
        stdout, help, cmd, opts, nopts,
        "Deterministic for a fixed --seed, whatever the thread count. EXR layers: RGBA\n"
        "beauty (A = coverage), direct (at most one scattering event), indirect,\n"
        "albedo, normal (world, facing the camera), depth (camera-space z, depth.Z).\n"
        "Radiance in W/(m^2 sr) per linear Rec.709 channel. No NaN or Inf is ever\n"
        "written: non-finite samples are dropped and counted (guarded samples).");
    return 0;
  }
  if (npos != 1 || !c.out)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "reference: expected SCENE and -o OUT.exr "
                                                  "(see 'photonbridge reference --help')"));
  /* -o is the scene-linear EXR (with its AOVs); a PNG is --png's. */
  {
    size_t ol = strlen(c.out);
    if (ol < 4 || strcasecmp(c.out + ol - 4, ".exr") != 0) {
      const char *dot = strrchr(c.out, '.');
      return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "reference: -o %s: %s%s%s; accepted: .exr (a display-referred "
                                      "PNG: --png FILE.png)", c.out, dot && !strchr(dot, '/') ? "unknown extension '" : "no file extension",
                                      dot && !strchr(dot, '/') ? dot : "", dot && !strchr(dot, '/') ? "'" : ""));
    }
  }
  if (o.caustics) o.mode = PB_REF_MODE_SPPM;

  /* Outputs that cannot be written fail now, not after the render. */
  const char *outs[] = {c.out, o.png, c.json};
  for (size_t i = 0; i < sizeof outs / sizeof *outs; ++i)
    if ((r = pb_check_writable(outs[i])) != PB_OK) return pb_cli_exit(cmd, r);
  pb_scene s;
  r = pb_cli_load_scene(pos[0], &c, &s);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  pb_ref_result res;
  memset(&res, 0, sizeof res);
  pb_color *color = NULL, *metric_color = NULL;
  int wrote_exr = 0, wrote_png = 0;
  int camera;
  uint32_t w, h;
  r = pb_cli_pose(&s, &pose, NULL);
  if (r == PB_OK) r = pb_cli_pick_camera(&s, &c, &camera, &w, &h);
  if (r == PB_OK) pb_cli_warn_clip("reference", &s, camera);
  if (r != PB_OK) goto done;
  if (o.png && (r = pb_color_opts_open_scene(&co, &s, &color)) != PB_OK) goto done;
  if (o.estimate_noise &&
      (r = pb_color_opts_open_for(&co, PB_COLOR_METRICS, &metric_color)) != PB_OK)
    goto done;

  pb_ref_desc d;
  memset(&d, 0, sizeof d);
  d.spp = o.spp;
  d.max_bounces = o.max_bounces == UINT32_MAX ? 0
                  : o.max_bounces == 0        ? PB_REF_BOUNCES_ZERO
                                              : o.max_bounces;
  d.seed = c.seed;
  d.threads = o.threads;
  d.time_limit_s = o.time_limit;
  d.mode = (pb_ref_mode)o.mode;
  d.photons_per_pass = o.photons;
  d.photon_radius = (float)o.photon_radius;
  d.photon_alpha = (float)o.photon_alpha;
  d.estimate_noise = o.estimate_noise;
  pb_progress prog;
  pb_progress_begin(&prog, "reference", 1);
  d.progress = on_progress;
  d.progress_user = &prog;
  pb_log_verbose("reference: %s, camera '%s', %ux%u", s.path, s.cameras[camera].name, w, h);
  r = pb_ref_render(&s, camera, w, h, &d, &res);
  pb_progress_end(&prog);
  if (r != PB_OK) goto done;

  if (res.half_a && metric_color) {
    /* The noise's display PSNR through the same view compare uses. */
    pb_metrics_desc md = {display_view, metric_color};
    pb_noise_estimate ne;
    r = pb_metrics_noise_from_halves(res.half_a, res.half_b, w, h, 3, &md, &ne);
    if (r != PB_OK) goto done;
    res.stats.noise_psnr = ne.psnr;
  }

  const pb_ref_stats *st = &res.stats;
  const pb_image_layer layers[] = {
      {"", 4, res.beauty, NULL},         {"direct", 3, res.direct, NULL},
      {"indirect", 3, res.indirect, NULL}, {"albedo", 3, res.albedo, NULL},
      {"normal", 3, res.normal, NULL},   {"depth", 1, res.depth, NULL},
  };
  char spp_s[32], seed_s[32], bounce_s[32], noise_s[64], time_s[32];
  snprintf(spp_s, sizeof spp_s, "%u", st->spp);
  snprintf(seed_s, sizeof seed_s, "%llu", (unsigned long long)c.seed);
  snprintf(bounce_s, sizeof bounce_s, "%u",
           d.max_bounces == PB_REF_BOUNCES_ZERO ? 0u : d.max_bounces ? d.max_bounces : (unsigned)PB_REF_BOUNCE_CAP);
  if (st->noise_rmse >= 0)
    snprintf(noise_s, sizeof noise_s, "%.6g", st->noise_rmse);
  else
    snprintf(noise_s, sizeof noise_s, "not estimated");
  snprintf(time_s, sizeof time_s, "%.3f", st->time_s);
  const char *an[] = {"photonbridge/renderer", "photonbridge/mode",
                      "photonbridge/spp",      "photonbridge/seed",
                      "photonbridge/max_bounces", "photonbridge/noise_rmse",
                      "photonbridge/time_s"};
  const char *av[] = {"reference", pb_ref_mode_name(st->mode), spp_s, seed_s, bounce_s,
                      noise_s, time_s};
  pb_exr_desc ed;
  memset(&ed, 0, sizeof ed);
  ed.width = w;
  ed.height = h;
  ed.layers = layers;
  ed.layer_count = sizeof layers / sizeof *layers;
  ed.attr_names = an;
  ed.attr_values = av;
  ed.attr_count = sizeof an / sizeof *an;
  r = pb_exr_write(c.out, &ed);
  if (r != PB_OK) goto done;
  wrote_exr = 1;
  if (o.png) {
    r = pb_png_write_display(o.png, color, w, h, 4, res.beauty);
    if (r != PB_OK) goto done;
    wrote_png = 1;
  }
  if (c.json) {
    r = write_json(c.json, &s, s.cameras[camera].name, &res, &o, &d, c.seed);
    if (r != PB_OK) goto done;
  }
  {
    double rays_s = st->time_s > 0 ? (double)st->rays / st->time_s : 0.0;
    char noise[128] = "";
    if (st->noise_rmse >= 0)
      snprintf(noise, sizeof noise, ", noise RMSE %.3g relMSE %.3g PSNR %.1f dB",
               st->noise_rmse, st->noise_relmse, st->noise_psnr);
    pb_log_info("reference: %ux%u, %u spp (%s), %.1f s, %.1f Mrays (%.2f Mrays/s, %.2f "
                "Mrays/s/core on %u threads, %.2f Mrays per CPU-second), %llu guarded "
                "samples%s -> %s",
                w, h, st->spp, pb_ref_mode_name(st->mode), st->time_s, (double)st->rays * 1e-6,
                rays_s * 1e-6, st->threads ? rays_s * 1e-6 / st->threads : 0.0, st->threads,
                st->cpu_s > 0 ? (double)st->rays * 1e-6 / st->cpu_s : 0.0,
                (unsigned long long)st->guarded_samples, noise, c.out);
  }

done:
  if (r != PB_OK) {
    if (wrote_exr) unlink(c.out);
    if (wrote_png) unlink(o.png);
  }
  pb_color_destroy(color);
  pb_color_destroy(metric_color);
  pb_ref_result_destroy(&res);
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
}
