/* A small streaming JSON writer for --json statistics. Keys and strings are
 * escaped; non-finite numbers are written as null (JSON has no NaN). */
#ifndef PB_JSON_H
#define PB_JSON_H

#include <stdint.h>
#include <stdio.h>

#include "core/result.h"

enum { PB_JSON_MAX_DEPTH = 32 };

typedef struct pb_json {
  FILE *f;
  int depth;
  int count[PB_JSON_MAX_DEPTH]; /* items written at each depth */
} pb_json;

void pb_json_begin_object(pb_json *j, const char *key);
void pb_json_end_object(pb_json *j);
void pb_json_begin_array(pb_json *j, const char *key);
void pb_json_end_array(pb_json *j);
/* key may be NULL inside arrays. */
void pb_json_string(pb_json *j, const char *key, const char *value);
void pb_json_number(pb_json *j, const char *key, double value);
void pb_json_int(pb_json *j, const char *key, int64_t value);
void pb_json_bool(pb_json *j, const char *key, int value);
void pb_json_null(pb_json *j, const char *key);

/* Open `path` for writing ("-" is stdout). Written to PATH.tmp and renamed on
 * close, so a failed run leaves no half file. */
pb_result pb_json_open(pb_json *j, const char *path, char **tmp_path);
pb_result pb_json_close(pb_json *j, const char *path, char *tmp_path);

#endif
