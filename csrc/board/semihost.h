/* SPDX-License-Identifier: MIT */
/*
 * Arm semihosting: the board's only output channel (QEMU: -semihosting-config enable=on; on a
 * real board a debug probe with semihosting enabled, or replace these two functions with a UART).
 */
#ifndef BOARD_SEMIHOST_H
#define BOARD_SEMIHOST_H

/* Writes a NUL-terminated string to the host's console. */
void semihost_write(const char *s);

/* Ends the program: status 0 -> the emulator exits 0, anything else -> it exits 1. */
void semihost_exit(int status) __attribute__((noreturn));

#endif
