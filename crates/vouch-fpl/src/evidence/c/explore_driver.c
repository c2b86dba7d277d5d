/*
 * vouch translation-validation driver (evidence module). Linked with the generated
 * instrumented flight_plan.h (plus one VOUCH_REGISTER line after each of its static
 * declarations, written by evidence/cstate.rs) and the project's stub runtime
 * (tests/stub/fp_stub.c, whose own scripted oracle is renamed away at compile time).
 *
 * The C state. Every registered variable (header statics, `for` counters inside auto_nav,
 * runtime globals of fp_stub.h) is one field of the *state bytes*, in registration order. A
 * request gives a state; the driver writes it into the variables ("restore"), runs, and reads
 * them back. Whatever else the program keeps in static storage must never change: after every
 * run the driver compares the program's whole static storage (as the platform finds it:
 * vouch_watch_range) outside the registered variables with its image taken at start-up, and
 * reports any difference (`H`): state the validator does not see.
 *
 * Requests on stdin, one per line; every answer ends with "done <cut>":
 *
 *   I                       auto_nav_init() from the initial state:
 *                             I, its event lines, Z <state hex>
 *   X <jumps> <hex> <n> <k> <hex1> .. <hexn>
 *                           every path of one auto_nav() call from state <hex>: at each question
 *                           (condition 0/1, non-literal value: every int8_t) the call is run
 *                           again from the restored state with a longer answer prefix:
 *                             P k a1..ak, event lines, S <changes>     one complete path
 *                             T i <changes> | T i !                     the same answers from <hexi>
 *                             L k a1..ak                                more questions than allowed
 *                           then, when <jumps> is 1, an operator jump to every block:
 *                             J b, event lines, S <changes>, T ...
 *                           <hex1>..<hexn> are copies of the state with the parts the validator
 *                           drops changed; T gives the changes from copy i, or "!" (then that
 *                           run's event lines, and no more T lines for the record) when it asked
 *                           other questions or produced other events.
 *                           <changes>: " offset=value" for every byte that differs. With
 *                           joining (K), a run from copy k or later that meets the explored
 *                           run at a stage start with only put-back counters differing stops:
 *                           T a-b = for copies a to b (the rest is the explored run's, those
 *                           counters at each copy's own start values).
 *   W <calls> <n> a1 .. an  one plain run from the initial state in a child process, answers
 *                           beyond n are 0, printed in the format of tests/stub/driver.c.
 *   K <join> <mask> <bytes> <n> ...  join the runs of one call at stage starts (X requests): n loops
 *                           as (counter variable id, block, init stage, loop-back stage), whose
 *                           counters are put back at stages outside the loop when <mask> is 1;
 *                           a run that reaches a stage start in the state an earlier run of
 *                           the call had there stops: P k a1..ak, event lines, M <node>;
 *                           the join points may take <bytes> of memory (0: no limit)
 *   F                       the decimal constants of the plan's comparisons as compiled
 *                           (vouch_consts.h): F <hex of the double's bytes, lowest first>
 *
 *   done <cut>              after an X request: 0 complete, 1 the run budget was reached, 2
 *                           no memory was left for the join points (and no jumps were made)
 *   H <offset>              (after a record) its runs wrote outside the registered variables
 *   A <signal> k a1..ak     the process dies (crash, time-out) on that answer prefix (or
 *   A <signal> J b          during the jump to block b); the answer is then "done 0" and the
 *                           process exits.
 *
 * argv (or, on the target, the first request line "L <budget> <limit> <lo> <hi>"): leaf budget
 * (paths per request), question limit (per call), lowest and highest value tried for a
 * non-literal value.
 *
 * This file is portable C99 (plus the linker-section registration of GCC): the same code runs
 * on the host and on an emulated Cortex-M core. What differs — crash and time-out handlers, the
 * extent of the program's static storage, running a plain walk isolated from the server's
 * state — is behind the small platform interface below, implemented by host_rt.c (POSIX:
 * signals, alarm, fork, /proc/self/maps) and target_rt.c (Cortex-M: fault handlers, SysTick,
 * linker symbols, semihosting I/O through newlib).
 *
 * Its parts, included here in this order: driver_text.h (buffers, number printing, the line
 * input), driver_vars.h (the registered variables and the watch of static storage),
 * explore_join.h (joining the runs of one call at stage starts), driver_answers.h (the
 * oracle: answers from the prefix, pending prefixes); this file holds the runs, the records
 * and the requests.
 */
/* The stub runtime is compiled in the same cc call with its own oracle renamed away
 * (-Dfp_cond=vouch_stub_fp_cond ...); this file defines the real ones. */
#undef fp_cond
#undef fp_code
#undef fp_value
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include <setjmp.h>
#include <unistd.h>
#include "vouch_platform.h"
#include "driver_text.h"

struct vouch_var { unsigned long magic; long id; void *addr; unsigned long size; };
/* truncated alike on 32- and 64-bit targets */
#define VOUCH_MAGIC ((unsigned long)0x766f7563685f7661ULL)
#define VOUCH_REGISTER(id, name) \
  static struct vouch_var vouch_var_##id __attribute__((used, section("vouch_vars"))) = \
    { VOUCH_MAGIC, id, (void *)&(name), sizeof(name) };
#include "fp_stub.h"
/* Every stage start of the header's auto_nav also reports to the driver, where the runs of one
 * call are joined (see vouch_at_stage). */
void vouch_at_stage(void);
#undef Stage
#define Stage(s) case s: set_nav_stage(s); vouch_at_stage();
#include "vouch_runtime_vars.h"
#include "vouch_consts.h"
#define NAV_C
#include "flight_plan.h"

extern struct vouch_var __start_vouch_vars[], __stop_vouch_vars[];

#define ALARM_SECONDS VOUCH_ALARM_SECONDS
enum mode { SCRIPT, EXPLORE, FORCED };

/* All mutable driver state lives on the heap, outside the data segment it watches. */
struct driver {
  /* registered variables, by id */
  size_t n_vars, state_len;
  struct vouch_var **vars;
  size_t *offset;
  unsigned char *init_state, *state, *after;
  unsigned char *copies;   /* n_copies states */
  size_t n_copies, cap_copies;
  /* the watched data segment and its image */
  char *lo, *hi;
  unsigned char *image;
  size_t n_clean;
  size_t (*clean)[2];
  int watching;
  long hidden[8];          /* offsets written outside the registered variables, this run */
  size_t n_hidden;
  /* answers */
  enum mode mode;
  long *prefix, *taken;
  size_t n_prefix, n_taken, cap_answers;
  long *pending;           /* stacked prefixes: values, then their length */
  size_t n_pending, cap_pending;
  int deviated;
  int jumping;             /* the block of the operator jump in progress, or -1 */
  long question_limit, leaf_budget, value_lo, value_hi;
  jmp_buf too_long;        /* longjmp 1: too many questions, 2: joined an earlier run */
  /* joining the runs of one call (request K): at a stage start, the counters of the loops the
   * stage is not inside are put back as they were at the start of the call (`start`); a run
   * that then holds a state an earlier run of this call held at a stage start stops there */
  int join, mask;
  size_t join_bytes;       /* memory the join points may take (0: no limit) */
  long *loops;             /* n_loops × (variable id, block, init stage, loop-back stage) */
  size_t n_loops;
  const unsigned char *start;
  unsigned char *nodes;    /* n_nodes states */
  size_t n_nodes, cap_nodes;
  long *slots;             /* hash table of node numbers + 1 */
  size_t n_slots;
  long joined;             /* the node the run joined */
  /* the stage starts of the last explored run (state, events, answers at each), so that a
   * copy's run whose changes are all put back can stop where it meets that run again */
  unsigned char *snaps;
  size_t *snap_ev, *snap_taken;
  long *snap_node;         /* the join point of each stage start */
  unsigned long *met;      /* hash set of (copy, join point) + 1 where a copy's run met */
  size_t n_met, n_met_slots;
  size_t n_snaps, cap_snaps, snap_seen;
  size_t first_stoppable;  /* copies from this one on may stop so (request X) */
  int stoppable;
  /* output: events are recorded into *rec when it is set */
  struct buf *rec;
  struct buf ev, ev2, out;
  struct input in;
};
static struct driver *D;

static void flush_out(void) { write_all(D->out.p, D->out.len); D->out.len = 0; }
#include "driver_vars.h"

#include "explore_join.h"

#include "driver_answers.h"

/* ---- crashes and time-outs (called by the platform's handlers) ---- */
static void on_crash(int status)
{
  flush_out();
  put_s(&D->out, "A ");
  put_l(&D->out, status);
  put_s(&D->out, " ");
  if (D->jumping >= 0) {
    put_s(&D->out, "J ");
    put_l(&D->out, D->jumping);
    put_s(&D->out, "\n");
  } else {
    put_answers(&D->out, D->taken, D->mode == SCRIPT ? 0 : D->n_taken);
  }
  put_s(&D->out, "done 0\n");
  flush_out();
  vouch_exit(0);
}

/* ---- runs ---- */
static void put_changes(const unsigned char *from, const unsigned char *to)
{
  for (size_t i = 0; i < D->state_len; i++) {
    if (from[i] != to[i]) {
      put_s(&D->out, " ");
      put_l(&D->out, (long)i);
      put_s(&D->out, "=");
      put_l(&D->out, to[i]);
    }
  }
  put_s(&D->out, "\n");
}

/* One call (jump_to < 0) or an operator jump from state `s` with the current prefix; events
 * in `ev`, the state after in D->after; 1 when it ended, 0 when the call asked more questions
 * than allowed, 2 when it joined an earlier run of the call at a stage start (D->joined), 3
 * when a copy's run met the explored run (meets_explored_run), 4 when there was no memory
 * left for a join point. */
static int run_from(const unsigned char *s, struct buf *ev, enum mode mode, int jump_to)
{
  restore(s);
  D->start = s;
  D->snap_seen = 0;
  if (mode == EXPLORE) { D->n_snaps = 0; }
  D->mode = mode;
  D->n_taken = 0;
  D->deviated = 0;
  ev->len = 0;
  D->rec = ev;
  int stop = setjmp(D->too_long);
  int ended = stop == 0 ? 1 : stop >= 2 ? stop : 0;
  D->jumping = jump_to;
  if (stop == 0) {
    if (jump_to < 0) { auto_nav(); } else { nav_goto_block((uint8_t)jump_to); }
  }
  D->jumping = -1;
  D->rec = NULL;
  capture(D->after);
  hidden_check();
  return ended;
}

/* The same answers from copy i: "T i changes", or "T i !" (and 0) when the run asked other
 * questions or produced other events than the first one (whose events are in D->ev). */
static int replay_copy(size_t n, size_t i, int jump_to)
{
  const unsigned char *s2 = D->copies + i * D->state_len;
  D->n_prefix = n;
  D->stoppable = i >= D->first_stoppable && jump_to < 0;
  int r = 0;
  for (size_t j = 0; D->stoppable && j < D->n_snaps; j++) {
    if (met_find(met_key(i, D->snap_node[j]), 0)) { r = 3; break; }
  }
  if (r != 3) {
    r = run_from(s2, &D->ev2, FORCED, jump_to);
    if (r == 3) { met_find(met_key(i, D->snap_node[D->snap_seen - 1]), 1); }
  }
  D->stoppable = 0;
  /* met: the rest of the run is the explored run's, with the put-back counters at the copy's
   * own start values (put_run prints these as ranges: T a-b =) */
  if (r == 3) { return 2; }
  int ended = r == 1;
  put_s(&D->out, "T ");
  put_l(&D->out, (long)i);
  if (!ended || D->deviated || D->n_taken != n || D->ev2.len != D->ev.len
      || memcmp(D->ev2.p, D->ev.p, D->ev.len) != 0) {
    /* the copy's events follow */
    put_s(&D->out, " !\n");
    put(&D->out, D->ev2.p, D->ev2.len);
    return 0;
  }
  put_changes(s2, D->after);
  return 1;
}

static void put_met(size_t a, size_t b)
{
  put_s(&D->out, "T ");
  put_l(&D->out, (long)a);
  put_s(&D->out, "-");
  put_l(&D->out, (long)b);
  put_s(&D->out, " =\n");
}

/* P or J record of the run just made (events in D->ev, answers in D->taken). */
static void put_run(int jump_to)
{
  if (jump_to < 0) {
    put_s(&D->out, "P ");
    put_answers(&D->out, D->taken, D->n_taken);
  } else {
    put_s(&D->out, "J ");
    put_l(&D->out, jump_to);
    put_s(&D->out, "\n");
  }
  put(&D->out, D->ev.p, D->ev.len);
  put_s(&D->out, "S");
  put_changes(D->state, D->after);
  size_t n = D->n_taken;
  /* the answers of this run, for every copy (the copies' runs overwrite D->taken) */
  memcpy(D->prefix, D->taken, n * sizeof(long));
  size_t met_from = 0;
  int streak = 0;
  for (size_t i = 0; i < D->n_copies; i++) {
    int r = replay_copy(n, i, jump_to);
    if (r == 2) {
      if (!streak) { met_from = i; streak = 1; }
      continue;
    }
    if (streak) { put_met(met_from, i - 1); streak = 0; }
    if (!r) { break; }
  }
  if (streak) { put_met(met_from, D->n_copies - 1); }
  put_hidden();
}

static void explore(int jumps)
{
  long leaves = 0;
  int cut = 0;
  D->n_pending = 0;
  D->n_prefix = 0;
  D->n_nodes = 0;
  if (D->slots) { memset(D->slots, 0, D->n_slots * sizeof(long)); }
  D->n_met = 0;
  if (D->met) { memset(D->met, 0, D->n_met_slots * sizeof *D->met); }
  for (;;) {
    if (leaves >= D->leaf_budget) { cut = 1; break; }
    /* the time limit is per run: a call with many runs takes as long as it needs */
    vouch_timer_arm(ALARM_SECONDS);
    int ended = run_from(D->state, &D->ev, EXPLORE, -1);
    leaves++;
    if (ended == 4) {
      /* out of memory for join points: the request is cut, this run not reported */
      cut = 2;
      break;
    }
    if (ended == 1) {
      put_run(-1);
    } else if (ended == 2) {
      /* joined: its answers and events up to the stage start, and the node */
      put_s(&D->out, "P ");
      put_answers(&D->out, D->taken, D->n_taken);
      put(&D->out, D->ev.p, D->ev.len);
      put_s(&D->out, "M ");
      put_l(&D->out, D->joined);
      put_s(&D->out, "\n");
      put_hidden();
    } else {
      put_s(&D->out, "L ");
      put_answers(&D->out, D->taken, D->n_taken);
      put_hidden();
    }
    if (D->out.len > (1 << 16)) { flush_out(); }
    if (!pop_pending()) { break; }
  }
  for (int b = 0; jumps && cut != 2 && b < NB_BLOCK; b++) {
    vouch_timer_arm(ALARM_SECONDS);
    D->n_prefix = 0;
    run_from(D->state, &D->ev, FORCED, b);
    put_run(b);
  }
  put_s(&D->out, "done ");
  put_l(&D->out, cut);
  put_s(&D->out, "\n");
}

static void initial(void)
{
  restore(D->init_state);
  put_s(&D->out, "I\n");
  D->ev.len = 0;
  D->mode = SCRIPT;
  D->n_prefix = 0;
  D->n_taken = 0;
  D->rec = &D->ev;
  auto_nav_init();
  D->rec = NULL;
  put(&D->out, D->ev.p, D->ev.len);
  capture(D->after);
  hidden_check();
  put_hidden();
  put_s(&D->out, "Z ");
  for (size_t i = 0; i < D->state_len; i++) {
    static const char hex[] = "0123456789abcdef";
    put(&D->out, &hex[D->after[i] >> 4], 1);
    put(&D->out, &hex[D->after[i] & 15], 1);
  }
  put_s(&D->out, "\ndone 0\n");
}

static void put_state(struct buf *b)
{
  put_l(b, nav_block); put_s(b, " "); put_l(b, nav_stage); put_s(b, " ");
  put_l(b, last_block); put_s(b, " "); put_l(b, last_stage); put_s(b, "\n");
}

/* The body of a plain walk: from the initial state, `calls` calls, the trace written out. */
static void walk_body(long calls)
{
  restore(D->init_state);
  D->mode = SCRIPT;
  D->n_taken = 0;
  D->ev.len = 0;
  D->rec = &D->ev;
  put_s(&D->ev, "init\n");
  auto_nav_init();
  for (long i = 1; i <= calls; i++) {
    put_s(&D->ev, "step "); put_l(&D->ev, i); put_s(&D->ev, "\n");
    auto_nav();
    put_s(&D->ev, "S ");
    put_state(&D->ev);
  }
  D->rec = NULL;
  write_all(D->ev.p, D->ev.len);
}

static void walk(long calls)
{
  int st = vouch_isolated(walk_body, calls);
  if (st < 0) {
    /* ran in this process: leave nothing of it behind */
    restore(D->init_state);
    reset_watched();
    st = 0;
  }
  if (st != 0) {
    put_s(&D->out, "A ");
    put_l(&D->out, st);
    put_s(&D->out, " 0\n");
  }
  put_s(&D->out, "done 0\n");
}

static int parse_hex(const char **p, unsigned char *s)
{
  const char *c = *p;
  while (*c == ' ') { c++; }
  for (size_t i = 0; i < D->state_len; i++) {
    int v = 0;
    for (int k = 0; k < 2; k++, c++) {
      int d = *c >= 'a' ? *c - 'a' + 10 : *c - '0';
      if (d < 0 || d > 15) { return 0; }
      v = v * 16 + d;
    }
    s[i] = (unsigned char)v;
  }
  *p = c;
  return 1;
}

/* The comparison constants as this build reads them: the bytes of each double, lowest first. */
static void constants(void)
{
  static const char hex[] = "0123456789abcdef";
  for (size_t i = 1; i <= VOUCH_N_CONSTS; i++) {
    unsigned char b[sizeof(double)];
    memcpy(b, &vouch_consts[i], sizeof b);
    put_s(&D->out, "F ");
    for (size_t k = 0; k < sizeof b; k++) {
      put(&D->out, &hex[b[k] >> 4], 1);
      put(&D->out, &hex[b[k] & 15], 1);
    }
    put_s(&D->out, "\n");
  }
  put_s(&D->out, "done 0\n");
}

static void request(const char *line)
{
  char *end;
  const char *p = line + 1;
  if (line[0] == 'I') { initial(); return; }
  if (line[0] == 'F') { constants(); return; }
  if (line[0] == 'K') {
    /* K <join> <mask> <bytes> <n> then n × (variable id, block, init stage, loop-back
     * stage) */
    D->join = (int)strtol(p, &end, 10);
    D->mask = (int)strtol(end, &end, 10);
    D->join_bytes = (size_t)strtol(end, &end, 10);
    long n = strtol(end, &end, 10);
    D->n_loops = 0;
    D->loops = grow(D->loops, (size_t)(n > 0 ? n : 1) * 4 * sizeof(long));
    for (long i = 0; i < n; i++) {
      for (int k = 0; k < 4; k++) { D->loops[4 * i + k] = strtol(end, &end, 10); }
      D->n_loops++;
    }
    put_s(&D->out, "done 0\n");
    return;
  }
  if (line[0] == 'X') {
    int jumps = (int)strtol(p, &end, 10);
    p = end;
    if (!parse_hex(&p, D->state)) { put_s(&D->out, "done 0\n"); return; }
    long n = strtol(p, &end, 10);
    p = end;
    D->first_stoppable = (size_t)strtol(p, &end, 10);
    p = end;
    D->n_copies = 0;
    if (n > 0 && (size_t)n > D->cap_copies) {
      D->cap_copies = (size_t)n;
      D->copies = grow(D->copies, D->cap_copies * (D->state_len ? D->state_len : 1));
    }
    for (long i = 0; i < n; i++) {
      if (!parse_hex(&p, D->copies + (size_t)i * D->state_len)) { break; }
      D->n_copies++;
    }
    vouch_timer_arm(ALARM_SECONDS);
    explore(jumps);
    vouch_timer_arm(0);
    return;
  }
  if (line[0] == 'W') {
    long calls = strtol(p, &end, 10);
    long n = strtol(end, &end, 10);
    D->n_prefix = 0;
    reserve_answers(n > 0 ? (size_t)n : 0);
    for (long i = 0; i < n; i++) {
      D->prefix[D->n_prefix++] = strtol(end, &end, 10);
    }
    walk(calls);
  }
}

static void set_limits(long budget, long limit, long lo, long hi)
{
  D->leaf_budget = budget;
  D->question_limit = limit;
  D->value_lo = lo;
  D->value_hi = hi;
  if (D->question_limit < 1 || D->question_limit > 1 << 20) { D->question_limit = 4096; }
  D->cap_answers = (size_t)D->question_limit + 1 > 1 << 16 ? (size_t)D->question_limit + 1 : 1 << 16;
  D->prefix = grow(D->prefix, D->cap_answers * sizeof(long));
  D->taken = grow(D->taken, D->cap_answers * sizeof(long));
}

int main(int argc, char **argv)
{
  D = calloc(1, sizeof *D);
  if (D == NULL) { return 4; }
  D->jumping = -1;
  collect_vars();
  capture(D->init_state);
  if (argc > 4) {
    set_limits(strtol(argv[1], NULL, 10), strtol(argv[2], NULL, 10),
               strtol(argv[3], NULL, 10), strtol(argv[4], NULL, 10));
  } else {
    /* no arguments (the target): the limits are the first request */
    if (!next_line(&D->in) || D->in.line[0] != 'L') { return 4; }
    char *p = D->in.line + 1, *e;
    long v[4];
    for (int i = 0; i < 4; i++) { v[i] = strtol(p, &e, 10); p = e; }
    set_limits(v[0], v[1], v[2], v[3]);
    consume_line(&D->in);
  }
  vouch_platform_init(on_crash);
  /* the variable table: id and size of every registered variable */
  put_s(&D->out, "vars ");
  put_l(&D->out, (long)D->n_vars);
  for (size_t i = 0; i < D->n_vars; i++) {
    put_s(&D->out, " ");
    put_l(&D->out, D->vars[i] ? (long)D->vars[i]->size : 0);
  }
  put_s(&D->out, "\nwatch ");
  watch_segment();
  put_l(&D->out, D->watching ? (long)(D->hi - D->lo) : -1);
  put_s(&D->out, "\n");
  flush_out();
  while (next_line(&D->in)) {
    request(D->in.line);
    consume_line(&D->in);
    flush_out();
  }
  return 0;
}
