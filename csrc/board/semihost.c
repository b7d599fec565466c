/* SPDX-License-Identifier: MIT */
/*
 * Arm semihosting calls (Arm "Semihosting for AArch32 and AArch64", version 2): the operation in
 * r0, its argument in r1, then BKPT 0xAB on M-profile cores. Without a debugger or an emulator
 * listening, BKPT faults: these calls are for the emulator and the bench, not for production.
 */
#include "semihost.h"

enum {
    SYS_WRITE0 = 0x04,
    SYS_EXIT = 0x18,
    ADP_STOPPED_APPLICATION_EXIT = 0x20026,
    ADP_STOPPED_RUN_TIME_ERROR = 0x20023
};

static int semihost_call(int op, const void *arg)
{
    register int r0 __asm__("r0") = op;
    register const void *r1 __asm__("r1") = arg;
    __asm__ volatile("bkpt 0xab" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

void semihost_write(const char *s)
{
    (void)semihost_call(SYS_WRITE0, s);
}

void semihost_exit(int status)
{
    /* On AArch32, SYS_EXIT takes the reason code itself (not a pointer to a block). */
    (void)semihost_call(SYS_EXIT, (const void *)(status == 0 ? ADP_STOPPED_APPLICATION_EXIT
                                                             : ADP_STOPPED_RUN_TIME_ERROR));
    for (;;) {
    }
}
