/* SPDX-License-Identifier: MIT */
/*
 * Replays fuzz inputs through the fuzz target's checks without libFuzzer: every file given, and
 * every regular file in every directory given (the regression corpus fuzz/corpus/). A contract
 * violation aborts (nonzero exit); the sanitizers, when built in, catch the rest.
 * Prints "N passed, 0 failed" at the end.
 */
/* 64-bit inode numbers: else readdir fails with EOVERFLOW on 32-bit targets (armhf under qemu). */
#define _FILE_OFFSET_BITS 64
#define _POSIX_C_SOURCE 200809L
#include <dirent.h>
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static int n_files;

static int run_file(const char *path)
{
    FILE *f = fopen(path, "rb");
    uint8_t *buf;
    long len;

    if (!f) {
        perror(path);
        return 1;
    }
    if (fseek(f, 0, SEEK_END) != 0 || (len = ftell(f)) < 0 || fseek(f, 0, SEEK_SET) != 0) {
        fclose(f);
        perror(path);
        return 1;
    }
    buf = (uint8_t *)malloc(len ? (size_t)len : 1);
    if (!buf || fread(buf, 1, (size_t)len, f) != (size_t)len) {
        fclose(f);
        free(buf);
        fprintf(stderr, "%s: read error\n", path);
        return 1;
    }
    fclose(f);
    LLVMFuzzerTestOneInput(buf, (size_t)len);
    free(buf);
    ++n_files;
    return 0;
}

int main(int argc, char **argv)
{
    int i, bad = 0;

    for (i = 1; i < argc; ++i) {
        struct stat st;
        if (stat(argv[i], &st) != 0) {
            perror(argv[i]);
            bad = 1;
        } else if (S_ISDIR(st.st_mode)) {
            DIR *d = opendir(argv[i]);
            struct dirent *e;
            if (!d) {
                perror(argv[i]);
                bad = 1;
                continue;
            }
            errno = 0;
            while ((e = readdir(d)) != NULL) {
                char path[4096];
                struct stat fst;
                if (e->d_name[0] == '.')
                    continue;
                snprintf(path, sizeof path, "%s/%s", argv[i], e->d_name);
                if (stat(path, &fst) == 0 && S_ISREG(fst.st_mode))
                    bad |= run_file(path);
                errno = 0;
            }
            if (errno != 0) {
                perror(argv[i]);
                bad = 1;
            }
            closedir(d);
        } else {
            bad |= run_file(argv[i]);
        }
    }
    /* the empty input (the default scenario) always runs */
    LLVMFuzzerTestOneInput((const uint8_t *)"", 0);
    ++n_files;
    printf("replay: %d passed, %d failed\n", n_files, bad);
    return bad;
}
