/* vouch stub runtime: stand-in for Paparazzi's std.h (only what generated headers use). */
#ifndef VOUCH_STUB_STD_H
#define VOUCH_STUB_STD_H
#include <stdint.h>
#include <stdbool.h>
#include <math.h>
#ifndef TRUE
#define TRUE true
#endif
#ifndef FALSE
#define FALSE false
#endif
/* GCC >= 7 understands the statement attribute; the generated NextStage() relies on it. */
#if defined(__GNUC__) && __GNUC__ >= 7
#define INTENTIONAL_FALLTHRU __attribute__((fallthrough));
#else
#define INTENTIONAL_FALLTHRU
#endif
#endif
