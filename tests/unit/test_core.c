/* Core: result table, one-line errors, CLI parsing, JSON writer, atomic files,
 * sRGB transfer, texture sampling, camera image sizes. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "core/srgb.h"
#include "app/cli.h"
#include "core/fs.h"
#include "core/json.h"
#include "core/result.h"
#include "pbtest.h"
#include "scene/scene.h"

static int dummy_run(int argc, char **argv) { (void)argc, (void)argv; return 0; }

static void test_results(void) {
  /* Exit codes are distinct per code (scripts branch on them) and OK is 0. */
  CHECK_EQ_INT(pb_result_exit_code(PB_OK), 0);
  for (int a = 0; a < PB_RESULT_COUNT; ++a) {
    CHECK(pb_result_message(a)[0] != 0);
    CHECK(strncmp(pb_result_name(a), "PB_", 3) == 0);
    for (int b = a + 1; b < PB_RESULT_COUNT; ++b) CHECK(pb_result_exit_code(a) != pb_result_exit_code(b));
  }
  CHECK_EQ_INT(pb_result_exit_code(PB_ERR_USAGE), 2);
  CHECK_EQ_INT(pb_result_exit_code(PB_ERR_INTERRUPTED), 130);
  CHECK_EQ_INT(pb_result_exit_code((pb_result)9999), 70);

  pb_error_clear();
  CHECK_EQ_INT(pb_fail(PB_ERR_IO, "a.gltf: line\nbreak %d", 7), PB_ERR_IO);
  CHECK(strcmp(pb_error_message(), "a.gltf: line break 7") == 0); /* one line */
  pb_fail(PB_ERR_LIMIT, "second");                                 /* first failure wins */
  CHECK_EQ_INT(pb_error_result(), PB_ERR_IO);
  pb_error_clear();
  CHECK_EQ_INT(pb_error_result(), PB_OK);
  CHECK(strcmp(pb_error_message(), "") == 0);
}

static void test_cli(void) {
  pb_command cmd = {"t", "X", "test", dummy_run};
  uint32_t w = 0;
  uint64_t seed = 0;
  double f = 0;
  int flag = 0, choice = 0;
  const char *s = NULL;
  static const char *const ch[] = {"a", "b", NULL};
  pb_opt o[] = {{"width", 0, PB_OPT_U32, &w, "W", "", NULL, 1, 100, NULL, 0},
                {"seed", 0, PB_OPT_U64, &seed, "N", "", NULL, 0, 0, NULL, 0},
                {"f", 0, PB_OPT_FLOAT, &f, "F", "", NULL, 0, 0, NULL, 0},
                {"flag", 'x', PB_OPT_FLAG, &flag, NULL, "", NULL, 0, 0, NULL, 0},
                {"mode", 0, PB_OPT_CHOICE, &choice, "M", "", ch, 0, 0, NULL, 0},
                {"out", 'o', PB_OPT_STRING, &s, "F", "", NULL, 0, 0, NULL, 0}};
  const char *pos[2];
  size_t np;
  int help;
  char *a1[] = {"t", "--width", "64", "--seed=12345678901", "--f", "2.5", "-x", "--mode", "b", "-o", "y.exr", "scene", NULL};
  pb_error_clear();
  CHECK_EQ_INT(pb_cli_parse(&cmd, 12, a1, o, 6, pos, 2, &np, &help), PB_OK);
  CHECK_EQ_INT(w, 64);
  CHECK(seed == 12345678901ull);
  CHECK_NEAR(f, 2.5, 0);
  CHECK_EQ_INT(flag, 1);
  CHECK_EQ_INT(choice, 1);
  CHECK(s && strcmp(s, "y.exr") == 0);
  CHECK_EQ_INT(np, 1);
  CHECK(strcmp(pos[0], "scene") == 0);

  struct { int argc; char *argv[4]; } bad[] = {
      {3, {"t", "--width", "0"}},     /* below range */
      {3, {"t", "--width", "-3"}},    /* negative */
      {3, {"t", "--width", "12x"}},   /* trailing junk */
      {2, {"t", "--width"}},          /* missing value */
      {2, {"t", "--nope"}},           /* unknown option */
      {3, {"t", "--mode", "c"}},      /* bad choice */
      {3, {"t", "--f", "nan"}},       /* not finite */
      {2, {"t", "--flag=1"}},         /* flag with value */
      {4, {"t", "a", "b", "c"}},      /* too many positionals */
  };
  for (size_t i = 0; i < sizeof bad / sizeof *bad; ++i) {
    pb_error_clear();
    CHECK_EQ_INT(pb_cli_parse(&cmd, bad[i].argc, bad[i].argv, o, 6, pos, 2, &np, &help), PB_ERR_USAGE);
    CHECK(strchr(pb_error_message(), '\n') == NULL && pb_error_message()[0]);
  }
  char *a2[] = {"t", "--help", "--nope", NULL};
  pb_error_clear();
  CHECK_EQ_INT(pb_cli_parse(&cmd, 3, a2, o, 6, pos, 2, &np, &help), PB_OK);
  CHECK_EQ_INT(help, 1);
  char *a3[] = {"t", "--", "--width", NULL}; /* after --, everything is positional */
  CHECK_EQ_INT(pb_cli_parse(&cmd, 3, a3, o, 6, pos, 2, &np, &help), PB_OK);
  CHECK_EQ_INT(np, 1);
}

static void test_json_and_files(void) {
  char dir[] = "/tmp/pbtest_core_XXXXXX";
  CHECK(mkdtemp(dir) != NULL);
  char path[256];
  snprintf(path, sizeof path, "%s/s.json", dir);
  pb_json j;
  char *tmp;
  pb_error_clear();
  CHECK_EQ_INT(pb_json_open(&j, path, &tmp), PB_OK);
  pb_json_begin_object(&j, NULL);
  pb_json_string(&j, "s", "a\"b\\c\n");
  pb_json_number(&j, "nan", NAN);
  pb_json_int(&j, "i", -5);
  pb_json_begin_array(&j, "a");
  pb_json_bool(&j, NULL, 1);
  pb_json_end_array(&j);
  pb_json_begin_array(&j, "empty");
  pb_json_end_array(&j);
  pb_json_end_object(&j);
  CHECK(access(path, F_OK) != 0); /* nothing at the final path before commit */
  CHECK_EQ_INT(pb_json_close(&j, path, tmp), PB_OK);
  uint8_t *data;
  size_t n;
  CHECK_EQ_INT(pb_read_file(path, 1 << 20, &data, &n), PB_OK);
  const char *want = "{\n  \"s\": \"a\\\"b\\\\c\\n\",\n  \"nan\": null,\n  \"i\": -5,\n  \"a\": [\n    true\n  ],\n  \"empty\": []\n}\n";
  CHECK(n == strlen(want) && memcmp(data, want, n) == 0);
  if (!(n == strlen(want) && memcmp(data, want, n) == 0)) fprintf(stderr, "got:\n%s\n", (const char *)data);
  free(data);
  /* Size limit and missing files give exact codes. */
  pb_error_clear();
  CHECK_EQ_INT(pb_read_file(path, 4, &data, &n), PB_ERR_LIMIT);
  pb_error_clear();
  CHECK_EQ_INT(pb_read_file("/nonexistent/x", 4, &data, &n), PB_ERR_IO);
  pb_error_clear();
  CHECK_EQ_INT(pb_read_file(dir, 1 << 20, &data, &n), PB_ERR_IO); /* a directory */
  /* Abort leaves nothing behind; unwritable folder is PB_ERR_IO. */
  char p2[256];
  snprintf(p2, sizeof p2, "%s/aborted.json", dir);
  FILE *f;
  CHECK_EQ_INT(pb_atomic_open(p2, &f, &tmp), PB_OK);
  fputs("half", f);
  pb_atomic_abort(f, tmp);
  CHECK(access(p2, F_OK) != 0);
  pb_error_clear();
  CHECK_EQ_INT(pb_atomic_open("/nonexistent/dir/x.json", &f, &tmp), PB_ERR_IO);
  unlink(path);
  rmdir(dir);
  CHECK(strcmp(pb_basename("a/b/c.gltf"), "c.gltf") == 0);
  char *d = pb_dirname("a/b/c.gltf");
  CHECK(d && strcmp(d, "a/b") == 0);
  free(d);
  d = pb_dirname("c.gltf");
  CHECK(d && strcmp(d, ".") == 0);
  free(d);
}

static int mode_of(const char *path) {
  struct stat st;
  return lstat(path, &st) == 0 ? (int)(st.st_mode & 07777) : -1;
}

/* serve's private session folder (core/fs.h): 0700 and 0600 exactly under
 * umask 000, a planted symlink never followed, the folder emptied and
 * removed by the signal handler's path and by pb_private_dir_remove. */
static void test_private_files(void) {
  char base[] = "/tmp/pbtest_private_XXXXXX";
  CHECK(mkdtemp(base) != NULL);
  mode_t old = umask(0);
  char dir[512], path[600], victim[600], link[600];
  pb_error_clear();
  CHECK_EQ_INT(pb_private_dir_create(base, "pbt", dir, sizeof dir), PB_OK);
  CHECK(strncmp(dir, base, strlen(base)) == 0 && strstr(dir, "/pbt-") != NULL);
  CHECK_EQ_INT(mode_of(dir), 0700);
  snprintf(path, sizeof path, "%s/frame.bin", dir);
  FILE *f;
  char *tmp;
  for (int i = 0; i < 2; ++i) { /* the second write replaces the first */
    CHECK_EQ_INT(pb_atomic_open_private(path, &f, &tmp), PB_OK);
    CHECK_EQ_INT(mode_of(tmp), 0600);
    fputs("frame", f);
    CHECK_EQ_INT(pb_atomic_commit(path, f, tmp), PB_OK);
    CHECK_EQ_INT(mode_of(path), 0600);
  }
  /* A symlink at the temporary's name: the write fails, the target stays. */
  snprintf(victim, sizeof victim, "%s/victim", base);
  FILE *v = fopen(victim, "w");
  CHECK(v != NULL);
  if (v) fputs("untouched", v), fclose(v);
  char *t = pb_tmp_name(path);
  CHECK(t && symlink(victim, t) == 0);
  pb_error_clear();
  CHECK_EQ_INT(pb_atomic_open_private(path, &f, &tmp), PB_ERR_IO);
  CHECK(strstr(pb_error_message(), "exists") != NULL);
  uint8_t *data;
  size_t n;
  CHECK_EQ_INT(pb_read_file(victim, 100, &data, &n), PB_OK);
  CHECK(n == 9 && memcmp(data, "untouched", 9) == 0);
  free(data);
  CHECK_EQ_INT(pb_private_open(t), -1);
  CHECK_EQ_INT(errno, EEXIST);
  free(t);
  /* The handler's path removes the registered folder with files nobody
   * registered (the symlink, a stray file), never the symlink's target. */
  snprintf(link, sizeof link, "%s/stray", dir);
  int fd = pb_private_open(link);
  CHECK(fd >= 0);
  if (fd >= 0) close(fd);
  pb_tmp_remove_all_signal_safe();
  CHECK(access(dir, F_OK) != 0);
  CHECK(access(victim, F_OK) == 0);
  pb_private_dir_remove(dir); /* unregisters; the folder is already gone */
  /* The clean end: pb_private_dir_remove. */
  CHECK_EQ_INT(pb_private_dir_create(base, "pbt", dir, sizeof dir), PB_OK);
  snprintf(path, sizeof path, "%s/frame.bin", dir);
  CHECK_EQ_INT(pb_atomic_open_private(path, &f, &tmp), PB_OK);
  CHECK_EQ_INT(pb_atomic_commit(path, f, tmp), PB_OK);
  pb_private_dir_remove(dir);
  CHECK(access(dir, F_OK) != 0);
  /* A base that cannot hold it: PB_ERR_IO naming the base, out "". */
  pb_error_clear();
  CHECK_EQ_INT(pb_private_dir_create("/nonexistent/base", "pbt", dir, sizeof dir), PB_ERR_IO);
  CHECK(dir[0] == 0 && strstr(pb_error_message(), "/nonexistent/base") != NULL);
  pb_error_clear();
  CHECK_EQ_INT(pb_private_dir_create(victim, "pbt", dir, sizeof dir), PB_ERR_IO); /* a file */
  umask(old);
  unlink(victim);
  CHECK(rmdir(base) == 0); /* nothing else was left in the base */
}

static void test_color_and_textures(void) {
  /* IEC 61966-2-1 values. */
  CHECK_NEAR(pb_linear_to_srgb(0.18f), 0.46135613f, 1e-6);
  CHECK_NEAR(pb_srgb_to_linear(0.5f), 0.21404114f, 1e-6);
  CHECK_NEAR(pb_linear_to_srgb(0.002f), 0.02584f, 1e-6);
  CHECK_NEAR(pb_linear_to_srgb(NAN), 0.0, 0);
  for (int i = 0; i <= 255; ++i) {
    float v = (float)i / 255.0f;
    CHECK_NEAR(pb_linear_to_srgb(pb_srgb_to_linear(v)), v, 2e-6);
  }
  /* A 2x1 texture: black, white. Bilinear at texel centres and between. */
  uint8_t px[8] = {0, 0, 0, 255, 255, 255, 255, 255};
  pb_texture t = {.width = 2, .height = 1, .rgba8 = px, .srgb = 0, .wrap_s = PB_WRAP_CLAMP, .wrap_t = PB_WRAP_CLAMP};
  float o[4];
  pb_texture_sample(&t, 0.25f, 0.5f, o);
  CHECK_NEAR(o[0], 0, 1e-6);
  pb_texture_sample(&t, 0.75f, 0.5f, o);
  CHECK_NEAR(o[0], 1, 1e-6);
  pb_texture_sample(&t, 0.5f, 0.5f, o);
  CHECK_NEAR(o[0], 0.5, 1e-6);
  pb_texture_sample(&t, -3.0f, 0.5f, o); /* clamp: left texel */
  CHECK_NEAR(o[0], 0, 1e-6);
  t.wrap_s = PB_WRAP_REPEAT;
  pb_texture_sample(&t, 1.25f, 0.5f, o); /* repeat: same as 0.25 */
  CHECK_NEAR(o[0], 0, 1e-6);
  pb_texture_sample(&t, 0.0f, 0.5f, o); /* repeat: halfway between last and first */
  CHECK_NEAR(o[0], 0.5, 1e-6);
  t.wrap_s = PB_WRAP_MIRROR;
  pb_texture_sample(&t, -0.25f, 0.5f, o); /* mirror: same as 0.25 */
  CHECK_NEAR(o[0], 0, 1e-6);
  pb_texture_sample(&t, 1.25f, 0.5f, o); /* mirror: same as 0.75 */
  CHECK_NEAR(o[0], 1, 1e-6);
  t.srgb = 1;
  t.wrap_s = PB_WRAP_CLAMP;
  t.nearest = 1;
  uint8_t g[4] = {128, 128, 128, 255};
  pb_texture t2 = {.width = 1, .height = 1, .rgba8 = g, .srgb = 1, .nearest = 1};
  pb_texture_sample(&t2, 0.3f, 0.3f, o);
  CHECK_NEAR(o[0], pb_srgb_to_linear(128.0f / 255.0f), 1e-6);
  CHECK_NEAR(o[3], 1.0, 1e-6); /* alpha is never sRGB-decoded */
  pb_texture_sample(&t2, NAN, INFINITY, o); /* never out of bounds */
  CHECK(isfinite(o[0]));

  pb_camera c = {.aspect = 16.0f / 9.0f};
  uint32_t w, h;
  pb_camera_image_size(&c, 0, 0, &w, &h);
  CHECK(w == 640 && h == 360);
  pb_camera_image_size(&c, 0, 720, &w, &h);
  CHECK(w == 1280 && h == 720);
  pb_camera_image_size(&c, 100, 10, &w, &h);
  CHECK(w == 100 && h == 10);
  c.aspect = 0; /* unknown aspect: 4:3 */
  pb_camera_image_size(&c, 0, 0, &w, &h);
  CHECK(w == 640 && h == 480);
}

int main(void) {
  test_results();
  test_cli();
  test_json_and_files();
  test_private_files();
  test_color_and_textures();
  return pbt_done();
}
