/* The interactive viewer's loop (viewer.h). */
#include "view/viewer.h"

#include <GLFW/glfw3.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "render/frame/result_exr.h"
#include "core/fs.h"
#include "core/json.h"
#include "core/log.h"
#include "image/image.h"
#include "metrics/metrics.h"
#include "view/controller.h"
#include "view/present.h"
#include "view/present_pass.h"
#include "view/session.h"
#include "shared/pb_resolve.h"

/* stb_image_write's implementation lives in src/image/png.c; this is only
 * its declarations (as src/color/png_display.c). */
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmissing-prototypes"
#pragma GCC diagnostic ignored "-Wshadow"
#pragma GCC diagnostic ignored "-Wsign-compare"
#pragma GCC diagnostic ignored "-Wunused-parameter"
#include <stb_image_write.h>
#pragma GCC diagnostic pop

/* The AOVs the window can show, in Tab / F1.. order. */
enum { AOV_BEAUTY, AOV_DIRECT, AOV_INDIRECT, AOV_CAUSTIC, AOV_EMISSION, AOV_ALBEDO, AOV_NORMAL, AOV_DEPTH, AOV_COUNT };
static const char *const aov_names[AOV_COUNT] = {"beauty",   "direct", "indirect", "caustic",
                                                 "emission", "albedo", "normal",   "depth"};

/* A --script event: at frame `frame` (0 = before the first frame). */
enum { EV_CURSOR, EV_PRESS, EV_RELEASE, EV_SCROLL, EV_KEY, EV_KEYDOWN, EV_KEYUP, EV_RESIZE, EV_SCREENSHOT };
typedef struct script_event {
  uint32_t frame;
  int kind;
  double a, b;
  int key; /* GLFW key or mouse button */
  char path[256];
} script_event;

/* Per-frame statistics for --json. */
typedef struct frame_stat {
  double wall_ms, render_ms, present_ms, psnr, t;
  int still;
  int rested;          /* --noise-threshold reached: nothing rendered, the picture stays */
  uint32_t run_frames; /* frames refined by the current still run */
  double noise;        /* the still run's noise estimate (-1: none yet) */
  /* Host <-> device bytes: the frame's (pb_render_stats: the readback's,
   * the uploads') and the picture's (the display pass's upload, or 0). */
  uint64_t readback_bytes, upload_bytes, download_bytes, display_up_bytes;
  uint64_t ring_bytes; /* frames in flight: what the frame's ring copy moved (the shown AOV's planes) */
} frame_stat;

static uint32_t validation_messages;
uint32_t pb_view_validation_total(void) { return validation_messages; }

typedef struct viewer {
  pb_gpu *g;
  pb_scene *s;
  pb_gpu_scene *gs;
  const pb_view_desc *d;
  GLFWwindow *win;
  pb_present *pres;
  pb_view_session ses;   /* the frame loop (session.h), shared with `serve` */
  pb_view_controller ctl;
  int follow;            /* 1: the scene camera `camera` as the file (and its animation) has it */
  pb_camera file_cam;    /* the bound slot's own camera, restored when following */
  int selected;          /* the glTF camera chosen with 1-9 / [ ] */
  unsigned moves_seen;
  int playing;
  double t;              /* animation time now */
  int aov;
  int aov_shown;         /* the AOV of the picture shown last */
  /* Frames in flight with the display-only readback: the frame's ring slot
   * keeps only the planes the picture reads (pb_render_desc.keep_planes):
   * lean_ring 1, keep what the next frame keeps. */
  int lean_ring;
  uint64_t keep;
  double exposure;
  pb_color *color, *metric;
  float *ref_display;    /* the reference through the metrics view, RGB */
  float *tmp;            /* RGBA floats of the shown AOV */
  uint8_t *rgba;         /* the bytes shown (GPU display: fetched when asked, rgba_stale) */
  /* The picture made on the render device: the view
   * baked to a LUT, the display pass writing RGBA8 into a buffer the
   * presenter copies into the swapchain. gpu_display 0: the host path
   * (its own presentation device, PB_VIEW_HOST_DISPLAY=1, a depth AOV). */
  int gpu_display;
  pb_color_lut lut;
  pb_present_pass pass;
  int rgba_stale;        /* the shown bytes are in pass.out, not yet in rgba */
  uint32_t gpu_frames;   /* frames shown through the display pass */
  uint32_t frame;
  /* --noise-threshold: a still view whose estimate reached it rests (no
   * frame rendered) until the camera or the time moves, or an input asks
   * for a new picture (repaint: a key, a resize, an exposed window). */
  int repaint;
  int rendered_once;
  pb_camera last_want;   /* the camera of the last frame rendered */
  double last_t;         /* and its time */
  int save;              /* P / F12 pressed */
  uint32_t saves;
  const char *note;      /* a one-off remark for the title */
  pb_result error;       /* set by a handler (colour view failing) */
  script_event *events;
  size_t event_count, event_next;
  frame_stat *stats;
  size_t stat_cap;
} viewer;

/* ---- input: the GLFW callbacks and the script call these ---------------- */

static void select_camera(viewer *v, int k) {
  if (k < 0 || (uint32_t)k >= v->s->camera_count) return;
  v->selected = k;
  v->follow = k == v->d->camera;
  /* The bound slot holds the view's camera; every other slot is the file's
   * (posed at the current time when animated). */
  const pb_camera *c = v->follow ? &v->file_cam : &v->s->cameras[k];
  pb_view_controller_reset(&v->ctl, c, v->s->bounds_min, v->s->bounds_max);
  v->moves_seen = v->ctl.moves;
}

static void set_exposure(viewer *v, double ev) {
  pb_color_desc cd = v->d->color;
  cd.exposure = ev;
  pb_color *c = NULL;
  pb_result r = pb_color_open(&cd, &c);
  if (r != PB_OK) {
    v->error = r;
    return;
  }
  pb_color_destroy(v->color);
  v->color = c;
  v->exposure = ev;
}

static void on_key_event(viewer *v, int key, int action, int mods) {
  (void)mods;
  int down = action != GLFW_RELEASE;
  static const struct { int key; unsigned bit; } fly[] = {
      {GLFW_KEY_W, PB_VIEW_FLY_FORWARD}, {GLFW_KEY_S, PB_VIEW_FLY_BACK}, {GLFW_KEY_A, PB_VIEW_FLY_LEFT},
      {GLFW_KEY_D, PB_VIEW_FLY_RIGHT},   {GLFW_KEY_E, PB_VIEW_FLY_UP},   {GLFW_KEY_Q, PB_VIEW_FLY_DOWN}};
  for (size_t i = 0; i < sizeof fly / sizeof fly[0]; ++i)
    if (key == fly[i].key) {
      pb_view_controller_fly_key(&v->ctl, fly[i].bit, down);
      return;
    }
  if (key == GLFW_KEY_LEFT_SHIFT || key == GLFW_KEY_RIGHT_SHIFT) {
    pb_view_controller_shift(&v->ctl, down);
    return;
  }
  if (action != GLFW_PRESS) return;
  v->repaint = 1;
  int n = (int)v->s->camera_count;
  if (key >= GLFW_KEY_1 && key <= GLFW_KEY_9) select_camera(v, key - GLFW_KEY_1);
  else if (key == GLFW_KEY_LEFT_BRACKET) select_camera(v, (v->selected + n - 1) % n);
  else if (key == GLFW_KEY_RIGHT_BRACKET) select_camera(v, (v->selected + 1) % n);
  else if (key == GLFW_KEY_HOME) select_camera(v, v->selected);
  else if (key == GLFW_KEY_SPACE) {
    if (v->s->anim) v->playing = !v->playing;
    else v->note = "no animation";
  } else if (key == GLFW_KEY_TAB) v->aov = (v->aov + 1) % AOV_COUNT;
  else if (key >= GLFW_KEY_F1 && key < GLFW_KEY_F1 + AOV_COUNT) v->aov = key - GLFW_KEY_F1;
  else if (key == GLFW_KEY_EQUAL || key == GLFW_KEY_KP_ADD) set_exposure(v, v->exposure + 0.5);
  else if (key == GLFW_KEY_MINUS || key == GLFW_KEY_KP_SUBTRACT) set_exposure(v, v->exposure - 0.5);
  else if (key == GLFW_KEY_0) set_exposure(v, v->d->color.exposure);
  else if (key == GLFW_KEY_P || key == GLFW_KEY_F12) v->save = 1;
  else if (key == GLFW_KEY_ESCAPE) glfwSetWindowShouldClose(v->win, GLFW_TRUE);
}

static int view_button(int glfw_button) {
  if (glfw_button == GLFW_MOUSE_BUTTON_LEFT) return PB_VIEW_BUTTON_LEFT;
  if (glfw_button == GLFW_MOUSE_BUTTON_MIDDLE) return PB_VIEW_BUTTON_MIDDLE;
  if (glfw_button == GLFW_MOUSE_BUTTON_RIGHT) return PB_VIEW_BUTTON_RIGHT;
  return -1;
}

static void on_cursor_event(viewer *v, double x, double y) {
  int ww = 0, wh = 0;
  glfwGetWindowSize(v->win, &ww, &wh);
  pb_view_controller_cursor(&v->ctl, x, y, wh > 0 ? wh : 1);
}

static void cb_key(GLFWwindow *w, int key, int scancode, int action, int mods) {
  (void)scancode;
  on_key_event(glfwGetWindowUserPointer(w), key, action, mods);
}
static void cb_button(GLFWwindow *w, int button, int action, int mods) {
  (void)mods;
  viewer *v = glfwGetWindowUserPointer(w);
  pb_view_controller_button(&v->ctl, view_button(button), action == GLFW_PRESS);
}
static void cb_cursor(GLFWwindow *w, double x, double y) { on_cursor_event(glfwGetWindowUserPointer(w), x, y); }
static void cb_scroll(GLFWwindow *w, double dx, double dy) {
  (void)dx;
  viewer *v = glfwGetWindowUserPointer(w);
  pb_view_controller_scroll(&v->ctl, dy);
}
static void cb_repaint(GLFWwindow *w) { ((viewer *)glfwGetWindowUserPointer(w))->repaint = 1; }
static void cb_framebuffer(GLFWwindow *w, int width, int height) {
  (void)width, (void)height;
  cb_repaint(w);
}

/* ---- the script ------------------------------------------------------------ */

static int key_by_name(const char *n) {
  static const struct { const char *name; int key; } named[] = {
      {"space", GLFW_KEY_SPACE}, {"home", GLFW_KEY_HOME}, {"tab", GLFW_KEY_TAB}, {"escape", GLFW_KEY_ESCAPE},
      {"plus", GLFW_KEY_EQUAL},  {"minus", GLFW_KEY_MINUS}, {"[", GLFW_KEY_LEFT_BRACKET},
      {"]", GLFW_KEY_RIGHT_BRACKET}, {"shift", GLFW_KEY_LEFT_SHIFT}, {"f12", GLFW_KEY_F12}};
  for (size_t i = 0; i < sizeof named / sizeof named[0]; ++i)
    if (strcmp(n, named[i].name) == 0) return named[i].key;
  if ((n[0] == 'f' || n[0] == 'F') && n[1] >= '1' && n[1] <= '8' && !n[2]) return GLFW_KEY_F1 + (n[1] - '1');
  if (n[0] && !n[1]) {
    if (n[0] >= 'a' && n[0] <= 'z') return GLFW_KEY_A + (n[0] - 'a');
    if (n[0] >= 'A' && n[0] <= 'Z') return GLFW_KEY_A + (n[0] - 'A');
    if (n[0] >= '0' && n[0] <= '9') return GLFW_KEY_0 + (n[0] - '0');
  }
  return -1;
}

static int button_by_name(const char *n) {
  if (strcmp(n, "left") == 0) return GLFW_MOUSE_BUTTON_LEFT;
  if (strcmp(n, "middle") == 0) return GLFW_MOUSE_BUTTON_MIDDLE;
  if (strcmp(n, "right") == 0) return GLFW_MOUSE_BUTTON_RIGHT;
  return -1;
}

/* One event a line: FRAME ACTION ARGS, '#' starts a comment. FRAME: the
 * event happens before that frame renders (0: before the first). Actions:
 * cursor X Y | press BUTTON | release BUTTON (left, middle, right) |
 * scroll DY | key NAME (press and release) | keydown NAME | keyup NAME |
 * resize W H (the window, through the window system) | screenshot FILE.
 * Frames must not decrease. */
static pb_result load_script(viewer *v, const char *path) {
  FILE *f = fopen(path, "r");
  if (!f) return pb_fail(PB_ERR_IO, "%s: cannot open the script", path);
  char line[512];
  size_t cap = 0;
  uint32_t last = 0;
  pb_result r = PB_OK;
  for (unsigned ln = 1; fgets(line, sizeof line, f); ++ln) {
    char *hash = strchr(line, '#');
    if (hash) *hash = 0;
    char act[32], a1[256] = "", a2[64] = "";
    unsigned long fr;
    int n = sscanf(line, "%lu %31s %255s %63s", &fr, act, a1, a2);
    if (n <= 0) continue;
    script_event e;
    memset(&e, 0, sizeof e);
    e.frame = (uint32_t)fr;
    char *end1 = NULL, *end2 = NULL;
    double x = strtod(a1, &end1), y = strtod(a2, &end2);
    int ok = n >= 2 && fr <= 10000000 && fr >= last;
    if (ok && strcmp(act, "cursor") == 0) e.kind = EV_CURSOR, e.a = x, e.b = y, ok = n == 4 && !*end1 && !*end2;
    else if (ok && (strcmp(act, "press") == 0 || strcmp(act, "release") == 0))
      e.kind = act[0] == 'p' ? EV_PRESS : EV_RELEASE, e.key = button_by_name(a1), ok = n == 3 && e.key >= 0;
    else if (ok && strcmp(act, "scroll") == 0) e.kind = EV_SCROLL, e.a = x, ok = n == 3 && !*end1;
    else if (ok && (strcmp(act, "key") == 0 || strcmp(act, "keydown") == 0 || strcmp(act, "keyup") == 0))
      e.kind = act[3] == 0 ? EV_KEY : (act[3] == 'd' ? EV_KEYDOWN : EV_KEYUP), e.key = key_by_name(a1),
      ok = n == 3 && e.key >= 0;
    else if (ok && strcmp(act, "resize") == 0)
      e.kind = EV_RESIZE, e.a = x, e.b = y, ok = n == 4 && !*end1 && !*end2 && x >= 1 && y >= 1 && x <= 16384 && y <= 16384;
    else if (ok && strcmp(act, "screenshot") == 0)
      e.kind = EV_SCREENSHOT, ok = n == 3 && snprintf(e.path, sizeof e.path, "%s", a1) < (int)sizeof e.path;
    else ok = 0;
    if (!ok) {
      r = pb_fail(PB_ERR_USAGE, "%s: line %u: expected 'FRAME ACTION ARGS' (frames not decreasing; cursor X Y, press|release "
                  "left|middle|right, scroll DY, key|keydown|keyup NAME, resize W H, screenshot FILE)", path, ln);
      break;
    }
    last = e.frame;
    if (v->event_count == cap) {
      size_t nc = cap ? 2 * cap : 64;
      script_event *ne = realloc(v->events, nc * sizeof *ne);
      if (!ne) {
        r = pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
        break;
      }
      v->events = ne, cap = nc;
    }
    v->events[v->event_count++] = e;
  }
  fclose(f);
  return r;
}

static pb_result write_screenshot(viewer *v, const char *path);

/* The events due before frame v->frame, through the handlers the GLFW
 * callbacks call (a key is a press then a release). */
static pb_result run_script(viewer *v) {
  while (v->event_next < v->event_count && v->events[v->event_next].frame <= v->frame) {
    const script_event *e = &v->events[v->event_next++];
    switch (e->kind) {
      case EV_CURSOR: on_cursor_event(v, e->a, e->b); break;
      case EV_PRESS: pb_view_controller_button(&v->ctl, view_button(e->key), 1); break;
      case EV_RELEASE: pb_view_controller_button(&v->ctl, view_button(e->key), 0); break;
      case EV_SCROLL: pb_view_controller_scroll(&v->ctl, e->a); break;
      case EV_KEY: on_key_event(v, e->key, GLFW_PRESS, 0), on_key_event(v, e->key, GLFW_RELEASE, 0); break;
      case EV_KEYDOWN: on_key_event(v, e->key, GLFW_PRESS, 0); break;
      case EV_KEYUP: on_key_event(v, e->key, GLFW_RELEASE, 0); break;
      case EV_RESIZE:
        glfwSetWindowSize(v->win, (int)e->a, (int)e->b);
        glfwPollEvents();
        break;
      case EV_SCREENSHOT: {
        pb_result r = v->frame ? write_screenshot(v, e->path) : pb_fail(PB_ERR_USAGE, "view: --script: a screenshot "
                                                                       "at frame 0 has nothing to show");
        if (r != PB_OK) return r;
        break;
      }
    }
  }
  return PB_OK;
}

/* ---- pictures --------------------------------------------------------------- */

/* The shown AOV as RGBA floats into v->tmp, display-encoded into v->rgba:
 * colour AOVs through the OCIO view (exposure included), normal as
 * 0.5 + 0.5 n and depth as 1 - z / z_max (near bright), both raw data. */
static const uint32_t aov_plane[AOV_COUNT] = {PB_RESOLVE_BEAUTY, PB_RESOLVE_DIRECT,   PB_RESOLVE_INDIRECT,
                                              PB_RESOLVE_CAUSTIC, PB_RESOLVE_EMISSION, PB_RESOLVE_ALBEDO,
                                              PB_RESOLVE_NORMAL, PB_RESOLVE_DEPTH};

/* The planes a frame must keep in its ring slot for AOV a: the depth AOV
 * (the host path) and P / F12 read every AOV (pb_render_result_read_gpu). */
static uint64_t aov_keep(int a) { return a == AOV_DEPTH ? PB_RENDER_KEEP_ALL : PB_RENDER_KEEP(aov_plane[a]); }

static int aov_kept(const pb_render_result *res, int a) {
  uint64_t k = aov_keep(a);
  return (res->gpu.kept & k) == k;
}

/* The planes the next frame keeps (lean_ring): what the shown AOV reads,
 * every plane when a save waits for them. */
static void set_keep(viewer *v) {
  if (!v->lean_ring) return;
  uint64_t keep = v->save ? PB_RENDER_KEEP_ALL : aov_keep(v->aov);
  if (keep == v->keep) return;
  v->keep = keep;
  v->ses.desc.keep_planes = keep;
  pb_sequence_set_keep_planes(v->ses.seq, keep);
}

static pb_result make_picture(viewer *v, int *on_gpu) {
  pb_render_result *res = &v->ses.res;
  *on_gpu = 0;
  size_t n = (size_t)res->width * res->height;
  /* Frames in flight with a lean ring: the frame that comes out kept the
   * planes of the AOV shown when it was rendered, so an AOV switch takes
   * effect on the next frame; this one shows an AOV it has. */
  int aov = v->aov;
  if (v->lean_ring && res->stats.readback_mode != PB_RENDER_READBACK_ALL && res->gpu.planes && !aov_kept(res, aov)) {
    aov = aov_kept(res, v->aov_shown) ? v->aov_shown : AOV_BEAUTY;
    for (int a = 0; a < AOV_COUNT && !aov_kept(res, aov); ++a) aov = a;
  }
  v->aov_shown = aov;
  if (v->gpu_display && aov != AOV_DEPTH && res->stats.readback_mode != PB_RENDER_READBACK_ALL &&
      res->gpu.planes) {
    /* The display-only readback (sequence.h desc.readback): the AOV where
     * the frame left it on the GPU (its planes, shared/pb_resolve.h, or
     * with frames in flight its ring slot), through the display pass;
     * nothing comes to the host and nothing goes up. */
    uint32_t p = aov_plane[aov];
    int second = p >= PB_RESOLVE_BASE_CHANNELS;
    const pb_gpu_buffer *src = second ? res->gpu.pplanes : res->gpu.planes;
    if (!src) {
      v->note = "this AOV is empty here (no photon stages)";
    } else {
      pb_present_job job = {.src = src,
                            .offset = (p - (second ? PB_RESOLVE_BASE_CHANNELS : 0u)) * res->gpu.pixels,
                            .channels = aov == AOV_BEAUTY ? 4u : 3u, .pixels = (uint32_t)n,
                            .scale = (float)exp2(v->exposure), .data = aov == AOV_NORMAL, .data_scale = 0.5f,
                            .data_bias = 0.5f};
      /* Bound afresh each frame: the planes are the context's (a new
       * context can put new buffers at the same address, which the pass's
       * pointer check would take for the bound ones). */
      v->pass.bound_src = NULL;
      pb_result r = pb_present_pass_run(v->g, &v->pass, &job);
      if (r != PB_OK) return r;
      v->rgba_stale = 1;
      *on_gpu = 1;
      return PB_OK;
    }
  }
  /* The host path (the depth AOV, a host display): the arrays the lean
   * readback left on the GPU come now (counted in the frame's bytes). */
  if (res->stats.readback_mode != PB_RENDER_READBACK_ALL) {
    pb_result r = pb_render_result_read_gpu(v->g, res);
    if (r != PB_OK) return r;
  }
  const float *src = NULL;
  int ch = 3;
  switch (aov) {
    case AOV_BEAUTY: src = res->beauty, ch = 4; break;
    case AOV_DIRECT: src = res->direct; break;
    case AOV_INDIRECT: src = res->indirect; break;
    case AOV_CAUSTIC: src = res->caustic; break;
    case AOV_EMISSION: src = res->emission; break;
    case AOV_ALBEDO: src = res->albedo; break;
    case AOV_NORMAL: src = res->normal; break;
    case AOV_DEPTH: src = res->depth, ch = 1; break;
  }
  if (!src) v->note = "this AOV is empty here (no photon stages)";
  if (v->gpu_display && src && aov != AOV_DEPTH) {
    /* The display pass: the AOV through the baked view (exposure a scale
     * in the pass), normals as 0.5 + 0.5 n; the bytes stay on the device. */
    pb_present_job job = {.channels = (uint32_t)ch, .pixels = (uint32_t)n, .scale = (float)exp2(v->exposure),
                          .data = aov == AOV_NORMAL, .data_scale = 0.5f, .data_bias = 0.5f};
    pb_result r = pb_present_pass_upload(v->g, &v->pass, src, (uint32_t)n, (uint32_t)ch);
    if (r == PB_OK) r = pb_present_pass_run(v->g, &v->pass, &job);
    if (r != PB_OK) return r;
    v->rgba_stale = 1;
    *on_gpu = 1;
    return PB_OK;
  }
  v->rgba_stale = 0;
  float zmax = 0;
  if (aov == AOV_DEPTH)
    for (size_t i = 0; i < n; ++i) zmax = src[i] > zmax ? src[i] : zmax;
  for (size_t i = 0; i < n; ++i) {
    float *o = v->tmp + 4 * i;
    if (!src) {
      o[0] = o[1] = o[2] = 0;
    } else if (ch == 1) {
      o[0] = o[1] = o[2] = src[i] > 0 && zmax > 0 ? 1.0f - src[i] / zmax : 0.0f;
    } else {
      for (int k = 0; k < 3; ++k) o[k] = src[(size_t)ch * i + k];
      if (aov == AOV_NORMAL)
        for (int k = 0; k < 3; ++k) o[k] = 0.5f + 0.5f * o[k];
    }
    o[3] = 1.0f;
  }
  int data = aov == AOV_NORMAL || aov == AOV_DEPTH;
  if (!data) {
    pb_result r = pb_color_apply_display(v->color, v->tmp, res->width, res->height, 4);
    if (r != PB_OK) return r;
  }
  /* The rounding pb_png_write_display uses, so that the window's bytes are
   * display's PNG. */
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 4; ++k) {
      float x = k == 3 ? 1.0f : v->tmp[4 * i + k];
      v->rgba[4 * i + k] = !(x > 0.0f) ? 0 : x >= 1.0f ? 255 : (uint8_t)(x * 255.0f + 0.5f);
    }
  return PB_OK;
}

typedef struct sink {
  FILE *f;
  int failed;
} sink;
static void sink_write(void *ctx, void *data, int size) {
  sink *s = ctx;
  if (size > 0 && fwrite(data, 1, (size_t)size, s->f) != (size_t)size) s->failed = 1;
}

/* The bytes shown, in v->rgba (the display pass's, read back once). */
static pb_result fetch_shown(viewer *v) {
  if (!v->rgba_stale) return PB_OK;
  pb_result r = pb_present_pass_download(v->g, &v->pass, v->rgba, v->ses.res.width * v->ses.res.height);
  if (r == PB_OK) v->rgba_stale = 0;
  return r;
}

/* The bytes shown (RGB, the frame's size), atomically. */
static pb_result write_screenshot(viewer *v, const char *path) {
  size_t n = (size_t)v->ses.res.width * v->ses.res.height;
  pb_result fr = fetch_shown(v);
  if (fr != PB_OK) return fr;
  uint8_t *rgb = malloc(3 * n);
  if (!rgb) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) rgb[3 * i + k] = v->rgba[4 * i + k];
  FILE *f = NULL;
  char *tmp = NULL;
  pb_result r = pb_atomic_open(path, &f, &tmp);
  if (r != PB_OK) {
    free(rgb);
    return r;
  }
  sink s = {f, 0};
  int ok = stbi_write_png_to_func(sink_write, &s, (int)v->ses.res.width, (int)v->ses.res.height, 3, rgb,
                                  (int)(3 * v->ses.res.width));
  free(rgb);
  if (!ok || s.failed) {
    pb_atomic_abort(f, tmp);
    return pb_fail(ok ? PB_ERR_IO : PB_ERR_NOMEM, "%s: %s", path, ok ? "write failed" : "PNG encoding ran out of memory");
  }
  return pb_atomic_commit(path, f, tmp);
}

/* P / F12: every AOV of the current image as an EXR (scene-linear, as
 * `render` writes it) and the shown picture as a PNG. */
static pb_result save_current(viewer *v) {
  char exr[1200], png[1200];
  pb_result rr = pb_render_result_read_gpu(v->g, &v->ses.res); /* every AOV, also after a lean readback */
  if (rr != PB_OK) return rr;
  snprintf(exr, sizeof exr, "%s_%04u.exr", v->d->save_prefix, v->saves);
  snprintf(png, sizeof png, "%s_%04u.png", v->d->save_prefix, v->saves);
  char frames_s[32];
  snprintf(frames_s, sizeof frames_s, "%u", v->ses.run_frames);
  const char *an[] = {"photonbridge/renderer", "photonbridge/view_frames"};
  const char *av[] = {"gpu view", frames_s};
  pb_result r = pb_render_write_exr(exr, &v->ses.res, NULL, NULL, an, av, 2);
  if (r == PB_OK && (r = write_screenshot(v, png)) != PB_OK) unlink(exr);
  if (r != PB_OK) return r;
  pb_log_info("view: wrote %s and %s (%u frames refined)", exr, png, v->ses.run_frames);
  v->saves++;
  return PB_OK;
}

static pb_result load_reference(viewer *v) {
  pb_image img;
  pb_result r = pb_exr_read(v->d->reference, NULL, &img);
  if (r != PB_OK) return r;
  int idx[3] = {pb_image_find_channel(&img, "R"), pb_image_find_channel(&img, "G"), pb_image_find_channel(&img, "B")};
  if (idx[0] < 0 || idx[1] < 0 || idx[2] < 0) r = pb_fail(PB_ERR_IMAGE, "%s: no R, G, B channels", v->d->reference);
  else if (img.width != v->d->width || img.height != v->d->height)
    r = pb_fail(PB_ERR_IMAGE_MISMATCH, "%s: %ux%u, but the view renders %ux%u (--width/--height)", v->d->reference,
                img.width, img.height, v->d->width, v->d->height);
  size_t n = (size_t)img.width * img.height;
  if (r == PB_OK && !(v->ref_display = malloc(3 * n * sizeof(float)))) r = pb_fail(PB_ERR_NOMEM, "view: out of memory");
  if (r == PB_OK) {
    for (size_t i = 0; i < n; ++i)
      for (int k = 0; k < 3; ++k) v->ref_display[3 * i + k] = img.pixels[i * img.channel_count + (uint32_t)idx[k]];
    r = pb_color_apply_display(v->metric, v->ref_display, img.width, img.height, 3);
  }
  pb_image_destroy(&img);
  return r;
}

/* PSNR of the beauty against --reference, as `compare` computes it (its
 * default metrics view, display MSE over R, G, B). */
static pb_result frame_psnr(viewer *v, double *psnr) {
  size_t n = (size_t)v->ses.res.width * v->ses.res.height;
  if (!v->ses.res.beauty) { /* a display-only readback (the viewer asks for the beauty with --reference) */
    pb_result rr = pb_render_result_read_gpu(v->g, &v->ses.res);
    if (rr != PB_OK) return rr;
  }
  float *t = malloc(3 * n * sizeof *t);
  if (!t) return pb_fail(PB_ERR_NOMEM, "view: out of memory");
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) {
      float x = v->ses.res.beauty[4 * i + k];
      t[3 * i + k] = isfinite(x) ? x : 0.0f;
    }
  pb_result r = pb_color_apply_display(v->metric, t, v->ses.res.width, v->ses.res.height, 3);
  double se = 0;
  for (size_t i = 0; r == PB_OK && i < 3 * n; ++i) se += (double)(t[i] - v->ref_display[i]) * (t[i] - v->ref_display[i]);
  free(t);
  *psnr = pb_metrics_psnr_from_mse(se / (double)(3 * n));
  return r;
}

static void set_title(viewer *v, double fps, const frame_stat *fs) {
  const pb_render_stats *st = &v->ses.res.stats;
  char title[512], psnr[96] = "", tm[48] = "";
  if (v->ref_display) snprintf(psnr, sizeof psnr, " | PSNR %.2f dB", fs->psnr);
  if (v->s->anim) snprintf(tm, sizeof tm, " | t %.2f s%s", v->t, v->playing ? " >" : " ||");
  if (v->d->noise_threshold > 0 && fs->noise >= 0)
    snprintf(psnr + strlen(psnr), sizeof psnr - strlen(psnr), " | noise %.1f dB%s",
             fs->noise > 0 ? -20.0 * log10(fs->noise) : INFINITY,
             pb_view_session_noise_reached(&v->ses, v->d->noise_threshold) ? " (rests)" : "");
  snprintf(title, sizeof title, "photonbridge view: %s | %.1f fps | %.0f ms/pass | %llu photons stored | %u %s%s%s | %s | EV %+.1f%s%s",
           v->s->cameras[v->selected].name[0] ? v->s->cameras[v->selected].name : "camera", fps, fs->render_ms,
           (unsigned long long)st->photons_stored, v->ses.run_frames, v->ses.run_frames == 1 ? "pass" : "passes", psnr, tm,
           aov_names[v->aov], v->exposure, v->note ? " | " : "", v->note ? v->note : "");
  glfwSetWindowTitle(v->win, title);
}

static pb_result write_stats(const viewer *v, const char *path) {
  pb_json j;
  char *tmp;
  pb_result r = pb_json_open(&j, path, &tmp);
  if (r != PB_OK) return r;
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "renderer", "gpu view");
  pb_json_string(&j, "scene", v->s->path);
  pb_json_string(&j, "device", pb_gpu_device_name(v->g));
  pb_json_string(&j, "traversal", pb_gpu_traversal(v->g));
  pb_json_int(&j, "width", v->d->width);
  pb_json_int(&j, "height", v->d->height);
  pb_json_int(&j, "photons_per_frame", v->ses.res.stats.photons_emitted);
  pb_json_int(&j, "photons_stored", (int64_t)v->ses.res.stats.photons_stored);
  pb_json_int(&j, "swapchain_recreations", pb_present_recreations(v->pres));
  pb_json_bool(&j, "present_shared_device", pb_present_shared(v->pres));
  pb_json_bool(&j, "gpu_display", v->gpu_display);
  if (v->d->noise_threshold > 0) {
    pb_json_number(&j, "noise_threshold", v->d->noise_threshold);
    pb_json_bool(&j, "noise_reached", pb_view_session_noise_reached(&v->ses, v->d->noise_threshold));
  }
  pb_json_int(&j, "gpu_display_frames", v->gpu_frames);
  if (v->gpu_display) {
    pb_json_int(&j, "display_lut_size", v->lut.size);
    pb_json_number(&j, "display_lut_lo", v->lut.lo);
    pb_json_number(&j, "display_lut_hi", v->lut.hi);
    pb_json_number(&j, "display_lut_error", v->lut.max_error);
  }
  pb_json_begin_array(&j, "frames");
  for (uint32_t i = 0; i < v->frame; ++i) {
    const frame_stat *f = &v->stats[i];
    pb_json_begin_object(&j, NULL);
    pb_json_number(&j, "wall_ms", f->wall_ms);
    pb_json_number(&j, "render_ms", f->render_ms);
    pb_json_number(&j, "present_ms", f->present_ms);
    pb_json_bool(&j, "still", f->still);
    if (v->d->noise_threshold > 0) {
      pb_json_bool(&j, "rested", f->rested);
      if (f->noise >= 0) pb_json_number(&j, "noise", f->noise);
    }
    pb_json_int(&j, "run_frames", f->run_frames);
    pb_json_int(&j, "readback_bytes", (int64_t)f->readback_bytes);
    pb_json_int(&j, "ring_bytes", (int64_t)f->ring_bytes);
    pb_json_int(&j, "upload_bytes", (int64_t)f->upload_bytes);
    pb_json_int(&j, "download_bytes", (int64_t)f->download_bytes);
    pb_json_int(&j, "display_upload_bytes", (int64_t)f->display_up_bytes);
    pb_json_number(&j, "t", f->t);
    if (v->ref_display && isfinite(f->psnr)) pb_json_number(&j, "psnr", f->psnr);
    pb_json_end_object(&j);
  }
  pb_json_end_array(&j);
  pb_json_end_object(&j);
  return pb_json_close(&j, path, tmp);
}

/* ---- the loop --------------------------------------------------------------- */

/* The statistics slot of frame v->frame, zeroed (the array grows). */
static pb_result next_stat(viewer *v, frame_stat **out) {
  if (v->frame == v->stat_cap) {
    size_t nc = v->stat_cap ? 2 * v->stat_cap : 256;
    frame_stat *ns = realloc(v->stats, nc * sizeof *ns);
    if (!ns) return pb_fail(PB_ERR_NOMEM, "view: out of memory");
    v->stats = ns, v->stat_cap = nc;
  }
  *out = &v->stats[v->frame];
  memset(*out, 0, sizeof **out);
  return PB_OK;
}

/* A frame where the view rests (--noise-threshold reached, nothing moved):
 * scripted runs (--script, --exit-after) count it, with the picture kept;
 * an interactive one does not, and waits for input. */
static pb_result rest_frame(viewer *v, double dt) {
  if (!v->d->script && !v->d->exit_after) return PB_OK;
  frame_stat *fs;
  pb_result r = next_stat(v, &fs);
  if (r != PB_OK) return r;
  fs->wall_ms = dt * 1e3, fs->still = 1, fs->rested = 1, fs->run_frames = v->ses.run_frames, fs->t = v->t;
  fs->psnr = v->frame ? v->stats[v->frame - 1].psnr : NAN, fs->noise = pb_view_session_noise(&v->ses);
  v->frame++;
  return r;
}

static pb_result one_frame(viewer *v, double dt, int *rested) {
  pb_scene *s = v->s;
  pb_result r;
  double t0 = pb_time_now();
  /* A frame slower than 4 fps flies as if it took 0.25 s, so that a held
   * key on a slow device moves in steps one can steer. */
  pb_view_controller_tick(&v->ctl, dt < 0.25 ? dt : 0.25);
  if (v->ctl.moves != v->moves_seen) { /* the user took the camera */
    v->moves_seen = v->ctl.moves;
    v->follow = 0;
  }
  if (v->playing) {
    v->t += dt;
    if (v->t > s->anim_end) v->t = s->anim_start + fmod(v->t - s->anim_start, fmax(s->anim_end - s->anim_start, 1e-6));
  }
  pb_camera want = v->follow ? v->file_cam : v->ctl.cam;
  double thr = v->d->noise_threshold;
  if (thr > 0 && v->rendered_once && !v->repaint && !v->save && !v->playing && v->t == v->last_t &&
      memcmp(&want, &v->last_want, sizeof want) == 0 && pb_view_session_noise_reached(&v->ses, thr)) {
    *rested = 1;
    return rest_frame(v, dt);
  }
  v->repaint = 0, v->rendered_once = 1, v->last_want = want, v->last_t = v->t;
  set_keep(v);
  if ((r = pb_view_session_frame(&v->ses, &want, v->t)) != PB_OK) return r;
  const pb_sequence_frame_info fi = v->ses.info;
  /* The camera of the frame just rendered (the scene's slot): with frames
   * in flight the frame that came out (fi) is the one before. */
  const pb_camera rendered = s->cameras[v->ses.camera];
  if (!v->follow && memcmp(rendered.position, want.position, sizeof want.position)) {
    /* The animation moved the bound camera over the user's: stop playing,
     * so that the next frame shows the user's camera (the session does not
     * pose the scene again while the time stays). */
    v->playing = 0;
    v->note = "paused: the scene camera is animated";
  }
  if (v->follow) pb_view_controller_reset(&v->ctl, &rendered, s->bounds_min, s->bounds_max);
  /* Frames in flight (--frames-in-flight 2): the first call renders and
   * shows nothing; from then on each call shows the frame before the one
   * it rendered, so the window runs one frame behind the input and
   * v->frame counts the frames shown. */
  if (!fi.ready) return PB_OK;
  if ((r = pb_view_session_noise_update(&v->ses, thr)) != PB_OK) return r;
  double t1 = pb_time_now();
  pb_gpu_transfers tp0 = pb_gpu_transfers_get(v->g);
  int on_gpu = 0;
  if ((r = make_picture(v, &on_gpu)) != PB_OK) return r;
  if (on_gpu) {
    v->gpu_frames++;
    r = pb_present_frame_buffer(v->pres, v->pass.out.buffer, v->ses.res.width, v->ses.res.height);
  } else {
    r = pb_present_frame(v->pres, v->rgba, v->ses.res.width, v->ses.res.height);
  }
  if (r != PB_OK) return r;
  double t2 = pb_time_now();
  frame_stat *fs;
  if ((r = next_stat(v, &fs)) != PB_OK) return r;
  pb_gpu_transfers tp1 = pb_gpu_transfers_get(v->g);
  fs->readback_bytes = v->ses.res.stats.readback_bytes, fs->upload_bytes = v->ses.res.stats.upload_bytes;
  fs->ring_bytes = v->ses.res.stats.ring_bytes;
  fs->download_bytes = v->ses.res.stats.download_bytes, fs->display_up_bytes = tp1.upload_bytes - tp0.upload_bytes;
  fs->render_ms = (t1 - t0) * 1e3, fs->present_ms = (t2 - t1) * 1e3, fs->wall_ms = dt * 1e3;
  fs->still = fi.still && v->frame > 0, fs->run_frames = v->ses.run_frames, fs->t = v->t, fs->psnr = NAN;
  fs->noise = pb_view_session_noise(&v->ses);
  if (v->ref_display && (r = frame_psnr(v, &fs->psnr)) != PB_OK) return r;
  v->frame++;
  set_title(v, dt > 0 ? 1.0 / dt : 0.0, fs);
  v->note = NULL;
  /* A lean ring: the save waits for a frame that kept every plane
   * (set_keep asks the next one for them). */
  if (v->save && (!v->lean_ring || v->ses.res.stats.readback_mode == PB_RENDER_READBACK_ALL ||
                  v->ses.res.gpu.kept == PB_RENDER_KEEP_ALL)) {
    v->save = 0;
    if ((r = save_current(v)) != PB_OK) return r;
  }
  return PB_OK;
}

pb_result pb_view_check_display(void) {
  const char *disp = getenv("DISPLAY"), *way = getenv("WAYLAND_DISPLAY");
  if ((!disp || !disp[0]) && (!way || !way[0]))
    return pb_fail(PB_ERR_NOT_AVAILABLE, "view: no display (neither DISPLAY nor WAYLAND_DISPLAY is set); render to "
                   "a file with 'photonbridge render', or run under 'xvfb-run -a'");
  return PB_OK;
}

static void on_glfw_error(int code, const char *text) { pb_log_verbose("view: GLFW error %d: %s", code, text); }

static int glfw_can_present(void *user, VkInstance instance, VkPhysicalDevice phys, uint32_t family) {
  (void)user;
  return glfwGetPhysicalDevicePresentationSupport(instance, phys, family) == GLFW_TRUE;
}

void pb_view_gpu_desc(pb_gpu_desc *gd) {
  if (pb_view_check_display() != PB_OK) return;
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit() || !glfwVulkanSupported()) return; /* pb_view_run reports it */
  uint32_t n = 0;
  const char **ext = glfwGetRequiredInstanceExtensions(&n); /* valid until glfwTerminate */
  if (!ext || !n) return;
  gd->instance_extensions = ext;
  gd->instance_extension_count = n;
  gd->can_present = glfw_can_present;
}

pb_result pb_view_run(pb_gpu *g, pb_scene *s, pb_gpu_scene *gs, const pb_view_desc *d) {
  viewer v;
  memset(&v, 0, sizeof v);
  v.g = g, v.s = s, v.gs = gs, v.d = d;
  v.selected = d->camera, v.follow = 1, v.file_cam = s->cameras[d->camera];
  v.exposure = d->color.exposure;
  v.t = s->anim ? s->anim_start : 0.0;
  pb_result r = PB_OK;
  const char *disp = getenv("DISPLAY"), *way = getenv("WAYLAND_DISPLAY");
  int glfw_on = 0;
  if ((r = pb_view_check_display()) != PB_OK) goto done;
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: cannot open the display '%s' (glfwInit failed); render to a file with "
                "'photonbridge render'", disp && disp[0] ? disp : way);
    goto done;
  }
  glfw_on = 1;
  if (!glfwVulkanSupported()) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: GLFW finds no Vulkan loader with window-system surfaces; render to a "
                "file with 'photonbridge render'");
    goto done;
  }
  size_t n = (size_t)d->width * d->height;
  v.tmp = malloc(4 * n * sizeof *v.tmp);
  v.rgba = malloc(4 * n);
  if (!v.tmp || !v.rgba) {
    r = pb_fail(PB_ERR_NOMEM, "view: out of memory for %ux%u pixels", d->width, d->height);
    goto done;
  }
  if ((r = pb_color_open(&d->color, &v.color)) != PB_OK) goto done;
  if (d->reference) {
    pb_color_desc md = {.purpose = PB_COLOR_METRICS};
    if ((r = pb_color_open(&md, &v.metric)) != PB_OK || (r = load_reference(&v)) != PB_OK) goto done;
  }
  if (d->script && (r = load_script(&v, d->script)) != PB_OK) goto done;
  glfwWindowHint(GLFW_CLIENT_API, GLFW_NO_API);
  glfwWindowHint(GLFW_RESIZABLE, GLFW_TRUE);
  v.win = glfwCreateWindow((int)d->width, (int)d->height, "photonbridge view", NULL, NULL);
  if (!v.win) {
    r = pb_fail(PB_ERR_NOT_AVAILABLE, "view: the display refused a window; render to a file with 'photonbridge render'");
    goto done;
  }
  glfwSetWindowUserPointer(v.win, &v);
  glfwSetKeyCallback(v.win, cb_key);
  glfwSetMouseButtonCallback(v.win, cb_button);
  glfwSetCursorPosCallback(v.win, cb_cursor);
  glfwSetScrollCallback(v.win, cb_scroll);
  glfwSetFramebufferSizeCallback(v.win, cb_framebuffer);
  glfwSetWindowRefreshCallback(v.win, cb_repaint);
  pb_gpu_vk vk;
  pb_gpu_vk_handles(g, &vk);
  pb_present_desc pd = {.window = v.win, .device_name = pb_gpu_device_name(g), .validation = d->validation,
                        .shared = &vk};
  if ((r = pb_present_create(&pd, &v.pres)) != PB_OK) goto done;
  if ((r = pb_view_session_create(&v.ses, g, s, gs, d->camera, d->width, d->height, &d->seq)) != PB_OK) goto done;
  {
    /* The picture on the render device when the presenter shares it (the
     * host path otherwise, and with PB_VIEW_HOST_DISPLAY=1). */
    const char *host = getenv("PB_VIEW_HOST_DISPLAY");
    if (pb_present_shared(v.pres) && !(host && host[0] == '1')) {
      if ((r = pb_color_bake_lut(v.color, 0, &v.lut)) != PB_OK ||
          (r = pb_present_pass_create(g, &v.lut, (uint32_t)n, &v.pass)) != PB_OK)
        goto done;
      v.gpu_display = 1;
      /* Display-only readback: the picture is made from the
       * planes on the GPU, so the frames bring no AOV to the host but the
       * beauty for --reference's PSNR; the depth AOV and P / F12 fetch the
       * rest when asked (pb_render_result_read_gpu). */
      int mode = d->reference || d->noise_threshold > 0 ? PB_RENDER_READBACK_BEAUTY : PB_RENDER_READBACK_STATS;
      const char *full = getenv("PB_VIEW_READBACK_ALL"); /* benchmarks: the former readback of every AOV */
      if (full && full[0] == '1') mode = PB_RENDER_READBACK_ALL;
      v.ses.desc.readback = mode;
      pb_sequence_set_readback(v.ses.seq, mode);
      /* Frames in flight: the frame's ring slot keeps what the picture
       * reads (render.h pb_render_desc.keep_planes): the shown AOV's planes
       * (set_keep, before each frame), every plane for the depth AOV and
       * while P / F12 waits; --reference's beauty comes with the readback. */
      v.lean_ring = v.ses.desc.frames_in_flight >= 2 && mode != PB_RENDER_READBACK_ALL;
      v.keep = v.lean_ring ? aov_keep(v.aov) : PB_RENDER_KEEP_ALL;
      v.ses.desc.keep_planes = v.keep;
      pb_sequence_set_keep_planes(v.ses.seq, v.keep);
      pb_log_verbose("view: the picture is made on the render device (a %u^3 LUT, shaper 2^%g .. 2^%g, bake error %.2g)",
                     v.lut.size, v.lut.lo, v.lut.hi, v.lut.max_error);
    }
  }
  pb_view_controller_reset(&v.ctl, &v.file_cam, s->bounds_min, s->bounds_max);
  double last = pb_time_now();
  while (!glfwWindowShouldClose(v.win)) {
    glfwPollEvents();
    if (glfwGetWindowAttrib(v.win, GLFW_ICONIFIED) && !d->script && !d->exit_after) {
      /* Minimised: nothing is shown, so nothing is rendered until restored
       * (scripted runs go on: their frames are counted). */
      glfwWaitEventsTimeout(0.25);
      last = pb_time_now();
      continue;
    }
    if ((r = run_script(&v)) != PB_OK || (r = v.error) != PB_OK) goto done;
    double now = pb_time_now(), dt = now - last;
    last = now;
    int rested = 0;
    if ((r = one_frame(&v, v.frame ? dt : 0.0, &rested)) != PB_OK) goto done;
    if (rested && !d->script && !d->exit_after) {
      glfwWaitEventsTimeout(0.1); /* at the threshold: idle until something happens */
      last = pb_time_now();
    }
    if (d->exit_after && v.frame >= d->exit_after) break;
  }
  if ((r = run_script(&v)) != PB_OK) goto done; /* events at the last frame (a final screenshot) */
  if (d->screenshot && v.frame && (r = write_screenshot(&v, d->screenshot)) != PB_OK) goto done;
  if (d->json && (r = write_stats(&v, d->json)) != PB_OK) goto done;
  if (!d->quiet && v.frame) {
    double still = 0, moving = 0;
    uint32_t ns = 0, nm = 0;
    for (uint32_t i = 1; i < v.frame; ++i) {
      if (v.stats[i].rested) continue;
      if (v.stats[i].still) still += v.stats[i].wall_ms, ns++;
      else moving += v.stats[i].wall_ms, nm++;
    }
    pb_log_info("view: %u frames of %ux%u on %s: %.1f fps still (%u frames), %.1f fps moving (%u)", v.frame,
                d->width, d->height, pb_gpu_device_name(g), ns ? 1e3 * ns / still : 0.0, ns,
                nm ? 1e3 * nm / moving : 0.0, nm);
  }
done:
  validation_messages += pb_present_validation_messages(v.pres);
  if (v.gpu_display) (void)pb_gpu_wait(g);
  pb_view_session_destroy(&v.ses);
  pb_present_destroy(v.pres); /* waits for the device: its copies read v.pass.out */
  pb_present_pass_destroy(g, &v.pass);
  pb_color_lut_destroy(&v.lut);
  if (v.win) glfwDestroyWindow(v.win);
  if (glfw_on) glfwTerminate();
  pb_color_destroy(v.color);
  pb_color_destroy(v.metric);
  free(v.ref_display);
  free(v.tmp);
  free(v.rgba);
  free(v.events);
  free(v.stats);
  return r;
}
