#define _POSIX_C_SOURCE 200809L
#define _DEFAULT_SOURCE /* syscall(): the signal handler's directory listing */
#include "core/fs.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>
#ifdef __linux__
#include <sys/syscall.h>
#endif

pb_result pb_read_file(const char *path, uint64_t max_bytes, uint8_t **data,
                       size_t *size) {
  *data = NULL;
  *size = 0;
  FILE *f = fopen(path, "rb");
  if (!f) return pb_fail(PB_ERR_IO, "%s: cannot open: %s", path, strerror(errno));
  struct stat st;
  if (fstat(fileno(f), &st) != 0 || !S_ISREG(st.st_mode)) {
    fclose(f);
    return pb_fail(PB_ERR_IO, "%s: not a regular file", path);
  }
  if ((uint64_t)st.st_size > max_bytes) {
    fclose(f);
    return pb_fail(PB_ERR_LIMIT, "%s: file is %lld bytes, over the limit of %llu",
                   path, (long long)st.st_size, (unsigned long long)max_bytes);
  }
  size_t n = (size_t)st.st_size;
  uint8_t *buf = malloc(n + 1);
  if (!buf) {
    fclose(f);
    return pb_fail(PB_ERR_NOMEM, "%s: cannot allocate %zu bytes", path, n);
  }
  size_t got = fread(buf, 1, n, f);
  int err = ferror(f);
  fclose(f);
  if (got != n || err) {
    free(buf);
    return pb_fail(PB_ERR_IO, "%s: read error", path);
  }
  buf[n] = 0;
  *data = buf;
  *size = n;
  return PB_OK;
}

char *pb_tmp_name(const char *path) {
  size_t n = strlen(path) + 32;
  char *t = malloc(n);
  if (t) snprintf(t, n, "%s.tmp.%ld", path, (long)getpid());
  return t;
}

/* PB_TEST_HOLD_OUTPUT=1 (fs.h): wait with the finished temporary in place. */
static void test_hold(const char *tmp_path) {
  const char *v = getenv("PB_TEST_HOLD_OUTPUT");
  if (!v || strcmp(v, "1") != 0) return;
  fprintf(stderr, "photonbridge: test hook: holding %s\n", tmp_path);
  fflush(stderr);
  for (int i = 0; i < 30; ++i) sleep(1);
}

pb_result pb_commit_rename(const char *tmp_path, const char *path) {
  test_hold(tmp_path);
  if (rename(tmp_path, path) != 0) {
    int e = errno;
    unlink(tmp_path);
    pb_tmp_unregister(tmp_path);
    return pb_fail(PB_ERR_IO, "%s: cannot write: %s", path, strerror(e));
  }
  pb_tmp_unregister(tmp_path);
  return PB_OK;
}

pb_result pb_atomic_open(const char *path, FILE **f, char **tmp_path) {
  *f = NULL;
  *tmp_path = pb_tmp_name(path);
  if (!*tmp_path) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  *f = fopen(*tmp_path, "wb");
  if (!*f) {
    int e = errno;
    free(*tmp_path);
    *tmp_path = NULL;
    return pb_fail(PB_ERR_IO, "%s: cannot write: %s", path, strerror(e));
  }
  pb_tmp_register(*tmp_path);
  return PB_OK;
}

int pb_private_open(const char *path) {
  /* O_EXCL: a file (or a symlink: O_EXCL never follows one) already at
   * `path` is an error, never opened, truncated or written through.
   * fchmod: the mode is 0600 whatever the umask (open's mode is ANDed with
   * it; a umask can only take bits away, but 0600 is the contract). */
  int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
  if (fd < 0) return -1;
  if (fchmod(fd, 0600) != 0) {
    int e = errno;
    close(fd);
    unlink(path);
    errno = e;
    return -1;
  }
  return fd;
}

pb_result pb_atomic_open_private(const char *path, FILE **f, char **tmp_path) {
  *f = NULL;
  *tmp_path = pb_tmp_name(path);
  if (!*tmp_path) return pb_fail(PB_ERR_NOMEM, "%s: out of memory", path);
  int fd = pb_private_open(*tmp_path);
  if (fd >= 0) {
    /* Registered only once it is ours: the handler never unlinks a file
     * someone else put at the name. */
    pb_tmp_register(*tmp_path);
    if ((*f = fdopen(fd, "wb"))) return PB_OK;
    close(fd);
  }
  int e = errno;
  if (fd >= 0) {
    unlink(*tmp_path);
    pb_tmp_unregister(*tmp_path);
  }
  free(*tmp_path);
  *tmp_path = NULL;
  return pb_fail(PB_ERR_IO, "%s: cannot write: %s", path, strerror(e));
}

pb_result pb_check_writable(const char *path) {
  if (!path || strcmp(path, "-") == 0) return PB_OK;
  FILE *f;
  char *tmp;
  pb_result r = pb_atomic_open(path, &f, &tmp);
  if (r == PB_OK) pb_atomic_abort(f, tmp);
  return r;
}

pb_result pb_atomic_commit(const char *path, FILE *f, char *tmp_path) {
  int bad = ferror(f);
  int e = bad ? errno : 0;
  /* errno of the failed write may have been overwritten since (any library
   * call may set it): fclose flushes what is still buffered and sets it
   * again, so a stale 0 ("Success") is replaced by the flush's error. */
  errno = 0;
  if (fclose(f) != 0 && (!bad || e == 0)) {
    bad = 1;
    e = errno;
  }
  if (bad && e == 0) e = EIO;
  if (bad) {
    unlink(tmp_path);
    pb_tmp_unregister(tmp_path);
    free(tmp_path);
    return pb_fail(PB_ERR_IO, "%s: write failed: %s", path, strerror(e));
  }
  pb_result r = pb_commit_rename(tmp_path, path);
  free(tmp_path);
  return r;
}

void pb_atomic_abort(FILE *f, char *tmp_path) {
  if (f) fclose(f);
  if (tmp_path) {
    unlink(tmp_path);
    pb_tmp_unregister(tmp_path);
    free(tmp_path);
  }
}

char *pb_dirname(const char *path) {
  const char *slash = strrchr(path, '/');
  if (!slash) return strdup(".");
  if (slash == path) return strdup("/");
  size_t n = (size_t)(slash - path);
  char *d = malloc(n + 1);
  if (!d) return NULL;
  memcpy(d, path, n);
  d[n] = 0;
  return d;
}

const char *pb_basename(const char *path) {
  const char *slash = strrchr(path, '/');
  return slash ? slash + 1 : path;
}

/* A small fixed table: a process has at most a handful of outputs open. */
enum { PB_TMP_SLOTS = 16, PB_TMP_LEN = 4096, PB_TMP_DIR_SLOTS = 4 };
static char tmp_table[PB_TMP_SLOTS][PB_TMP_LEN];
static char tmp_dir_table[PB_TMP_DIR_SLOTS][PB_TMP_LEN];

pb_result pb_private_dir_create(const char *base, const char *prefix, char *out, size_t cap) {
  int n = snprintf(out, cap, "%s/%s-XXXXXX", base, prefix);
  if (n < 0 || (size_t)n >= cap || (size_t)n >= PB_TMP_LEN) {
    if (cap) out[0] = 0;
    return pb_fail(PB_ERR_USAGE, "cannot create a private folder in %s: the path is too long", base);
  }
  /* mkdtemp: an unpredictable name, created (never reused) with mode 0700
   * less the umask; chmod makes it 0700 exactly. */
  if (!mkdtemp(out)) {
    int e = errno;
    out[0] = 0;
    return pb_fail(PB_ERR_IO, "cannot create a private folder in %s: %s", base, strerror(e));
  }
  if (chmod(out, 0700) != 0) {
    int e = errno;
    rmdir(out);
    out[0] = 0;
    return pb_fail(PB_ERR_IO, "cannot create a private folder in %s: %s", base, strerror(e));
  }
  for (int i = 0; i < PB_TMP_DIR_SLOTS; ++i)
    if (!tmp_dir_table[i][0]) {
      memcpy(tmp_dir_table[i], out, strlen(out) + 1);
      break;
    }
  return PB_OK;
}

void pb_private_dir_remove(const char *dir) {
  if (!dir || !dir[0]) return;
  DIR *d = opendir(dir);
  if (d) {
    struct dirent *e;
    while ((e = readdir(d)))
      if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) unlinkat(dirfd(d), e->d_name, 0);
    closedir(d);
  }
  rmdir(dir);
  for (int i = 0; i < PB_TMP_DIR_SLOTS; ++i)
    if (strcmp(tmp_dir_table[i], dir) == 0) tmp_dir_table[i][0] = 0;
}

void pb_tmp_register(const char *t) {
  for (int i = 0; i < PB_TMP_SLOTS; ++i)
    if (!tmp_table[i][0] && strlen(t) < PB_TMP_LEN) {
      memcpy(tmp_table[i], t, strlen(t) + 1);
      return;
    }
}
void pb_tmp_unregister(const char *t) {
  for (int i = 0; i < PB_TMP_SLOTS; ++i)
    if (strcmp(tmp_table[i], t) == 0) tmp_table[i][0] = 0;
}
static const char *volatile interrupt_note;
void pb_tmp_set_interrupt_note(const char *note) { interrupt_note = note; }
const char *pb_tmp_interrupt_note(void) { return interrupt_note ? interrupt_note : "no output written"; }

/* Empties a registered private folder from a signal handler: open, the raw
 * getdents64 system call and unlinkat only (opendir/readdir may allocate).
 * This also catches a file created but not yet registered when the signal
 * came. Elsewhere than Linux only the registered files go (and the rmdir
 * then fails if anything else was there). */
static void empty_dir_signal_safe(const char *dir) {
#ifdef __linux__
  int fd = open(dir, O_RDONLY | O_DIRECTORY | O_NOFOLLOW | O_CLOEXEC);
  if (fd < 0) return;
  /* Entries are removed while listing: list again until a pass finds none. */
  for (int pass = 0; pass < 64; ++pass) {
    char buf[4096] __attribute__((aligned(8)));
    long n, removed = 0;
    while ((n = syscall(SYS_getdents64, fd, buf, sizeof buf)) > 0) {
      for (long o = 0; o < n;) {
        /* struct linux_dirent64: d_ino (8), d_off (8), d_reclen (2), d_type (1), d_name */
        unsigned short reclen;
        memcpy(&reclen, buf + o + 16, sizeof reclen);
        if (!reclen) break;
        const char *name = buf + o + 19;
        if (strcmp(name, ".") && strcmp(name, "..") && unlinkat(fd, name, 0) == 0) removed++;
        o += reclen;
      }
    }
    if (!removed || lseek(fd, 0, SEEK_SET) != 0) break;
  }
  close(fd);
#else
  (void)dir;
#endif
}

void pb_tmp_remove_all_signal_safe(void) {
  for (int i = 0; i < PB_TMP_SLOTS; ++i)
    if (tmp_table[i][0]) unlink(tmp_table[i]);
  for (int i = 0; i < PB_TMP_DIR_SLOTS; ++i)
    if (tmp_dir_table[i][0]) {
      empty_dir_signal_safe(tmp_dir_table[i]);
      rmdir(tmp_dir_table[i]);
    }
}
