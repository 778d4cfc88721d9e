/* libFuzzer target: the EXR reader (pb_exr_read) on arbitrary bytes.
 *
 * The reader takes a path, so each input is written to a per-process folder
 * ($TMPDIR or /tmp, pb_fuzz_exr.XXXXXX) as in.exr. Besides memory errors and
 * undefined behaviour in our code (ASan + UBSan; OpenEXRCore itself is the
 * system library, not instrumented), the target aborts when the reader breaks
 * its contract (image.h):
 *   - failure: PB_ERR_IMAGE, PB_ERR_LIMIT or PB_ERR_NOMEM (the file exists
 *     and is regular, so never PB_ERR_IO), a one-line message naming the
 *     file, and *out zeroed;
 *   - success: a size within the limits, named channels, and every pixel
 *     readable (the sum touches the whole allocation). */
#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "core/result.h"
#include "image/image.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static char dir[512], path[600];
static int verbose; /* PB_FUZZ_VERBOSE=1: print each input's result */

#define FAIL(...)                                   \
  do {                                              \
    fprintf(stderr, "fuzz_exr: contract: ");        \
    fprintf(stderr, __VA_ARGS__);                   \
    fprintf(stderr, "\n");                          \
    abort();                                        \
  } while (0)

static void cleanup(void) {
  unlink(path);
  rmdir(dir);
}

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  const char *tmp = getenv("TMPDIR");
  snprintf(dir, sizeof dir, "%s/pb_fuzz_exr.XXXXXX", tmp && tmp[0] ? tmp : "/tmp");
  if (!mkdtemp(dir)) {
    fprintf(stderr, "fuzz_exr: cannot create a folder in %s: %s\n", tmp ? tmp : "/tmp", strerror(errno));
    abort();
  }
  snprintf(path, sizeof path, "%s/in.exr", dir);
  atexit(cleanup);
  pb_log_set_level(PB_LOG_QUIET); /* multi-part files warn */
  const char *v = getenv("PB_FUZZ_VERBOSE");
  verbose = v && v[0] == '1';
  return 0;
}

static int all_zero(const void *p, size_t n) {
  const uint8_t *b = p;
  for (size_t i = 0; i < n; ++i)
    if (b[i]) return 0;
  return 1;
}

static volatile float sink;

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) FAIL("cannot create %s: %s", path, strerror(errno));
  for (size_t off = 0; off < size;) {
    ssize_t k = write(fd, data + off, size - off);
    if (k <= 0) FAIL("cannot write %s: %s", path, strerror(errno));
    off += (size_t)k;
  }
  close(fd);

  /* Limits below the defaults keep every run inside libFuzzer's 2 GB
   * allocation limit (the defaults allow 256 Mpixel x 64 channels); the code
   * paths are the same. */
  const pb_exr_read_limits lim = {.max_dim = 4096, .max_pixels = 1u << 20, .max_channels = 16};
  pb_image img;
  pb_error_clear();
  pb_result r = pb_exr_read(path, &lim, &img);
  if (verbose) fprintf(stderr, "fuzz_exr: result %d: %s\n", (int)r, r ? pb_error_message() : "ok");
  if (r != PB_OK) {
    if (r != PB_ERR_IMAGE && r != PB_ERR_LIMIT && r != PB_ERR_NOMEM)
      FAIL("pb_exr_read returned %d (%s)", (int)r, pb_error_message());
    const char *msg = pb_error_message();
    if (!msg || !msg[0]) FAIL("failure %d without a message", (int)r);
    if (strchr(msg, '\n') || strchr(msg, '\r')) FAIL("message is not one line: %s", msg);
    if (!strstr(msg, path)) FAIL("message does not name the file: %s", msg);
    if (!all_zero(&img, sizeof img)) FAIL("failure %d left a non-empty image (%s)", (int)r, msg);
  } else {
    if (!img.width || !img.height || img.width > lim.max_dim || img.height > lim.max_dim ||
        (uint64_t)img.width * img.height > lim.max_pixels)
      FAIL("image %ux%u is outside the limits", img.width, img.height);
    if (!img.channel_count || img.channel_count > lim.max_channels || !img.pixels || !img.channel_names)
      FAIL("image with %u channels", img.channel_count);
    for (uint32_t k = 0; k < img.channel_count; ++k) {
      size_t n = strnlen(img.channel_names[k], sizeof img.channel_names[k]);
      if (n == 0 || n == sizeof img.channel_names[k]) FAIL("channel %u: name of %zu bytes", k, n);
      if (pb_image_find_channel(&img, img.channel_names[k]) < 0) FAIL("channel %u not found by name", k);
    }
    float acc = 0;
    size_t n = (size_t)img.width * img.height * img.channel_count;
    for (size_t i = 0; i < n; ++i) acc += img.pixels[i];
    sink = acc;
    pb_image_destroy(&img);
  }
  pb_error_clear();
  unlink(path);
  return 0;
}
