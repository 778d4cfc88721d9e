/* Helpers for tests that write small glTF files (buffers as base64 data
 * URIs). Include after pbtest.h. */
#ifndef PB_TEST_GLTF_TEST_H
#define PB_TEST_GLTF_TEST_H

#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

/* RFC 4648 base64 of n bytes; malloc'd, NUL-terminated. */
static inline char *pbt_b64(const void *data, size_t n) {
  static const char t[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const uint8_t *p = data;
  char *o = malloc(4 * ((n + 2) / 3) + 1), *q = o;
  if (!o) return NULL;
  for (size_t i = 0; i < n; i += 3) {
    uint32_t v = (uint32_t)p[i] << 16 | (i + 1 < n ? (uint32_t)p[i + 1] << 8 : 0) | (i + 2 < n ? p[i + 2] : 0);
    *q++ = t[v >> 18 & 63];
    *q++ = t[v >> 12 & 63];
    *q++ = i + 1 < n ? t[v >> 6 & 63] : '=';
    *q++ = i + 2 < n ? t[v & 63] : '=';
  }
  *q = 0;
  return o;
}

#endif
