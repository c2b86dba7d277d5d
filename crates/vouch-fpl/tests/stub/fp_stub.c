/*
 * vouch stub runtime: state, block/stage changes and the scripted oracle (see fp_stub.h).
 * Compiled together with a generated header (included here without NAV_C, as upstream's
 * common_flight_plan.c does) and driver.c (which includes it with NAV_C).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <errno.h>
#include "fp_stub.h"
#include "flight_plan.h"

uint8_t nav_block, nav_stage, last_block, last_stage, last_wp;
uint16_t stage_time, block_time;

/* The waypoint tables must be valid C initialisers: using them here checks them. */
struct stub_lla { int32_t lat, lon, alt; };
static const float stub_wp_utm[][3] = WAYPOINTS_UTM
static const float stub_wp_enu[][3] = WAYPOINTS_ENU
static const struct stub_lla stub_wp_lla[] = WAYPOINTS_LLA
static const struct stub_lla stub_wp_lla_wgs84[] = WAYPOINTS_LLA_WGS84
static const bool stub_wp_global[] = WAYPOINTS_GLOBAL
static const char *const stub_blocks[] = FP_BLOCKS;

float WaypointX(uint8_t wp) { return wp < NB_WAYPOINT ? stub_wp_enu[wp][0] : 0.f; }
float WaypointY(uint8_t wp) { return wp < NB_WAYPOINT ? stub_wp_enu[wp][1] : 0.f; }

/* Keeps the tables referenced (they are checked for syntax and size, not used). */
int stub_table_sizes_ok(void);
int stub_table_sizes_ok(void)
{
  return sizeof(stub_wp_utm) / sizeof(stub_wp_utm[0]) == NB_WAYPOINT
      && sizeof(stub_wp_lla) / sizeof(stub_wp_lla[0]) == NB_WAYPOINT
      && sizeof(stub_wp_lla_wgs84) / sizeof(stub_wp_lla_wgs84[0]) == NB_WAYPOINT
      && sizeof(stub_wp_global) / sizeof(stub_wp_global[0]) == NB_WAYPOINT
      && sizeof(stub_blocks) / sizeof(stub_blocks[0]) == NB_BLOCK;
}

/* ---- runtime (2024-10 semantics) ---- */

/* NB_BLOCK through a variable: with NB_BLOCK == 1 (a plan with only HOME) comparisons of a
 * uint8_t against NB_BLOCK - 1 would be constant and trip -Wtype-limits. */
static int stub_nb_block = NB_BLOCK;

void nav_init_stage(void) { stage_time = 0; }

void set_nav_block(uint8_t b) { nav_block = (int)b >= stub_nb_block ? NB_BLOCK - 1 : b; }
void set_nav_stage(uint8_t s) { nav_stage = s; }

void nav_init_block(void)
{
  if ((int)nav_block >= stub_nb_block) { nav_block = NB_BLOCK - 1; }
  nav_stage = 0;
  block_time = 0;
  nav_init_stage();
  nav_on_enter_block(nav_block);
}

void nav_goto_block(uint8_t b)
{
  if (b != nav_block) {
    /* only a real change is remembered, so GotoBlock(current) keeps the last position */
    last_block = nav_block;
    last_stage = nav_stage;
  }
  nav_on_exit_block(nav_block);
  nav_block = b;
  nav_init_block();
}

void nav_goto_next_block(void)
{
  nav_goto_block((int)nav_block < stub_nb_block - 1 ? (uint8_t)(nav_block + 1) : nav_block);
}

void nav_goto_next_stage(void) { nav_stage++; nav_init_stage(); }

void nav_return(uint8_t reset)
{
  nav_on_exit_block(nav_block);
  nav_block = last_block;
  nav_stage = reset == 1 ? 0 : last_stage;
  block_time = 0;
  nav_init_stage();
  nav_on_enter_block(nav_block);
}

/* ---- scripted oracle and trace ---- */

static long *answers;
static size_t n_answers, next_answer;
static FILE *trace_out;

void stub_oracle_load(const char *path, FILE *out);
void stub_oracle_load(const char *path, FILE *out)
{
  size_t cap = 64;
  long v;
  FILE *f = fopen(path, "r");
  trace_out = out;
  answers = malloc(cap * sizeof(long));
  if (f == NULL || answers == NULL) { fprintf(stderr, "cannot read %s\n", path); exit(2); }
  while (fscanf(f, "%ld", &v) == 1) {
    if (n_answers == cap) {
      cap *= 2;
      answers = realloc(answers, cap * sizeof(long));
      if (answers == NULL) { exit(2); }
    }
    answers[n_answers++] = v;
  }
  fclose(f);
}

/* An exhausted sequence answers 0 (condition false, value 0), like the Rust oracle. */
static long next_number(void) { return next_answer < n_answers ? answers[next_answer++] : 0; }

/* Text is printed with backslash, newline and carriage return escaped: one event per line. */
static void put_text(const char *text)
{
  for (; *text; text++) {
    if (*text == '\\') { fputs("\\\\", trace_out); }
    else if (*text == '\n') { fputs("\\n", trace_out); }
    else if (*text == '\r') { fputs("\\r", trace_out); }
    else { fputc(*text, trace_out); }
  }
  fputc('\n', trace_out);
}

bool fp_cond(const char *text)
{
  bool v = (next_number() & 1) != 0;
  fprintf(trace_out, "C %d ", v ? 1 : 0);
  put_text(text);
  return v;
}

void fp_code(const char *text)
{
  fputs("X ", trace_out);
  put_text(text);
}

bool fp_literal_value(const char *text, long *v)
{
  char *end;
  errno = 0;
  *v = strtol(text, &end, 10);
  return errno == 0 && end != text && *end == '\0' && (text[0] == '-' || (text[0] >= '0' && text[0] <= '9'));
}

long fp_value_of_number(long n)
{
  return n >= 0 ? n / 2 : -((-n) / 2);
}

int fp_value(const char *text)
{
  long v;
  /* a plain decimal literal is its own value; anything else is asked to the oracle */
  if (!fp_literal_value(text, &v)) {
    v = fp_value_of_number(next_number());
  }
  fprintf(trace_out, "V %ld ", v);
  put_text(text);
  return (int)v;
}
