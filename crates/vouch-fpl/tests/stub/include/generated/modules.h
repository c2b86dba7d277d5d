/* vouch stub runtime: the generated module list is empty in tests. */
#ifndef VOUCH_STUB_MODULES_H
#define VOUCH_STUB_MODULES_H
#endif
