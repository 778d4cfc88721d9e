/* spv_embed IN.spv OUT.h NAME: writes the SPIR-V words of IN as
 * `static const uint32_t pb_spv_NAME[]` (SPIR-V is a little-endian word
 * stream; glslc writes host order), eight words a line, through OUT.tmp
 * renamed onto OUT, so an interrupted build never leaves half a header.
 * A build-time tool (shaders/shaders.cmake), not part of photonbridge. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int main(int argc, char **argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: spv_embed IN.spv OUT.h NAME\n");
    return 2;
  }
  FILE *in = fopen(argv[1], "rb");
  if (!in) {
    perror(argv[1]);
    return 1;
  }
  if (fseek(in, 0, SEEK_END) != 0) return perror(argv[1]), 1;
  long n = ftell(in);
  rewind(in);
  if (n <= 0 || n % 4 != 0) {
    fprintf(stderr, "%s: not a whole number of 32-bit words\n", argv[1]);
    return 1;
  }
  unsigned char *b = malloc((size_t)n);
  if (!b || fread(b, 1, (size_t)n, in) != (size_t)n) {
    fprintf(stderr, "%s: cannot read\n", argv[1]);
    return 1;
  }
  fclose(in);
  char tmp[4096];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", argv[2]) >= (int)sizeof tmp) return 1;
  FILE *out = fopen(tmp, "w");
  if (!out) {
    perror(tmp);
    return 1;
  }
  fprintf(out, "/* Generated from %s by shaders/spv_embed.c. */\n#include <stdint.h>\nstatic const uint32_t pb_spv_%s[] = {\n",
          argv[1], argv[3]);
  for (long i = 0; i < n; i += 4) {
    uint32_t w = (uint32_t)b[i] | (uint32_t)b[i + 1] << 8 | (uint32_t)b[i + 2] << 16 | (uint32_t)b[i + 3] << 24;
    fprintf(out, "0x%08xu,%s", w, (i / 4) % 8 == 7 ? "\n" : "");
  }
  fprintf(out, "\n};\n");
  free(b);
  if (fclose(out) != 0 || rename(tmp, argv[2]) != 0) {
    perror(argv[2]);
    return 1;
  }
  return 0;
}
