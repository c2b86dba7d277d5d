/*
 * vouch translation-validation driver, target platform: a bare Cortex-M core (M4/M7, as on
 * Paparazzi's STM32 autopilots) run by an emulator with semihosting. newlib's rdimon start-up
 * code and system calls carry the standard input and output of the driver over semihosting;
 * this file supplies what a bare core lacks: the vector table and reset (FPU enabled, then
 * newlib's _start), fault handlers that report a crash, a SysTick time limit, and the extent
 * of the program's static storage from the linker script (target.ld), which keeps the C
 * library's own data apart so that only the program's variables are watched.
 *
 * Its own mutable state (the tick count) lies outside the watched storage (target.ld).
 */
#include <stdint.h>
#include <stdlib.h>
#include <unistd.h>
#include "vouch_platform.h"

extern void _start(void);
extern void _exit(int status) __attribute__((noreturn));
extern uint32_t __stack_top;
extern char __vouch_watch_start[], __vouch_watch_end[];

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)
/* SysTick from the processor clock (25 MHz on the MPS2 boards): one tick per 10 ms */
#define TICKS_PER_SECOND 100u
#define CPU_HZ 25000000u

/* in .vouch_rt (target.ld): not part of the watched storage */
static void (*crash_handler)(int) __attribute__((section(".vouch_rt")));
static volatile uint32_t ticks_left __attribute__((section(".vouch_rt")));

void vouch_reset(void);
void vouch_fault(void);
void vouch_systick(void);

void vouch_reset(void)
{
  /* coprocessors 10 and 11 (the FPU): full access, before any floating-point instruction */
  SCB_CPACR |= 0xFu << 20;
  __asm volatile ("dsb\n\tisb" ::: "memory");
  _start();
  for (;;) { }
}

void vouch_fault(void)
{
  if (crash_handler != 0) { crash_handler(139); }
  _exit(139);
}

void vouch_systick(void)
{
  if (ticks_left > 0 && --ticks_left == 0 && crash_handler != 0) {
    SYST_CSR = 0;
    crash_handler(142);
  }
}

__attribute__((section(".vectors"), used))
void (*const vouch_vectors[16])(void) = {
  (void (*)(void))&__stack_top, vouch_reset,
  vouch_fault, /* NMI */ vouch_fault, /* HardFault */ vouch_fault, /* MemManage */
  vouch_fault, /* BusFault */ vouch_fault, /* UsageFault */
  0, 0, 0, 0, vouch_fault, /* SVCall */ vouch_fault, /* DebugMonitor */ 0,
  vouch_fault, /* PendSV */ vouch_systick,
};

void vouch_platform_init(void (*on_crash)(int status)) { crash_handler = on_crash; }

void vouch_timer_arm(int seconds)
{
  SYST_CSR = 0;
  if (seconds <= 0) { ticks_left = 0; return; }
  ticks_left = (uint32_t)seconds * TICKS_PER_SECOND;
  SYST_RVR = CPU_HZ / TICKS_PER_SECOND - 1u;
  SYST_CVR = 0;
  SYST_CSR = 7u; /* enable, interrupt, processor clock */
}

int vouch_watch_range(char **lo, char **hi)
{
  *lo = __vouch_watch_start;
  *hi = __vouch_watch_end;
  return 1;
}

int vouch_isolated(void (*body)(long), long arg)
{
  body(arg);
  return -1;
}

void vouch_exit(int status) { _exit(status); }
