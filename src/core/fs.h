/* File helpers: whole-file reads with a size limit, and atomic writes (write
 * PATH.tmp.PID, fsync-free rename on success, unlink on failure) so that no
 * failure, interruption or full disk leaves a half-written output. */
#ifndef PB_FS_H
#define PB_FS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "core/result.h"

/* Reads all of `path` into a malloc'd buffer (NUL-terminated for convenience).
 * Files over `max_bytes` fail with PB_ERR_LIMIT. */
pb_result pb_read_file(const char *path, uint64_t max_bytes, uint8_t **data,
                       size_t *size);

/* Opens a temporary sibling of `path` for writing. */
pb_result pb_atomic_open(const char *path, FILE **f, char **tmp_path);
/* Flushes and closes `f`; on success renames the temporary onto `path`, on any
 * write error removes it. Frees tmp_path. */
pb_result pb_atomic_commit(const char *path, FILE *f, char *tmp_path);
/* Closes and removes the temporary without touching `path`. */
void pb_atomic_abort(FILE *f, char *tmp_path);
/* Checks, before any long work, that `path` could be written: creates and
 * removes its temporary sibling. NULL and "-" (stdout) pass. Errors as
 * pb_atomic_open's (PB_ERR_IO naming the path). */
pb_result pb_check_writable(const char *path);

/* A temporary sibling name for `path` ("PATH.tmp.PID"); malloc'd. Writers
 * that own their file handle (OpenEXR) use it with pb_commit_rename. */
char *pb_tmp_name(const char *path);
/* Renames the finished temporary onto `path` (removing it on failure).
 * Test hook: with PB_TEST_HOLD_OUTPUT=1 in the environment it first prints
 * "photonbridge: test hook: holding TMP" to stderr and waits up to 30 s, so
 * that tests/faults.sh can interrupt a process while a temporary exists and
 * check that the signal handler removes it. */
pb_result pb_commit_rename(const char *tmp_path, const char *path);

/* The directory part of `path` ("." when none), malloc'd. */
char *pb_dirname(const char *path);
/* The last component of `path` (points into `path`). */
const char *pb_basename(const char *path);

/* Temporaries created by this process that are still open; a SIGINT handler
 * removes them (async-signal-safe unlink). */
void pb_tmp_register(const char *tmp_path);
void pb_tmp_unregister(const char *tmp_path);
void pb_tmp_remove_all_signal_safe(void);
/* What the interrupt message says was kept (main.c's handler): NULL (the
 * default) "no output written"; a sequence that has finished frames sets
 * its own (a string constant: the handler reads it asynchronously). */
void pb_tmp_set_interrupt_note(const char *note);
const char *pb_tmp_interrupt_note(void);

#endif
