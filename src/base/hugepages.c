/* hugepages.c -- base_hugepages: ask Linux for transparent huge pages on a big array.
 *
 * The kernel's working mesh is read at random (a walk, a cavity's neighbours): with 4 KiB
 * pages nearly every tet visited is a TLB miss, and on a virtual machine each miss walks two
 * page tables.  madvise(MADV_HUGEPAGE) lets the page-fault handler map 2 MiB pages there (in
 * the default THP mode "madvise"); it changes nothing else -- the contents, the addresses and
 * the result are the same, and where the kernel cannot or will not (THP "never", no huge page
 * free), the array simply stays on 4 KiB pages.  Measured in NOTES.md E19.  Only whole 2 MiB
 * pages inside the array are advised, never memory the array does not own.
 *
 * Where a 4 KiB fault is expensive (a guest whose page tables its host shadows), big arrays
 * belong on huge pages from their first byte (base_alloc_huge), and base_populate maps an
 * array's pages right after others were freed, while the freed huge pages are still the
 * guest's (NOTES.md E110, E111).  Where the guest hands its free 2 MiB blocks back to its host
 * and 4 KiB faults are cheap, 4 KiB pages are faster: base_page_mode decides (below).
 */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include "base.h"

#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#if defined(__linux__)
#include <dirent.h>
#include <sys/mman.h>
#include <time.h>
#endif

#define BASE_HUGE_PAGE ((uintptr_t)2 << 20)

/* Which pages the big arrays ask for, decided once a process (base_page_mode):
 *   GTET_HUGEPAGES=on           huge pages (MADV_HUGEPAGE);
 *   GTET_HUGEPAGES=off (or 0)   4 KiB pages (MADV_NOHUGEPAGE);
 *   unset, auto or anything else: 4 KiB pages when the machine is a virtual machine that reports
 *     its free memory to its host (a virtio balloon with free page reporting) and a 4 KiB page
 *     fault is cheap there (measured: below SMALL_FAULT_CHEAP_US); huge pages otherwise.
 * Why both tests: a guest that reports its free 2 MiB blocks to the host makes every huge page
 * it faults afresh a host fault (the block was given back), while 4 KiB pages come first from
 * smaller free blocks, which are never reported; but where a 4 KiB fault itself is slow (a
 * guest whose page tables the host shadows) huge pages still win, by the faults and the TLB
 * misses they save.  On a machine that reports nothing, huge pages cost one zeroing of 2 MiB
 * and save TLB misses: the default.  The choice changes speed only, never the mesh.  The
 * measurements behind it: NOTES.md Q26, E162, E163. */
#define SMALL_FAULT_CHEAP_US 5.0

static _Atomic int page_mode;  /* 0 undecided, else BASE_PAGES_HUGE / BASE_PAGES_SMALL */
static _Atomic int page_auto;  /* page_mode was decided automatically (no GTET_HUGEPAGES) */
static _Atomic int run_huge;   /* the current run touches more than the cheap pool (base_page_run) */
static _Atomic double small_fault_us = -1.0;

#if defined(__linux__)
/* 1 when a virtio balloon offers free page reporting (VIRTIO_BALLOON_F_REPORTING, feature bit
 * 5; sysfs lists a device's features as a string of '0'/'1' from bit 0).  0 when none is seen
 * or sysfs cannot be read. */
static int host_takes_free_pages(void)
{
    DIR *d = opendir("/sys/bus/virtio/devices");
    if (!d) return 0;
    int found = 0;
    struct dirent *e;
    while (!found && (e = readdir(d)) != NULL) {
        if (e->d_name[0] == '.') continue;
        char path[512], id[16] = "", feat[160] = "";
        snprintf(path, sizeof path, "/sys/bus/virtio/devices/%s/device", e->d_name);
        FILE *f = fopen(path, "r");
        if (!f) continue;
        const int ok = fgets(id, sizeof id, f) != NULL;
        fclose(f);
        if (!ok || strtol(id, NULL, 16) != 5) continue;  /* 5: the balloon */
        snprintf(path, sizeof path, "/sys/bus/virtio/devices/%s/features", e->d_name);
        if (!(f = fopen(path, "r"))) continue;
        if (fgets(feat, sizeof feat, f) && strlen(feat) > 5 && feat[5] == '1') found = 1;
        fclose(f);
    }
    closedir(d);
    return found;
}

static double seconds_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The cost of a fresh 4 KiB page fault in microseconds: the fastest of five batches of 256
 * (a batch the scheduler interrupts is slower, never faster).  About 2 ms in all where faults
 * are cheap.  A negative value when memory cannot be mapped. */
static double measure_small_fault_us(void)
{
    const size_t pages = 256, bytes = pages * 4096;
    double best = -1.0;
    for (int r = 0; r < 5; r++) {
        char *p = mmap(NULL, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
        if (p == MAP_FAILED) break;
        (void)madvise(p, bytes, MADV_NOHUGEPAGE);
        const double t0 = seconds_now();
        for (size_t i = 0; i < bytes; i += 4096) ((volatile char *)p)[i] = 1;
        const double us = (seconds_now() - t0) * 1e6 / (double)pages;
        munmap(p, bytes);
        if (best < 0 || us < best) best = us;
    }
    return best;
}

/* The memory a run can fault with 4 KiB pages without the host: the free blocks below the
 * balloon's reporting order (page_reporting_order, 9 unless said otherwise), which were never
 * handed to the host, and the page cache, which the guest reclaims from memory it holds;
 * /proc/buddyinfo and /proc/meminfo (Active(file) + Inactive(file)).  UINT64_MAX when they
 * cannot be read (then nothing is known to be dear). */
static uint64_t cheap_pool_bytes(void)
{
    int order = 9;
    FILE *f = fopen("/sys/module/page_reporting/parameters/page_reporting_order", "r");
    if (f) {
        int o;
        if (fscanf(f, "%d", &o) == 1 && o > 0 && o < 20) order = o;
        fclose(f);
    }
    if (!(f = fopen("/proc/buddyinfo", "r"))) return UINT64_MAX;
    uint64_t pages = 0;
    char line[512];
    while (fgets(line, sizeof line, f)) {
        const char *z = strstr(line, "zone");
        if (!z) continue;
        z += 4;
        while (*z == ' ') z++;
        while (*z && *z != ' ') z++;  /* the zone's name */
        char *end;
        for (int k = 0;; k++) {
            const unsigned long long c = strtoull(z, &end, 10);
            if (end == z) break;
            if (k < order) pages += (uint64_t)c << k;
            z = end;
        }
    }
    fclose(f);
    uint64_t file_kib = 0;
    if ((f = fopen("/proc/meminfo", "r"))) {
        unsigned long long kib;
        while (fgets(line, sizeof line, f))
            if (sscanf(line, "Active(file): %llu kB", &kib) == 1 ||
                sscanf(line, "Inactive(file): %llu kB", &kib) == 1)
                file_kib += kib;
        fclose(f);
    }
    return pages * 4096 + file_kib * 1024;
}
#endif

static int decide_page_mode(void)
{
    const char *e = getenv("GTET_HUGEPAGES");
    if (e && (strcmp(e, "off") == 0 || strcmp(e, "0") == 0)) return BASE_PAGES_SMALL;
    if (e && strcmp(e, "on") == 0) return BASE_PAGES_HUGE;
    page_auto = 1;
#if defined(__linux__)
    if (!host_takes_free_pages()) return BASE_PAGES_HUGE;
    const double us = measure_small_fault_us();
    small_fault_us = us;
    return us >= 0 && us < SMALL_FAULT_CHEAP_US ? BASE_PAGES_SMALL : BASE_PAGES_HUGE;
#else
    return BASE_PAGES_HUGE;
#endif
}

static int process_page_mode(void)
{
    int m = page_mode;
    if (!m) {  /* two threads deciding at once measure twice and agree but for noise: either */
        m = decide_page_mode();  /* answer is a valid choice, and the first stored one stays */
        int expected = 0;
        if (!atomic_compare_exchange_strong(&page_mode, &expected, m)) m = expected;
    }
    return m;
}

int base_page_mode(void)
{
    const int m = process_page_mode();
    return m == BASE_PAGES_SMALL && run_huge ? BASE_PAGES_HUGE : m;
}

/* A run that will touch about peak_bytes: where 4 KiB pages were chosen automatically, they
 * are cheap only while the guest has memory it never gave its host (cheap_pool_bytes); a run
 * that needs more faults memory fresh from the host with either page size, and then huge
 * pages fault 512 times less often and miss the TLB less (NOTES.md Q38, E168).  The choice
 * holds until the next run's call; two runs at once in one process share the last one's (a
 * matter of speed only). */
void base_page_run(size_t peak_bytes)
{
    int huge = 0;
#if defined(__linux__)
    if (process_page_mode() == BASE_PAGES_SMALL && page_auto)
        huge = (uint64_t)peak_bytes > cheap_pool_bytes();
#else
    (void)peak_bytes;
#endif
    run_huge = huge;
}

uint64_t base_page_pool_bytes(void)
{
#if defined(__linux__)
    return cheap_pool_bytes();
#else
    return UINT64_MAX;
#endif
}

double base_small_fault_us(void)
{
    return small_fault_us;
}

void base_page_mode_reset(void)
{
    page_mode = 0;
    page_auto = 0;
    run_huge = 0;
    small_fault_us = -1.0;
}

void base_hugepages(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < 2 * BASE_HUGE_PAGE) return;
    const uintptr_t a = ((uintptr_t)p + BASE_HUGE_PAGE - 1) & ~(BASE_HUGE_PAGE - 1);
    const uintptr_t e = ((uintptr_t)p + bytes) & ~(BASE_HUGE_PAGE - 1);
    if (e > a)
        (void)madvise((void *)a, (size_t)(e - a),
                      base_page_mode() == BASE_PAGES_SMALL ? MADV_NOHUGEPAGE : MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

void *base_alloc_big(size_t bytes)
{
    return bytes >= BASE_BIG_MIN ? base_alloc_huge(bytes) : malloc(bytes ? bytes : 1);
}

int base_populate(void *p, size_t bytes)
{
#if defined(__linux__)
#ifndef MADV_POPULATE_WRITE
#define MADV_POPULATE_WRITE 23 /* Linux 5.14; an older kernel answers EINVAL: nothing done */
#endif
    const uintptr_t page = 4096;
    const uintptr_t a = ((uintptr_t)p + page - 1) & ~(page - 1);
    const uintptr_t e = ((uintptr_t)p + bytes) & ~(page - 1);
    if (!p || e <= a) return 0;
    return madvise((void *)a, (size_t)(e - a), MADV_POPULATE_WRITE) == 0 ? 0 : -1;
#else
    (void)p;
    (void)bytes;
    return -1;
#endif
}

void *base_alloc_huge(size_t bytes)
{
    if (bytes < 2 * BASE_HUGE_PAGE) return malloc(bytes ? bytes : 1);
    const size_t whole = (bytes + BASE_HUGE_PAGE - 1) & ~(size_t)(BASE_HUGE_PAGE - 1);
    void *p = aligned_alloc(BASE_HUGE_PAGE, whole);  /* C11: size a multiple of the alignment */
    base_hugepages(p, whole);  /* the block owns its last, partly used huge page too */
    return p;
}
