/*
 * vouch stub driver: runs a generated (instrumented) flight_plan.h step by step.
 * usage: driver ANSWERS_FILE STEPS [JUMPS_FILE]
 * JUMPS_FILE holds "call block" pairs: an operator block change (nav_goto_block, as the ground
 * station does) applied just before that call (several for one call in their order); printed as
 * "goto B" followed by its hook events.
 * Prints "init", the events of auto_nav_init(), then for each call "step N", its events and
 * "S block stage last_block last_stage". The Rust interpreter prints the same format.
 */
#include <stdio.h>
#include <stdlib.h>
#include "fp_stub.h"
#define NAV_C
#include "flight_plan.h"

void stub_oracle_load(const char *path, FILE *out);
int stub_table_sizes_ok(void);

int main(int argc, char **argv)
{
  long steps, i;
  long jump_call[1024], jump_block[1024];
  size_t n_jumps = 0, j;
  if (argc != 3 && argc != 4) { fprintf(stderr, "usage: %s ANSWERS STEPS [JUMPS]\n", argv[0]); return 2; }
  if (argc == 4) {
    FILE *f = fopen(argv[3], "r");
    if (f == NULL) { fprintf(stderr, "cannot read %s\n", argv[3]); return 2; }
    while (n_jumps < 1024 && fscanf(f, "%ld %ld", &jump_call[n_jumps], &jump_block[n_jumps]) == 2) { n_jumps++; }
    fclose(f);
  }
  steps = strtol(argv[2], NULL, 10);
  stub_oracle_load(argv[1], stdout);
  if (!stub_table_sizes_ok()) { fprintf(stderr, "waypoint/block tables have wrong sizes\n"); return 3; }
  /* initial state of common_flight_plan_init(): everything 0, no hooks */
  nav_block = 0; nav_stage = 0; last_block = 0; last_stage = 0;
  printf("init\n");
  auto_nav_init();
  for (i = 1; i <= steps; i++) {
    for (j = 0; j < n_jumps; j++) {
      if (jump_call[j] == i) {
        printf("goto %ld\n", jump_block[j]);
        nav_goto_block((uint8_t)jump_block[j]);
      }
    }
    printf("step %ld\n", i);
    auto_nav();
    printf("S %u %u %u %u\n", (unsigned)nav_block, (unsigned)nav_stage, (unsigned)last_block,
           (unsigned)last_stage);
  }
  return 0;
}
