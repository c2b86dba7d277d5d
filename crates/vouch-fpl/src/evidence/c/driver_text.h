/*
 * vouch translation-validation driver: growing text buffers, async-signal-safe number printing
 * and the line input of requests (plain read(2), so that the same code reads a pipe on the
 * host and the semihosting console on the target). Included once, by explore_driver.c.
 */
#ifndef VOUCH_DRIVER_TEXT_H
#define VOUCH_DRIVER_TEXT_H
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <unistd.h>
#include "vouch_platform.h"

struct buf { char *p; size_t len, cap; };


/* The request input: bytes read so far, and where the line just returned ends. */
struct input { char *line; size_t cap, len, next; };

static void *grow(void *p, size_t n)
{
  void *q = realloc(p, n ? n : 1);
  if (q == NULL) { vouch_exit(4); }
  return q;
}

/* ---- output ---- */
static void put(struct buf *b, const char *s, size_t n)
{
  if (b->len + n > b->cap) {
    size_t cap = b->cap ? b->cap : 4096;
    while (cap < b->len + n) { cap *= 2; }
    b->p = grow(b->p, cap);
    b->cap = cap;
  }
  memcpy(b->p + b->len, s, n);
  b->len += n;
}
static void put_s(struct buf *b, const char *s) { put(b, s, strlen(s)); }
/* async-signal-safe decimal printing */
static void put_l(struct buf *b, long v)
{
  char tmp[24];
  int k = 24;
  unsigned long u = v < 0 ? 0UL - (unsigned long)v : (unsigned long)v;
  do { tmp[--k] = (char)('0' + u % 10); u /= 10; } while (u > 0);
  if (v < 0) { tmp[--k] = '-'; }
  put(b, tmp + k, (size_t)(24 - k));
}
static void put_text(struct buf *b, const char *t)
{
  for (; *t; t++) {
    if (*t == '\\') { put_s(b, "\\\\"); }
    else if (*t == '\n') { put_s(b, "\\n"); }
    else if (*t == '\r') { put_s(b, "\\r"); }
    else { put(b, t, 1); }
  }
  put_s(b, "\n");
}
static void write_all(const char *s, size_t n)
{
  while (n > 0) {
    ssize_t w = write(1, s, n);
    if (w < 0) { if (errno == EINTR) { continue; } vouch_exit(5); }
    s += w;
    n -= (size_t)w;
  }
}
static void put_answers(struct buf *b, const long *a, size_t n)
{
  put_l(b, (long)n);
  for (size_t i = 0; i < n; i++) { put_s(b, " "); put_l(b, a[i]); }
  put_s(b, "\n");
}

/* The next request line (without its newline) in in->line, read with plain read(2) so that the
 * same code serves a pipe on the host and the semihosting console on the target; 0 at the end
 * of the input. */
static int next_line(struct input *in)
{
  size_t scanned = 0;
  for (;;) {
    for (size_t i = scanned; i < in->len; i++) {
      if (in->line[i] == '\n') {
        in->line[i] = '\0';
        in->next = i + 1;
        return 1;
      }
    }
    scanned = in->len;
    if (in->len + 4096 + 1 > in->cap) {
      in->cap = (in->len + 4096 + 1) * 2;
      in->line = grow(in->line, in->cap);
    }
    ssize_t n = read(0, in->line + in->len, in->cap - in->len - 1);
    if (n < 0 && errno == EINTR) { continue; }
    if (n <= 0) { return 0; }
    in->len += (size_t)n;
  }
}

/* Drops the line just handled from the input buffer. */
static void consume_line(struct input *in)
{
  memmove(in->line, in->line + in->next, in->len - in->next);
  in->len -= in->next;
  in->next = 0;
}

#endif
