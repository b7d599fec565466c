/* SPDX-License-Identifier: MIT */
/*
 * Startup for a Cortex-M4F without an OS: the vector table, the reset handler (FPU on, .data
 * copied from flash, .bss zeroed, then main) and a fault handler that reports over semihosting.
 * No interrupts are used. This file and mps2_an386.ld are what a real board replaces with its
 * vendor's (CMSIS) startup code; the core itself needs nothing from here but a stack and the FPU.
 */
#include <stdint.h>
#include "semihost.h"

extern uint32_t __data_start[], __data_end[], __data_load[], __bss_start[], __bss_end[];
extern uint32_t __stack_top[];
int main(void);

void board_reset(void) __attribute__((noreturn));
static void board_fault(void) __attribute__((noreturn));

/* System Control Block: CPACR grants the FPU (coprocessors 10 and 11) full access. */
#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)

void board_reset(void)
{
    uint32_t *dst;
    const uint32_t *src;

    /* Before any floating-point instruction: the core is built with -mfloat-abi=hard. */
    SCB_CPACR |= (3u << 20) | (3u << 22);
    __asm__ volatile("dsb\n\tisb" ::: "memory");
    for (src = __data_load, dst = __data_start; dst < __data_end;)
        *dst++ = *src++;
    for (dst = __bss_start; dst < __bss_end;)
        *dst++ = 0;
    semihost_exit(main());
}

static void board_fault(void)
{
    semihost_write("fault: the CPU took an exception\n");
    semihost_exit(1);
}

/* The 16 system exceptions of ARMv7-M (no device interrupts are enabled). */
__attribute__((section(".vectors"), used)) static void (*const vectors[16])(void) = {
    (void (*)(void))(uintptr_t)__stack_top, /* initial main stack pointer */
    board_reset,
    board_fault, /* NMI */
    board_fault, /* HardFault */
    board_fault, /* MemManage */
    board_fault, /* BusFault */
    board_fault, /* UsageFault */
    0, 0, 0, 0,
    board_fault, /* SVCall */
    board_fault, /* DebugMonitor */
    0,
    board_fault, /* PendSV */
    board_fault, /* SysTick */
};
