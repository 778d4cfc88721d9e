/* Result codes: one X-macro table gives the enum, its message and the process
 * exit code of every subcommand. Programming mistakes are asserts; everything
 * the world can cause (files, drivers, scenes) is one of these. */
#ifndef PB_RESULT_H
#define PB_RESULT_H

#include <stdarg.h>

/*  X(name,                       exit, message) */
#define PB_RESULT_TABLE(X)                                                     \
  X(PB_OK,                        0,  "ok")                                    \
  X(PB_ERR_USAGE,                 2,  "bad command line")                      \
  X(PB_ERR_IO,                    3,  "file could not be read or written")     \
  X(PB_ERR_SCENE_PARSE,           4,  "scene file is not valid glTF")          \
  X(PB_ERR_SCENE_INVALID,         5,  "scene file breaks a glTF rule")         \
  X(PB_ERR_SCENE_UNSUPPORTED,     6,  "scene uses an unsupported feature")     \
  X(PB_ERR_SCENE_EMPTY,           7,  "scene has nothing to render")           \
  X(PB_ERR_IMAGE,                 8,  "image file is malformed")               \
  X(PB_ERR_IMAGE_MISMATCH,        9,  "images do not match in size or channels") \
  X(PB_ERR_LIMIT,                 10, "input exceeds a size limit")            \
  X(PB_ERR_NOMEM,                 11, "out of memory")                         \
  X(PB_ERR_NO_DEVICE,             12, "no usable Vulkan device")               \
  X(PB_ERR_VULKAN,                13, "Vulkan call failed")                    \
  X(PB_ERR_DEVICE_LOST,           14, "Vulkan device lost")                    \
  X(PB_ERR_NOT_AVAILABLE,         15, "component not built or not installed")  \
  X(PB_ERR_INTERRUPTED,           130, "interrupted")                          \
  X(PB_ERR_INTERNAL,              70, "internal error")

typedef enum pb_result {
#define PB_X_ENUM(name, exit_code, msg) name,
  PB_RESULT_TABLE(PB_X_ENUM)
#undef PB_X_ENUM
  PB_RESULT_COUNT
} pb_result;

const char *pb_result_name(pb_result r);
const char *pb_result_message(pb_result r);
int pb_result_exit_code(pb_result r);

/* The one-line error of the last failure on this thread: "what: where: why",
 * e.g. "scene.gltf: accessors[3]: count 900 x stride 12 exceeds bufferViews[2]
 * (1024 bytes)". pb_fail() records it and returns `r`, so a failing path reads
 * `return pb_fail(PB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));`.
 * The first failure wins until pb_error_clear(): the innermost, most precise
 * message is the one the user sees. */
pb_result pb_fail(pb_result r, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));
const char *pb_error_message(void);
pb_result pb_error_result(void);
void pb_error_clear(void);

#endif
