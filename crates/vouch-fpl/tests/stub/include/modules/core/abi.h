/* vouch stub runtime: ABI event type; bindings are exercised as trace events. */
#ifndef VOUCH_STUB_ABI_H
#define VOUCH_STUB_ABI_H
/* Variables of this type may stay unused: in the instrumented header the AbiBindMsg call that
 * uses them is a recorded string (GCC's type attribute `unused`). */
typedef struct { int unused; } __attribute__((unused)) abi_event;
#endif
