/* serve's JSON-lines protocol (serve/protocol.h), without a GPU: every
 * request parses into its fields (ids echoed, escapes decoded); malformed
 * JSON, a non-object, no or an unknown "cmd", an unknown field and values
 * of the wrong type or range are errors naming what is wrong (and the
 * command, when there is one); the camera from a view and a projection
 * matrix (perspective with lens shift and clip planes, orthographic, and
 * Blender's Z-up axes) is the camera the matrices were built from; reply
 * lines are one line of JSON with the strings escaped. */
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "pbtest.h"
#include "render/estimate/estimator.h"
#include "render/photon/tracer.h"
#include "serve/protocol.h"

static pb_serve_request req;
static char cmd[80], err[600];

static int parse(const char *line) { return pb_serve_parse(line, strlen(line), &req, cmd, sizeof cmd, err, sizeof err); }

static int fails_with(const char *line, const char *needle) {
  int rc = parse(line);
  int ok = rc == -1 && strstr(err, needle) != NULL;
  if (!ok) fprintf(stderr, "  %s -> rc %d, '%s' (wanted '%s')\n", line, rc, err, needle);
  return ok;
}

static void test_requests(void) {
  CHECK(parse("{\"cmd\":\"frame\"}") == 0);
  CHECK_EQ_INT(req.cmd, PB_SERVE_FRAME);
  CHECK(req.id[0] == 0);
  CHECK(parse(" { \"id\" : 17 , \"cmd\" : \"quit\" } ") == 0);
  CHECK_EQ_INT(req.cmd, PB_SERVE_QUIT);
  CHECK(strcmp(req.id, "17") == 0);
  CHECK(parse("{\"cmd\":\"time\",\"t\":1.25e0,\"id\":\"a\\\"b\"}") == 0);
  CHECK_EQ_INT(req.cmd, PB_SERVE_TIME);
  CHECK_NEAR(req.t, 1.25, 0);
  CHECK(strcmp(req.id, "\"a\\\"b\"") == 0); /* the id's JSON text, echoed as it came */
  CHECK(parse("{\"cmd\":\"resolution\",\"width\":320,\"height\":200}") == 0);
  CHECK_EQ_INT(req.width, 320);
  CHECK_EQ_INT(req.height, 200);
  CHECK(parse("{\"cmd\":\"settings\",\"photons\":65536,\"progressive\":true,\"seed\":12345678901,\"atrous_iterations\":0}") == 0);
  CHECK(req.settings.set.given ==
        (PB_SETTING_BIT(photons) | PB_SETTING_BIT(progressive) | PB_SETTING_BIT(atrous_iterations)));
  CHECK_EQ_INT(req.settings.seed_given, 1);
  CHECK_EQ_INT(req.settings.set.photons, 65536);
  CHECK_EQ_INT(req.settings.set.progressive, 1);
  CHECK(req.settings.seed == 12345678901ull);
  CHECK_EQ_INT(req.settings.set.atrous_iterations, 0);
  /* Every setting of the table offered to requests, with its kind: the
   * estimator (a choice), a number, a flag that is on by default. */
  CHECK(parse("{\"cmd\":\"settings\",\"estimator\":\"knn\",\"knn_k\":16,\"atrous_clip\":0.5,"
              "\"temporal\":false,\"photon_bounces\":200}") == 0);
  CHECK(req.settings.set.given == (PB_SETTING_BIT(estimator) | PB_SETTING_BIT(knn_k) | PB_SETTING_BIT(atrous_clip) |
                                   PB_SETTING_BIT(temporal) | PB_SETTING_BIT(photon_bounces)));
  CHECK_EQ_INT(req.settings.set.estimator, PB_ESTIMATOR_KNN);
  CHECK_EQ_INT(req.settings.set.knn_k, 16);
  CHECK(req.settings.set.atrous_clip == 0.5);
  CHECK_EQ_INT(req.settings.set.temporal, 0);
  CHECK_EQ_INT(req.settings.set.photon_bounces, 200);
  CHECK_EQ_INT(req.settings.seed_given, 0);
  /* The photon tracer (render --tracer) and the images tracer's maps. */
  CHECK(parse("{\"cmd\":\"settings\",\"tracer\":\"images\",\"image_maps\":4,\"image_map_resolution\":32}") == 0);
  CHECK(req.settings.set.given ==
        (PB_SETTING_BIT(tracer) | PB_SETTING_BIT(image_maps) | PB_SETTING_BIT(image_map_resolution)));
  CHECK_EQ_INT(req.settings.set.tracer, PB_TRACER_IMAGES);
  CHECK_EQ_INT(req.settings.set.image_maps, 4);
  CHECK_EQ_INT(req.settings.set.image_map_resolution, 32);
  CHECK(parse("{\"cmd\":\"settings\",\"tracer\":\"bvh\"}") == 0);
  CHECK(req.settings.set.given == PB_SETTING_BIT(tracer));
  CHECK_EQ_INT(req.settings.set.tracer, PB_TRACER_BVH);
  CHECK(parse("{\"cmd\":\"stream\",\"on\":true,\"max_passes\":8}") == 0);
  CHECK_EQ_INT(req.stream_on, 1);
  CHECK_EQ_INT(req.max_passes, 8);
  CHECK(req.noise_threshold == -1.0); /* not given: the session's --noise-threshold */
  CHECK(parse("{\"cmd\":\"stream\",\"on\":true,\"noise_threshold\":0.05}") == 0);
  CHECK(req.noise_threshold == 0.05);
  CHECK(parse("{\"cmd\":\"reload\",\"scene\":\"/tmp/caf\\u00e9 \\ud83d\\ude00\\n.gltf\"}") == 0);
  CHECK(strcmp(req.scene, "/tmp/caf\xc3\xa9 \xf0\x9f\x98\x80\n.gltf") == 0);
  CHECK(parse("{\"cmd\":\"reload\"}") == 0);
  CHECK(req.scene[0] == 0);
  CHECK(parse("{\"cmd\":\"camera\",\"index\":2}") == 0);
  CHECK_EQ_INT(req.camera_index, 2);
  CHECK(parse("{\"cmd\":\"camera\",\"axes\":\"blender\",\"view\":[1,0,0,0, 0,1,0,0, 0,0,1,-5, 0,0,0,1],"
              "\"projection\":[2,0,0,0, 0,2,0,0, 0,0,-1.002,-0.2002, 0,0,-1,0]}") == 0);
  CHECK_EQ_INT(req.camera_index, -1);
  CHECK_EQ_INT(req.blender_axes, 1);
  CHECK_NEAR(req.view[11], -5, 0);
  CHECK_NEAR(req.projection[14], -1, 0);
}

static void test_errors(void) {
  CHECK(fails_with("", "end of the line"));
  CHECK(fails_with("{\"cmd\":\"frame\"", "expected ','"));
  CHECK(fails_with("{\"cmd\":\"frame\"} x", "text after"));
  CHECK(fails_with("[1,2]", "JSON object"));
  CHECK(fails_with("{\"cmd\":\"fra\\qme\"}", "bad escape"));
  CHECK(fails_with("{\"cmd\":\"x\",\"t\":01}", "expected ','")); /* a leading zero ends the number */
  CHECK(fails_with("{\"cmd\":\"time\",\"t\":-}", "bad number"));
  CHECK(fails_with("{\"cmd\":\"frame\",\"s\":\"\\ud800\"}", "surrogate"));
  CHECK(fails_with("{\"cmd\":\"fr\xc3\"}", "not UTF-8"));
  CHECK(fails_with("{\"cmd\":\"\xed\xa0\x80\"}", "not UTF-8")); /* an encoded surrogate */
  CHECK(fails_with("{\"cmd\":\xff}", "unexpected byte 0xff"));
  CHECK(fails_with("{\"t\":1}", "no \"cmd\""));
  CHECK(fails_with("{\"cmd\":\"teleport\"}", "unknown command \"teleport\""));
  CHECK(strcmp(cmd, "teleport") == 0); /* the error reply names it */
  CHECK(fails_with("{\"cmd\":\"frame\",\"colour\":1}", "\"frame\": unknown field \"colour\""));
  CHECK(strcmp(cmd, "frame") == 0);
  CHECK(fails_with("{\"cmd\":\"resolution\",\"width\":0,\"height\":10}", "\"width\" must be an integer in [1, 16384]"));
  CHECK(fails_with("{\"cmd\":\"resolution\",\"width\":10}", "needs \"width\" and \"height\""));
  CHECK(fails_with("{\"cmd\":\"resolution\",\"width\":10.5,\"height\":10}", "integer"));
  CHECK(fails_with("{\"cmd\":\"time\",\"t\":\"soon\"}", "needs \"t\""));
  CHECK(fails_with("{\"cmd\":\"settings\",\"progressive\":1}", "true or false"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"photons\":-4}", "\"photons\" must be an integer"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"tracer\":\"kdtree\"}", "\"tracer\" must be one of \"bvh\", \"images\""));
  CHECK(fails_with("{\"cmd\":\"settings\",\"photon_bounces\":256}", "\"photon_bounces\" must be an integer in [1, 255]"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"atrous_clip\":101}", "\"atrous_clip\" must be a number in [0, 100]"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"noise_threshold\":0.1}", "unknown field \"noise_threshold\""));
  CHECK(fails_with("{\"cmd\":\"settings\",\"tracer\":1}", "\"tracer\" must be"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"image_maps\":16}", "\"image_maps\" must be an integer in [1, 15]"));
  CHECK(fails_with("{\"cmd\":\"settings\",\"image_map_resolution\":4}", "\"image_map_resolution\" must be"));
  CHECK(fails_with("{\"cmd\":\"stream\"}", "needs \"on\""));
  CHECK(fails_with("{\"cmd\":\"camera\",\"view\":[1,2,3]}", "\"view\" must be an array of 16"));
  CHECK(fails_with("{\"cmd\":\"camera\",\"view\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1]}", "needs \"projection\""));
  CHECK(fails_with("{\"cmd\":\"camera\",\"index\":1,\"view\":[]}", "either \"index\""));
  CHECK(fails_with("{\"cmd\":\"camera\",\"axes\":\"x\",\"view\":[1,0,0,0,0,1,0,0,0,0,1,0,0,0,0,1],"
                   "\"projection\":[1,0,0,0,0,1,0,0,0,0,-1,-1,0,0,-1,0]}", "\"axes\" must be"));
  CHECK(fails_with("{\"cmd\":\"frame\",\"id\":[1]}", "\"id\" must be"));
  CHECK(fails_with("{\"cmd\":\"reload\",\"scene\":\"\"}", "non-empty path"));
  /* Deep nesting and many values stop at their limits, not at the stack's. */
  char deep[200];
  memset(deep, '[', 100);
  deep[100] = 0;
  CHECK(fails_with(deep, "nested more than"));
  static char many[8192];
  size_t o = (size_t)snprintf(many, sizeof many, "{\"cmd\":\"frame\",\"x\":[");
  for (int i = 0; i < 600; ++i) o += (size_t)snprintf(many + o, sizeof many - o, "%s0", i ? "," : "");
  snprintf(many + o, sizeof many - o, "]}");
  CHECK(fails_with(many, "more than 512 values"));
}

/* Row-major OpenGL matrices of a camera: view = [R t] with R's rows right,
 * up, -forward. */
static void view_of(const double pos[3], const double fwd[3], const double up[3], double V[16]) {
  double r[3] = {fwd[1] * up[2] - fwd[2] * up[1], fwd[2] * up[0] - fwd[0] * up[2], fwd[0] * up[1] - fwd[1] * up[0]};
  const double *rows[3] = {r, up, fwd};
  double sign[3] = {1, 1, -1};
  memset(V, 0, 16 * sizeof *V);
  for (int i = 0; i < 3; ++i) {
    double t = 0;
    for (int k = 0; k < 3; ++k) V[4 * i + k] = sign[i] * rows[i][k], t -= V[4 * i + k] * pos[k];
    V[4 * i + 3] = t;
  }
  V[15] = 1;
}

/* glFrustum of a window at distance n: l..r, b..t. */
static void frustum(double l, double r, double b, double t, double n, double f, double P[16]) {
  memset(P, 0, 16 * sizeof *P);
  P[0] = 2 * n / (r - l), P[2] = (r + l) / (r - l);
  P[5] = 2 * n / (t - b), P[6] = (t + b) / (t - b);
  P[10] = -(f + n) / (f - n), P[11] = -2 * f * n / (f - n);
  P[14] = -1;
}

static void test_camera(void) {
  pb_camera c;
  double V[16], P[16];
  /* Perspective: 60 degrees vertical, 16:9, shifted window, clip 0.1..100. */
  double pos[3] = {1, 2, 3}, fwd[3] = {0, 0, -1}, up[3] = {0, 1, 0};
  view_of(pos, fwd, up, V);
  double n = 0.1, f = 100, ht = tan(M_PI / 6), wt = ht * 16.0 / 9.0;
  double cx = 0.2 * 2 * ht, cy = -0.1 * 2 * ht; /* shift 0.2, -0.1 of the vertical extent */
  frustum((cx - wt) * n, (cx + wt) * n, (cy - ht) * n, (cy + ht) * n, n, f, P);
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == 0);
  CHECK_EQ_INT(c.orthographic, 0);
  CHECK_EQ_INT(c.fit, PB_CAMERA_FIT_VERTICAL);
  CHECK_NEAR(c.yfov, M_PI / 3, 1e-6);
  CHECK_NEAR(c.aspect, 16.0 / 9.0, 1e-5);
  CHECK_NEAR(c.shift[0], 0.2, 1e-6);
  CHECK_NEAR(c.shift[1], -0.1, 1e-6);
  CHECK_NEAR(c.znear, 0.1, 1e-5);
  CHECK_NEAR(c.zfar, 100, 1e-2);
  for (int k = 0; k < 3; ++k) {
    CHECK_NEAR(c.position[k], pos[k], 1e-6);
    CHECK_NEAR(c.forward[k], fwd[k], 1e-6);
    CHECK_NEAR(c.up[k], up[k], 1e-6);
  }
  CHECK_NEAR(c.right[0], 1, 1e-6);
  /* A tilted camera: the frame comes back orthonormal. */
  double f2[3] = {0.6, -0.8, 0}, u2[3] = {0.8, 0.6, 0}, p2[3] = {-4, 0.5, 7};
  view_of(p2, f2, u2, V);
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == 0);
  for (int k = 0; k < 3; ++k) {
    CHECK_NEAR(c.position[k], p2[k], 1e-5);
    CHECK_NEAR(c.forward[k], f2[k], 1e-6);
    CHECK_NEAR(c.up[k], u2[k], 1e-6);
  }
  CHECK_NEAR(c.right[2], 1, 1e-6); /* forward x up = (0.6, -0.8, 0) x (0.8, 0.6, 0) = (0, 0, 1) */
  /* Blender's axes: a camera at Blender (0, -5, 1) looking along Blender +Y
   * with +Z up is glTF (0, 1, 5) looking along -Z with +Y up. */
  double pb[3] = {0, -5, 1}, fb[3] = {0, 1, 0}, ub[3] = {0, 0, 1};
  view_of(pb, fb, ub, V);
  CHECK(pb_serve_camera_from_matrices(V, P, 1, &c, err, sizeof err) == 0);
  double pg[3] = {0, 1, 5}, fg[3] = {0, 0, -1}, ug[3] = {0, 1, 0}, rg[3] = {1, 0, 0};
  for (int k = 0; k < 3; ++k) {
    CHECK_NEAR(c.position[k], pg[k], 1e-6);
    CHECK_NEAR(c.forward[k], fg[k], 1e-6);
    CHECK_NEAR(c.up[k], ug[k], 1e-6);
    CHECK_NEAR(c.right[k], rg[k], 1e-6);
  }
  /* Orthographic: 6 m tall, 4:3, centred 0.5 m right, clip 1..50. */
  memset(P, 0, sizeof P);
  double w = 8, h = 6, ox = 0.5;
  P[0] = 2 / w, P[3] = -(2 * ox) / w; /* x_ndc = (x - ox) * 2 / w */
  P[5] = 2 / h;
  P[10] = -2 / (50 - 1.0), P[11] = -(50 + 1.0) / (50 - 1.0);
  P[15] = 1;
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == 0);
  CHECK_EQ_INT(c.orthographic, 1);
  CHECK_NEAR(c.ortho_size, 6, 1e-6);
  CHECK_NEAR(c.aspect, 4.0 / 3.0, 1e-6);
  CHECK_NEAR(c.shift[0], ox / h, 1e-6);
  CHECK_NEAR(c.znear, 1, 1e-5);
  CHECK_NEAR(c.zfar, 50, 1e-4);
  /* Orthographic with the clip range behind the view (Blender: -50..50):
   * the camera moves back 50 m along its axis, clipping 0..100. */
  P[10] = -2 / 100.0, P[11] = 0;
  view_of(pos, fwd, up, V);
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == 0);
  CHECK_NEAR(c.position[2], pos[2] + 50, 1e-4);
  CHECK_NEAR(c.znear, 0, 0);
  CHECK_NEAR(c.zfar, 100, 1e-4);
  /* Bad matrices. */
  P[15] = 0.5;
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == -1 && strstr(err, "projection"));
  double Z[16] = {0};
  Z[15] = 1;
  frustum(-1, 1, -1, 1, 1, 10, P);
  CHECK(pb_serve_camera_from_matrices(Z, P, 0, &c, err, sizeof err) == -1 && strstr(err, "view"));
  view_of(pos, fwd, up, V);
  V[0] = -1; /* mirrored */
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == -1 && strstr(err, "mirrored"));
  V[0] = NAN;
  CHECK(pb_serve_camera_from_matrices(V, P, 0, &c, err, sizeof err) == -1 && strstr(err, "non-finite"));
}

static void test_replies(void) {
  char buf[512];
  size_t n = pb_serve_format_ok(buf, sizeof buf, "camera", "7");
  CHECK(n == strlen(buf) && strcmp(buf, "{\"reply\":\"camera\",\"id\":7,\"ok\":true}\n") == 0);
  n = pb_serve_format_error(buf, sizeof buf, NULL, "", "line 3: bad \"x\"\tand\\");
  CHECK(strcmp(buf, "{\"reply\":null,\"ok\":false,\"error\":\"line 3: bad \\\"x\\\"\\u0009and\\\\\"}\n") == 0);
  pb_serve_frame_reply f = {.requested = 1, .frame = 4, .path = "/dev/shm/p.rgba32f", .format = "rgba32f",
                            .width = 64, .height = 48, .passes = 3, .still = 1, .render_ms = 12.5,
                            .photons_stored = 1000};
  n = pb_serve_format_frame(buf, sizeof buf, "\"q\"", &f);
  CHECK(strcmp(buf, "{\"reply\":\"frame\",\"id\":\"q\",\"ok\":true,\"frame\":4,\"path\":\"/dev/shm/p.rgba32f\","
                    "\"width\":64,\"height\":48,\"format\":\"rgba32f\",\"passes\":3,\"still\":true,"
                    "\"render_ms\":12.500,\"photons_stored\":1000,\"tracer\":\"none\"}\n") == 0);
  f.tracer = "images", f.image_miss_rate = 0.25; /* the images tracer adds its miss rate */
  pb_serve_format_frame(buf, sizeof buf, "\"q\"", &f);
  CHECK(strstr(buf, ",\"tracer\":\"images\",\"image_miss_rate\":0.25}\n") != NULL);
  f.tracer = "bvh";
  pb_serve_format_frame(buf, sizeof buf, "\"q\"", &f);
  CHECK(strstr(buf, ",\"tracer\":\"bvh\"}\n") != NULL);
  f.requested = 0;
  pb_serve_format_frame(buf, sizeof buf, "\"q\"", &f);
  CHECK(strncmp(buf, "{\"event\":\"frame\",\"ok\":true,", 27) == 0); /* a streamed frame answers no request */
  CHECK(strchr(buf, '\n') == buf + strlen(buf) - 1);
  CHECK(pb_serve_format_ok(buf, 10, "camera", "") == 0); /* too small: nothing, never a cut line */
  pb_serve_json_string(buf, sizeof buf, "caf\xc3\xa9 \xff\x7f");
  CHECK(strcmp(buf, "\"caf\xc3\xa9 \\ufffd\\u007f\"") == 0); /* replies stay UTF-8 */
}

int main(void) {
  test_requests();
  test_errors();
  test_camera();
  test_replies();
  return pbt_done();
}
