#define _POSIX_C_SOURCE 200809L
#include "core/json.h"

#include <assert.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/fs.h"

static void put_string(FILE *f, const char *s) {
  fputc('"', f);
  for (const unsigned char *p = (const unsigned char *)s; *p; ++p) {
    switch (*p) {
    case '"': fputs("\\\"", f); break;
    case '\\': fputs("\\\\", f); break;
    case '\n': fputs("\\n", f); break;
    case '\r': fputs("\\r", f); break;
    case '\t': fputs("\\t", f); break;
    default:
      if (*p < 0x20) fprintf(f, "\\u%04x", *p);
      else fputc(*p, f);
    }
  }
  fputc('"', f);
}

static void item(pb_json *j, const char *key) {
  if (j->count[j->depth]++) fputc(',', j->f);
  fputc('\n', j->f);
  for (int i = 0; i < j->depth; ++i) fputs("  ", j->f);
  if (key) {
    put_string(j->f, key);
    fputs(": ", j->f);
  }
}

static void open_(pb_json *j, const char *key, char c) {
  if (j->depth == 0 && j->count[0] == 0 && !key) {
    j->count[0] = 1;
  } else {
    item(j, key);
  }
  fputc(c, j->f);
  assert(j->depth + 1 < PB_JSON_MAX_DEPTH);
  j->depth++;
  j->count[j->depth] = 0;
}
static void close_(pb_json *j, char c) {
  assert(j->depth > 0);
  int had = j->count[j->depth];
  j->depth--;
  if (had) {
    fputc('\n', j->f);
    for (int i = 0; i < j->depth; ++i) fputs("  ", j->f);
  }
  fputc(c, j->f);
  if (j->depth == 0) fputc('\n', j->f);
}

void pb_json_begin_object(pb_json *j, const char *key) { open_(j, key, '{'); }
void pb_json_end_object(pb_json *j) { close_(j, '}'); }
void pb_json_begin_array(pb_json *j, const char *key) { open_(j, key, '['); }
void pb_json_end_array(pb_json *j) { close_(j, ']'); }
void pb_json_string(pb_json *j, const char *key, const char *v) {
  item(j, key);
  if (v) put_string(j->f, v);
  else fputs("null", j->f);
}
void pb_json_number(pb_json *j, const char *key, double v) {
  item(j, key);
  if (isfinite(v)) fprintf(j->f, "%.9g", v);
  else fputs("null", j->f);
}
void pb_json_int(pb_json *j, const char *key, int64_t v) {
  item(j, key);
  fprintf(j->f, "%lld", (long long)v);
}
void pb_json_bool(pb_json *j, const char *key, int v) {
  item(j, key);
  fputs(v ? "true" : "false", j->f);
}
void pb_json_null(pb_json *j, const char *key) {
  item(j, key);
  fputs("null", j->f);
}

pb_result pb_json_open(pb_json *j, const char *path, char **tmp_path) {
  memset(j, 0, sizeof *j);
  *tmp_path = NULL;
  if (strcmp(path, "-") == 0) {
    j->f = stdout;
    return PB_OK;
  }
  pb_result r = pb_atomic_open(path, &j->f, tmp_path);
  return r;
}

pb_result pb_json_close(pb_json *j, const char *path, char *tmp_path) {
  if (j->f == stdout) {
    fflush(stdout);
    return PB_OK;
  }
  return pb_atomic_commit(path, j->f, tmp_path);
}
