/* render --frames A:B (render_seq.h): frames rendered by render/frame/sequence.h,
 * each written as its own EXR (atomically, so a failure leaves only whole
 * frames behind), after --warmup N unwritten frames before A that build the
 * temporal history (a chunk of a shot on a farm), with optional
 * per-frame references and metrics:
 *
 *  error    per frame, the result against the reference renderer's render
 *           of the same pose (src/ref, cached on disk by content: the posed
 *           geometry, lights, camera, size, samples and seed), as PSNR of
 *           the display image and relMSE (metrics.h);
 *  flicker  mean over pixels and R,G,B of |I_f - I_{f-1}| (scene-linear
 *           beauty) averaged over the frame pairs, for the result and for
 *           the reference; the excess flicker is the difference: the
 *           frame-to-frame change the renderer adds to the change the
 *           motion itself causes. */
#include "app/render_seq.h"
#include "app/render_out.h"

#include <errno.h>
#include <inttypes.h>
#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/fs.h"
#include "core/json.h"
#include "core/log.h"
#include "core/version.h"
#include "image/image.h"
#include "metrics/metrics.h"
#include "ref/ref.h"

enum { MAX_FRAMES = 100000 };

pb_result pb_seq_parse_frames(const char *text, int32_t *first, int32_t *last) {
  char *end;
  errno = 0;
  long a = strtol(text, &end, 10), b = a;
  if (end == text || errno) goto bad;
  if (*end == ':') {
    const char *p = end + 1;
    b = strtol(p, &end, 10);
    if (end == p || errno) goto bad;
  }
  if (*end || a < -1000000 || b > 1000000 || b < a) goto bad;
  if (b - a + 1 > MAX_FRAMES)
    return pb_fail(PB_ERR_USAGE, "render: --frames %s: %ld frames (at most %d)", text, b - a + 1, MAX_FRAMES);
  *first = (int32_t)a;
  *last = (int32_t)b;
  return PB_OK;
bad:
  return pb_fail(PB_ERR_USAGE, "render: --frames '%s': expected A:B, two frame numbers with A <= B", text);
}

pb_result pb_seq_frame_path(const char *pattern, int32_t frame, char *out, size_t size) {
  const char *h = strchr(pattern, '#');
  if (!h) {
    if (snprintf(out, size, "%s", pattern) >= (int)size) goto long_name;
    return PB_OK;
  }
  size_t run = strspn(h, "#");
  if (strchr(h + run, '#'))
    return pb_fail(PB_ERR_USAGE, "render: output pattern '%s' has two runs of '#'", pattern);
  int n = snprintf(out, size, "%.*s%0*" PRId32 "%s", (int)(h - pattern), pattern, (int)run, frame, h + run);
  if (n < 0 || (size_t)n >= size) goto long_name;
  return PB_OK;
long_name:
  return pb_fail(PB_ERR_USAGE, "render: output path from '%s' too long", pattern);
}

/* ---- the reference cache --------------------------------------------------- */

static uint64_t fnv(uint64_t h, const void *data, size_t n) {
  const unsigned char *p = data;
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

/* Content key of a reference render: the reference renderer's version (the
 * program's version and git description, and its path-length rule: a cache
 * written before the unbounded default held 8-event references), the scene file (path,
 * size, time), the posed geometry, lights and camera, and the reference's
 * settings. Fields are hashed one by one (no struct padding). */
static uint64_t reference_key(const pb_scene *s, const pb_camera *cam, uint32_t w, uint32_t h, uint32_t spp,
                              uint64_t seed) {
  uint64_t k = 0xcbf29ce484222325ull;
  k = fnv(k, "pbref2", 6);
  k = fnv(k, PB_VERSION, strlen(PB_VERSION));
  k = fnv(k, PB_GIT_DESCRIBE, strlen(PB_GIT_DESCRIBE));
  const uint32_t cap = PB_REF_BOUNCE_CAP;
  k = fnv(k, &cap, sizeof cap);
  k = fnv(k, s->path, strlen(s->path));
  struct stat st;
  if (stat(s->path, &st) == 0) {
    int64_t v[2] = {(int64_t)st.st_size, (int64_t)st.st_mtime};
    k = fnv(k, v, sizeof v);
  }
  k = fnv(k, s->positions, (size_t)s->vertex_count * sizeof *s->positions);
  k = fnv(k, s->normals, (size_t)s->vertex_count * sizeof *s->normals);
  for (uint32_t i = 0; i < s->light_count; ++i) {
    const pb_light *l = &s->lights[i];
    float f[13] = {l->position[0], l->position[1], l->position[2], l->direction[0], l->direction[1], l->direction[2],
                   l->color[0], l->color[1], l->color[2], l->intensity, l->inner_cone, l->outer_cone, l->range};
    k = fnv(k, f, sizeof f);
    k = fnv(k, &l->type, sizeof l->type);
  }
  float c[19] = {cam->position[0], cam->position[1], cam->position[2], cam->forward[0], cam->forward[1],
                 cam->forward[2], cam->up[0], cam->up[1], cam->up[2], cam->right[0], cam->right[1], cam->right[2],
                 cam->yfov, cam->ortho_size, cam->shift[0], cam->shift[1], cam->znear, cam->zfar,
                 (float)(cam->orthographic * 4 + (int)cam->fit)};
  k = fnv(k, c, sizeof c);
  float lens[14] = {cam->aperture_radius, cam->focus_distance, cam->aperture_rotation, cam->aperture_ratio,
                    (float)cam->aperture_blades, (float)cam->panorama, cam->latitude[0], cam->latitude[1],
                    cam->longitude[0], cam->longitude[1], cam->fisheye_fov, cam->fisheye_lens, cam->sensor[0],
                    cam->sensor[1]};
  k = fnv(k, lens, sizeof lens);
  uint64_t v[4] = {w, h, spp, seed};
  return fnv(k, v, sizeof v);
}

/* The reference beauty (RGBA) of the current pose: read from the cache or
 * rendered and stored there (at `path`, PATH_MAX bytes). *cached: whether
 * it came from the cache. */
static pb_result reference_frame(pb_scene *s, int camera, uint32_t w, uint32_t h, const pb_seq_opts *so,
                                 uint64_t seed, const char *cache_dir, float *rgba, int *cached, double *ms,
                                 char *path) {
  uint64_t key = reference_key(s, &s->cameras[camera], w, h, so->reference_spp, seed);
  if (snprintf(path, PATH_MAX, "%s/ref_%016" PRIx64 ".exr", cache_dir, key) >= PATH_MAX)
    return pb_fail(PB_ERR_USAGE, "render: reference cache path too long");
  *cached = 0;
  *ms = 0;
  pb_image img;
  if (access(path, R_OK) == 0 && pb_exr_read(path, NULL, &img) == PB_OK) {
    int ch[4] = {pb_image_find_channel(&img, "R"), pb_image_find_channel(&img, "G"), pb_image_find_channel(&img, "B"),
                 pb_image_find_channel(&img, "A")};
    int ok = img.width == w && img.height == h && ch[0] >= 0 && ch[1] >= 0 && ch[2] >= 0 && ch[3] >= 0;
    if (ok) {
      for (size_t i = 0; i < (size_t)w * h; ++i)
        for (int k = 0; k < 4; ++k) rgba[4 * i + k] = img.pixels[i * img.channel_count + (size_t)ch[k]];
      *cached = 1;
    }
    pb_image_destroy(&img);
    if (ok) return PB_OK;
    pb_log_warn("render: reference cache entry %s unusable; rendering it again", path);
  }
  pb_error_clear();
  pb_ref_desc d = {.spp = so->reference_spp, .seed = seed};
  pb_ref_result res;
  double t0 = pb_time_now();
  pb_result r = pb_ref_render(s, camera, w, h, &d, &res);
  if (r != PB_OK) return r;
  *ms = (pb_time_now() - t0) * 1e3;
  memcpy(rgba, res.beauty, (size_t)w * h * 4 * sizeof *rgba);
  pb_image_layer layer = {"", 4, res.beauty, NULL};
  const char *an[] = {"photonbridge/renderer"};
  const char *av[] = {"reference"};
  pb_exr_desc ed = {.width = w, .height = h, .layers = &layer, .layer_count = 1, .attr_names = an,
                    .attr_values = av, .attr_count = 1};
  r = pb_exr_write(path, &ed);
  pb_ref_result_destroy(&res);
  return r;
}

static double mean_abs_change(const float *a, const float *b, size_t pixels) {
  double sum = 0;
  for (size_t i = 0; i < pixels; ++i)
    for (int k = 0; k < 3; ++k) sum += fabs((double)a[4 * i + k] - b[4 * i + k]);
  return pixels ? sum / (3.0 * (double)pixels) : 0.0;
}

/* ---- frames ------------------------------------------------------------------ */

typedef struct frame_record {
  int32_t frame;
  pb_sequence_frame_info info;
  pb_render_stats stats;
  double psnr, relmse, flicker_result, flicker_reference; /* NAN when absent */
  int reference_cached;
  double reference_ms;
  char reference_file[PATH_MAX]; /* the cached reference EXR of this frame */
} frame_record;

static void json_frame(pb_json *j, const frame_record *f, uint64_t pixels) {
  const pb_render_stats *st = &f->stats;
  pb_json_begin_object(j, NULL);
  pb_json_int(j, "frame", f->frame);
  pb_json_number(j, "time_s", f->info.time);
  pb_json_bool(j, "still", f->info.still);
  pb_json_bool(j, "geometry_moved", f->info.geometry_moved);
  pb_json_bool(j, "lights_moved", f->info.lights_moved);
  pb_json_bool(j, "camera_moved", f->info.camera_moved);
  pb_json_number(j, "wall_ms", st->wall_ms);
  pb_json_begin_object(j, "timing"); /* the whole frame (pb_render_stats.frame_*_ms) */
  pb_json_number(j, "frame_wall_ms", st->frame_wall_ms);
  if (st->frame_gpu_ms >= 0) pb_json_number(j, "frame_gpu_ms", st->frame_gpu_ms);
  else pb_json_null(j, "frame_gpu_ms");
  pb_json_number(j, "frame_interval_ms", st->frame_interval_ms);
  pb_json_bool(j, "in_flight", st->in_flight);
  pb_json_bool(j, "record_overlapped", st->record_overlapped); /* recorded before the previous frame was waited for */
  pb_json_bool(j, "record_running", st->record_running);       /* ... and while it still ran on the GPU */
  pb_json_bool(j, "still_on_gpu", st->still_on_gpu); /* a still run averaged on the GPU */
  pb_json_end_object(j);
  /* Host <-> device bytes of the frame (pb_render_stats): the readback's,
   * and what else went up or down (constants, scene data, photon counts). */
  pb_json_begin_object(j, "transfers");
  pb_json_int(j, "upload_bytes", (int64_t)st->upload_bytes);
  pb_json_int(j, "download_bytes", (int64_t)st->download_bytes);
  pb_json_int(j, "readback_bytes", (int64_t)st->readback_bytes);
  pb_json_int(j, "ring_bytes", (int64_t)st->ring_bytes);
  pb_json_end_object(j);
  pb_json_begin_object(j, "passes_ms");
  pb_json_number(j, "pose", f->info.pose_ms);
  pb_json_number(j, "pose_cpu", f->info.pose_cpu_ms);
  pb_json_number(j, "scene_update", f->info.scene_update_ms);
  if (st->timestamps) {
    pb_json_number(j, "gbuffer", st->gbuffer_ms);
    pb_json_number(j, "direct", st->direct_ms);
  }
  if (st->iterations) {
    pb_json_number(j, "photon_trace", st->photon_trace_ms);
    pb_json_number(j, "estimator_build", st->estimator_build_ms);
    pb_json_number(j, "lbvh_build", st->estimator_build_ms); /* the former name, for readers */
    if (st->timestamps) pb_json_number(j, "gather", st->gather_ms);
  }
  pb_json_number(j, "motion", f->info.motion_ms);
  pb_json_number(j, "temporal", st->temporal_ms);
  pb_json_number(j, "atrous", st->filter_ms);
  pb_json_end_object(j);
  if (st->temporal_surface_pixels) {
    pb_json_begin_object(j, "temporal");
    pb_json_number(j, "reset_fraction", (double)st->temporal_reset_pixels / (double)st->temporal_surface_pixels);
    pb_json_number(j, "mean_history", st->temporal_mean_history);
    pb_json_end_object(j);
  }
  if (st->iterations) {
    pb_json_begin_object(j, "photons");
    pb_json_int(j, "emitted", (int64_t)st->photons_emitted);
    pb_json_int(j, "stored", (int64_t)st->photons_stored);
    if (st->tracer) pb_json_string(j, "tracer", st->tracer); /* render/photon/tracer.h and its statistics */
    for (uint32_t i = 0; i < st->tracer_stat_count; ++i)
      pb_json_number(j, st->tracer_stats[i].name, st->tracer_stats[i].value);
    double miss_rate = pb_render_image_miss_rate(st);
    if (miss_rate >= 0) pb_json_number(j, "image_miss_rate", miss_rate);
    pb_json_end_object(j);
    pb_render_json_estimator(j, st);
  }
  (void)pixels;
  if (!isnan(f->psnr)) {
    pb_json_begin_object(j, "reference");
    pb_json_number(j, "psnr_db", f->psnr);
    pb_json_number(j, "relmse", f->relmse);
    if (!isnan(f->flicker_result)) {
      pb_json_number(j, "change_result", f->flicker_result);
      pb_json_number(j, "change_reference", f->flicker_reference);
    }
    pb_json_bool(j, "cached", f->reference_cached);
    pb_json_string(j, "file", f->reference_file);
    pb_json_number(j, "render_ms", f->reference_ms);
    pb_json_end_object(j);
  }
  pb_json_end_object(j);
}

static pb_result write_json(const char *path, const pb_scene *s, const pb_gpu *g, uint32_t w, uint32_t h,
                            const pb_sequence_desc *sd, const pb_seq_opts *so, const frame_record *fr, size_t n) {
  pb_json j;
  char *tmp;
  pb_result r = pb_json_open(&j, path, &tmp);
  if (r != PB_OK) return r;
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "renderer", "gpu");
  pb_json_string(&j, "scene", s->path);
  pb_json_string(&j, "device", pb_gpu_device_name(g));
  pb_json_string(&j, "device_type", pb_gpu_device_type(g));
  pb_json_string(&j, "traversal", pb_gpu_traversal(g));
  pb_json_int(&j, "width", w);
  pb_json_int(&j, "height", h);
  pb_json_number(&j, "fps", so->fps);
  pb_json_int(&j, "first_frame", so->first);
  pb_json_int(&j, "last_frame", so->last);
  pb_json_int(&j, "warmup_frames", so->warmup);
  pb_json_begin_object(&j, "filters");
  pb_json_bool(&j, "temporal", sd->temporal);
  pb_json_int(&j, "atrous_iterations", sd->render.atrous_iterations);
  pb_json_end_object(&j);
  pb_json_bool(&j, "orbit", sd->orbit);
  pb_json_int(&j, "frames_in_flight", sd->frames_in_flight >= 2 ? 2 : 1);
  pb_json_begin_array(&j, "frames");
  for (size_t i = 0; i < n; ++i) json_frame(&j, &fr[i], (uint64_t)w * h);
  pb_json_end_array(&j);
  /* Summary: means over frames (error) and over frame pairs (flicker). */
  double ps = 0, rm = 0, fl_r = 0, fl_ref = 0, filt = 0, wall = 0;
  size_t np = 0, nf = 0, overlapped = 0, running = 0;
  for (size_t i = 0; i < n; ++i) {
    overlapped += fr[i].stats.record_overlapped != 0;
    running += fr[i].stats.record_running != 0;
    filt += fr[i].stats.temporal_ms + fr[i].stats.filter_ms;
    wall += fr[i].stats.wall_ms;
    if (!isnan(fr[i].psnr)) ps += fr[i].psnr, rm += fr[i].relmse, ++np;
    if (!isnan(fr[i].flicker_result)) fl_r += fr[i].flicker_result, fl_ref += fr[i].flicker_reference, ++nf;
  }
  pb_json_begin_object(&j, "summary");
  pb_json_int(&j, "frames", (int64_t)n);
  pb_json_number(&j, "mean_wall_ms", n ? wall / (double)n : 0);
  pb_json_number(&j, "mean_filter_ms", n ? filt / (double)n : 0);
  /* Frames in flight: frames recorded while the previous frame's last
   * submission ran, and what the submission ring did (gpu.h). */
  pb_json_int(&j, "records_overlapped", (int64_t)overlapped);
  pb_json_int(&j, "records_running", (int64_t)running);
  pb_gpu_ring_stats rs = pb_gpu_ring_stats_get(g);
  pb_json_begin_object(&j, "gpu_ring");
  pb_json_int(&j, "contexts", PB_GPU_FRAMES);
  pb_json_int(&j, "submissions", (int64_t)rs.submissions);
  pb_json_int(&j, "async_submissions", (int64_t)rs.async_submissions);
  pb_json_int(&j, "begin_waits", (int64_t)rs.begin_waits);
  pb_json_int(&j, "held_stolen", (int64_t)rs.held_stolen);
  pb_json_int(&j, "deferred_writes", (int64_t)rs.deferred_writes);
  pb_json_int(&j, "deferred_bytes", (int64_t)rs.deferred_bytes);
  pb_json_int(&j, "bind_skips", (int64_t)rs.bind_skips);
  pb_json_int(&j, "late_writes", (int64_t)rs.late_writes);
  pb_json_end_object(&j);
  if (np) {
    pb_json_int(&j, "reference_spp", so->reference_spp);
    pb_json_number(&j, "mean_psnr_db", ps / (double)np);
    pb_json_number(&j, "mean_relmse", rm / (double)np);
  }
  if (nf) {
    pb_json_number(&j, "flicker_result", fl_r / (double)nf);
    pb_json_number(&j, "flicker_reference", fl_ref / (double)nf);
    pb_json_number(&j, "flicker_excess", (fl_r - fl_ref) / (double)nf);
  }
  pb_json_end_object(&j);
  pb_json_end_object(&j);
  return pb_json_close(&j, path, tmp);
}

static pb_result ensure_dir(const char *dir) {
  if (mkdir(dir, 0777) == 0 || errno == EEXIST) {
    struct stat st;
    if (stat(dir, &st) == 0 && S_ISDIR(st.st_mode)) return PB_OK;
  }
  return pb_fail(PB_ERR_IO, "%s: cannot create the reference cache folder: %s", dir, strerror(errno));
}

pb_result pb_render_sequence(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, int camera, uint32_t w, uint32_t h,
                             const pb_sequence_desc *sd, const pb_seq_opts *so, const pb_core_opts *c,
                             pb_color *color) {
  size_t count = (size_t)(so->last - so->first) + 1;
  if (count > 1 && !strchr(c->out, '#'))
    return pb_fail(PB_ERR_USAGE, "render: -o %s: a sequence needs '#' in the name for the frame number "
                   "(out/frame_####.exr)", c->out);
  if (so->png && count > 1 && !strchr(so->png, '#'))
    return pb_fail(PB_ERR_USAGE, "render: --png %s: a sequence needs '#' in the name for the frame number", so->png);
  char path[PATH_MAX], png[PATH_MAX];
  /* Every output path is checked before the first frame renders. */
  if (c->json) {
    pb_result r = pb_check_writable(c->json);
    if (r != PB_OK) return r;
  }
  for (int32_t f = so->first; f <= so->last; ++f) {
    pb_result r = pb_seq_frame_path(c->out, f, path, sizeof path);
    if (r == PB_OK) r = pb_check_writable(path);
    if (r == PB_OK && so->png && (r = pb_seq_frame_path(so->png, f, png, sizeof png)) == PB_OK) r = pb_check_writable(png);
    if (r != PB_OK) return r;
    if (f - so->first > 2 && f != so->last) f = so->last - 1; /* first frames and the last suffice */
  }
  char *cache_dir = NULL;
  size_t pixels = (size_t)w * h;
  double t_start = pb_time_now();
  float *ref = NULL, *ref_prev = NULL, *res_prev = NULL;
  frame_record *rec = calloc(count, sizeof *rec);
  pb_sequence *q = NULL;
  pb_render_result res;
  memset(&res, 0, sizeof res);
  pb_result r = PB_OK;
  if (!rec) return pb_fail(PB_ERR_NOMEM, "render: out of memory");
  res_prev = malloc(pixels * 4 * sizeof *res_prev);
  if (so->reference_spp) {
    if (so->reference_cache) {
      cache_dir = strdup(so->reference_cache);
    } else {
      char *d = pb_dirname(c->out);
      size_t n = d ? strlen(d) + 32 : 0;
      cache_dir = d ? malloc(n) : NULL;
      if (cache_dir) snprintf(cache_dir, n, "%s/reference_cache", d);
      free(d);
    }
    ref = malloc(pixels * 4 * sizeof *ref);
    ref_prev = malloc(pixels * 4 * sizeof *ref_prev);
    if (!cache_dir || !ref || !ref_prev) {
      r = pb_fail(PB_ERR_NOMEM, "render: out of memory");
      goto done;
    }
    if ((r = ensure_dir(cache_dir)) != PB_OK) goto done;
  }
  if (!res_prev) {
    r = pb_fail(PB_ERR_NOMEM, "render: out of memory");
    goto done;
  }
  if ((r = pb_sequence_create(g, s, gs, camera, w, h, sd, &q)) != PB_OK) goto done;
  /* Warm-up: the frames first-warmup .. first-1 render as they
   * would in a run of the whole shot (the photon seeds follow the frame
   * number, not the position in this run) and fill the temporal history;
   * none is written. The last one's reference gives the first written
   * frame its flicker.
   *
   * With frames in flight (sd->frames_in_flight 2, sequence.h) a call
   * returns the frame before the one it started (info.ready, info.index),
   * and the flush after the last call the last: the loop handles whatever
   * frame comes out, by its number, while the GPU runs the next. */
  size_t total = (size_t)so->warmup + count;
  int32_t f0 = so->first - (int32_t)so->warmup;
  {
    char stage[64];
    snprintf(stage, sizeof stage, "frame 0/%zu%s", count, so->warmup ? " (warming up)" : "");
    pb_render_bar_stage(stage, 0, count, -1);
  }
  for (size_t k = 0; k <= total; ++k) {
    pb_sequence_frame_info info;
    if (k < total) {
      int32_t fk = f0 + (int32_t)k;
      if ((r = pb_sequence_frame(g, q, (uint32_t)fk, (double)fk / so->fps, &res, &info)) != PB_OK) goto done;
    } else if ((r = pb_sequence_flush(g, q, &res, &info)) != PB_OK) {
      goto done;
    }
    if (!info.ready) continue;
    int32_t f = (int32_t)info.index; /* the frame that came out (indices wrap like frame numbers) */
    double t = (double)f / so->fps;
    size_t kk = (size_t)(int64_t)(f - f0);
    if (f < f0 || kk >= total) {
      r = pb_fail(PB_ERR_INTERNAL, "render: the sequence returned frame %" PRId32 ", not one of this run", f);
      goto done;
    }
    if (kk < so->warmup) {
      if (kk + 1 == so->warmup) {
        memcpy(res_prev, res.beauty, pixels * 4 * sizeof *res_prev);
        if (so->reference_spp) {
          int cached;
          double ms;
          char file[PATH_MAX];
          if ((r = reference_frame(s, camera, w, h, so, c->seed, cache_dir, ref_prev, &cached, &ms, file)) != PB_OK)
            goto done;
        }
      }
      if (!c->quiet)
        pb_log_info("render: warm-up frame %" PRId32 " (t %.3f s): %.0f ms, not written", f, t, res.stats.wall_ms);
      pb_render_result_destroy(&res);
      continue;
    }
    size_t i = kk - so->warmup;
    frame_record *fr = &rec[i];
    fr->frame = f;
    fr->psnr = fr->relmse = fr->flicker_result = fr->flicker_reference = NAN;
    fr->info = info;
    fr->stats = res.stats;
    if (so->reference_spp) {
      if ((r = reference_frame(s, camera, w, h, so, c->seed, cache_dir, ref, &fr->reference_cached,
                               &fr->reference_ms, fr->reference_file)) != PB_OK)
        goto done;
      pb_metrics m;
      if ((r = pb_metrics_compute(res.beauty, ref, w, h, 4, NULL, &m)) != PB_OK) goto done;
      fr->psnr = m.psnr;
      fr->relmse = m.relmse;
      if (i > 0 || so->warmup > 0) {
        fr->flicker_result = mean_abs_change(res.beauty, res_prev, pixels);
        fr->flicker_reference = mean_abs_change(ref, ref_prev, pixels);
      }
      memcpy(ref_prev, ref, pixels * 4 * sizeof *ref);
    }
    memcpy(res_prev, res.beauty, pixels * 4 * sizeof *res_prev);
    /* The frame's files, each atomic. */
    char spp_s[32], time_s[32], frame_s[32];
    snprintf(spp_s, sizeof spp_s, "%u", res.stats.spp);
    snprintf(time_s, sizeof time_s, "%.9g", t);
    snprintf(frame_s, sizeof frame_s, "%" PRId32, f);
    const char *an[] = {"photonbridge/renderer", "photonbridge/device", "photonbridge/spp", "photonbridge/frame",
                        "photonbridge/time"};
    const char *av[] = {"gpu", pb_gpu_device_name(g), spp_s, frame_s, time_s};
    if ((r = pb_seq_frame_path(c->out, f, path, sizeof path)) != PB_OK) goto done;
    pb_render_out_format fmt = PB_RENDER_OUT_EXR;
    if ((r = pb_render_out_format_of(path, &fmt)) != PB_OK) goto done;
    if (fmt == PB_RENDER_OUT_PNG) r = pb_png_write_display(path, color, w, h, 4, res.beauty);
    else r = pb_render_write_exr(path, &res, so->blender_layer, so->blender_passes, an, av, 5);
    if (r != PB_OK) goto done;
    if (so->png) {
      if ((r = pb_seq_frame_path(so->png, f, png, sizeof png)) != PB_OK) goto done;
      if ((r = pb_png_write_display(png, color, w, h, 4, res.beauty)) != PB_OK) goto done;
    }
    /* An interrupt from now on keeps the finished frames (each file whole). */
    pb_tmp_set_interrupt_note("the frames written before it are complete; the frame in progress was not written");
    pb_progress_line_frame(f, (uint32_t)i, (uint32_t)count, path);
    {
      char stage[64];
      double el = pb_time_now() - t_start;
      snprintf(stage, sizeof stage, "frame %zu/%zu", (size_t)i + 1, count);
      pb_render_bar_stage(stage, (uint64_t)i + 1, count, el / (double)(i + 1) * (double)(count - (size_t)i - 1));
    }
    pb_render_warn_reliability("render", &res.stats);
    if (!c->quiet) {
      const pb_render_stats *st = &res.stats;
      char metric[96] = "";
      if (!isnan(fr->psnr)) snprintf(metric, sizeof metric, ", %.2f dB against the reference", fr->psnr);
      pb_log_info("render: frame %" PRId32 " (t %.3f s%s): %.0f ms, filters %.2f ms%s -> %s", f, t,
                  fr->info.still ? ", still" : "", st->wall_ms, st->temporal_ms + st->filter_ms, metric, path);
    }
    pb_render_result_destroy(&res);
  }
  pb_render_bar_end();
  if (c->json) r = write_json(c->json, s, g, w, h, sd, so, rec, count);
  if (r == PB_OK) pb_progress_line_done(c->out, pb_time_now() - t_start);
done:
  pb_tmp_set_interrupt_note(NULL);
  pb_render_result_destroy(&res);
  pb_sequence_destroy(g, q);
  free(rec);
  free(ref);
  free(ref_prev);
  free(res_prev);
  free(cache_dir);
  return r;
}
