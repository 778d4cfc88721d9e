/* libFuzzer target: the EXR reader (pb_exr_read) on arbitrary bytes.
 *
 * The reader takes a path, so each input is written to the target's folder
 * (fuzz_util.h) as in.exr. Besides memory errors and undefined behaviour in
 * our code (ASan + UBSan; OpenEXRCore itself is Debian's library, not
 * instrumented), the target aborts when the reader breaks its contract
 * (image.h; pb_fuzz_check_image_read). */
#include <stdint.h>
#include <unistd.h>

#include "core/result.h"
#include "fuzz_util.h"
#include "image/image.h"

int LLVMFuzzerInitialize(int *argc, char ***argv);
int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static const char *path;

int LLVMFuzzerInitialize(int *argc, char ***argv) {
  (void)argc, (void)argv;
  pb_fuzz_init("exr"); /* also quiets the log: multi-part files warn */
  path = pb_fuzz_path("in.exr");
  return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  pb_fuzz_write(path, data, size);
  /* Limits below the defaults keep every run inside libFuzzer's 2 GB
   * allocation limit (the defaults allow 256 Mpixel x 64 channels); the code
   * paths are the same. */
  const pb_exr_read_limits lim = {.max_dim = 4096, .max_pixels = 1u << 20, .max_channels = 16};
  pb_image img;
  pb_error_clear();
  pb_result r = pb_exr_read(path, &lim, &img);
  pb_fuzz_check_image_read(path, r, &lim, &img);
  pb_error_clear();
  unlink(path);
  return 0;
}
