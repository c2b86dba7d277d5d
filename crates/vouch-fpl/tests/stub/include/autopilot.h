/* vouch stub runtime: the flight-plan runtime contract lives in fp_stub.h. */
#ifndef VOUCH_STUB_AUTOPILOT_H
#define VOUCH_STUB_AUTOPILOT_H
#include "fp_stub.h"
#endif
