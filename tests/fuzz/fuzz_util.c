/* Shared set-up of the libFuzzer targets (fuzz_util.h). */
#include "fuzz_util.h"

#include <errno.h>
#include <fcntl.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#include "core/log.h"
#include "core/result.h"
#include "image/image.h"

enum { MAX_FILES = 8 };
static char target_name[32], dir[512];
static char files[MAX_FILES][600];
static int file_count, verbose;

static void cleanup(void) {
  for (int i = 0; i < file_count; ++i) unlink(files[i]);
  rmdir(dir);
}

void pb_fuzz_fail(const char *fmt, ...) {
  va_list ap;
  va_start(ap, fmt);
  fprintf(stderr, "fuzz_%s: contract: ", target_name);
  vfprintf(stderr, fmt, ap);
  fputc('\n', stderr);
  va_end(ap);
  abort();
}

void pb_fuzz_init(const char *target) {
  snprintf(target_name, sizeof target_name, "%s", target);
  const char *tmp = getenv("TMPDIR");
  snprintf(dir, sizeof dir, "%s/pb_fuzz_%s.XXXXXX", tmp && tmp[0] ? tmp : "/tmp", target);
  if (!mkdtemp(dir)) pb_fuzz_fail("cannot create a folder in %s: %s", tmp ? tmp : "/tmp", strerror(errno));
  atexit(cleanup);
  pb_log_set_level(PB_LOG_QUIET);
  const char *v = getenv("PB_FUZZ_VERBOSE");
  verbose = v && v[0] == '1';
}

const char *pb_fuzz_path(const char *name) {
  char p[600];
  snprintf(p, sizeof p, "%s/%s", dir, name);
  for (int i = 0; i < file_count; ++i)
    if (strcmp(files[i], p) == 0) return files[i];
  if (file_count == MAX_FILES) pb_fuzz_fail("more than %d file names", MAX_FILES);
  memcpy(files[file_count], p, sizeof p);
  return files[file_count++];
}

void pb_fuzz_write(const char *path, const uint8_t *data, size_t size) {
  int fd = open(path, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
  if (fd < 0) pb_fuzz_fail("cannot create %s: %s", path, strerror(errno));
  while (size) {
    ssize_t k = write(fd, data, size);
    if (k <= 0) pb_fuzz_fail("cannot write %s: %s", path, strerror(errno));
    data += k;
    size -= (size_t)k;
  }
  close(fd);
}

int pb_fuzz_verbose(void) { return verbose; }

int pb_fuzz_all_zero(const void *p, size_t n) {
  const uint8_t *b = p;
  for (size_t i = 0; i < n; ++i)
    if (b[i]) return 0;
  return 1;
}

static volatile float sink;

void pb_fuzz_check_image_read(const char *path, pb_result r, const pb_exr_read_limits *lim, pb_image *img) {
  if (verbose) fprintf(stderr, "fuzz_%s: %s: result %d: %s\n", target_name, path, (int)r, r ? pb_error_message() : "ok");
  if (r != PB_OK) {
    if (r != PB_ERR_IMAGE && r != PB_ERR_LIMIT && r != PB_ERR_NOMEM)
      pb_fuzz_fail("reading %s returned %d (%s)", path, (int)r, pb_error_message());
    const char *msg = pb_error_message();
    if (!msg || !msg[0]) pb_fuzz_fail("failure %d without a message", (int)r);
    if (strchr(msg, '\n') || strchr(msg, '\r')) pb_fuzz_fail("message is not one line: %s", msg);
    if (!strstr(msg, path)) pb_fuzz_fail("message does not name the file: %s", msg);
    /* A size over the limits leaves the declared width and height, nothing
     * else (image.h). */
    pb_image rest = *img;
    if (r == PB_ERR_LIMIT && (img->width || img->height)) {
      if (!(img->width > lim->max_dim || img->height > lim->max_dim ||
            (uint64_t)img->width * img->height > lim->max_pixels))
        pb_fuzz_fail("PB_ERR_LIMIT with a size %ux%u within the limits (%s)", img->width, img->height, msg);
      rest.width = rest.height = 0;
    }
    if (!pb_fuzz_all_zero(&rest, sizeof rest)) pb_fuzz_fail("failure %d left a non-empty image (%s)", (int)r, msg);
    return;
  }
  if (!img->width || !img->height || img->width > lim->max_dim || img->height > lim->max_dim ||
      (uint64_t)img->width * img->height > lim->max_pixels)
    pb_fuzz_fail("image %ux%u is outside the limits", img->width, img->height);
  if (!img->channel_count || img->channel_count > lim->max_channels || !img->pixels || !img->channel_names)
    pb_fuzz_fail("image with %u channels", img->channel_count);
  for (uint32_t k = 0; k < img->channel_count; ++k) {
    size_t n = strnlen(img->channel_names[k], sizeof img->channel_names[k]);
    if (n == 0 || n == sizeof img->channel_names[k]) pb_fuzz_fail("channel %u: name of %zu bytes", k, n);
    if (pb_image_find_channel(img, img->channel_names[k]) < 0) pb_fuzz_fail("channel %u not found by name", k);
  }
  float acc = 0;
  size_t n = (size_t)img->width * img->height * img->channel_count;
  for (size_t i = 0; i < n; ++i) acc += img->pixels[i];
  sink = acc;
  pb_image_destroy(img);
}
