/* What every libFuzzer target here shares: a private folder for the files
 * the code under test reads by path, writing an input there, the contract
 * failure that aborts (and so becomes a libFuzzer finding), and the
 * PB_FUZZ_VERBOSE switch. */
#ifndef PB_FUZZ_UTIL_H
#define PB_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>

#include "core/result.h"
#include "image/image.h"

/* Creates $TMPDIR/pb_fuzz_TARGET.XXXXXX (or under /tmp), removed with every
 * file named through pb_fuzz_path at exit; quiets the log. Aborts when the
 * folder cannot be made. Call once, from LLVMFuzzerInitialize. */
void pb_fuzz_init(const char *target);

/* DIR/NAME as a path inside the folder (static storage, one per name). */
const char *pb_fuzz_path(const char *name);

/* Writes `size` bytes to `path` (create or truncate); aborts on failure. */
void pb_fuzz_write(const char *path, const uint8_t *data, size_t size);

/* PB_FUZZ_VERBOSE=1: print each input's result (reproducing a finding). */
int pb_fuzz_verbose(void);

/* A broken contract: prints "fuzz_TARGET: contract: ..." and aborts. */
void pb_fuzz_fail(const char *fmt, ...) __attribute__((format(printf, 1, 2), noreturn));

/* 1 when the first n bytes of p are all zero. */
int pb_fuzz_all_zero(const void *p, size_t n);

/* The contract of a float image reader (pb_exr_read's shape, image.h), for
 * `path` read with `lim`:
 *   - failure: PB_ERR_IMAGE, PB_ERR_LIMIT or PB_ERR_NOMEM (the file exists
 *     and is regular, so never PB_ERR_IO), a one-line message naming the
 *     file, and *img zeroed;
 *   - success: a size within the limits, named channels that are found by
 *     name, and every pixel readable (summed). The image is destroyed. */
void pb_fuzz_check_image_read(const char *path, pb_result r, const pb_exr_read_limits *lim, pb_image *img);

#endif
