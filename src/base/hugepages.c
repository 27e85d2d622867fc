/* hugepages.c -- base_hugepages: ask Linux for transparent huge pages on a big array.
 *
 * The kernel's working mesh is read at random (a walk, a cavity's neighbours): with 4 KiB
 * pages nearly every tet visited is a TLB miss, and on a virtual machine each miss walks two
 * page tables.  madvise(MADV_HUGEPAGE) lets the page-fault handler map 2 MiB pages there (in
 * the default THP mode "madvise"); it changes nothing else -- the contents, the addresses and
 * the result are the same, and where the kernel cannot or will not (THP "never", no huge page
 * free), the array simply stays on 4 KiB pages.  Measured in NOTES.md E19.  Only whole 2 MiB
 * pages inside the array are advised, never memory the array does not own.
 */
#define _DEFAULT_SOURCE /* madvise, MADV_HUGEPAGE */
#include "base.h"

#include <stdint.h>
#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#endif

#define BASE_HUGE_PAGE ((uintptr_t)2 << 20)

void base_hugepages(void *p, size_t bytes)
{
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    if (!p || bytes < 2 * BASE_HUGE_PAGE) return;
    const uintptr_t a = ((uintptr_t)p + BASE_HUGE_PAGE - 1) & ~(BASE_HUGE_PAGE - 1);
    const uintptr_t e = ((uintptr_t)p + bytes) & ~(BASE_HUGE_PAGE - 1);
    if (e > a) (void)madvise((void *)a, (size_t)(e - a), MADV_HUGEPAGE);
#else
    (void)p;
    (void)bytes;
#endif
}

void *base_alloc_huge(size_t bytes)
{
    if (bytes < 2 * BASE_HUGE_PAGE) return malloc(bytes ? bytes : 1);
    const size_t whole = (bytes + BASE_HUGE_PAGE - 1) & ~(size_t)(BASE_HUGE_PAGE - 1);
    void *p = aligned_alloc(BASE_HUGE_PAGE, whole);  /* C11: size a multiple of the alignment */
    base_hugepages(p, bytes);
    return p;
}
