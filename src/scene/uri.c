/* URI resolution for buffers and images: relative references only, percent
 * decoded, and confined to the scene's folder unless the user allows external
 * files (a downloaded scene must not make us read ~/.ssh). */
#include <ctype.h>
#include <errno.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"
#include "scene/gltf_doc.h"

static int hexval(int c) {
  if (c >= '0' && c <= '9') return c - '0';
  c = tolower(c);
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

pb_result pb_gltf_resolve_uri(const char *scene_path, const char *dir, const char *uri,
                              int allow_external, const char *where, char **out) {
  *out = NULL;
  size_t n = strlen(uri);
  if (n == 0) return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: empty uri", scene_path, where);
  /* A scheme ("http:", "file:") is not a relative reference. */
  const char *colon = strchr(uri, ':');
  const char *slash = strchr(uri, '/');
  if (colon && (!slash || colon < slash))
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: %s: '%s': only relative file references and data URIs are supported",
                   scene_path, where, uri);
  if (!dir)
    return pb_fail(PB_ERR_SCENE_UNSUPPORTED, "%s: %s: '%s': an external file, and the scene was loaded from memory "
                   "without a folder (embed it as a data URI or in the GLB)", scene_path, where, uri);
  char *dec = malloc(n + 1);
  if (!dec) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", scene_path);
  size_t k = 0;
  for (size_t i = 0; i < n; ++i) {
    if (uri[i] == '%') {
      int hi = i + 1 < n ? hexval((unsigned char)uri[i + 1]) : -1;
      int lo = i + 2 < n ? hexval((unsigned char)uri[i + 2]) : -1;
      if (hi < 0 || lo < 0 || (hi == 0 && lo == 0)) {
        free(dec);
        return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: '%s': bad percent-encoding", scene_path, where, uri);
      }
      dec[k++] = (char)(hi * 16 + lo);
      i += 2;
      continue;
    }
    dec[k++] = uri[i];
  }
  dec[k] = 0;
  if (dec[0] == '/' && !allow_external) {
    free(dec);
    return pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: '%s' is an absolute path (use --allow-external-files to allow it)",
                   scene_path, where, uri);
  }
  size_t len = strlen(dir) + strlen(dec) + 2;
  char *joined = malloc(len);
  if (!joined) {
    free(dec);
    return pb_fail(PB_ERR_NOMEM, "%s: out of memory", scene_path);
  }
  if (dec[0] == '/') snprintf(joined, len, "%s", dec);
  else snprintf(joined, len, "%s/%s", dir, dec);
  free(dec);

  char *real_file = realpath(joined, NULL);
  if (!real_file) {
    int e = errno;
    pb_fail(e == ENOMEM ? PB_ERR_NOMEM : PB_ERR_IO, "%s: %s: cannot open '%s': %s", scene_path, where, uri, strerror(e));
    free(joined);
    return pb_error_result();
  }
  if (!allow_external) {
    char *real_dir = realpath(dir, NULL);
    size_t dl = real_dir ? strlen(real_dir) : 0;
    int inside = real_dir && strncmp(real_file, real_dir, dl) == 0 &&
                 (real_file[dl] == '/' || (dl == 1 && real_dir[0] == '/'));
    free(real_dir);
    if (!inside) {
      pb_fail(PB_ERR_SCENE_INVALID, "%s: %s: '%s' leaves the scene's folder (use --allow-external-files to allow it)",
              scene_path, where, uri);
      free(joined), free(real_file);
      return PB_ERR_SCENE_INVALID;
    }
  }
  free(joined);
  *out = real_file;
  return PB_OK;
}
