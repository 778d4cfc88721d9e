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
/* As pb_atomic_open, for a private folder (pb_private_dir_create): the
 * temporary is created with pb_private_open (exclusively, 0600 whatever the
 * umask), so a file or symlink already at its name fails the write instead
 * of being followed or clobbered. Finish with pb_atomic_commit / _abort. */
pb_result pb_atomic_open_private(const char *path, FILE **f, char **tmp_path);
/* Creates `path` exclusively (O_CREAT|O_EXCL|O_NOFOLLOW) with mode 0600
 * exactly, whatever the umask; the open descriptor, or -1 with errno set
 * (EEXIST when anything, a symlink included, is already there). */
int pb_private_open(const char *path);
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
/* A private folder for one process's files (serve's frames): BASE/PREFIX-
 * XXXXXX made by mkdtemp (an unpredictable name, never an existing
 * folder), mode 0700 exactly whatever the umask, its path in `out` (cap
 * bytes). It is registered: pb_tmp_remove_all_signal_safe empties and
 * removes it (the files in it need not be registered). On failure `out` is
 * "" and the error (PB_ERR_IO) names BASE and the reason. */
pb_result pb_private_dir_create(const char *base, const char *prefix, char *out, size_t cap);
/* Removes the files in `dir` (not recursively: a private folder holds
 * files only) and `dir`, and unregisters it. NULL or "" does nothing. */
void pb_private_dir_remove(const char *dir);
/* What the interrupt message says was kept (main.c's handler): NULL (the
 * default) "no output written"; a sequence that has finished frames sets
 * its own (a string constant: the handler reads it asynchronously). */
void pb_tmp_set_interrupt_note(const char *note);
const char *pb_tmp_interrupt_note(void);

#endif
