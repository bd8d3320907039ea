/* A hook for the signal and kill tests (tests/cli/test_faults.py, test_resume.py,
 * test_mpi_signals.py, test_mpi_resume.py), so that they wait for a state of the run instead of
 * sleeping for a time: preloaded (LD_PRELOAD) into rodend, it lets the first
 * RODEND_PAUSE_AFTER=N renames of a case file into place (a name of 16 hexadecimal digits and
 * ".h5") through, and holds every later one, in every thread, before it renames: the process
 * then has exactly N case files per process under their final names and its other cases in
 * flight. When the first rename is held it creates RODEND_PAUSE_DIR/paused.<pid> (the state a
 * test waits for); a held rename goes on once RODEND_PAUSE_DIR/release exists (a test creates it
 * after what it wanted to do in that state: signal the run, start a second run) or once
 * RODEND_PAUSE_DIR is removed, or never (kill).
 * Without RODEND_PAUSE_AFTER it does nothing. Test code only: never linked into rodend. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <fcntl.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static atomic_long renamed = 0;
static atomic_int announced = 0;

static int is_case_file(const char* path) {
  const char* name = strrchr(path, '/');
  name = name ? name + 1 : path;
  if (strlen(name) != 19 || strcmp(name + 16, ".h5") != 0) return 0;
  for (int i = 0; i < 16; ++i)
    if (!strchr("0123456789abcdef", name[i])) return 0;
  return 1;
}

static void touch(const char* dir, const char* name) {
  char path[4096];
  snprintf(path, sizeof path, "%s/%s", dir, name);
  const int fd = open(path, O_WRONLY | O_CREAT | O_CLOEXEC, 0644);
  if (fd >= 0) close(fd);
}

/* Holds the calling thread if this rename is past the first N (see above). */
static void maybe_pause(const char* new_path) {
  const char* after = getenv("RODEND_PAUSE_AFTER");
  const char* dir = getenv("RODEND_PAUSE_DIR");
  if (after == NULL || dir == NULL || !is_case_file(new_path)) return;
  if (atomic_fetch_add(&renamed, 1) < atol(after)) return;
  char name[64], release[4096];
  snprintf(name, sizeof name, "paused.%ld", (long)getpid());
  if (atomic_exchange(&announced, 1) == 0) touch(dir, name);
  snprintf(release, sizeof release, "%s/release", dir);
  const struct timespec tick = {0, 5 * 1000 * 1000};
  /* a test that ended without releasing (its folder removed) leaves no process held */
  while (access(release, F_OK) != 0 && access(dir, F_OK) == 0) nanosleep(&tick, NULL);
}

int renameat(int olddirfd, const char* oldpath, int newdirfd, const char* newpath) {
  static int (*real)(int, const char*, int, const char*);
  if (real == NULL)
    real = (int (*)(int, const char*, int, const char*))dlsym(RTLD_NEXT, "renameat");
  maybe_pause(newpath);
  return real(olddirfd, oldpath, newdirfd, newpath);
}

int rename(const char* oldpath, const char* newpath) {
  static int (*real)(const char*, const char*);
  if (real == NULL) real = (int (*)(const char*, const char*))dlsym(RTLD_NEXT, "rename");
  maybe_pause(newpath);
  return real(oldpath, newpath);
}
