/* vouch stub: runs a *drop-in* header (no instrumentation) a few calls, with the stub runtime,
 * the no-op navigation API and the module environment of paparazzi_env.h. */
#include <stdio.h>
#include "fp_stub.h"
#include "nav_api_stub.h"
#include "paparazzi_env.h"
#define NAV_C
#include "flight_plan.h"

int main(void)
{
  int i;
  auto_nav_init();
  for (i = 0; i < 5; i++) { auto_nav(); }
  printf("%u %u\n", (unsigned)nav_block, (unsigned)nav_stage);
  /* The runtime clamps block changes to the plan: anything else is a broken header. */
  return nav_block < NB_BLOCK ? 0 : 1;
}
