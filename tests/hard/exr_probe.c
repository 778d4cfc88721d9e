/* exr_probe FILE.exr: every channel of an EXR as JSON on stdout, for the
 * hard-case driver (hard_cases.py), which has no EXR reader of its own:
 *   {"width": W, "height": H, "channels": {"R": [...], ...}}
 * Values are printed with %.9g; NaN and Inf as the strings "nan", "inf",
 * "-inf" (JSON has no literal for them). Errors: the reader's one line and its
 * exit code. */
#include <math.h>
#include <stdio.h>

#include "core/log.h"
#include "core/result.h"
#include "image/image.h"

static void value(float v) {
  if (isnan(v)) fputs("\"nan\"", stdout);
  else if (isinf(v)) fputs(v > 0 ? "\"inf\"" : "\"-inf\"", stdout);
  else printf("%.9g", (double)v);
}

int main(int argc, char **argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: exr_probe FILE.exr\n");
    return pb_result_exit_code(PB_ERR_USAGE);
  }
  pb_image img;
  pb_result r = pb_exr_read(argv[1], NULL, &img);
  if (r != PB_OK) {
    fprintf(stderr, "exr_probe: error: %s\n", pb_error_message());
    return pb_result_exit_code(r);
  }
  size_t n = (size_t)img.width * img.height;
  printf("{\"width\": %u, \"height\": %u, \"channels\": {", img.width, img.height);
  for (uint32_t c = 0; c < img.channel_count; ++c) {
    printf("%s\"%s\": [", c ? ", " : "", img.channel_names[c]);
    for (size_t i = 0; i < n; ++i) {
      if (i) putchar(',');
      value(img.pixels[i * img.channel_count + c]);
    }
    putchar(']');
  }
  printf("}}\n");
  pb_image_destroy(&img);
  return 0;
}
