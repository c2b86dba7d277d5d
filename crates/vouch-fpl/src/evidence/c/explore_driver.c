/*
 * vouch translation-validation driver (evidence module). Linked with the generated
 * instrumented flight_plan.h and the project's stub runtime (tests/stub/fp_stub.c, whose own
 * scripted oracle is renamed away at compile time). It answers requests on stdin, one per line:
 *
 *   E <calls> <n> a1 .. an   replay auto_nav_init() and <calls> calls with the answers a1..an,
 *                            then explore the next call: at every question (condition or
 *                            non-literal value) the process forks, one child per answer
 *                            (conditions 0/1, values 0/2/6 = 0/1/3), so the replayed prefix is
 *                            shared and every leaf is one complete path of the call. Output:
 *                              [I + init events, when calls = 0]
 *                              Q b s lb ls                       state after the replay
 *                              P k b1..bk, event lines, S b s lb ls   one record per leaf
 *                              L k b1..bk                        a path asked more questions than
 *                                                                the limit (argv[2]): a loop
 *                              A status k b1..bk                 a path crashed or timed out
 *   W <calls> <n> a1 .. an   one plain run of <calls> calls (answers beyond n are 0), printed in
 *                            the format of tests/stub/driver.c.
 *
 * Each request ends with "done <cut>" where cut is 1 when the leaf budget ran out.
 * Every request runs in a fresh child of this server, so the function-local `static` for-loop
 * counters of auto_nav() start from zero each time, as in a fresh process.
 * All output goes through write(2) in whole records; processes never run concurrently (a
 * parent waits for its child), so records never interleave.
 */
#define _GNU_SOURCE
/* The stub runtime is compiled in the same cc call with its own oracle renamed away
 * (-Dfp_cond=vouch_stub_fp_cond ...); this file defines the real ones. */
#undef fp_cond
#undef fp_code
#undef fp_value
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <unistd.h>
#include <signal.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <sys/mman.h>
#include "fp_stub.h"
#define NAV_C
#include "flight_plan.h"

#define MAX_QUESTIONS 4096
static long question_limit = MAX_QUESTIONS;
#define ALARM_SECONDS 5

/* ---- output buffer ---- */
static char *buf;
static size_t blen, bcap;

static void put(const char *s, size_t n)
{
  if (blen + n > bcap) {
    size_t cap = bcap ? bcap : 4096;
    while (cap < blen + n) { cap *= 2; }
    buf = realloc(buf, cap);
    if (buf == NULL) { _exit(4); }
    bcap = cap;
  }
  memcpy(buf + blen, s, n);
  blen += n;
}
static void put_s(const char *s) { put(s, strlen(s)); }
static void put_l(long v)
{
  char tmp[32];
  int k = snprintf(tmp, sizeof tmp, "%ld", v);
  put(tmp, (size_t)k);
}
static void put_text(const char *t)
{
  for (; *t; t++) {
    if (*t == '\\') { put_s("\\\\"); }
    else if (*t == '\n') { put_s("\\n"); }
    else if (*t == '\r') { put_s("\\r"); }
    else { put(t, 1); }
  }
  put_s("\n");
}
static void write_all(const char *s, size_t n)
{
  while (n > 0) {
    ssize_t w = write(1, s, n);
    if (w < 0) { if (errno == EINTR) { continue; } _exit(5); }
    s += w;
    n -= (size_t)w;
  }
}
static void flush_buf(void) { write_all(buf, blen); blen = 0; }

/* ---- answers ---- */
static long *answers;
static size_t n_answers, next_answer;
static int recording, exploring;
static long taken[MAX_QUESTIONS];
static size_t n_taken;
static long *shared; /* [0] = leaves written, [1] = cut flag, [2] = leaf budget */

static void put_taken(long extra, int with_extra)
{
  put_l((long)n_taken + (with_extra ? 1 : 0));
  for (size_t i = 0; i < n_taken; i++) { put_s(" "); put_l(taken[i]); }
  if (with_extra) { put_s(" "); put_l(extra); }
  put_s("\n");
}

static long next_number(int is_value)
{
  static const long cond_choices[2] = {0, 1};
  static const long value_choices[3] = {0, 2, 6};
  const long *choices = is_value ? value_choices : cond_choices;
  int k = is_value ? 3 : 2;
  if (!exploring) { return next_answer < n_answers ? answers[next_answer++] : 0; }
  if (n_taken >= (size_t)question_limit) {
    blen = 0;
    put_s("L ");
    put_taken(0, 0);
    flush_buf();
    _exit(0);
  }
  for (int i = 0; i < k - 1; i++) {
    pid_t pid = fork();
    if (pid < 0) { _exit(6); }
    if (pid == 0) {
      alarm(ALARM_SECONDS);
      taken[n_taken++] = choices[i];
      return choices[i];
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) { }
    if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) {
      /* the record is built in a fresh buffer: this process's events stay untouched */
      char *keep = buf;
      size_t keep_len = blen, keep_cap = bcap;
      buf = NULL; blen = 0; bcap = 0;
      put_s("A ");
      put_l(WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st));
      put_s(" ");
      put_taken(choices[i], 1);
      flush_buf();
      free(buf);
      buf = keep; blen = keep_len; bcap = keep_cap;
    }
    if (shared[1]) { _exit(0); }
  }
  taken[n_taken++] = choices[k - 1];
  return choices[k - 1];
}

bool fp_cond(const char *text)
{
  bool v = (next_number(0) & 1) != 0;
  if (recording) { put_s(v ? "C 1 " : "C 0 "); put_text(text); }
  return v;
}

void fp_code(const char *text)
{
  if (recording) { put_s("X "); put_text(text); }
}

int fp_value(const char *text)
{
  long v;
  /* same literal test and number-to-value map as the stub runtime's own oracle */
  if (!fp_literal_value(text, &v)) {
    v = fp_value_of_number(next_number(1));
  }
  if (recording) { put_s("V "); put_l(v); put_s(" "); put_text(text); }
  return (int)v;
}

static void put_state(const char *tag)
{
  put_s(tag);
  put_l(nav_block); put_s(" "); put_l(nav_stage); put_s(" ");
  put_l(last_block); put_s(" "); put_l(last_stage); put_s("\n");
}

/* ---- requests ---- */
static void explore(long calls)
{
  nav_block = 0; nav_stage = 0; last_block = 0; last_stage = 0;
  recording = calls == 0;
  if (recording) { put_s("I\n"); }
  auto_nav_init();
  for (long i = 0; i < calls; i++) { auto_nav(); }
  put_state("Q ");
  flush_buf();
  recording = 1;
  exploring = 1;
  auto_nav();
  /* a leaf: one complete path */
  if (shared[0] >= shared[2]) { shared[1] = 1; _exit(0); }
  shared[0]++;
  {
    char *events = malloc(blen + 1);
    size_t elen = blen;
    if (events == NULL) { _exit(4); }
    memcpy(events, buf, blen);
    blen = 0;
    put_s("P ");
    put_taken(0, 0);
    put(events, elen);
    free(events);
  }
  put_state("S ");
  flush_buf();
  _exit(0);
}

static void walk(long calls)
{
  nav_block = 0; nav_stage = 0; last_block = 0; last_stage = 0;
  recording = 1;
  put_s("init\n");
  auto_nav_init();
  for (long i = 1; i <= calls; i++) {
    put_s("step "); put_l(i); put_s("\n");
    auto_nav();
    put_state("S ");
    if (blen > 65536) { flush_buf(); }
  }
  flush_buf();
  _exit(0);
}

int main(int argc, char **argv)
{
  char *line = NULL;
  size_t cap = 0;
  shared = mmap(NULL, 3 * sizeof(long), PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (shared == MAP_FAILED) { return 2; }
  shared[2] = argc > 1 ? strtol(argv[1], NULL, 10) : 100000;
  /* questions allowed in one explored call: the static bound of the plan, so a call that
   * loops is reported as soon as it asks more than any correct call can */
  if (argc > 2) { question_limit = strtol(argv[2], NULL, 10); }
  if (question_limit < 1 || question_limit > MAX_QUESTIONS) { question_limit = MAX_QUESTIONS; }
  while (getline(&line, &cap, stdin) > 0) {
    char *p = line + 1, *end;
    char kind = line[0];
    long calls, n;
    if (kind != 'E' && kind != 'W') { continue; }
    calls = strtol(p, &end, 10); p = end;
    n = strtol(p, &end, 10); p = end;
    free(answers);
    answers = malloc((size_t)(n > 0 ? n : 1) * sizeof(long));
    if (answers == NULL) { return 4; }
    n_answers = 0;
    for (long i = 0; i < n; i++) { answers[n_answers++] = strtol(p, &end, 10); p = end; }
    next_answer = 0;
    shared[0] = 0; shared[1] = 0;
    pid_t pid = fork();
    if (pid < 0) { return 6; }
    if (pid == 0) {
      alarm(ALARM_SECONDS * 4);
      if (kind == 'E') { explore(calls); } else { walk(calls); }
    }
    int st = 0;
    while (waitpid(pid, &st, 0) < 0 && errno == EINTR) { }
    blen = 0;
    if (!(WIFEXITED(st) && WEXITSTATUS(st) == 0)) {
      put_s("A "); put_l(WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st)); put_s(" 0\n");
    }
    put_s("done "); put_l(shared[1]); put_s("\n");
    flush_buf();
  }
  return 0;
}
