/* Colour management: the built-in OCIO config against analytic transforms,
 * error messages, PNG output through the view, and (with --blender, its own
 * ctest entry) Blender's Filmic view through our shim against Blender's own
 * view transform on the same EXR. */
#define _POSIX_C_SOURCE 200809L
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/srgb.h"
#include "color/color.h"
#include "core/fs.h"
#include "image/image.h"
#include "pbtest.h"
#include "image/decode.h"
#include "scene/scene.h"

#define BLENDER_CONFIG "/usr/share/blender/datafiles/colormanagement/config.ocio"

static float clamp01(float v) { return v > 0 ? (v < 1 ? v : 1) : 0; }

/* Standard view == clamp(sRGB encode(x)), per channel, to 1e-4, over a ramp
 * from -0.1 to 4 (values above 1 clip), grey and coloured. */
static void test_standard_view(void) {
  pb_color *c = NULL;
  pb_color_desc d = {.purpose = PB_COLOR_METRICS}; /* metrics: built-in Standard, always */
  unsetenv("OCIO");
  setenv("PB_BLENDER_OCIO", BLENDER_CONFIG, 1);
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_OK);
  setenv("PB_BLENDER_OCIO", "", 1);
  if (!c) return;
  CHECK(strcmp(pb_color_config_name(c), "built-in") == 0);
  CHECK(strcmp(pb_color_display(c), "sRGB") == 0);
  CHECK(strcmp(pb_color_view(c), "Standard") == 0);
  enum { N = 4200 };
  static float px[N * 4];
  for (int i = 0; i < N; ++i) {
    float v = -0.1f + 4.1f * (float)i / (N - 1);
    px[i * 4 + 0] = v;
    px[i * 4 + 1] = v * 0.5f;                      /* coloured: channels differ */
    px[i * 4 + 2] = (float)((i * 37) % 101) / 50.0f; /* 0..2, scrambled */
    px[i * 4 + 3] = 0.25f;
  }
  static float ref[N * 4];
  memcpy(ref, px, sizeof px);
  CHECK_EQ_INT(pb_color_apply_display(c, px, N, 1, 4), PB_OK);
  double max_diff = 0;
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < 3; ++k) {
      double e = clamp01(pb_linear_to_srgb(clamp01(ref[i * 4 + k])));
      max_diff = fmax(max_diff, fabs(px[i * 4 + k] - e));
    }
  printf("Standard view vs analytic sRGB: max |diff| %.3g over %d pixels\n", max_diff, N);
  CHECK(max_diff < 1e-4);
  CHECK(px[3] == 0.25f); /* alpha untouched */
  CHECK(px[(N - 1) * 4] == 1.0f); /* 4.0 clips */
  CHECK(px[0] == 0.0f);           /* negative clips */

  /* NaN gives 0, 3 channels work. */
  float nan3[3] = {NAN, 0.5f, 1.0f};
  CHECK_EQ_INT(pb_color_apply_display(c, nan3, 1, 1, 3), PB_OK);
  CHECK(nan3[0] == 0.0f);
  CHECK_NEAR(nan3[1], pb_linear_to_srgb(0.5f), 1e-4);
  CHECK_EQ_INT(pb_color_apply_display(c, nan3, 1, 1, 2), PB_ERR_IMAGE);
  pb_error_clear();

  /* ACEScg: the published Rec.709 -> AP1 (Bradford) matrix, and back. */
  static const double m709_to_ap1[3][3] = {{0.6130974, 0.3395231, 0.0473795},
                                           {0.0701937, 0.9163539, 0.0134524},
                                           {0.0206156, 0.1095698, 0.8698146}};
  float rgb[4 * 3] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0.3f, 2.5f, 0.01f};
  float orig[12];
  memcpy(orig, rgb, sizeof rgb);
  CHECK_EQ_INT(pb_color_convert(c, "Linear Rec.709 (sRGB)", "ACEScg", rgb, 4, 1, 3), PB_OK);
  double max_m = 0;
  for (int i = 0; i < 4; ++i)
    for (int r = 0; r < 3; ++r) {
      double e = 0;
      for (int k = 0; k < 3; ++k) e += m709_to_ap1[r][k] * orig[i * 3 + k];
      max_m = fmax(max_m, fabs(rgb[i * 3 + r] - e));
    }
  printf("Rec.709 -> ACEScg vs published matrix: max |diff| %.3g\n", max_m);
  CHECK(max_m < 1e-5 * 3);
  CHECK_EQ_INT(pb_color_convert(c, "ACEScg", "ACES2065-1", rgb, 4, 1, 3), PB_OK);
  CHECK_EQ_INT(pb_color_convert(c, "ACES2065-1", "lin_rec709", rgb, 4, 1, 3), PB_OK);
  double max_rt = 0;
  for (int i = 0; i < 12; ++i) max_rt = fmax(max_rt, fabs(rgb[i] - orig[i]) / fmax(1.0, fabs(orig[i])));
  printf("Rec.709 -> ACEScg -> ACES2065-1 -> Rec.709 round trip: max rel diff %.3g\n", max_rt);
  CHECK(max_rt < 1e-5);
  CHECK_EQ_INT(pb_color_convert(c, "Linear Rec.709 (sRGB)", "NoSuchSpace", rgb, 4, 1, 3), PB_ERR_USAGE);
  CHECK(strstr(pb_error_message(), "NoSuchSpace") != NULL);
  pb_error_clear();
  pb_color_destroy(c);
  pb_color_destroy(NULL);
}

static void test_aces_view(void) {
  pb_color *c = NULL;
  pb_color_desc d = {.view = "ACES 1.0 - SDR Video"};
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_OK);
  if (!c) return;
  float px[5 * 3] = {0, 0, 0, 0.18f, 0.18f, 0.18f, 1, 1, 1, 16, 16, 16, 1000, 1000, 1000};
  CHECK_EQ_INT(pb_color_apply_display(c, px, 5, 1, 3), PB_OK);
  printf("ACES SDR view: 0 -> %.4f, 0.18 -> %.4f, 1 -> %.4f, 16 -> %.4f\n", px[0], px[3], px[6], px[9]);
  CHECK(px[0] < 0.01f);
  CHECK(px[3] > 0.3f && px[3] < 0.5f); /* mid grey lands near 0.39 (ACES 1.0 RRT+ODT) */
  CHECK(px[6] > px[3] && px[9] > px[6]);
  CHECK(px[6] < 0.95f);  /* tone mapped: scene 1.0 is not display white */
  CHECK(px[12] <= 1.0f);
  pb_color_destroy(c);
}

static void test_errors(void) {
  pb_color *c = (pb_color *)1;
  pb_color_desc d = {.display = "Nope"};
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_ERR_USAGE);
  CHECK(c == NULL);
  printf("error: %s\n", pb_error_message());
  CHECK(strstr(pb_error_message(), "built-in") && strstr(pb_error_message(), "no display 'Nope'") &&
        strstr(pb_error_message(), "sRGB"));
  pb_error_clear();
  pb_color_desc v = {.view = "False Color"};
  CHECK_EQ_INT(pb_color_open(&v, &c), PB_ERR_USAGE);
  printf("error: %s\n", pb_error_message());
  CHECK(strstr(pb_error_message(), "no view 'False Color'") && strstr(pb_error_message(), "Filmic") &&
        strstr(pb_error_message(), "Standard"));
  pb_error_clear();
  pb_color_desc ex = {.exposure = NAN};
  CHECK_EQ_INT(pb_color_open(&ex, &c), PB_ERR_USAGE);
  CHECK(strstr(pb_error_message(), "exposure") != NULL);
  pb_error_clear();
  pb_color_desc ga = {.gamma = -1};
  CHECK_EQ_INT(pb_color_open(&ga, &c), PB_ERR_USAGE);
  CHECK(strstr(pb_error_message(), "gamma") != NULL);
  pb_error_clear();
  pb_color_desc l = {.look = "Punchy"};
  CHECK_EQ_INT(pb_color_open(&l, &c), PB_ERR_USAGE);
  CHECK(strstr(pb_error_message(), "no look 'Punchy'") != NULL);
  pb_error_clear();
  pb_color_desc none = {.look = "None"};
  CHECK_EQ_INT(pb_color_open(&none, &c), PB_OK);
  pb_color_destroy(c);
  pb_color_desc f = {.config = "does/not/exist.ocio"};
  CHECK_EQ_INT(pb_color_open(&f, &c), PB_ERR_IO);
  CHECK(strstr(pb_error_message(), "does/not/exist.ocio") != NULL);
  pb_error_clear();
  /* $OCIO is used when no config is given, and named in errors. */
  setenv("OCIO", "/nonexistent/env.ocio", 1);
  CHECK_EQ_INT(pb_color_open(NULL, &c), PB_ERR_IO);
  CHECK(strstr(pb_error_message(), "$OCIO=/nonexistent/env.ocio") != NULL);
  pb_error_clear();
  setenv("OCIO", "config/ocio/photonbridge.ocio", 1);
  CHECK_EQ_INT(pb_color_open(NULL, &c), PB_OK);
  if (c) CHECK(strcmp(pb_color_view(c), "Standard") == 0);
  pb_color_destroy(c);
  unsetenv("OCIO");
  /* A file that is not a config. */
  char bad[64];
  snprintf(bad, sizeof bad, "/tmp/pb_color_test_%d.ocio", (int)getpid());
  FILE *b = fopen(bad, "w");
  if (b) {
    fputs("ocio_profile_version: 2\nroles: [this is not: valid\n", b);
    fclose(b);
    pb_color_desc bd = {.config = bad};
    CHECK_EQ_INT(pb_color_open(&bd, &c), PB_ERR_NOT_AVAILABLE);
    CHECK(strstr(pb_error_message(), bad) != NULL && strchr(pb_error_message(), '\n') == NULL);
    pb_error_clear();
    remove(bad);
  }
}

/* The embedded config is the committed file, byte for byte. */
static void test_embedded_matches_file(void) {
  uint8_t *data = NULL;
  size_t size = 0;
  CHECK_EQ_INT(pb_read_file("config/ocio/photonbridge.ocio", 1 << 20, &data, &size), PB_OK);
  if (!data) return;
  CHECK_EQ_INT(size, strlen(pb_color_builtin_config_text));
  CHECK(memcmp(data, pb_color_builtin_config_text, size) == 0);
  free(data);
}

static void test_png(void) {
  pb_color *c = NULL;
  pb_color_desc sd = {.view = "Standard"};
  CHECK_EQ_INT(pb_color_open(&sd, &c), PB_OK);
  enum { W = 256 };
  static float px[W * 3];
  for (int i = 0; i < W; ++i) px[i * 3] = px[i * 3 + 1] = px[i * 3 + 2] = (float)i / (W - 1);
  char path[64];
  snprintf(path, sizeof path, "/tmp/pb_color_test_%d.png", (int)getpid());
  CHECK_EQ_INT(pb_png_write_display(path, c, W, 1, 3, px), PB_OK);
  uint8_t *bytes = NULL;
  size_t size = 0;
  CHECK_EQ_INT(pb_read_file(path, 1 << 20, &bytes, &size), PB_OK);
  pb_decoded dec = {0};
  const pb_decode_limits lim = {.max_dim = 4096, .max_pixels = 1 << 20};
  if (bytes) CHECK_EQ_INT(pb_decode_image_rgba8(bytes, size, &lim, &dec), PB_DECODE_OK);
  uint8_t *rgba = dec.rgba;
  uint32_t w = dec.width;
  if (rgba) {
    CHECK_EQ_INT(w, W);
    int worst = 0;
    for (int i = 0; i < W; ++i) {
      int e = (int)(pb_linear_to_srgb((float)i / (W - 1)) * 255.0f + 0.5f);
      worst = abs(e - rgba[i * 4]) > worst ? abs(e - rgba[i * 4]) : worst;
    }
    CHECK(worst <= 1); /* rounding at exact .5 boundaries only */
  }
  free(rgba);
  free(bytes);
  /* The fallback without OCIO is pb_png_write_srgb, same bytes. */
  CHECK_EQ_INT(pb_png_write_display(path, NULL, W, 1, 3, px), PB_OK);
  CHECK_EQ_INT(pb_png_write_display(path, c, W, 1, 2, px), PB_ERR_IMAGE);
  pb_error_clear();
  remove(path);
  pb_color_destroy(c);
}

/* Defaults: pictures through the config's default view (Filmic, as in
 * Blender), metrics through the built-in Standard view; Blender's config is
 * preferred for pictures where it is installed. */
static void test_defaults(void) {
  pb_color *c = NULL;
  setenv("PB_BLENDER_OCIO", "", 1);
  CHECK_EQ_INT(pb_color_open(NULL, &c), PB_OK);
  if (c) {
    CHECK(strcmp(pb_color_config_name(c), "built-in") == 0);
    CHECK(strcmp(pb_color_view(c), "Filmic") == 0);
    float px[3] = {0.18f, 0.18f, 0.18f};
    CHECK_EQ_INT(pb_color_apply_display(c, px, 1, 1, 3), PB_OK);
    printf("built-in Filmic: 0.18 -> %.4f\n", px[0]);
    CHECK(px[0] > 0.4f && px[0] < 0.6f);
    char line[512];
    pb_color_describe(c, line, sizeof line);
    printf("describe: %s\n", line);
    CHECK(strstr(line, "sRGB / Filmic, look None, exposure 0, gamma 1 (OCIO config built-in)") != NULL);
  }
  pb_color_destroy(c);
  pb_color_desc m = {.purpose = PB_COLOR_METRICS};
  CHECK_EQ_INT(pb_color_open(&m, &c), PB_OK);
  if (c) CHECK(strcmp(pb_color_view(c), "Standard") == 0);
  pb_color_destroy(c);
  if (access(BLENDER_CONFIG, R_OK) == 0) {
    unsetenv("PB_BLENDER_OCIO");
    CHECK(pb_color_blender_config() && strcmp(pb_color_blender_config(), BLENDER_CONFIG) == 0);
    CHECK_EQ_INT(pb_color_open(NULL, &c), PB_OK);
    if (c) {
      CHECK(strstr(pb_color_config_name(c), "Blender's") && strstr(pb_color_config_name(c), BLENDER_CONFIG));
      CHECK(strcmp(pb_color_view(c), "Filmic") == 0);
    }
    pb_color_destroy(c);
    /* Metrics never follow Blender's config. */
    CHECK_EQ_INT(pb_color_open(&m, &c), PB_OK);
    if (c) CHECK(strcmp(pb_color_config_name(c), "built-in") == 0);
    pb_color_destroy(c);
  }
  setenv("PB_BLENDER_OCIO", "/nonexistent/config.ocio", 1);
  CHECK(pb_color_blender_config() == NULL);
  setenv("PB_BLENDER_OCIO", "", 1);
}

/* Exposure scales scene-linear by 2^EV before the view; gamma raises the
 * display value to 1/gamma after it (Blender's display processor). */
static void test_exposure_gamma(void) {
  pb_color *base = NULL, *ev = NULL, *gm = NULL;
  pb_color_desc b = {.view = "Standard"}, e = {.view = "Standard", .exposure = 1.5},
                g = {.view = "Standard", .gamma = 2.2};
  CHECK_EQ_INT(pb_color_open(&b, &base), PB_OK);
  CHECK_EQ_INT(pb_color_open(&e, &ev), PB_OK);
  CHECK_EQ_INT(pb_color_open(&g, &gm), PB_OK);
  if (base && ev && gm) {
    CHECK_NEAR(pb_color_exposure(ev), 1.5, 0);
    CHECK_NEAR(pb_color_gamma(gm), 2.2, 0);
    CHECK_NEAR(pb_color_gamma(base), 1.0, 0);
    double worst_e = 0, worst_g = 0;
    for (int i = 0; i < 64; ++i) {
      float v = 0.003f * (float)i;
      float a[3] = {v * exp2f(1.5f), v, v * 0.5f * exp2f(1.5f)}, x[3] = {v, v / exp2f(1.5f), v * 0.5f};
      float p[3] = {v, v, v}, q[3] = {v, v, v};
      pb_color_apply_display(base, a, 1, 1, 3);
      pb_color_apply_display(ev, x, 1, 1, 3);
      pb_color_apply_display(base, p, 1, 1, 3);
      pb_color_apply_display(gm, q, 1, 1, 3);
      for (int k = 0; k < 3; ++k) worst_e = fmax(worst_e, fabs(a[k] - x[k]));
      worst_g = fmax(worst_g, fabs(powf(p[0], 1.0f / 2.2f) - q[0]));
    }
    printf("exposure 1.5 vs scaled input: %.3g; gamma 2.2 vs pow(1/2.2): %.3g\n", worst_e, worst_g);
    CHECK(worst_e < 1e-5);
    CHECK(worst_g < 1e-4);
  }
  pb_color_destroy(base);
  pb_color_destroy(ev);
  pb_color_destroy(gm);
}

/* Blender 4.5's AgX looks, which the built-in config reproduces. */
static const char *const agx_looks[] = {"AgX - Punchy", "AgX - Greyscale", "AgX - Very High Contrast",
                                        "AgX - High Contrast", "AgX - Medium High Contrast",
                                        "AgX - Base Contrast", "AgX - Medium Low Contrast",
                                        "AgX - Low Contrast", "AgX - Very Low Contrast"};
enum { N_AGX_LOOKS = sizeof agx_looks / sizeof agx_looks[0] };

/* Blender's Filmic looks (3.4's and 4.x's), which it reproduces too. */
static const char *const filmic_looks[] = {"Very High Contrast", "High Contrast", "Medium High Contrast",
                                           "Medium Contrast", "Medium Low Contrast", "Low Contrast",
                                           "Very Low Contrast"};
enum { N_FILMIC_LOOKS = sizeof filmic_looks / sizeof filmic_looks[0] };

/* 200k scene-linear colours over 24 stops (a sixteenth of the channels 0, a
 * third of the colours grey), from seed. */
static void stops_colours(float *p, int n, uint64_t st) {
  for (int i = 0; i < n * 3; ++i) {
    st = st * 6364136223846793005ull + 1442695040888963407ull;
    float u = (float)(st >> 40) / (float)(1 << 24);
    p[i] = ((st >> 20) & 15) == 0 ? 0.0f : 0.18f * exp2f(-14.0f + 24.0f * u);
    if ((i / 3) % 3 == 0 && i % 3) p[i] = p[i - i % 3];
  }
}

/* max |built-in - config| in 8-bit steps over those colours for one view
 * and look (NULL: none); -1 when either does not open. When plain is given,
 * also the max |built-in with the look - built-in without it| there. */
static double builtin_vs_config(const char *cfg, const char *view, const char *look, double *plain) {
  pb_color *mine = NULL, *theirs = NULL, *bare = NULL;
  pb_color_desc a = {.config = "built-in", .view = view, .look = look};
  pb_color_desc b = {.config = cfg, .view = view, .look = look};
  pb_color_desc c = {.config = "built-in", .view = view};
  CHECK_EQ_INT(pb_color_open(&a, &mine), PB_OK);
  CHECK_EQ_INT(pb_color_open(&b, &theirs), PB_OK);
  if (plain) CHECK_EQ_INT(pb_color_open(&c, &bare), PB_OK);
  enum { N = 200000 };
  float *p = malloc(sizeof(float) * N * 3), *q = malloc(sizeof(float) * N * 3);
  float *r = malloc(sizeof(float) * N * 3);
  double mx = -1;
  if (mine && theirs && p && q && r && (!plain || bare)) {
    stops_colours(p, N, 777);
    memcpy(q, p, sizeof(float) * N * 3);
    memcpy(r, p, sizeof(float) * N * 3);
    CHECK_EQ_INT(pb_color_apply_display(mine, p, N, 1, 3), PB_OK);
    CHECK_EQ_INT(pb_color_apply_display(theirs, q, N, 1, 3), PB_OK);
    mx = 0;
    for (int i = 0; i < N * 3; ++i) mx = fmax(mx, fabs(p[i] - q[i]) * 255.0);
    if (plain) {
      CHECK_EQ_INT(pb_color_apply_display(bare, r, N, 1, 3), PB_OK);
      *plain = 0;
      for (int i = 0; i < N * 3; ++i) *plain = fmax(*plain, fabs(p[i] - r[i]) * 255.0);
    }
  } else {
    if (!mine || !theirs) printf("%s\n", pb_error_message()), pb_error_clear();
    CHECK(0);
  }
  free(p);
  free(q);
  free(r);
  pb_color_destroy(mine);
  pb_color_destroy(theirs);
  pb_color_destroy(bare);
  return mx;
}

/* The built-in Filmic against Blender's config's Filmic on 200k scene-linear
 * colours over 24 stops (grey, saturated, zeros): the same four steps, so
 * they agree far inside one 8-bit step. Needs Blender's config files only. */
static void test_builtin_filmic_vs_blender_config(void) {
  if (access(BLENDER_CONFIG, R_OK) != 0) {
    printf("skip: %s not installed\n", BLENDER_CONFIG);
    return;
  }
  pb_color *mine = NULL, *theirs = NULL;
  pb_color_desc a = {.view = "Filmic"}, b = {.config = BLENDER_CONFIG, .view = "Filmic"};
  setenv("PB_BLENDER_OCIO", "", 1);
  CHECK_EQ_INT(pb_color_open(&a, &mine), PB_OK);
  CHECK_EQ_INT(pb_color_open(&b, &theirs), PB_OK);
  if (mine && theirs) {
    CHECK(strcmp(pb_color_config_name(mine), "built-in") == 0);
    enum { N = 200000 };
    float *p = malloc(sizeof(float) * N * 3), *q = malloc(sizeof(float) * N * 3);
    uint64_t st = 12345;
    for (int i = 0; i < N * 3 && p && q; ++i) {
      st = st * 6364136223846793005ull + 1442695040888963407ull;
      float u = (float)(st >> 40) / (float)(1 << 24);
      float stops = -14.0f + 24.0f * u;
      p[i] = ((st >> 20) & 15) == 0 ? 0.0f : 0.18f * exp2f(stops);
      if ((i / 3) % 3 == 0 && i % 3) p[i] = p[i - i % 3]; /* a third grey */
      q[i] = p[i];
    }
    if (p && q) {
      CHECK_EQ_INT(pb_color_apply_display(mine, p, N, 1, 3), PB_OK);
      CHECK_EQ_INT(pb_color_apply_display(theirs, q, N, 1, 3), PB_OK);
      double mx = 0;
      for (int i = 0; i < N * 3; ++i) mx = fmax(mx, fabs(p[i] - q[i]) * 255.0);
      printf("built-in Filmic vs Blender's config: max %.4f 8-bit steps over %d colours\n", mx, N);
      CHECK(mx < 0.05);
    } else {
      CHECK(0);
    }
    free(p);
    free(q);
  }
  pb_color_destroy(mine);
  pb_color_destroy(theirs);
  /* Its looks through the Filmic view, against Blender 3.4's. */
  for (int l = 0; l < N_FILMIC_LOOKS; ++l) {
    double plain = 0;
    const double mx = builtin_vs_config(BLENDER_CONFIG, "Filmic", filmic_looks[l], &plain);
    printf("built-in Filmic + '%s' vs Blender 3.4's: max %.4f 8-bit steps (the look moves values by up to %.1f)\n",
           filmic_looks[l], mx, plain);
    CHECK(mx >= 0 && mx < 0.05); /* as the view's own */
    /* "Medium Contrast" is Filmic Log there and back (desaturated twice). */
    if (strcmp(filmic_looks[l], "Medium Contrast") != 0) CHECK(plain > 2.0);
  }
}

/* Blender's config, when installed: Filmic loads through the shim and maps
 * mid grey near the middle of the display range. */
static void test_blender_config(void) {
  if (access(BLENDER_CONFIG, R_OK) != 0) {
    printf("skip: %s not installed\n", BLENDER_CONFIG);
    return;
  }
  pb_color *c = NULL;
  pb_color_desc d = {.config = BLENDER_CONFIG, .display = "sRGB", .view = "Filmic"};
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_OK);
  if (!c) return;
  float px[3] = {0.18f, 0.18f, 0.18f};
  CHECK_EQ_INT(pb_color_apply_display(c, px, 1, 1, 3), PB_OK);
  printf("Blender Filmic: 0.18 -> %.4f\n", px[0]);
  CHECK(px[0] > 0.4f && px[0] < 0.6f);
  pb_color_destroy(c);
  pb_color_desc std = {.config = BLENDER_CONFIG, .view = "Standard"};
  CHECK_EQ_INT(pb_color_open(&std, &c), PB_OK);
  if (c) {
    float g[3] = {0.5f, 0.5f, 0.5f};
    CHECK_EQ_INT(pb_color_apply_display(c, g, 1, 1, 3), PB_OK);
    CHECK_NEAR(g[0], pb_linear_to_srgb(0.5f), 2e-3); /* Blender's sRGB is a LUT-free curve too */
  }
  pb_color_destroy(c);
}

/* ---- Blender 4.x's AgX and Khronos PBR Neutral views --------------------- */

/* The scene-linear colours of the committed table: greys from 2^-12 to 2^10
 * (and 0), the primaries and secondaries at 0.18, 1, 4 and 16, and 40
 * colours with channels 0 or 2^U(-10, 8) (a fixed LCG). */
enum { B4_N = 1 + 23 + 24 + 40 };
static void blender4_inputs(float (*rgb)[3]) {
  int i = 0;
  rgb[i][0] = rgb[i][1] = rgb[i][2] = 0.0f, ++i;
  for (int e = -12; e <= 10; ++e, ++i) rgb[i][0] = rgb[i][1] = rgb[i][2] = exp2f((float)e);
  static const float scale[4] = {0.18f, 1.0f, 4.0f, 16.0f};
  static const int hue[6][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {0, 1, 1}, {1, 0, 1}};
  for (int s = 0; s < 4; ++s)
    for (int h = 0; h < 6; ++h, ++i)
      for (int k = 0; k < 3; ++k) rgb[i][k] = hue[h][k] ? scale[s] : 0.0f;
  uint64_t st = 0x2545F4914F6CDD1Dull;
  for (; i < B4_N; ++i)
    for (int k = 0; k < 3; ++k) {
      st = st * 6364136223846793005ull + 1442695040888963407ull;
      const double u = (double)(st >> 11) / 9007199254740992.0;
      rgb[i][k] = u < 0.15 ? 0.0f : (float)exp2(-10.0 + 18.0 * (u - 0.15) / 0.85);
    }
}

/* Display values (sRGB display, clamped as pb_color_apply_display) of the
 * colours above through Blender 4.5's own config.ocio by OpenColorIO 2.1:
 * `test_color --blender4-table .../4.5/datafiles/colormanagement/config.ocio`
 * prints this table. */
#include "color_blender4_table.h"

static void blender4_apply(const char *config, const char *view, float (*rgb)[3]) {
  pb_color *c = NULL;
  pb_color_desc d = {.config = config, .display = "sRGB", .view = view};
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_OK);
  if (c) CHECK_EQ_INT(pb_color_apply_display(c, &rgb[0][0], B4_N, 1, 3), PB_OK);
  if (!c) printf("%s\n", pb_error_message()), pb_error_clear();
  pb_color_destroy(c);
}

static int blender4_table(const char *config) {
  float in[B4_N][3], agx[B4_N][3], pbr[B4_N][3];
  blender4_inputs(in);
  memcpy(agx, in, sizeof in);
  memcpy(pbr, in, sizeof in);
  blender4_apply(config, "AgX", agx);
  blender4_apply(config, "Khronos PBR Neutral", pbr);
  if (pbt_fail) return pbt_done();
  printf("/* Generated by `test_color --blender4-table %s`;\n * do not edit. Rows: AgX r g b, Khronos PBR Neutral r g b. */\n", config);
  printf("static const float blender4_expected[B4_N][6] = {\n");
  for (int i = 0; i < B4_N; ++i)
    printf("    {%.7ff, %.7ff, %.7ff, %.7ff, %.7ff, %.7ff},\n", agx[i][0], agx[i][1], agx[i][2], pbr[i][0], pbr[i][1],
           pbr[i][2]);
  printf("};\n");
  return 0;
}

/* The built-in AgX and Khronos PBR Neutral views against the table (what
 * Blender 4.5's config gives): within a quarter of an 8-bit step. */
static void test_builtin_blender4_views(void) {
  float in[B4_N][3], agx[B4_N][3], pbr[B4_N][3];
  blender4_inputs(in);
  memcpy(agx, in, sizeof in);
  memcpy(pbr, in, sizeof in);
  blender4_apply("built-in", "AgX", agx);
  blender4_apply("built-in", "Khronos PBR Neutral", pbr);
  double worst[2] = {0, 0};
  int at[2] = {0, 0};
  for (int i = 0; i < B4_N; ++i)
    for (int k = 0; k < 3; ++k) {
      const double a = fabs(agx[i][k] - blender4_expected[i][k]) * 255.0;
      const double p = fabs(pbr[i][k] - blender4_expected[i][3 + k]) * 255.0;
      if (a > worst[0]) worst[0] = a, at[0] = i;
      if (p > worst[1]) worst[1] = p, at[1] = i;
    }
  printf("built-in vs Blender 4.5's config (%d colours): AgX max %.4f 8-bit steps (colour %d), "
         "Khronos PBR Neutral max %.4f (colour %d)\n", B4_N, worst[0], at[0], worst[1], at[1]);
  CHECK(worst[0] < 0.25);
  CHECK(worst[1] < 0.25);
  printf("grey 0.25: AgX -> %.4f, Khronos PBR Neutral -> %.4f\n", agx[1 + 12 - 2][0], pbr[1 + 12 - 2][0]);
}

/* With $PB_BLENDER4_OCIO (Blender 4.2+'s config.ocio): the built-in views,
 * and the AgX looks through the AgX view, against it on 200k scene-linear
 * colours over 24 stops. */
static void test_builtin_blender4_vs_config(void) {
  const char *cfg = getenv("PB_BLENDER4_OCIO");
  if (!cfg || !*cfg || access(cfg, R_OK) != 0) {
    printf("skip: $PB_BLENDER4_OCIO (Blender 4's config.ocio) not given\n");
    return;
  }
  static const char *views[2] = {"AgX", "Khronos PBR Neutral"};
  for (int v = 0; v < 2; ++v) {
    const double mx = builtin_vs_config(cfg, views[v], NULL, NULL);
    printf("built-in %s vs %s: max %.4f 8-bit steps over 200000 colours\n", views[v], cfg, mx);
    CHECK(mx >= 0 && mx < 0.25);
  }
  for (int l = 0; l < N_AGX_LOOKS; ++l) {
    double plain = 0;
    const double mx = builtin_vs_config(cfg, "AgX", agx_looks[l], &plain);
    printf("built-in AgX + '%s' vs Blender 4.5's: max %.4f 8-bit steps (the look moves values by up to %.1f)\n",
           agx_looks[l], mx, plain);
    CHECK(mx >= 0 && mx < 0.25);
    /* The look is applied, or the comparison proves nothing ("Base Contrast"
     * is AgX Log there and back, through its luminance compensation). */
    if (strcmp(agx_looks[l], "AgX - Base Contrast") != 0) CHECK(plain > 2.0);
  }
}

/* ---- --blender: our Filmic against Blender's own on the same EXR ---------- */

enum { BW = 96, BH = 6 };

/* A ramp over 16 stops (2^-10 .. 2^6) in six hue mixes. */
static void ramp(float *px) {
  static const float tint[BH][3] = {{1, 1, 1}, {1, 0.2f, 0.05f}, {0.1f, 1, 0.3f},
                                    {0.05f, 0.2f, 1}, {1, 0.8f, 0.1f}, {0.6f, 0.1f, 0.9f}};
  for (int y = 0; y < BH; ++y)
    for (int x = 0; x < BW; ++x) {
      float v = exp2f(-10.0f + 16.0f * (float)x / (BW - 1));
      for (int k = 0; k < 3; ++k) px[(y * BW + x) * 3 + k] = v * tint[y][k];
    }
}

static int read_png(const char *path, uint8_t **rgba, uint32_t *w, uint32_t *h) {
  uint8_t *bytes = NULL;
  size_t size = 0;
  if (pb_read_file(path, 1 << 24, &bytes, &size) != PB_OK) return 0;
  pb_decoded dec;
  const pb_decode_limits lim = {.max_dim = 4096, .max_pixels = 1 << 22};
  int ok = pb_decode_image_rgba8(bytes, size, &lim, &dec) == PB_DECODE_OK;
  free(bytes);
  *rgba = dec.rgba;
  *w = dec.width;
  *h = dec.height;
  return ok;
}

/* max and mean |ours - Blender's| in 8-bit steps for one view/look. */
static void compare_with_blender(const char *config, const float *lin, const char *png, const char *look,
                                 double *max_d, double *mean_d) {
  *max_d = 1e9;
  *mean_d = 1e9;
  pb_color *c = NULL;
  pb_color_desc d = {.config = config, .display = "sRGB", .view = "Filmic", .look = look};
  CHECK_EQ_INT(pb_color_open(&d, &c), PB_OK);
  uint8_t *rgba = NULL;
  uint32_t w = 0, h = 0;
  CHECK(read_png(png, &rgba, &w, &h));
  if (!c || !rgba || w != BW || h != BH) {
    CHECK(0);
    pb_color_destroy(c);
    free(rgba);
    return;
  }
  static float px[BW * BH * 3];
  memcpy(px, lin, sizeof px);
  CHECK_EQ_INT(pb_color_apply_display(c, px, BW, BH, 3), PB_OK);
  double mx = 0, sum = 0;
  for (int i = 0; i < BW * BH; ++i)
    for (int k = 0; k < 3; ++k) {
      double e = fabs(px[i * 3 + k] * 255.0 - rgba[i * 4 + k]);
      mx = fmax(mx, e);
      sum += e;
    }
  *max_d = mx;
  *mean_d = sum / (BW * BH * 3);
  pb_color_destroy(c);
  free(rgba);
}

static int test_against_blender(void) {
  const char *blender = getenv("BLENDER");
  if (!blender || !*blender) blender = "blender";
  char probe[512];
  snprintf(probe, sizeof probe, "command -v '%s' >/dev/null 2>&1", blender);
  if (system(probe) != 0 || access(BLENDER_CONFIG, R_OK) != 0) {
    printf("skip: Blender or its OCIO config is not installed\n");
    return 77;
  }
  char dir[] = "/tmp/pb_color_blender.XXXXXX";
  if (!mkdtemp(dir)) {
    CHECK(0);
    return pbt_done();
  }
  char exr[256], png[256], png_look[256], cmd[4096];
  snprintf(exr, sizeof exr, "%s/ramp.exr", dir);
  snprintf(png, sizeof png, "%s/filmic.png", dir);
  snprintf(png_look, sizeof png_look, "%s/filmic_mhc.png", dir);
  static float lin[BW * BH * 3];
  ramp(lin);
  pb_image_layer layer = {NULL, 3, lin, NULL};
  pb_exr_desc ed = {.width = BW, .height = BH, .layers = &layer, .layer_count = 1};
  CHECK_EQ_INT(pb_exr_write(exr, &ed), PB_OK);
  /* Blender loads the EXR as a scene-linear image and saves it as 8-bit PNG
   * through the scene's view transform (Image.save_render), no dither. */
  static const char script[] =
      "import bpy, os\n"
      "sc = bpy.context.scene\n"
      "sc.display_settings.display_device = 'sRGB'\n"
      "sc.view_settings.view_transform = 'Filmic'\n"
      "sc.view_settings.exposure = 0.0\n"
      "sc.view_settings.gamma = 1.0\n"
      "sc.render.dither_intensity = 0.0\n"
      "s = sc.render.image_settings\n"
      "s.file_format = 'PNG'; s.color_mode = 'RGB'; s.color_depth = '8'; s.compression = 0\n"
      "img = bpy.data.images.load(os.environ['PB_EXR'])\n"
      "img.colorspace_settings.name = 'Linear'\n"
      "for look, out in (('None', os.environ['PB_PNG']), ('Medium High Contrast', os.environ['PB_PNG_LOOK'])):\n"
      "    sc.view_settings.look = look\n"
      "    img.save_render(out, scene=sc)\n"
      "print('pb_blender_done')\n";
  char script_path[300];
  snprintf(script_path, sizeof script_path, "%s/filmic.py", dir);
  FILE *f = fopen(script_path, "w");
  if (f) {
    fputs(script, f);
    fclose(f);
  }
  snprintf(cmd, sizeof cmd,
           "PB_EXR='%s' PB_PNG='%s' PB_PNG_LOOK='%s' '%s' -b --factory-startup --python-exit-code 1 -P '%s' "
           ">'%s/blender.log' 2>&1",
           exr, png, png_look, blender, script_path, dir);
  int rc = system(cmd);
  CHECK_EQ_INT(rc, 0);
  if (rc != 0) {
    snprintf(cmd, sizeof cmd, "tail -n 20 '%s/blender.log' >&2", dir);
    if (system(cmd) != 0) fprintf(stderr, "(no Blender log)\n");
  }
  double mx, mean;
  compare_with_blender(BLENDER_CONFIG, lin, png, NULL, &mx, &mean);
  printf("Filmic (Blender's config through our shim) vs Blender 3.4 save_render: max %.2f, mean %.3f (8-bit steps)\n",
         mx, mean);
  CHECK(mx <= 1.0); /* one 8-bit step: float vs Blender's rounding */
  CHECK(mean <= 0.35);
  compare_with_blender(NULL, lin, png, NULL, &mx, &mean);
  printf("built-in Filmic (no Blender files) vs Blender 3.4 save_render: max %.2f, mean %.3f (8-bit steps)\n",
         mx, mean);
  CHECK(mx <= 1.0);
  CHECK(mean <= 0.35);
  compare_with_blender(BLENDER_CONFIG, lin, png_look, "Medium High Contrast", &mx, &mean);
  printf("Filmic + 'Medium High Contrast' look vs Blender: max %.2f, mean %.3f (8-bit steps)\n", mx, mean);
  CHECK(mx <= 1.0);
  CHECK(mean <= 0.35);
  /* The look must change the picture, or the second comparison proves nothing. */
  uint8_t *a = NULL, *b = NULL;
  uint32_t w1, h1, w2, h2;
  if (read_png(png, &a, &w1, &h1) && read_png(png_look, &b, &w2, &h2) && w1 == w2 && h1 == h2) {
    double sum = 0;
    for (uint32_t i = 0; i < w1 * h1 * 4; ++i) sum += abs(a[i] - b[i]);
    printf("Blender with and without the look: mean |diff| %.2f (8-bit steps)\n", sum / (w1 * h1 * 3));
    CHECK(sum / (w1 * h1 * 3) > 2.0);
  } else {
    CHECK(0);
  }
  free(a);
  free(b);
  snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
  if (system(cmd) != 0) fprintf(stderr, "could not remove %s\n", dir);
  return pbt_done();
}

int main(int argc, char **argv) {
  /* The unit tests name their configs; Blender's is found only where a test
   * asks for it. */
  setenv("PB_BLENDER_OCIO", "", 1);
  if (argc > 1 && strcmp(argv[1], "--blender") == 0) return test_against_blender();
  if (argc > 2 && strcmp(argv[1], "--blender4-table") == 0) return blender4_table(argv[2]);
  test_standard_view();
  test_aces_view();
  test_errors();
  test_embedded_matches_file();
  test_png();
  test_defaults();
  test_exposure_gamma();
  test_builtin_filmic_vs_blender_config();
  test_blender_config();
  test_builtin_blender4_views();
  test_builtin_blender4_vs_config();
  return pbt_done();
}
