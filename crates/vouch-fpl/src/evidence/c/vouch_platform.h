/*
 * vouch translation-validation driver: what the portable driver (explore_driver.c) needs from
 * the platform it runs on. host_rt.c implements it with POSIX (signals, alarm, fork,
 * /proc/self/maps); target_rt.c on a bare Cortex-M core under an emulator (fault handlers,
 * SysTick, linker symbols; I/O is newlib's semihosting).
 */
#ifndef VOUCH_PLATFORM_H
#define VOUCH_PLATFORM_H

/* Crash and time-out handlers call on_crash(status): 128 + signal on the host; on the target
 * 139 for a fault and 142 for a time-out (the numbers of SIGSEGV and SIGALRM on the host). */
void vouch_platform_init(void (*on_crash)(int status));
/* A time limit for the request in progress (0: none). */
void vouch_timer_arm(int seconds);
/* The program's static storage whose changes the driver watches; 0 when unknown. */
int vouch_watch_range(char **lo, char **hi);
/* Runs body(arg) apart from the server's state when the platform can (host: a child process)
 * and returns its status (0, or 128 + signal); -1 when it ran in this process. */
int vouch_isolated(void (*body)(long), long arg);
/* Ends the program. */
void vouch_exit(int status) __attribute__((noreturn));

#ifndef VOUCH_ALARM_SECONDS
#define VOUCH_ALARM_SECONDS 20
#endif

#endif
