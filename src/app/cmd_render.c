/* photonbridge render SCENE -o OUT.exr: the GPU pipeline (Vulkan compute):
 * primary visibility, specular eye chains, direct light from point, spot and
 * directional lights and emissive triangles with shadow rays, photon mapping
 * for indirect light and caustics; AOVs into a multi-layer EXR
 * (render_out.c; Blender's channel names with --blender-layer), an optional
 * PNG and --json statistics with per-pass milliseconds. Outputs are written
 * only after the whole frame rendered, each atomically, so a failure (no
 * device, device lost) leaves none half-written; --preview writes the
 * refining image after each iteration, also atomically. */
#include <stdint.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "app/cli.h"
#include "app/color_opts.h"
#include "app/commands.h"
#include "core/fs.h"
#include "core/json.h"
#include "core/log.h"
#include "image/image.h"
#include "render/estimate/estimator.h"
#include "render/photon/photon.h"
#include "render/scene/scene_plan.h"
#include "render/render.h"
#include "app/render_out.h"
#include "app/settings_opts.h"
#include "app/render_seq.h"
#include "shared/pb_gpu.h"
#include "shared/pb_photon.h"
#include "shared/pb_lbvh.h"
#include "shared/pb_knn.h"
#include "render/photon/tracer.h"

enum { PB_PATH_STAGE = 96 }; /* "writing OUT" (the stage text is cut there) */

static const pb_command *self(void) {
  for (size_t i = 0; i < pb_command_count; ++i)
    if (pb_commands[i].run == pb_cmd_render) return &pb_commands[i];
  return NULL;
}

typedef struct render_opts {
  pb_settings set;  /* the render settings (render/settings.h) */
  uint32_t device;
  int validation;
  int traversal; /* PB_GPU_TRAVERSAL_* */
  const char *png;
  /* Sequences (render_seq.h). */
  const char *frames;
  double fps, orbit_seconds;
  int orbit, bvh_update;
  uint32_t reference_spp, warmup, frames_in_flight;
  const char *reference_cache;
  /* Driving photonbridge from another program (the Blender add-on). */
  const char *crop, *preview, *blender_layer, *blender_passes;
  double preview_interval;
  pb_gpu_pipeline_stats pipes_at_open; /* the device's pipeline cache before this render */
  double noise_threshold; /* resolved (pb_settings_render_desc): 0 off */
  double time_limit;
  int direct_only;        /* resolved: --direct-only or --max-bounces 1 */
  int progress_lines;
} render_opts;

/* --crop X,Y,W,H: four non-negative integers, W and H positive. */
static pb_result parse_crop(const char *text, uint32_t v[4]) {
  const char *p = text;
  for (int i = 0; i < 4; ++i) {
    char *end;
    if (*p < '0' || *p > '9') goto bad;
    unsigned long long x = strtoull(p, &end, 10);
    if (x > 65536 || end == p || (i < 3 ? *end != ',' : *end != 0)) goto bad;
    v[i] = (uint32_t)x;
    p = end + 1;
  }
  if (v[2] && v[3]) return PB_OK;
bad:
  return pb_fail(PB_ERR_USAGE, "render: --crop '%s' is not X,Y,W,H (pixels of the --width x --height frame, W and H "
                 "positive)", text);
}

/* The progress callback of a single frame: a progress line, and the preview
 * EXR (atomic) when the renderer passed the refining beauty. */
typedef struct progress_ctx {
  const render_opts *o;
} progress_ctx;

static pb_result on_progress(void *user, const pb_render_progress *p) {
  const progress_ctx *pc = user;
  const char *written = NULL;
  {
    /* The bar: maps done, samples, and the time left from the mean time of
     * a map so far (the time limit, when it comes first). */
    char stage[96];
    double per = p->iteration ? p->elapsed_s / p->iteration : 0;
    double eta = per * (double)(p->iterations - p->iteration);
    double nt = pc->o->noise_threshold;
    if (nt > 0 && p->noise > 0) /* the noise falls as 1 / sqrt(maps) */
      eta = per * fmax(0.0, (double)p->iteration * (p->noise / nt) * (p->noise / nt) - p->iteration);
    else if (nt > 0)
      eta = -1; /* not known before the second map */
    if (pc->o->time_limit > 0 && (eta < 0 || eta > pc->o->time_limit - p->elapsed_s + per))
      eta = pc->o->time_limit - p->elapsed_s + per > 0 ? pc->o->time_limit - p->elapsed_s + per : 0;
    if (pc->o->direct_only)
      snprintf(stage, sizeof stage, "direct light, %u/%u samples", p->samples, p->spp);
    else if (nt > 0 && p->noise > 0)
      snprintf(stage, sizeof stage, "photon map %u, noise %.1f dB (target %.1f dB), %u samples", p->iteration,
               -20.0 * log10(p->noise), -20.0 * log10(nt), p->samples);
    else if (nt > 0)
      snprintf(stage, sizeof stage, "photon map %u (noise threshold %.1f dB), %u samples", p->iteration,
               -20.0 * log10(nt), p->samples);
    else if (pc->o->time_limit > 0)
      snprintf(stage, sizeof stage, "photon map %u (time limit %gs), %u samples", p->iteration, pc->o->time_limit,
               p->samples);
    else
      snprintf(stage, sizeof stage, "photon map %u/%u, %u/%u samples", p->iteration, p->iterations, p->samples,
               p->spp);
    pb_render_bar_stage(stage, p->iteration, pc->o->time_limit > 0 || nt > 0 ? 0 : p->iterations, eta);
  }
  if (p->beauty && pc->o->preview) {
    pb_render_result pr;
    memset(&pr, 0, sizeof pr);
    pr.width = p->width, pr.height = p->height;
    pr.beauty = (float *)p->beauty;
    char spp_s[32];
    snprintf(spp_s, sizeof spp_s, "%u", p->samples);
    const char *an[] = {"photonbridge/renderer", "photonbridge/spp", "photonbridge/preview"};
    const char *av[] = {"gpu", spp_s, "1"};
    pb_result r = pb_render_write_exr(pc->o->preview, &pr, pc->o->blender_layer, pc->o->blender_passes, an, av, 3);
    if (r != PB_OK) return r;
    written = pc->o->preview;
    /* A preview is a whole file: an interrupt keeps it (main.c's note). */
    pb_tmp_set_interrupt_note("the last preview written is complete; the final image was not written");
  }
  pb_progress_line_iteration(p, written);
  return PB_OK;
}

/* --bvh-update, in PB_BVH_UPDATE_* order. */
static const char *const bvh_update_names[] = {"auto", "refit", "rebuild", NULL};


static pb_result write_json(const char *path, const pb_scene *s, const pb_gpu *g, const pb_render_result *res,
                            const render_opts *o, const pb_render_desc *rd) {
  pb_json j;
  char *tmp;
  pb_result r = pb_json_open(&j, path, &tmp);
  if (r != PB_OK) return r;
  const pb_render_stats *st = &res->stats;
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "renderer", "gpu");
  pb_json_string(&j, "scene", s->path);
  pb_json_string(&j, "device", pb_gpu_device_name(g));
  pb_json_string(&j, "device_type", pb_gpu_device_type(g)); /* cpu: a CPU Vulkan device */
  pb_json_string(&j, "traversal", pb_gpu_traversal(g));      /* ray-query or bvh */
  pb_json_int(&j, "width", res->width);
  pb_json_int(&j, "height", res->height);
  pb_json_int(&j, "spp", st->spp);
  pb_json_bool(&j, "direct_only", o->direct_only);
  pb_json_number(&j, "glossy_path_roughness",
                 o->set.glossy_path_roughness);
  pb_json_int(&j, "max_specular_depth", rd->max_specular_depth ? rd->max_specular_depth : PB_RENDER_MAX_SPECULAR_DEPTH);
  pb_json_int(&j, "max_bounces", o->set.max_bounces); /* 0: unbounded (Russian roulette) */
  pb_json_bool(&j, "timestamps", st->timestamps);
  pb_json_begin_object(&j, "passes_ms");
  pb_json_number(&j, "bvh_build", st->bvh_build_ms);
  pb_json_number(&j, "upload", st->upload_ms);
  if (st->timestamps) {
    pb_json_number(&j, "gbuffer", st->gbuffer_ms);
    pb_json_number(&j, "direct", st->direct_ms);
  } else {
    pb_json_null(&j, "gbuffer");
    pb_json_null(&j, "direct");
  }
  if (st->iterations) {
    pb_json_number(&j, "photon_trace", st->photon_trace_ms);
    pb_json_number(&j, "estimator_build", st->estimator_build_ms);
    pb_json_number(&j, "lbvh_build", st->estimator_build_ms); /* the former name, for readers */
    if (st->timestamps) pb_json_number(&j, "gather", st->gather_ms);
    else pb_json_null(&j, "gather");
    pb_json_number(&j, "filter", st->filter_ms);
  }
  pb_json_number(&j, "gpu_total", st->total_gpu_ms);
  pb_json_end_object(&j);
  if (st->iterations) {
    pb_json_begin_object(&j, "photons");
    pb_json_int(&j, "iterations", st->iterations);
    pb_json_int(&j, "emitted", (int64_t)st->photons_emitted);
    pb_json_int(&j, "stored", (int64_t)st->photons_stored);
    pb_json_int(&j, "caustic", (int64_t)st->photons_caustic);
    pb_json_int(&j, "clamped", (int64_t)st->photons_clamped); /* footprints at r_max */
    pb_json_number(&j, "clamped_share", st->photons_stored ? (double)st->photons_clamped / st->photons_stored : 0.0);
    /* The LBVH's (lbvh, knn): also under "estimator", kept here for the
     * readers of the former keys (bench/run_bench.py). */
    double t_auto = pb_render_estimator_stat(st, "t_auto", -1), leaf = pb_render_estimator_stat(st, "leaf_size", -1),
           leaves = pb_render_estimator_stat(st, "leaves", -1);
    if (t_auto >= 0) pb_json_int(&j, "t_auto", (int64_t)t_auto);
    if (leaf >= 0) pb_json_int(&j, "leaf_size", (int64_t)leaf);
    if (leaves >= 0) pb_json_int(&j, "lbvh_leaves", (int64_t)leaves);
    pb_json_number(&j, "k_pd", st->k_pd);
    pb_json_string(&j, "kernel", o->set.constant_kernel ? "constant" : "epanechnikov");
    pb_json_string(&j, "first_bounce", pb_settings_first_bounce_names[o->set.first_bounce]);
    pb_json_number(&j, "caustic_share", o->set.caustic_share);
    /* seed 003's variable bandwidth (--bandwidth-c0), 0: the differential footprints */
    pb_json_number(&j, "bandwidth_c0", o->set.bandwidth_c0);
    /* The photon tracer (render/photon/tracer.h) and its named statistics; the
     * images tracer's miss rate: segments no map confirmed, over all. */
    pb_json_string(&j, "tracer", st->tracer ? st->tracer : pb_tracer_names[o->set.tracer]);
    for (uint32_t i = 0; i < st->tracer_stat_count; ++i)
      pb_json_number(&j, st->tracer_stats[i].name, st->tracer_stats[i].value);
    double miss_rate = pb_render_image_miss_rate(st);
    if (miss_rate >= 0) pb_json_number(&j, "image_miss_rate", miss_rate);
    pb_json_int(&j, "atrous_iterations", rd->atrous_iterations);
    pb_json_int(&j, "upsample_levels", o->set.upsample_levels);
    double sort_ms = pb_render_estimator_stat(st, "sort_ms", -1);
    if (sort_ms >= 0) pb_json_number(&j, "lbvh_sort_ms", sort_ms);
    else pb_json_null(&j, "lbvh_sort_ms");
    if (st->radius_histogram) {
      /* Footprint radii over all maps (seed 000 Table 3): bins of r_max / 20
       * below the clamp, then the count at the clamp. */
      pb_json_begin_object(&j, "radius_histogram");
      pb_json_number(&j, "r_max_m", st->radius_r_max);
      pb_json_number(&j, "scene_radius_m", st->scene_radius);
      pb_json_number(&j, "bin_m", st->radius_r_max / (PB_RENDER_RADIUS_BINS - 1));
      pb_json_begin_array(&j, "counts");
      for (int b = 0; b < PB_RENDER_RADIUS_BINS; ++b) pb_json_int(&j, NULL, (int64_t)st->radius_hist[b]);
      pb_json_end_array(&j);
      pb_json_end_object(&j);
    }
    pb_json_end_object(&j);
    pb_render_json_estimator(&j, st);
  }
  /* Buffer memory photonbridge allocated on the device, at its peak (driver
   * and pipeline memory not included). */
  pb_json_begin_object(&j, "device_memory");
  pb_json_int(&j, "buffers_peak_bytes", (int64_t)pb_gpu_memory_peak(g));
  if (pb_gpu_memory_limit(g)) pb_json_int(&j, "limit_bytes", (int64_t)pb_gpu_memory_limit(g));
  else pb_json_null(&j, "limit_bytes");
  pb_json_end_object(&j);
  pb_render_plan pl;
  pb_render_plan_of(s, o->direct_only, &pl);
  pb_render_plan_json(&j, "pipeline", &pl); /* what the passes compiled in */
  pb_json_begin_object(&j, "guarded");
  pb_json_int(&j, "nonfinite_values", (int64_t)st->nonfinite_values);
  pb_json_int(&j, "photon_divisions", (int64_t)st->photon_guarded);
  pb_json_end_object(&j);
  /* What ended the refinement, and the render's own noise estimate
   * (render/frame/noise.h; null without a noise threshold or before two maps). */
  static const char *const stops[] = {"planned", "time_limit", "noise_threshold"};
  pb_json_string(&j, "stop", stops[st->stop >= 0 && st->stop < 3 ? st->stop : 0]);
  pb_json_begin_object(&j, "noise");
  if (o->noise_threshold > 0) {
    pb_json_number(&j, "threshold", o->noise_threshold);
    pb_json_number(&j, "threshold_psnr", -20.0 * log10(o->noise_threshold));
  } else {
    pb_json_null(&j, "threshold");
    pb_json_null(&j, "threshold_psnr");
  }
  if (st->noise_checks && st->noise_estimate >= 0) {
    pb_json_number(&j, "estimate", st->noise_estimate);
    if (isfinite(st->noise_psnr)) pb_json_number(&j, "psnr_estimate", st->noise_psnr);
    else pb_json_null(&j, "psnr_estimate");
  } else {
    pb_json_null(&j, "estimate");
    pb_json_null(&j, "psnr_estimate");
  }
  pb_json_int(&j, "checks", st->noise_checks);
  pb_json_end_object(&j);
  pb_json_number(&j, "wall_ms", st->wall_ms);
  /* The frame's wall and GPU time (timestamps; null without): the host's
   * share is (wall - gpu) / wall (bench/README.md). */
  pb_json_begin_object(&j, "timing");
  pb_json_number(&j, "frame_wall_ms", st->frame_wall_ms);
  if (st->frame_gpu_ms >= 0) pb_json_number(&j, "frame_gpu_ms", st->frame_gpu_ms);
  else pb_json_null(&j, "frame_gpu_ms");
  pb_json_end_object(&j);
  /* Host <-> device bytes of the frame (pb_render_stats): the readback's,
   * and what else went up or down (constants, scene data, photon counts). */
  pb_json_begin_object(&j, "transfers");
  pb_json_int(&j, "upload_bytes", (int64_t)st->upload_bytes);
  pb_json_int(&j, "download_bytes", (int64_t)st->download_bytes);
  pb_json_int(&j, "readback_bytes", (int64_t)st->readback_bytes);
  pb_json_end_object(&j);
  /* This render's compute pipelines: created (a driver compile) or taken
   * from the device's cache (`batch`'s later jobs). */
  pb_gpu_pipeline_stats ps = pb_gpu_pipeline_stats_get(g);
  pb_json_begin_object(&j, "pipelines");
  pb_json_int(&j, "created", (int64_t)(ps.created - o->pipes_at_open.created));
  pb_json_int(&j, "from_cache", (int64_t)(ps.reused - o->pipes_at_open.reused));
  pb_json_number(&j, "create_ms", ps.create_ms - o->pipes_at_open.create_ms);
  pb_json_end_object(&j);
  pb_json_int(&j, "primary_rays", (int64_t)st->primary_rays);
  pb_json_int(&j, "bvh_nodes", st->bvh_nodes);
  pb_json_int(&j, "bvh_depth", st->bvh_depth);
  pb_json_end_object(&j);
  return pb_json_close(&j, path, tmp);
}

int pb_cmd_render(int argc, char **argv) {
  const pb_command *cmd = self();
  pb_render_warn_reset(); /* once per command, also per job of `batch` */
  pb_core_opts c = {0};
  render_opts o = {.device = UINT32_MAX};
  int radius_histogram = 0;
  pb_color_opts co = PB_COLOR_OPTS_INIT;
  double gpu_memory_mb = 0; /* --gpu-memory-limit (faults) */
  pb_settings_init(&o.set);
  const pb_opt head[] = {
      PB_RENDER_OPTS_OUT(&c, "output file: .exr (scene-linear, every pass) or .png (the beauty, display-referred "
                             "through the OCIO view, as --png)"),
      PB_COLOR_OPTS(&co),
  };
  /* The settings' rows (the table, render/settings.h), then render's own. */
  const pb_opt tail[] = {
      {"radius-histogram", 0, PB_OPT_FLAG, &radius_histogram, NULL,
       "benchmark: bin every map's footprint radii into --json photons.radius_histogram (reads each map back; "
       "slows the render)", NULL, 0, 0, "Reporting", PB_OPT_ADVANCED},
      {"frames", 0, PB_OPT_STRING, &o.frames, "A:B",
       "render frames A to B (inclusive) of the scene's animation at time frame/fps; -o and --png then need a "
       "run of '#' for the frame number (out/frame_####.exr)", NULL, 0, 0, "Animation", 0},
      {"fps", 0, PB_OPT_FLOAT, &o.fps, "F", "--frames: frames per second (default 24)", NULL, 0, 0, "Animation", 0},
      {"warmup", 0, PB_OPT_U32, &o.warmup, "N",
       "--frames: first render the N frames before A (not written) to build the temporal history, so that a "
       "chunk of a shot continues as one run of the shot would (default 0)", NULL, 0, 10000, "Animation", 0},
      {"orbit", 0, PB_OPT_FLAG, &o.orbit, NULL,
       "--frames: move the camera on a circle around the scene's centre, one turn over the frames (or "
       "--orbit-seconds), looking at the centre", NULL, 0, 0, "Animation", 0},
      {"orbit-seconds", 0, PB_OPT_FLOAT, &o.orbit_seconds, "S", "--orbit: seconds per turn", NULL, 0, 0, "Animation", 0},
      {"bvh-update", 0, PB_OPT_CHOICE, &o.bvh_update, "MODE",
       "--frames: how moving geometry updates the scene BVH: auto, refit or rebuild (default auto)",
       bvh_update_names, 0, 0, "Animation", PB_OPT_ADVANCED},
      {"frames-in-flight", 0, PB_OPT_U32, &o.frames_in_flight, "N",
       "--frames: 2 (default): the GPU finishes a frame while the previous one is written and the next posed; "
       "1: one frame at a time (the same pixels either way; --reference-spp renders one at a time)", NULL, 1, 2, "Animation", PB_OPT_ADVANCED},
      {"reference-spp", 0, PB_OPT_U32, &o.reference_spp, "N",
       "--frames: render each frame with the reference renderer too (N samples per pixel, cached) and report "
       "per-frame error and flicker in --json", NULL, 1, 1 << 20, "Animation", PB_OPT_ADVANCED},
      {"reference-cache", 0, PB_OPT_STRING, &o.reference_cache, "DIR",
       "--reference-spp: cache folder (default: reference_cache beside -o)", NULL, 0, 0, "Animation", PB_OPT_ADVANCED},
      {"png", 0, PB_OPT_STRING, &o.png, "FILE", "also write a PNG of the beauty image through the OCIO view (--display/--view/--look)", NULL, 0, 0, "Output", 0},
      PB_DEVICE_OPTS(&o),
      {"gpu-memory-limit", 0, PB_OPT_FLOAT, &gpu_memory_mb, "MB", "cap on GPU buffer memory in MiB; a render that "
       "needs more fails with exit 11 (also PB_GPU_MEMORY_LIMIT)", NULL, 0, 1e9, "Device", PB_OPT_ADVANCED},
      {"crop", 0, PB_OPT_STRING, &o.crop, "X,Y,W,H",
       "render only the W x H pixels at column X, row Y (top row 0) of the --width x --height frame, with the "
       "frame's camera window and random numbers: with the same --iterations and --spp the crop equals that part of "
       "the full render (Blender's border; a noise threshold refines to the crop's own noise)",
       NULL, 0, 0, "Output", 0},
      {"preview", 0, PB_OPT_STRING, &o.preview, "FILE.exr",
       "after each finished iteration (but the last), write the image so far to FILE (beauty, atomically; the "
       "other passes 0)", NULL, 0, 0, "Output", 0},
      {"preview-interval", 0, PB_OPT_FLOAT, &o.preview_interval, "S",
       "--preview: at most one preview per S seconds (default 0: every iteration)", NULL, 0, 1e6, "Output", 0},
      {"progress-lines", 0, PB_OPT_FLAG, &o.progress_lines, NULL,
       "machine-readable progress on stderr: one 'photonbridge progress: {JSON}' line per stage, iteration, frame "
       "and at the end (for the Blender add-on)", NULL, 0, 0, "Blender add-on", PB_OPT_ADVANCED},
      {"blender-layer", 0, PB_OPT_STRING, &o.blender_layer, "NAME",
       "name the EXR's channels as Blender's multilayer EXR: NAME.Combined.R..A, NAME.Depth.Z, NAME.Normal.X..Z, "
       "NAME.Emit, NAME.Direct, NAME.Indirect, NAME.Caustic, NAME.Albedo (.R..B)", NULL, 0, 0, "Blender add-on", PB_OPT_ADVANCED},
      {"blender-passes", 0, PB_OPT_STRING, &o.blender_passes, "LIST",
       "--blender-layer: write only these passes (comma-separated; default all): the passes of Blender's render "
       "result, so that it finds every channel it reads and nothing else", NULL, 0, 0, "Blender add-on", PB_OPT_ADVANCED},
  };
  pb_opt opts[128];
  size_t nopts = 0;
  pb_opts_append(opts, &nopts, 128, head, sizeof head / sizeof *head);
  pb_settings_opts(&o.set, PB_SURFACE_RENDER, opts, &nopts, 128);
  pb_opts_append(opts, &nopts, 128, tail, sizeof tail / sizeof *tail);
  const char *pos[1];
  size_t npos;
  int help;
  unsigned char given[128];
  pb_result r = pb_cli_parse_given(cmd, argc, argv, opts, nopts, pos, 1, &npos, &help, given);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  pb_settings_mark_given(&o.set, opts, given, nopts);
  if (help) {
    pb_cli_print_help(stdout, help, cmd, opts, nopts,
                      "EXR layers: RGBA beauty, direct, albedo, normal, depth, material (index + 1),\n"
                      "emission, indirect, caustic; geo_normal, photon_dir in scenes with normal maps\n"
                      "(--blender-layer: Blender's names instead).\n"
                      "With photon mapping (default unless --direct-only; needs a point, spot or\n"
                      "directional light): also indirect and caustic layers, beauty = emission + direct\n"
                      "+ indirect + caustic.");
    return 0;
  }
  if (npos != 1 || !c.out)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: expected SCENE and -o OUT.exr (see 'photonbridge render --help')"));
  pb_render_out_format out_fmt;
  if ((r = pb_render_out_format_of(c.out, &out_fmt)) != PB_OK) return pb_cli_exit(cmd, r);
  if (out_fmt == PB_RENDER_OUT_PNG && o.blender_layer)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --blender-layer names EXR channels: write -o OUT.exr"));
  if ((r = pb_settings_check("render", &o.set, 1)) != PB_OK) return pb_cli_exit(cmd, r);
  int32_t first = 0, last = 0;
  if (o.frames && (r = pb_seq_parse_frames(o.frames, &first, &last)) != PB_OK) return pb_cli_exit(cmd, r);
  if (!o.frames && (o.orbit || o.fps != 0 || !o.set.temporal || o.reference_spp || o.reference_cache ||
                    o.orbit_seconds != 0 || o.warmup || o.frames_in_flight))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --orbit, --fps, --no-temporal, --warmup, "
                                    "--frames-in-flight and --reference-* need --frames A:B"));
  /* A sequence's names need the frame number: said before any work. */
  if (o.frames && last > first && (!strchr(c.out, '#') || (o.png && !strchr(o.png, '#'))))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: %s %s: a sequence needs '#' in the name for the frame "
                                    "number (out/frame_####.exr)", strchr(c.out, '#') ? "--png" : "-o",
                                    strchr(c.out, '#') ? o.png : c.out));
  if (o.frames && (int64_t)first - o.warmup < -1000000)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --warmup %u: frame %lld before the first "
                                    "allowed (-1000000)", o.warmup, (long long)first - o.warmup));
  if (o.frames && (o.fps < 0 || !(o.fps < 1e6) || o.orbit_seconds < 0 || !(o.orbit_seconds < 1e9)))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --fps and --orbit-seconds must be positive"));
  /* -q and -v hold from here (warnings below; the scene's load applies
   * them again). */
  if (c.quiet) pb_log_set_level(PB_LOG_QUIET);
  else if (c.verbose) pb_log_set_level(PB_LOG_VERBOSE);
  /* The frame's settings, resolved once (render/settings.h): the noise
   * threshold unless the work is set, the photon maps a threshold or a
   * time limit plans, --max-bounces' limits. */
  pb_render_desc rd;
  memset(&rd, 0, sizeof rd);
  pb_settings_render_desc(&o.set, o.frames != NULL, &rd);
  o.noise_threshold = rd.noise_threshold, o.time_limit = o.set.time_limit, o.direct_only = rd.direct_only;
  if ((o.set.given & PB_SETTING_BIT(noise_threshold)) && o.set.noise_threshold > 0 && (o.direct_only || o.frames))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --noise-threshold refines photon maps of one frame: "
                                    "not with --direct-only or --frames"));
  if (o.time_limit > 0 && !o.direct_only && !o.frames && rd.iterations == 1)
    pb_log_warn("render: --time-limit %g has no effect with --iterations 1 (one photon map): drop --iterations, "
                "or raise it, to refine until the time is up", o.time_limit);
  /* --progressive shrinks footprints between maps: one map has none. */
  if (rd.progressive && rd.iterations <= 1 && !o.direct_only && !o.frames && !(o.noise_threshold > 0))
    pb_log_warn("render: --progressive has no effect with one photon map: add --iterations K (K > 1) or "
                "--time-limit S");
  uint32_t crop[4] = {0, 0, 0, 0};
  if (o.crop && (r = parse_crop(o.crop, crop)) != PB_OK) return pb_cli_exit(cmd, r);
  if (o.frames && (o.crop || o.preview || o.time_limit > 0))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --crop, --preview and --time-limit render one frame; "
                                    "not with --frames"));
  if (o.blender_layer && (!o.blender_layer[0] || strchr(o.blender_layer, '.') || strlen(o.blender_layer) > 40))
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --blender-layer '%s': a view layer name of 1 to 40 "
                                    "characters without '.'", o.blender_layer));
  if (o.blender_passes && !o.blender_layer)
    return pb_cli_exit(cmd, pb_fail(PB_ERR_USAGE, "render: --blender-passes needs --blender-layer"));
  if ((r = pb_render_check_blender_passes(o.blender_passes)) != PB_OK) return pb_cli_exit(cmd, r);
  pb_progress_lines_enable(o.progress_lines);
  double t_start = pb_time_now();
  /* --progress-lines: its reader wants its own lines alone. */
  pb_render_bar_begin(!c.quiet && !o.progress_lines);
  pb_render_bar_stage("loading scene", 0, 0, -1);
  pb_scene s;
  /* Outputs that cannot be written fail now, not after the render
   * (sequences check their expanded names in render_seq.c). */
  if (!o.frames) {
    const char *outs[] = {c.out, o.png, c.json, o.preview};
    for (size_t i = 0; i < sizeof outs / sizeof *outs; ++i)
      if ((r = pb_check_writable(outs[i])) != PB_OK) return pb_cli_exit(cmd, r);
  }
  r = pb_cli_load_scene(pos[0], &c, &s);
  if (r != PB_OK) return pb_cli_exit(cmd, r);
  pb_progress_line_stage("loaded", pb_time_now() - t_start);
  int camera;
  uint32_t w, h;
  pb_gpu *g = NULL;
  pb_gpu_scene gs;
  memset(&gs, 0, sizeof gs);
  pb_render_result res;
  memset(&res, 0, sizeof res);
  pb_color *color = NULL;
  r = pb_cli_pick_camera(&s, &c, &camera, &w, &h);
  if (r == PB_OK) pb_cli_warn_clip("render", &s, camera);
  if (r != PB_OK) goto done;
  uint32_t full_w = w, full_h = h;
  if (o.crop) {
    if ((uint64_t)crop[0] + crop[2] > full_w || (uint64_t)crop[1] + crop[3] > full_h) {
      r = pb_fail(PB_ERR_USAGE, "render: --crop %s does not fit in the %ux%u frame", o.crop, full_w, full_h);
      goto done;
    }
    w = crop[2], h = crop[3];
  }
  /* The view is opened before any GPU work so that a misspelt view fails at
   * once. */
  if ((o.png || out_fmt == PB_RENDER_OUT_PNG) && (r = pb_color_opts_open_scene(&co, &s, &color)) != PB_OK) goto done;
  pb_render_bar_stage("starting the Vulkan device", 0, 0, -1);
  pb_gpu_desc gd = {.device_set = o.device != UINT32_MAX, .device = o.device, .validation = o.validation,
                    .traversal = o.traversal,
                    .memory_limit = (uint64_t)(gpu_memory_mb * 1048576.0)};
  r = pb_cli_gpu_open(&gd, &g); /* `batch` keeps it for its next job */
  if (r != PB_OK) goto done;
  o.pipes_at_open = pb_gpu_pipeline_stats_get(g);
  pb_cli_warn_cpu_device("render", g);
  if (o.set.estimator == PB_ESTIMATOR_SPLAT && !o.direct_only) {
    /* Splatting's own limit (estimator.c's auto rule, never chosen by auto):
     * caustics through glass stay biased whatever the photon count. */
    pb_render_plan pl;
    pb_render_plan_of(&s, 0, &pl);
    if (pl.photons && pl.refraction && pl.caustic_photons)
      pb_log_warn("render: %s: --estimator splat is biased on caustics through glass (it stays at 18-19 dB on "
                  "cornell_caustics whatever the photon count, docs/benchmarks.md); --estimator lbvh converges",
                  s.path);
  }
  pb_log_verbose("render: %s on %s, %ux%u, %u spp", s.path, pb_gpu_device_name(g), w, h, rd.spp ? rd.spp : 1);
  pb_render_bar_stage("building BVH, uploading the scene", 0, 0, -1);
  r = pb_gpu_scene_create(g, &s, &gs);
  if (r != PB_OK) goto done;
  pb_progress_line_stage("uploaded", pb_time_now() - t_start);
  rd.seed = c.seed;
  rd.radius_histogram = radius_histogram;
  rd.preview_interval_s = o.preview ? o.preview_interval : -1.0;
  progress_ctx pctx = {&o};
  pb_render_io rio = {.progress = on_progress, .progress_user = &pctx}; /* the bar, --preview, --progress-lines */
  if (o.crop) rd.full_width = full_w, rd.full_height = full_h, rd.crop_x = crop[0], rd.crop_y = crop[1];
  if (o.frames) {
    static const int bvh_modes[] = {PB_BVH_UPDATE_AUTO, PB_BVH_UPDATE_REFIT, PB_BVH_UPDATE_REBUILD};
    double fps = o.fps > 0 ? o.fps : 24.0;
    pb_sequence_desc sd = {.render = rd, .temporal = o.set.temporal, .bvh_update = bvh_modes[o.bvh_update],
                           .orbit = o.orbit,
                           .orbit_period = o.orbit_seconds > 0 ? o.orbit_seconds : (double)(last - first + 1) / fps,
                           /* The reference renderer poses from the scene, which holds the next
                            * frame's pose while a frame is in flight: one at a time then. */
                           .frames_in_flight = o.reference_spp ? 1 : (o.frames_in_flight ? o.frames_in_flight : 2),
                           .progress = rio.progress, .progress_user = rio.progress_user};
    pb_seq_opts so = {.first = first, .last = last, .warmup = o.warmup, .fps = fps, .png = o.png,
                      .reference_spp = o.reference_spp, .reference_cache = o.reference_cache,
                      .blender_layer = o.blender_layer, .blender_passes = o.blender_passes};
    r = pb_render_sequence(g, &s, &gs, camera, w, h, &sd, &so, &c, color);
    goto done;
  }
  {
    char stage[96];
    uint32_t maps = rd.direct_only ? 0 : (rd.iterations ? rd.iterations : 1);
    if (o.noise_threshold > 0)
      snprintf(stage, sizeof stage, "photon map 0 (noise threshold %.1f dB)", -20.0 * log10(o.noise_threshold));
    else if (o.time_limit > 0) snprintf(stage, sizeof stage, "photon map 0 (time limit %gs)", o.time_limit);
    else if (maps) snprintf(stage, sizeof stage, "photon map 0/%u", maps);
    else snprintf(stage, sizeof stage, "direct light, %u samples", rd.spp ? rd.spp : 1);
    pb_render_bar_stage(stage, 0, o.time_limit > 0 || o.noise_threshold > 0 ? 0 : maps, -1);
  }
  r = pb_render_frame_io(g, &s, &gs, camera, w, h, &rd, &rio, &res);
  if (r != PB_OK) goto done;
  pb_render_warn_reliability("render", &res.stats);
  {
    char stage[PB_PATH_STAGE];
    snprintf(stage, sizeof stage, "writing %s", c.out);
    pb_render_bar_stage(stage, 0, 0, -1);
  }

  /* Outputs, each atomic; a later failure removes the earlier ones. */
  char spp_s[32];
  snprintf(spp_s, sizeof spp_s, "%u", res.stats.spp);
  const char *an[] = {"photonbridge/renderer", "photonbridge/device", "photonbridge/spp", "photonbridge/mode"};
  const char *av[] = {"gpu", pb_gpu_device_name(g), spp_s, o.direct_only ? "direct-only" : (res.indirect ? "photon-mapping" : "direct+specular")};
  if (out_fmt == PB_RENDER_OUT_PNG) r = pb_png_write_display(c.out, color, w, h, 4, res.beauty);
  else r = pb_render_write_exr(c.out, &res, o.blender_layer, o.blender_passes, an, av, 4);
  if (r == PB_OK && o.png) {
    r = pb_png_write_display(o.png, color, w, h, 4, res.beauty);
    if (r != PB_OK) unlink(c.out);
  }
  if (r == PB_OK && c.json) {
    r = write_json(c.json, &s, g, &res, &o, &rd);
    if (r != PB_OK) {
      unlink(c.out);
      if (o.png) unlink(o.png);
    }
  }
  pb_render_bar_end();
  if (r == PB_OK) pb_progress_line_done(c.out, pb_time_now() - t_start);
  if (r == PB_OK && !c.quiet) {
    const pb_render_stats *st = &res.stats;
    if (st->timestamps)
      pb_log_info("render: %ux%u, %u spp on %s: gbuffer %.1f ms, direct %.1f ms (GPU), %.0f ms wall -> %s", w, h,
                  st->spp, pb_gpu_device_name(g), st->gbuffer_ms, st->direct_ms, st->wall_ms, c.out);
    else
      pb_log_info("render: %ux%u, %u spp on %s: %.0f ms -> %s", w, h, st->spp, pb_gpu_device_name(g), st->wall_ms,
                  c.out);
    if (st->iterations)
      pb_log_info("render: photons: %u maps, %llu emitted, %llu stored (%llu caustic), k_PD %.1f, estimator %s; trace "
                  "%.0f ms, build %.0f ms, estimate %.0f ms; device buffers peak %.1f MiB", st->iterations,
                  (unsigned long long)st->photons_emitted, (unsigned long long)st->photons_stored, (unsigned long long)st->photons_caustic, st->k_pd,
                  st->estimator ? st->estimator : "none", st->photon_trace_ms, st->estimator_build_ms, st->gather_ms,
                  (double)pb_gpu_memory_peak(g) / 1048576.0);
    if (st->nonfinite_values)
      pb_log_warn("render: %llu NaN/Inf values in the result were written as 0 (a pass failed to guard them)",
                  (unsigned long long)st->nonfinite_values);
  }
done:
  pb_color_destroy(color);
  pb_render_result_destroy(&res);
  pb_gpu_scene_destroy(g, &gs);
  pb_cli_gpu_close(g);
  pb_scene_destroy(&s);
  return pb_cli_exit(cmd, r);
}
