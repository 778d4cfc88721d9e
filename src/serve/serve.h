/* `photonbridge serve`: a persistent session. The scene
 * is loaded once; requests (protocol.h) change the camera, the size, the
 * time, the settings or the scene, and frames are rendered by the live
 * session (view/session.h, the loop `view` runs) and handed over as files
 * in a private folder of the session's own (mkdtemp under /dev/shm, else
 * $TMPDIR or /tmp, or --frame-dir; mode 0700, each file in it created
 * exclusively with mode 0600), each written atomically, the reply naming
 * it: clients take the path from the replies.
 *
 * The session ends, removing its files, on "quit", on EOF of its input
 * (the client closed the pipe or died), when a reply cannot be written
 * (the client is gone: EPIPE), and on SIGINT / SIGTERM (main.c's handler
 * removes the registered folder with its files). The base failing to hold
 * the folder is an error returned naming the base, before the scene loads. */
#ifndef PB_SERVE_SERVE_H
#define PB_SERVE_SERVE_H

#include <stdint.h>

#include "core/result.h"
#include "gpu/gpu.h"
#include "render/frame/sequence.h"
#include "render/settings.h"
#include "scene/scene.h"

enum { PB_SERVE_FORMAT_RGBA32F, PB_SERVE_FORMAT_EXR };

/* Loads the scene at `path` as the command line says (the scene options,
 * --camera, --width/--height): the scene, the camera to render and the
 * image size. Called for the first scene and for every "load" request. */
typedef pb_result (*pb_serve_load_fn)(void *user, const char *path, pb_scene *s, int *camera,
                                      uint32_t *w, uint32_t *h);

typedef struct pb_serve_desc {
  const char *scene;            /* the file loaded first */
  pb_serve_load_fn load;        /* how every scene is (re)loaded */
  void *load_user;
  pb_sequence_desc seq;         /* the frame settings; "settings" requests change them */
  pb_settings settings;         /* what seq was made from (render/settings.h) */
  const char *socket_path;      /* NULL: requests on stdin, replies on stdout */
  const char *frame_dir;        /* the base of the session folder; NULL: /dev/shm, else $TMPDIR or /tmp */
  int format;                   /* PB_SERVE_FORMAT_* */
} pb_serve_desc;

/* Runs the session until it ends. The scene failing to load at the start
 * is the error returned (one line on stderr, and an "event":"error" line
 * to the client); later failures (a reload, a bad request, a frame) are
 * error replies and the session goes on. */
pb_result pb_serve_run(pb_gpu *g, const pb_serve_desc *d);
/* --socket PATH usable (not too long; absent, or a stale socket): checked
 * before a Vulkan device is opened, so a wrong path fails at once. */
pb_result pb_serve_socket_check(const char *path);

#endif
