/* vouch stub runtime: ABI event type; bindings are exercised as trace events. */
#ifndef VOUCH_STUB_ABI_H
#define VOUCH_STUB_ABI_H
typedef struct { int unused; } abi_event;
#endif
