/* touch_probe.c -- how long this machine takes to hand a process fresh memory.
 *
 *   touch_probe [MIB [huge|small]]      (default 1024 huge)
 *
 * Allocates MIB MiB on 2 MiB boundaries with huge pages asked for (`huge`, as gigatet's big
 * arrays are by default: src/base/hugepages.c) or refused (`small`: MADV_NOHUGEPAGE, as with
 * GTET_HUGEPAGES=off), writes one byte per 4 KiB page, then does it again, and prints
 *   "first_touch_s_per_gib X second_touch_s_per_gib Y"
 * The first pass is what a run pays for every new page it writes: the kernel's zeroing, and in
 * a virtual machine whose host takes freed memory back (free page reporting) the host's fault
 * as well; the second pass is the memory's speed once it is mapped.  bench/scale.sh runs it
 * before each measured run, so that a slow run can be told from a slow host (NOTES.md,
 * issue 19). */
#define _GNU_SOURCE
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static double touch(volatile char *p, size_t n, char value)
{
    const double t0 = now();
    for (size_t i = 0; i < n; i += 4096) p[i] = value;
    return now() - t0;
}

int main(int argc, char **argv)
{
    const long mib = argc > 1 ? strtol(argv[1], NULL, 10) : 1024;
    if (mib <= 0 || mib > (1L << 20)) {
        fprintf(stderr, "touch_probe: MIB must be 1..1048576, not '%s'\n", argc > 1 ? argv[1] : "");
        return 2;
    }
    const char *mode = argc > 2 ? argv[2] : "huge";
    if (strcmp(mode, "huge") != 0 && strcmp(mode, "small") != 0) {
        fprintf(stderr, "touch_probe: the mode must be huge or small, not '%s'\n", mode);
        return 2;
    }
    const size_t n = (size_t)mib << 20;
    char *p = aligned_alloc((size_t)1 << 21, n);
    if (!p) {
        fprintf(stderr, "touch_probe: cannot allocate %ld MiB\n", mib);
        return 4;
    }
    madvise(p, n, strcmp(mode, "huge") == 0 ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
    const double gib = (double)mib / 1024.0;
    const double first = touch(p, n, 1), second = touch(p, n, 2);
    printf("first_touch_s_per_gib %.3f second_touch_s_per_gib %.3f\n", first / gib, second / gib);
    free(p);
    return 0;
}
