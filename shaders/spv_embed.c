/* spv_embed IN.spv OUT.h NAME: writes the SPIR-V words of IN as
 * `static const uint32_t pb_spv_NAME[]` (SPIR-V is a little-endian word
 * stream; glslc writes host order), eight words a line, through OUT.tmp
 * renamed onto OUT, so an interrupted build never leaves half a header.
 * A build-time tool (shaders/shaders.cmake), not part of photonbridge.
 *
 * glslc -g gives the modules their names (OpName, OpMemberName: the
 * contract test and the validation layer's messages read them) and also
 * the GLSL source and a line table (OpSource, OpString, OpLine), a third of
 * a large module that every driver and the validation layer parse at each
 * start; those are left out here. */
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { OP_SOURCE_CONTINUED = 2, OP_SOURCE = 3, OP_STRING = 7, OP_LINE = 8, OP_EXT_INST_IMPORT = 11, OP_NO_LINE = 317 };

/* Drops the source and line instructions of the n words at w in place;
 * returns the new word count, or 0 for a malformed stream or one whose
 * strings something else may name (a NonSemantic extended instruction set:
 * kept whole). */
static size_t strip_lines(uint32_t *w, size_t n) {
  if (n < 5 || w[0] != 0x07230203u) return 0;
  for (size_t i = 5; i < n;) {
    uint32_t len = w[i] >> 16;
    if (len == 0 || i + len > n) return 0;
    if ((w[i] & 0xffffu) == OP_EXT_INST_IMPORT && len > 2 &&
        strncmp((const char *)&w[i + 2], "NonSemantic.", 12) == 0)
      return n;
    i += len;
  }
  size_t o = 5;
  for (size_t i = 5; i < n;) {
    uint32_t op = w[i] & 0xffffu, len = w[i] >> 16;
    if (op != OP_SOURCE_CONTINUED && op != OP_SOURCE && op != OP_STRING && op != OP_LINE && op != OP_NO_LINE) {
      memmove(&w[o], &w[i], len * sizeof *w);
      o += len;
    }
    i += len;
  }
  return o;
}

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
  size_t words = (size_t)n / 4;
  uint32_t *w = malloc(words * sizeof *w);
  if (!w) return 1;
  for (size_t i = 0; i < words; ++i)
    w[i] = (uint32_t)b[4 * i] | (uint32_t)b[4 * i + 1] << 8 | (uint32_t)b[4 * i + 2] << 16 |
           (uint32_t)b[4 * i + 3] << 24;
  free(b);
  words = strip_lines(w, words);
  if (!words) {
    fprintf(stderr, "%s: not a SPIR-V module\n", argv[1]);
    return 1;
  }
  char tmp[4096];
  if (snprintf(tmp, sizeof tmp, "%s.tmp", argv[2]) >= (int)sizeof tmp) return 1;
  FILE *out = fopen(tmp, "w");
  if (!out) {
    perror(tmp);
    return 1;
  }
  fprintf(out, "/* Generated from %s by shaders/spv_embed.c. */\n#include <stdint.h>\nstatic const uint32_t pb_spv_%s[] = {\n",
          argv[1], argv[3]);
  for (size_t i = 0; i < words; ++i) fprintf(out, "0x%08xu,%s", w[i], i % 8 == 7 ? "\n" : "");
  fprintf(out, "\n};\n");
  free(w);
  if (fclose(out) != 0 || rename(tmp, argv[2]) != 0) {
    perror(argv[2]);
    return 1;
  }
  return 0;
}
