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
 * On this project's test machine (a PVM guest) a fault of a 4 KiB page costs ~20 us whether or
 * not the memory was just freed, while a 2 MiB page freed by one array and faulted by the next
 * within a second costs ~0.1 s a GiB instead of 2.5-3.5: big arrays belong on huge pages from
 * their first byte (base_alloc_huge), and base_populate maps an array's pages right after
 * others were freed (NOTES.md E110, E111).
 */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include "base.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#define BASE_HUGE_PAGE ((uintptr_t)2 << 20)

/* GTET_HUGEPAGES=off (or 0) in the environment: big arrays are advised MADV_NOHUGEPAGE
 * instead, for hosts where a fresh huge page costs more than the TLB misses it saves (a virtual
 * machine that hands its free 2 MiB blocks back to its host makes every huge page it faults
 * afresh cost a host fault; 4 KiB pages come first from smaller free blocks, which it keeps).
 * Which choice is faster is a property of the machine: NOTES.md Q26, E162.  Read at each call
 * (a few a run): no state. */
static int hugepages_off(void)
{
    const char *e = getenv("GTET_HUGEPAGES");
    return e && (strcmp(e, "off") == 0 || strcmp(e, "0") == 0);
}

void base_hugepages(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < 2 * BASE_HUGE_PAGE) return;
    const uintptr_t a = ((uintptr_t)p + BASE_HUGE_PAGE - 1) & ~(BASE_HUGE_PAGE - 1);
    const uintptr_t e = ((uintptr_t)p + bytes) & ~(BASE_HUGE_PAGE - 1);
    if (e > a)
        (void)madvise((void *)a, (size_t)(e - a), hugepages_off() ? MADV_NOHUGEPAGE : MADV_HUGEPAGE);
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
