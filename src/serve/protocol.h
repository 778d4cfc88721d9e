/* `photonbridge serve`'s protocol: JSON lines (one JSON object a line,
 * UTF-8, at most PB_SERVE_MAX_LINE bytes) in both directions. This module
 * only parses requests and formats replies; serve.c runs the session.
 *
 * Requests ("cmd" names one; any request may carry "id", a number or a
 * string, which its reply echoes):
 *   {"cmd":"camera","view":[16],"projection":[16],"axes":"scene"|"blender"}
 *       view: world-to-camera, projection: OpenGL clip from camera (camera
 *       looking down -Z, +Y up), both row-major (mathutils' Matrix rows:
 *       Blender's region_3d.view_matrix and window_matrix). axes "blender"
 *       (default "scene"): the view matrix is in Blender's Z-up world and is
 *       turned into the scene's glTF Y-up world (x, z, -y) as the add-on's
 *       writer turns the scene. {"cmd":"camera","index":K} goes back to the
 *       file's camera K.
 *   {"cmd":"resolution","width":W,"height":H}
 *   {"cmd":"time","t":SECONDS}
 *   {"cmd":"settings", "seed" (a non-negative integer) and any setting of
 *       the table render/settings.h offers to requests, under its id
 *       ("photons", "photon_bounces", "estimator", "temporal", ...: the
 *       option's name with '_' for '-', `photonbridge settings` lists
 *       them) with the option's type and range: integers and numbers,
 *       true/false for flags, a name for a choice ("tracer": "images").
 *       A setting not given keeps its value; the whole request is checked
 *       as the command line is, and refused whole}
 *   {"cmd":"frame"}            render one frame now; the reply is the frame
 *   {"cmd":"stream","on":BOOL,"max_passes":N,"noise_threshold":T}
 *                              while on and no request waits, refine frame
 *                              after frame (each an "event":"frame" line),
 *                              until N still passes (0: no limit) or, with
 *                              T in (0, 0.5], until the still run's noise
 *                              estimate (render/frame/noise.h: the RMS noise of
 *                              the displayed image, white 1) is at most T
 *                              (T not given: serve's --noise-threshold,
 *                              default 0)
 *   {"cmd":"reload","scene":PATH}  load PATH (default: the same file) again
 *   {"cmd":"quit"}
 * Replies: {"reply":CMD,"ok":true,...} for each request, in order; frames
 * {"reply":"frame"|"event":"frame","ok":true,"frame":N,"path":P,"width":W,
 * "height":H,"format":"rgba32f","passes":K,"still":B,"render_ms":MS,
 * "photons_stored":N,"tracer":T} (T the photon tracer that ran, "none" when
 * no photon map was traced; the images tracer adds "image_miss_rate"; a
 * stream with a noise threshold adds "noise", the estimate at the last
 * check, null before two passes); errors {"reply":CMD or null,"ok":false,
 * "error":"line L: ..."}. The frame file (rgba32f): a 32-byte header, the
 * bytes "PBFRAME1", then little-endian u32 width, height, channels (4),
 * u32 0, u64 frame number; then width x height RGBA float32 pixels,
 * scene-linear, top row first. */
#ifndef PB_SERVE_PROTOCOL_H
#define PB_SERVE_PROTOCOL_H

#include <stddef.h>
#include <stdint.h>

#include "render/settings.h"
#include "scene/scene.h"

enum { PB_SERVE_MAX_LINE = 1 << 16, PB_SERVE_MAX_PATH = 4096 };

typedef enum pb_serve_cmd {
  PB_SERVE_CAMERA,
  PB_SERVE_RESOLUTION,
  PB_SERVE_TIME,
  PB_SERVE_SETTINGS,
  PB_SERVE_FRAME,
  PB_SERVE_STREAM,
  PB_SERVE_RELOAD,
  PB_SERVE_QUIT,
  PB_SERVE_CMD_COUNT
} pb_serve_cmd;

/* The settings a "settings" request changes: those given (set.given),
 * and the seed. */
typedef struct pb_serve_settings {
  pb_settings set;               /* render/settings.h: the rows offered to
                                    requests (PB_SURFACE_REQUEST) */
  int seed_given;
  uint64_t seed;
} pb_serve_settings;

typedef struct pb_serve_request {
  pb_serve_cmd cmd;
  char id[80];                /* the "id" as JSON text, "" when none */
  /* camera */
  int camera_index;           /* >= 0: the file's camera; -1: the matrices */
  double view[16], projection[16];
  int blender_axes;
  /* resolution */
  uint32_t width, height;
  /* time */
  double t;
  pb_serve_settings settings;
  /* stream */
  int stream_on;
  uint32_t max_passes;
  double noise_threshold;     /* 0: none; -1: not given (the session's --noise-threshold) */
  /* reload: "" for the same file */
  char scene[PB_SERVE_MAX_PATH];
} pb_serve_request;

const char *pb_serve_cmd_name(pb_serve_cmd c);

/* Parses one line (without its newline; len bytes, NUL not needed).
 * Returns 0 and fills *req, or -1 with a one-line message in err naming
 * what is wrong (not JSON, not an object, no or an unknown "cmd", a field
 * of the wrong type or range); *cmd_name then holds the "cmd" string when
 * there was one (else ""), and req->id the id when there was one, so the
 * error reply can name both. */
int pb_serve_parse(const char *line, size_t len, pb_serve_request *req, char *cmd_name, size_t cmd_cap, char *err,
                   size_t err_cap);

/* The camera a "camera" request describes, for an image of width x
 * height: position and frame from the view matrix (orthonormalised),
 * perspective (yfov across the vertical side, lens shift, clip planes) or
 * orthographic (projection[15] == 1: size across the vertical side; a
 * clip range that starts behind the view, as Blender's orthographic views
 * have, moves the camera back to its near plane) from the projection. Returns 0, or -1 with err (a singular or non-finite
 * matrix, a projection that is neither). */
int pb_serve_camera_from_matrices(const double view[16], const double projection[16], int blender_axes,
                                  pb_camera *out, char *err, size_t err_cap);

/* Reply lines, formatted into buf (NUL-terminated, '\n' at the end);
 * they return the length, or 0 when buf is too small. `id` is the
 * request's id text ("" for none) and strings are escaped. */
size_t pb_serve_format_ok(char *buf, size_t cap, const char *cmd, const char *id);
size_t pb_serve_format_error(char *buf, size_t cap, const char *cmd, const char *id, const char *message);

typedef struct pb_serve_frame_reply {
  int requested;             /* 1: the reply to "frame"; 0: a streamed frame event */
  uint64_t frame;
  const char *path, *format;
  uint32_t width, height, passes;
  int still;
  double render_ms;
  uint64_t photons_stored;
  const char *tracer;        /* the photon tracer that ran; NULL: "none" */
  double image_miss_rate;    /* tracer "images" only: segments no map confirmed, over all */
  int has_noise;             /* a stream with a noise threshold: "noise" */
  double noise;              /* its estimate; < 0: null */
} pb_serve_frame_reply;
size_t pb_serve_format_frame(char *buf, size_t cap, const char *id, const pb_serve_frame_reply *f);

/* JSON string escaping of s into buf (with the quotes); the length, or 0
 * when it does not fit. */
size_t pb_serve_json_string(char *buf, size_t cap, const char *s);

#endif
