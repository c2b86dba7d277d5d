/* vouch stub: runs the *drop-in* demo header (examples/fpl/demo.xml) for a few calls. */
#include <stdio.h>
#include "fp_stub.h"
#include "nav_api_stub.h"
#include "demo_env.h"
#define NAV_C
#include "flight_plan.h"

float nav_radius = 80.f;
struct stub_autopilot autopilot;
float GetPosAlt(void) { return 200.f; }
float GetAltRef(void) { return 150.f; }
float GetPosX(void) { return 0.f; }
float GetPosY(void) { return 0.f; }
bool GpsFixValid(void) { return true; }
int NavCircleCount(void) { return 0; }

int main(void)
{
  int i;
  auto_nav_init();
  for (i = 0; i < 10; i++) { auto_nav(); }
  printf("%u %u\n", (unsigned)nav_block, (unsigned)nav_stage);
  return 0;
}
