#include "core/result.h"

#include <stdio.h>
#include <string.h>

static const char *const names[] = {
#define PB_X(name, exit_code, msg) #name,
    PB_RESULT_TABLE(PB_X)
#undef PB_X
};
static const char *const messages[] = {
#define PB_X(name, exit_code, msg) msg,
    PB_RESULT_TABLE(PB_X)
#undef PB_X
};
static const int exit_codes[] = {
#define PB_X(name, exit_code, msg) exit_code,
    PB_RESULT_TABLE(PB_X)
#undef PB_X
};

const char *pb_result_name(pb_result r) {
  return (unsigned)r < PB_RESULT_COUNT ? names[r] : "PB_ERR_UNKNOWN";
}
const char *pb_result_message(pb_result r) {
  return (unsigned)r < PB_RESULT_COUNT ? messages[r] : "unknown error";
}
int pb_result_exit_code(pb_result r) {
  return (unsigned)r < PB_RESULT_COUNT ? exit_codes[r] : 70;
}

static _Thread_local char err_msg[1024];
static _Thread_local pb_result err_result = PB_OK;

pb_result pb_fail(pb_result r, const char *fmt, ...) {
  if (err_result == PB_OK && r != PB_OK) {
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err_msg, sizeof err_msg, fmt, ap);
    va_end(ap);
    /* One line, always: a message quoting file content must not break it. */
    for (char *p = err_msg; *p; ++p)
      if (*p == '\n' || *p == '\r') *p = ' ';
    err_result = r;
  }
  return r;
}
const char *pb_error_message(void) {
  return err_result == PB_OK ? "" : err_msg;
}
pb_result pb_error_result(void) { return err_result; }
void pb_error_clear(void) {
  err_result = PB_OK;
  err_msg[0] = 0;
}
