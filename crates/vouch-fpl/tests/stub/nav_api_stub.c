/* vouch stub runtime: no-op navigation API for compiling drop-in headers (see nav_api_stub.h). */
#include "fp_stub.h"
#include "nav_api_stub.h"
#include "flight_plan.h"

struct stub_point waypoints[NB_WAYPOINT];

bool NavApproaching(uint8_t wp, float t) { (void)wp; (void)t; return false; }
bool NavApproachingFrom(uint8_t wp, uint8_t from, float t) { (void)wp; (void)from; (void)t; return false; }
void NavSetMaxSpeed(float s) { (void)s; }
void NavGotoWaypoint(uint8_t wp) { (void)wp; }
void NavSegment(uint8_t from, uint8_t to) { (void)from; (void)to; }
void NavGlide(uint8_t from, uint8_t to) { (void)from; (void)to; }
void NavCircleWaypoint(uint8_t wp, float radius) { (void)wp; (void)radius; }
void NavHeading(float course) { (void)course; }
void NavAttitude(float roll) { (void)roll; }
void NavVerticalAutoThrottleMode(float pitch) { (void)pitch; }
void NavVerticalAutoPitchMode(float throttle) { (void)throttle; }
void NavVerticalAltitudeMode(float alt, float pre_climb) { (void)alt; (void)pre_climb; }
void NavVerticalClimbMode(float climb) { (void)climb; }
void NavVerticalThrottleMode(float throttle) { (void)throttle; }
void NavSurveyRectangleInit(uint8_t wp1, uint8_t wp2, float grid, int orientation) { (void)wp1; (void)wp2; (void)grid; (void)orientation; }
void NavSurveyRectangle(uint8_t wp1, uint8_t wp2) { (void)wp1; (void)wp2; }
void nav_eight_init(void) {}
void Eight(uint8_t center, uint8_t turn_around, float radius) { (void)center; (void)turn_around; (void)radius; }
void nav_oval_init(void) {}
void Oval(uint8_t p1, uint8_t p2, float radius) { (void)p1; (void)p2; (void)radius; }
void nav_home(void) {}
void nav_goto3d(float radius) { (void)radius; }
