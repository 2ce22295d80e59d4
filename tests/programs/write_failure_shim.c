/* A full disk on demand, for the program tests (docs/testing.md, "Full disks"): loaded with
 * LD_PRELOAD into a gf-* program, it gives the files whose path contains
 * GRANFLOW_FULL_DISK_PATH GRANFLOW_FULL_DISK_AFTER bytes of space in all (default 0) and
 * then fails every write that needs more with ENOSPC, as a full file system does (the write
 * that crosses the limit is cut short first). Space is counted in 4 KiB blocks, as a file
 * system allocates it: a write into blocks already written needs none, a write into a hole
 * (left by a seek or an ftruncate past the end) does; a file found already there owns the
 * blocks of its length; cutting a file gives its blocks back. Without GRANFLOW_FULL_DISK_PATH
 * nothing changes. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/uio.h>
#include <unistd.h>

#define BLOCK 4096LL
#define FILES 64

struct file {
  dev_t dev;
  ino_t ino;
  unsigned char* used; /* one byte per block: 1 when it holds space */
  long long blocks;    /* length of used */
};

static struct file files[FILES];
static long long taken; /* blocks given out */

static int watched(int fd) {
  const char* pattern = getenv("GRANFLOW_FULL_DISK_PATH");
  if (pattern == NULL || *pattern == '\0') return 0;
  char link[64], path[4096];
  snprintf(link, sizeof link, "/proc/self/fd/%d", fd);
  const ssize_t n = readlink(link, path, sizeof path - 1);
  if (n <= 0) return 0;
  path[n] = '\0';
  return strstr(path, pattern) != NULL;
}

static struct file* file_of(int fd) {
  struct stat st;
  if (!watched(fd) || fstat(fd, &st) != 0) return NULL;
  for (int i = 0; i < FILES; ++i)
    if (files[i].used != NULL && files[i].dev == st.st_dev && files[i].ino == st.st_ino) return &files[i];
  for (int i = 0; i < FILES; ++i)
    if (files[i].used == NULL) {
      files[i].dev = st.st_dev;
      files[i].ino = st.st_ino;
      files[i].blocks = (st.st_size + BLOCK - 1) / BLOCK;
      files[i].used = calloc((size_t)files[i].blocks + 1, 1);
      memset(files[i].used, 1, (size_t)files[i].blocks);
      return &files[i];
    }
  return NULL;
}

static void grow(struct file* f, long long blocks) {
  if (blocks <= f->blocks) return;
  f->used = realloc(f->used, (size_t)blocks);
  memset(f->used + f->blocks, 0, (size_t)(blocks - f->blocks));
  f->blocks = blocks;
}

/* How many of `count` bytes written at `offset` may reach fd; takes their blocks. */
static size_t allowed(int fd, size_t count, off_t offset) {
  if (count == 0) return 0;
  struct file* f = file_of(fd);
  if (f == NULL) return count;
  if (offset < 0) offset = lseek(fd, 0, SEEK_CUR);
  const char* after = getenv("GRANFLOW_FULL_DISK_AFTER");
  const long long limit = (after != NULL ? atoll(after) : 0) / BLOCK;
  const long long first = offset / BLOCK, last = (offset + (long long)count - 1) / BLOCK;
  grow(f, last + 1);
  for (long long b = first; b <= last; ++b) {
    if (f->used[b]) continue;
    if (taken >= limit) {
      const long long fits = b * BLOCK - offset;
      return fits > 0 ? (size_t)fits : 0;
    }
    f->used[b] = 1;
    ++taken;
  }
  return count;
}

static ssize_t full(void) {
  errno = ENOSPC;
  return -1;
}

/* The C library's own `name` (a function pointer copied from dlsym's object pointer). */
#define NEXT(name, real)                 \
  __typeof__(&name) real;                \
  do {                                   \
    void* next = dlsym(RTLD_NEXT, #name); \
    memcpy(&real, &next, sizeof real);   \
  } while (0)

ssize_t write(int fd, const void* buffer, size_t count) {
  const size_t n = allowed(fd, count, -1);
  if (n == 0 && count > 0) return full();
  NEXT(write, real);
  return real(fd, buffer, n);
}

ssize_t pwrite(int fd, const void* buffer, size_t count, off_t offset) {
  const size_t n = allowed(fd, count, offset);
  if (n == 0 && count > 0) return full();
  NEXT(pwrite, real);
  return real(fd, buffer, n, offset);
}

ssize_t pwrite64(int fd, const void* buffer, size_t count, off64_t offset) {
  const size_t n = allowed(fd, count, offset);
  if (n == 0 && count > 0) return full();
  NEXT(pwrite64, real);
  return real(fd, buffer, n, offset);
}

ssize_t writev(int fd, const struct iovec* iov, int iovcnt) {
  size_t count = 0;
  for (int i = 0; i < iovcnt; ++i) count += iov[i].iov_len;
  if (allowed(fd, count, -1) < count) return full();
  NEXT(writev, real);
  return real(fd, iov, iovcnt);
}

int ftruncate(int fd, off_t length) {
  struct file* f = file_of(fd);
  if (f != NULL)
    for (long long b = (length + BLOCK - 1) / BLOCK; b < f->blocks; ++b)
      if (f->used[b]) {
        f->used[b] = 0;
        --taken;
      }
  NEXT(ftruncate, real);
  return real(fd, length);
}

int ftruncate64(int fd, off64_t length) { return ftruncate(fd, (off_t)length); }
