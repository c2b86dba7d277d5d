/*
 * vouch translation-validation driver, host platform (POSIX): crashes are signals, the time
 * limit is alarm(2), a walk runs in a forked child, and the watched static storage is the
 * executable's writable data segment, found from /proc/self/maps and the linker's
 * `edata`/`end` (the GOT is made read-only at link time, so the segment holds only the
 * program's own static variables).
 */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <errno.h>
#include <unistd.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include "vouch_platform.h"

extern char edata, end;

static const int crash_signals[] = { SIGSEGV, SIGBUS, SIGFPE, SIGILL, SIGABRT, SIGALRM };
/* set once at start-up, never written during a run */
static void (*crash_handler)(int);

static void on_signal(int sig) { crash_handler(128 + sig); }

void vouch_platform_init(void (*on_crash)(int status))
{
  crash_handler = on_crash;
  for (size_t i = 0; i < sizeof crash_signals / sizeof crash_signals[0]; i++) {
    signal(crash_signals[i], on_signal);
  }
}

void vouch_timer_arm(int seconds) { alarm((unsigned)seconds); }

/* The writable mappings covering [start of the one holding edata, end). */
int vouch_watch_range(char **lo_out, char **hi_out)
{
  FILE *f = fopen("/proc/self/maps", "r");
  unsigned long a, b, lo = 0, hi = 0;
  char perms[8];
  unsigned long e = (unsigned long)&edata - 1, stop = (unsigned long)&end;
  if (f == NULL) { return 0; }
  while (fscanf(f, "%lx-%lx %7s%*[^\n]", &a, &b, perms) == 3) {
    if (perms[0] != 'r' || perms[1] != 'w') { continue; }
    if (a <= e && e < b) { lo = a; hi = b; }
    else if (lo != 0 && a == hi && a < stop) { hi = b; }
  }
  fclose(f);
  if (lo == 0 || hi < stop) { return 0; }
  *lo_out = (char *)lo;
  *hi_out = (char *)stop;
  return 1;
}

int vouch_isolated(void (*body)(long), long arg)
{
  pid_t pid = fork();
  if (pid < 0) { _exit(6); }
  if (pid == 0) {
    for (size_t i = 0; i < sizeof crash_signals / sizeof crash_signals[0]; i++) {
      signal(crash_signals[i], SIG_DFL);
    }
    alarm(VOUCH_ALARM_SECONDS);
    body(arg);
    _exit(0);
  }
  int st = 0;
  while (waitpid(pid, &st, 0) < 0 && errno == EINTR) { }
  if (WIFEXITED(st)) { return WEXITSTATUS(st); }
  return 128 + WTERMSIG(st);
}

void vouch_exit(int status) { _exit(status); }
