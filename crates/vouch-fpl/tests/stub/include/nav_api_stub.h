/*
 * vouch stub runtime: the navigation API whose names the generator composes (GENERATOR_FACTS.md
 * section 5: Nav* functions, Height, WaypointAlt, RadOfDeg, CARROT, ...), declared with the
 * argument shapes the generated code uses, so that a *drop-in* header compiles as it is.
 * Implemented as no-ops in nav_api_stub.c (the differential test uses the instrumented flavour).
 */
#ifndef VOUCH_NAV_API_STUB_H
#define VOUCH_NAV_API_STUB_H
#include "std.h"

#define CARROT 0.f
#define RadOfDeg(x) ((x) * (3.14159265358979323846 / 180.))
#define Height(h) ((h) + GROUND_ALT)
#define NS 0
#define WE 1
#define Goto3D(r) { nav_goto3d((float)(r)); }

struct stub_point { float x, y, a, z; }; /* z: some plan headers read it */
extern struct stub_point waypoints[];

/* An lvalue, as in Paparazzi (plans assign `WaypointAlt(WP_X) = ...`). */
#define WaypointAlt(wp) (waypoints[wp].a)
bool NavApproaching(uint8_t wp, float t);
bool NavApproachingFrom(uint8_t wp, uint8_t from, float t);
void NavSetMaxSpeed(float s);
void NavGotoWaypoint(uint8_t wp);
void NavSegment(uint8_t from, uint8_t to);
void NavGlide(uint8_t from, uint8_t to);
void NavCircleWaypoint(uint8_t wp, float radius);
void NavHeading(float course);
void NavAttitude(float roll);
void NavVerticalAutoThrottleMode(float pitch);
void NavVerticalAutoPitchMode(float throttle);
void NavVerticalAltitudeMode(float alt, float pre_climb);
void NavVerticalClimbMode(float climb);
void NavVerticalThrottleMode(float throttle);
void NavSurveyRectangleInit(uint8_t wp1, uint8_t wp2, float grid, int orientation);
void NavSurveyRectangle(uint8_t wp1, uint8_t wp2);
void nav_eight_init(void);
void Eight(uint8_t center, uint8_t turn_around, float radius);
void nav_oval_init(void);
void Oval(uint8_t p1, uint8_t p2, float radius);
void nav_home(void);
void nav_goto3d(float radius);
#endif
