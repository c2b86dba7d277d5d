/* vouch stub: the user functions and variables that examples/fpl/demo.xml names. */
#ifndef VOUCH_DEMO_ENV_H
#define VOUCH_DEMO_ENV_H
#include "std.h"
float GetPosAlt(void);
float GetAltRef(void);
float GetPosX(void);
float GetPosY(void);
bool GpsFixValid(void);
int NavCircleCount(void);
extern float nav_radius;
struct stub_autopilot { int kill_throttle; };
extern struct stub_autopilot autopilot;
#endif
