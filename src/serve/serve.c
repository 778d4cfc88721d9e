/* `photonbridge serve`'s session (serve.h): the request loop around the
 * live session of view/session.h. */
#include "serve/serve.h"

#include <errno.h>
#include <limits.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include "render/frame/result_exr.h"
#include "core/fs.h"
#include "core/log.h"
#include "serve/protocol.h"
#include "view/session.h"

typedef struct server {
  pb_gpu *g;
  const pb_serve_desc *d;
  int in_fd, out_fd, listen_fd, client_gone;
  char *in;                    /* bytes read and not yet a whole line */
  size_t in_len, in_cap;
  int in_skip;                 /* discarding the rest of an over-long line */
  unsigned long line_no;
  /* the scene */
  char path[PB_SERVE_MAX_PATH];
  pb_scene s;
  pb_gpu_scene gs;
  int loaded;
  pb_camera *file_cams;        /* the file's cameras as loaded ("index") */
  uint32_t file_cam_count;
  /* the live session */
  pb_view_session ses;
  int ses_ok;
  pb_sequence_desc desc;
  pb_settings settings;        /* what desc was made from (settings.h) */
  uint32_t width, height;
  int size_set;                /* a "resolution" request chose the size */
  pb_camera cam;
  int cam_set;
  double t;
  int streaming, pending;      /* pending: something changed since the last frame */
  uint32_t max_passes;
  double noise_threshold;      /* the stream's (0: none) */
  uint64_t served;             /* frames handed over */
  char dir[PATH_MAX];          /* the session's private folder (0700): "" until made */
  char frame_path[PATH_MAX];   /* in it; written only through 0600 exclusive temporaries */
  char *reply;                 /* a reply line */
  int quit;
} server;

enum { REPLY_CAP = 2 * PB_SERVE_MAX_PATH + 4096 };

/* ---- output ---------------------------------------------------------------- */

static void send_line(server *v, const char *buf, size_t len) {
  if (v->client_gone || !len) return;
  size_t o = 0;
  while (o < len) {
    ssize_t n = write(v->out_fd, buf + o, len - o);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      /* EPIPE (SIGPIPE is ignored) or any other failure: nobody reads. */
      pb_log_verbose("serve: the client is gone (%s); ending", n < 0 ? strerror(errno) : "short write");
      v->client_gone = 1, v->quit = 1;
      return;
    }
    o += (size_t)n;
  }
}

static void reply_ok(server *v, pb_serve_cmd cmd, const char *id) {
  send_line(v, v->reply, pb_serve_format_ok(v->reply, REPLY_CAP, pb_serve_cmd_name(cmd), id));
}

static void reply_error(server *v, const char *cmd, const char *id, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void reply_error(server *v, const char *cmd, const char *id, const char *fmt, ...) {
  char msg[1400];
  va_list ap;
  va_start(ap, fmt);
  vsnprintf(msg, sizeof msg, fmt, ap);
  va_end(ap);
  send_line(v, v->reply, pb_serve_format_error(v->reply, REPLY_CAP, cmd, id, msg));
}

/* ---- the scene and the session ------------------------------------------------ */

static void drop_scene(server *v, pb_scene *s, pb_gpu_scene *gs) {
  pb_gpu_scene_destroy(v->g, gs);
  pb_scene_destroy(s);
  memset(gs, 0, sizeof *gs);
  memset(s, 0, sizeof *s);
}

/* Loads `path` as the command line says (--camera, --width/--height, the
 * scene options), builds its GPU scene and (re)starts the session on it;
 * the old scene is dropped only when the new one loaded. */
static pb_result load(server *v, const char *path) {
  pb_scene s;
  pb_gpu_scene gs;
  memset(&s, 0, sizeof s);
  memset(&gs, 0, sizeof gs);
  int camera;
  uint32_t w, h;
  pb_camera *cams = NULL;
  pb_result r = v->d->load(v->d->load_user, path, &s, &camera, &w, &h);
  if (r != PB_OK) return r;
  if ((r = pb_gpu_scene_create(v->g, &s, &gs)) != PB_OK)
    goto fail;
  if (!(cams = malloc(s.camera_count * sizeof *cams))) {
    r = pb_fail(PB_ERR_NOMEM, "serve: out of memory");
    goto fail;
  }
  memcpy(cams, s.cameras, s.camera_count * sizeof *cams);
  if (!v->size_set) v->width = w, v->height = h;
  pb_scene old = v->s;
  pb_gpu_scene old_gs = v->gs;
  int had = v->loaded;
  v->s = s, v->gs = gs, v->loaded = 1;
  free(v->file_cams);
  v->file_cams = cams, v->file_cam_count = s.camera_count;
  v->ses.camera = camera;
  if (!had) r = pb_view_session_create(&v->ses, v->g, &v->s, &v->gs, camera, v->width, v->height, &v->desc);
  else r = pb_view_session_reset(&v->ses, &v->s, &v->gs, v->width, v->height, &v->desc);
  v->ses_ok = r == PB_OK;
  if (had) drop_scene(v, &old, &old_gs);
  snprintf(v->path, sizeof v->path, "%s", path);
  v->pending = 1;
  return r;
fail:
  free(cams);
  drop_scene(v, &s, &gs);
  return r;
}

static pb_result restart(server *v) {
  pb_result r = pb_view_session_reset(&v->ses, &v->s, &v->gs, v->width, v->height, &v->desc);
  v->ses_ok = r == PB_OK;
  v->pending = 1;
  return r;
}

/* ---- frames ---------------------------------------------------------------- */

static pb_result write_rgba32f(const char *path, const pb_render_result *res, uint64_t frame) {
  FILE *f;
  char *tmp;
  pb_result r = pb_atomic_open_private(path, &f, &tmp);
  if (r != PB_OK) return r;
  unsigned char head[32];
  memset(head, 0, sizeof head);
  memcpy(head, "PBFRAME1", 8);
  uint32_t u[4] = {res->width, res->height, 4, 0};
  for (int i = 0; i < 4; ++i)
    for (int b = 0; b < 4; ++b) head[8 + 4 * i + b] = (unsigned char)(u[i] >> (8 * b));
  for (int b = 0; b < 8; ++b) head[24 + b] = (unsigned char)(frame >> (8 * b));
  /* The pixels: little-endian float32 on every host photonbridge builds on. */
  fwrite(head, 1, sizeof head, f);
  fwrite(res->beauty, sizeof(float), (size_t)res->width * res->height * 4, f);
  return pb_atomic_commit(path, f, tmp);
}

/* pb_exr_write writes the temporary pb_tmp_name(path) through OpenEXR,
 * which opens it with O_CREAT|O_TRUNC and mode 0666 less the umask. The
 * temporary is created here first, exclusively with mode 0600
 * (pb_private_open): OpenEXR then truncates that file, which keeps its
 * mode, so the frame is 0600 whatever the umask the client gave serve. */
static pb_result write_exr(const char *path, const pb_render_result *res) {
  char *tmp = pb_tmp_name(path);
  if (!tmp) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  int fd = pb_private_open(tmp);
  if (fd < 0) {
    pb_result r = pb_fail(PB_ERR_IO, "%s: cannot write: %s", path, strerror(errno));
    free(tmp);
    return r;
  }
  close(fd);
  pb_tmp_register(tmp);
  pb_result r = pb_render_write_exr(path, res, NULL, NULL, NULL, NULL, 0);
  if (r != PB_OK) unlink(tmp); /* a failure before OpenEXR opened it leaves it */
  pb_tmp_unregister(tmp);
  free(tmp);
  return r;
}

static void render_frame(server *v, int requested, const char *id) {
  if (!v->ses_ok) {
    reply_error(v, "frame", requested ? id : "", "no session to render (the last reload or reset failed: fix the "
                "scene and reload)");
    v->streaming = 0;
    return;
  }
  double t0 = pb_time_now();
  pb_result r = pb_view_session_frame(&v->ses, v->cam_set ? &v->cam : NULL, v->t);
  double ms = (pb_time_now() - t0) * 1e3;
  if (r == PB_OK)
    r = v->d->format == PB_SERVE_FORMAT_EXR ? write_exr(v->frame_path, &v->ses.res)
                                            : write_rgba32f(v->frame_path, &v->ses.res, v->served);
  if (r != PB_OK) {
    reply_error(v, "frame", requested ? id : "", "%s", pb_error_message());
    v->streaming = 0;
    if (r == PB_ERR_DEVICE_LOST) v->quit = 1;
    return;
  }
  v->pending = 0;
  if ((r = pb_view_session_noise_update(&v->ses, v->noise_threshold)) != PB_OK) {
    reply_error(v, "frame", requested ? id : "", "%s", pb_error_message());
    v->streaming = 0;
    return;
  }
  const pb_render_stats *st = &v->ses.res.stats;
  double miss_rate = pb_render_image_miss_rate(st); /* as render --json reports it */
  pb_serve_frame_reply f = {.requested = requested,
                            .frame = v->served++,
                            .path = v->frame_path,
                            .format = v->d->format == PB_SERVE_FORMAT_EXR ? "exr" : "rgba32f",
                            .width = v->ses.res.width,
                            .height = v->ses.res.height,
                            .passes = v->ses.run_frames,
                            .still = v->ses.info.still && v->ses.frame > 1,
                            .render_ms = ms,
                            .photons_stored = st->photons_stored,
                            .tracer = st->tracer,
                            .image_miss_rate = miss_rate > 0 ? miss_rate : 0.0,
                            .has_noise = v->noise_threshold > 0,
                            .noise = pb_view_session_noise(&v->ses)};
  send_line(v, v->reply, pb_serve_format_frame(v->reply, REPLY_CAP, id, &f));
}

/* ---- requests -------------------------------------------------------------- */

/* A "settings" request: the settings given merged into the session's,
 * checked as the command line's are, and the frames' desc made from them
 * (settings.h), as `serve`'s options made the first. */
static pb_result apply_settings(server *v, const pb_serve_settings *q, pb_settings *ns, pb_sequence_desc *nd) {
  *ns = v->settings;
  pb_settings_merge(ns, &q->set);
  pb_result r = pb_settings_check("serve", ns, 0);
  if (r != PB_OK) return r;
  *nd = v->desc;
  pb_settings_render_desc(ns, 1, &nd->render);
  nd->temporal = ns->temporal;
  if (q->seed_given) nd->render.seed = q->seed;
  return PB_OK;
}

static void handle_line(server *v, const char *line, size_t len) {
  v->line_no++;
  while (len && (line[len - 1] == '\r' || line[len - 1] == ' ' || line[len - 1] == '\t')) len--;
  size_t i = 0;
  while (i < len && (line[i] == ' ' || line[i] == '\t')) i++;
  if (i == len) return; /* blank lines are no requests */
  pb_serve_request *q = malloc(sizeof *q);
  if (!q) {
    reply_error(v, NULL, "", "line %lu: out of memory", v->line_no);
    return;
  }
  char cmd[80], err[600];
  if (pb_serve_parse(line, len, q, cmd, sizeof cmd, err, sizeof err)) {
    reply_error(v, cmd, q->id, "line %lu: %s", v->line_no, err);
    free(q);
    return;
  }
  const char *name = pb_serve_cmd_name(q->cmd);
  pb_result r = PB_OK;
  switch (q->cmd) {
    case PB_SERVE_CAMERA: {
      pb_camera c;
      if (q->camera_index >= 0) {
        if ((uint32_t)q->camera_index >= v->file_cam_count) {
          reply_error(v, name, q->id, "line %lu: camera index %d, but the scene has %u camera%s", v->line_no,
                      q->camera_index, v->file_cam_count, v->file_cam_count == 1 ? "" : "s");
          break;
        }
        c = v->file_cams[q->camera_index];
      } else if (pb_serve_camera_from_matrices(q->view, q->projection, q->blender_axes, &c, err, sizeof err)) {
        reply_error(v, name, q->id, "line %lu: %s", v->line_no, err);
        break;
      }
      /* The same camera again (a client that sends it with every redraw)
       * keeps refining. */
      if (!v->cam_set || memcmp(&c, &v->cam, sizeof c) != 0) v->pending = 1;
      v->cam = c, v->cam_set = 1;
      reply_ok(v, q->cmd, q->id);
      break;
    }
    case PB_SERVE_RESOLUTION:
      v->size_set = 1;
      if (q->width != v->width || q->height != v->height || !v->ses_ok) {
        v->width = q->width, v->height = q->height;
        r = restart(v);
      }
      if (r != PB_OK) reply_error(v, name, q->id, "line %lu: %s", v->line_no, pb_error_message());
      else reply_ok(v, q->cmd, q->id);
      break;
    case PB_SERVE_TIME:
      if (q->t != v->t) v->pending = 1;
      v->t = q->t;
      reply_ok(v, q->cmd, q->id);
      break;
    case PB_SERVE_SETTINGS: {
      pb_sequence_desc nd;
      pb_settings ns;
      if ((r = apply_settings(v, &q->settings, &ns, &nd)) == PB_OK) {
        v->settings = ns;
        if (memcmp(&nd, &v->desc, sizeof nd) != 0 || !v->ses_ok) {
          v->desc = nd;
          r = restart(v);
        }
      }
      if (r != PB_OK) reply_error(v, name, q->id, "line %lu: %s", v->line_no, pb_error_message());
      else reply_ok(v, q->cmd, q->id);
      break;
    }
    case PB_SERVE_FRAME: render_frame(v, 1, q->id); break;
    case PB_SERVE_STREAM:
      v->streaming = q->stream_on, v->max_passes = q->max_passes;
      v->noise_threshold = q->noise_threshold >= 0 ? q->noise_threshold : v->d->settings.noise_threshold;
      reply_ok(v, q->cmd, q->id);
      break;
    case PB_SERVE_RELOAD: {
      char path[PB_SERVE_MAX_PATH];
      snprintf(path, sizeof path, "%s", q->scene[0] ? q->scene : v->path);
      if ((r = load(v, path)) != PB_OK)
        reply_error(v, name, q->id, "line %lu: %s%s", v->line_no, pb_error_message(),
                    v->ses_ok ? " (the previous scene stays)" : "");
      else reply_ok(v, q->cmd, q->id);
      break;
    }
    case PB_SERVE_QUIT:
      reply_ok(v, q->cmd, q->id);
      v->quit = 1;
      break;
    case PB_SERVE_CMD_COUNT: break;
  }
  free(q);
}

/* Reads what is there; handles every whole line. 0 at EOF. */
static int read_input(server *v) {
  if (v->in_cap - v->in_len < 65536) {
    size_t nc = v->in_cap ? 2 * v->in_cap : 131072;
    char *ni = realloc(v->in, nc);
    if (!ni) {
      pb_fail(PB_ERR_NOMEM, "serve: out of memory for the input");
      return 0;
    }
    v->in = ni, v->in_cap = nc;
  }
  ssize_t n = read(v->in_fd, v->in + v->in_len, v->in_cap - v->in_len);
  if (n < 0 && (errno == EINTR || errno == EAGAIN)) return 1;
  int eof = n <= 0;
  if (n > 0) v->in_len += (size_t)n;
  size_t start = 0;
  for (size_t i = 0; i < v->in_len && !v->quit; ++i) {
    if (v->in[i] != '\n') continue;
    if (v->in_skip) v->in_skip = 0, v->line_no++;
    else handle_line(v, v->in + start, i - start);
    start = i + 1;
  }
  memmove(v->in, v->in + start, v->in_len - start);
  v->in_len -= start;
  if (v->in_len > PB_SERVE_MAX_LINE) {
    /* A line without its end past the limit: one error, then its rest is
     * dropped up to the next newline. */
    if (!v->in_skip) reply_error(v, NULL, "", "line %lu: longer than %d bytes", v->line_no + 1, PB_SERVE_MAX_LINE);
    v->in_skip = 1, v->in_len = 0;
  }
  if (eof && v->in_len && !v->in_skip && !v->quit) { /* a last line without its newline */
    handle_line(v, v->in, v->in_len);
    v->in_len = 0;
  }
  return !eof;
}

/* ---- the loop -------------------------------------------------------------- */

static const char *frame_dir(const pb_serve_desc *d) {
  if (d->frame_dir) return d->frame_dir;
  struct stat st;
  if (stat("/dev/shm", &st) == 0 && S_ISDIR(st.st_mode) && access("/dev/shm", W_OK) == 0) return "/dev/shm";
  const char *t = getenv("TMPDIR");
  return t && t[0] ? t : "/tmp";
}

pb_result pb_serve_socket_check(const char *path) {
  struct sockaddr_un a;
  if (strlen(path) >= sizeof a.sun_path)
    return pb_fail(PB_ERR_USAGE, "serve: --socket %s: longer than %zu bytes", path, sizeof a.sun_path - 1);
  struct stat st;
  if (lstat(path, &st) == 0 && !S_ISSOCK(st.st_mode))
    return pb_fail(PB_ERR_IO, "serve: --socket %s: exists and is not a socket", path);
  return PB_OK;
}

static pb_result open_socket(server *v, const char *path) {
  struct sockaddr_un a;
  memset(&a, 0, sizeof a);
  a.sun_family = AF_UNIX;
  pb_result r = pb_serve_socket_check(path);
  if (r != PB_OK) return r;
  snprintf(a.sun_path, sizeof a.sun_path, "%s", path);
  struct stat st;
  if (lstat(path, &st) == 0) unlink(path); /* a stale socket of a session that died */
  int fd = socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return pb_fail(PB_ERR_IO, "serve: socket: %s", strerror(errno));
  /* bind creates the socket file with mode 0777 less the umask, and
   * connecting needs write permission on it: umask 0177 for the bind makes
   * it 0600, so only this user can drive the session (serve is single-
   * threaded here; nothing else creates files meanwhile). */
  mode_t old_umask = umask(0177);
  int bound = bind(fd, (struct sockaddr *)&a, sizeof a) == 0;
  umask(old_umask);
  if (!bound || listen(fd, 1) != 0) {
    int e = errno;
    close(fd);
    return pb_fail(PB_ERR_IO, "serve: --socket %s: %s", path, strerror(e));
  }
  pb_tmp_register(path);
  v->listen_fd = fd;
  pb_log_info("serve: listening on %s", path);
  int c;
  do c = accept(fd, NULL, NULL);
  while (c < 0 && errno == EINTR);
  if (c < 0) return pb_fail(PB_ERR_IO, "serve: --socket %s: accept: %s", path, strerror(errno));
  v->in_fd = v->out_fd = c;
  return PB_OK;
}

pb_result pb_serve_run(pb_gpu *g, const pb_serve_desc *d) {
  server v;
  memset(&v, 0, sizeof v);
  v.g = g, v.d = d, v.desc = d->seq, v.settings = d->settings, v.in_fd = STDIN_FILENO, v.out_fd = STDOUT_FILENO, v.listen_fd = -1;
  /* rgba32f frames send the beauty alone, so only it comes to
   * the host (the EXR format writes every AOV: all are read). */
  if (d->format != PB_SERVE_FORMAT_EXR) v.desc.readback = PB_RENDER_READBACK_BEAUTY;
  signal(SIGPIPE, SIG_IGN); /* a dead client is a failed write, not a signal */
  pb_result r = PB_OK;
  if (!(v.reply = malloc(REPLY_CAP))) return pb_fail(PB_ERR_NOMEM, "serve: out of memory");
  /* The frames live in a folder of the session's own: an unpredictable
   * name (mkdtemp), mode 0700, so no other user can read them, and no name
   * in the shared base (/dev/shm, $TMPDIR, /tmp) is ever opened: nothing
   * planted there (a symlink at a name serve could guess) is followed.
   * Inside it every file is created exclusively with mode 0600. It is
   * registered (core/fs.h): SIGINT / SIGTERM remove it with what it holds
   * (main.c), as the end of the session does below. */
  const char *base = frame_dir(d);
  if (pb_private_dir_create(base, "photonbridge-serve", v.dir, sizeof v.dir) != PB_OK) {
    char why[1200];
    snprintf(why, sizeof why, "%s", pb_error_message());
    pb_error_clear(); /* the first failure wins: this one says which command */
    r = pb_fail(PB_ERR_IO, "serve: %s%s", why, d->frame_dir ? " (--frame-dir)" : "");
    reply_error(&v, NULL, "", "%s", pb_error_message());
    goto done;
  }
  int len = snprintf(v.frame_path, sizeof v.frame_path, "%s/frame.%s", v.dir,
                     d->format == PB_SERVE_FORMAT_EXR ? "exr" : "rgba32f");
  if (len < 0 || (size_t)len >= sizeof v.frame_path) {
    r = pb_fail(PB_ERR_USAGE, "serve: the session folder %s: its path is too long", v.dir);
    reply_error(&v, NULL, "", "%s", pb_error_message());
    goto done;
  }
  if (d->socket_path && (r = open_socket(&v, d->socket_path)) != PB_OK) goto done;
  if ((r = load(&v, d->scene)) != PB_OK) {
    reply_error(&v, NULL, "", "%s", pb_error_message());
    goto done;
  }
  {
    char scene[2 * PB_SERVE_MAX_PATH], dev[600];
    pb_serve_json_string(scene, sizeof scene, v.path);
    pb_serve_json_string(dev, sizeof dev, pb_gpu_device_name(g));
    int n = snprintf(v.reply, REPLY_CAP, "{\"event\":\"ready\",\"ok\":true,\"protocol\":1,\"scene\":%s,\"width\":%u,"
                     "\"height\":%u,\"cameras\":%u,\"device\":%s,\"device_type\":\"%s\",\"traversal\":\"%s\","
                     "\"frame_path\":", scene, v.width, v.height, v.file_cam_count, dev, pb_gpu_device_type(g),
                     pb_gpu_traversal(g));
    size_t m = pb_serve_json_string(v.reply + n, REPLY_CAP - (size_t)n - 4, v.frame_path);
    memcpy(v.reply + n + m, "}\n", 3);
    send_line(&v, v.reply, (size_t)n + m + 2);
  }
  while (!v.quit) {
    int want = v.streaming && v.ses_ok &&
               (v.pending || ((!v.max_passes || v.ses.run_frames < v.max_passes) && !pb_view_session_noise_reached(&v.ses, v.noise_threshold)));
    struct pollfd p = {.fd = v.in_fd, .events = POLLIN};
    int n = poll(&p, 1, want ? 0 : -1);
    if (n < 0) {
      if (errno == EINTR) continue;
      r = pb_fail(PB_ERR_IO, "serve: poll: %s", strerror(errno));
      break;
    }
    if (n > 0) {
      if (!read_input(&v)) break; /* EOF: the client closed its end or died */
    } else if (want) {
      render_frame(&v, 0, "");
    }
  }
  if (v.quit && !v.client_gone) pb_log_verbose("serve: quit after %lu request lines", v.line_no);
done:
  pb_private_dir_remove(v.dir); /* the frame and any temporary with it */
  if (v.listen_fd >= 0) {
    close(v.listen_fd);
    if (v.in_fd != STDIN_FILENO) close(v.in_fd);
    unlink(d->socket_path);
    pb_tmp_unregister(d->socket_path);
  }
  if (v.loaded) pb_view_session_destroy(&v.ses);
  drop_scene(&v, &v.s, &v.gs);
  free(v.file_cams);
  free(v.in);
  free(v.reply);
  return r;
}
