/* mpi_pages.c -- a dead array's written pages moved under an array about to be written for the
 * first time (NOTES.md E221).  A page a process writes for the first time costs a fault, its
 * zeroing and, on a guest that hands its free memory back to the host, a host fault (Q14); a
 * page moved by mremap keeps its frame and costs a page-table update.  The output step widens
 * the local mesh's rows into their blocks' untouched room (mpi_output.c): the pages of the
 * arrays it no longer needs can be that room instead of fresh ones. */
#define _GNU_SOURCE /* mremap, MREMAP_FIXED */
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

#include "mpi/mpi_internal.h"

#if defined(__linux__) && defined(MREMAP_FIXED)
/* the whole pages inside [p, p + bytes): first page address and count (0: none) */
static size_t inner_pages(const void *p, size_t bytes, uintptr_t pg, uintptr_t *first)
{
    uintptr_t a = ((uintptr_t)p + pg - 1) & ~(pg - 1), e = ((uintptr_t)p + bytes) & ~(pg - 1);
    *first = a;
    return p && bytes && e > a ? (size_t)((e - a) / pg) : 0;
}

/* move n pages from src to dst (both page-aligned, each range wholly the caller's), then map
 * fresh zero pages at src: 0, or -1 when nothing could be moved (both ranges then mapped, src's
 * contents kept, dst's contents undefined) */
static int move_run(uintptr_t src, uintptr_t dst, size_t bytes)
{
    void *r = mremap((void *)src, bytes, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, (void *)dst);
    if (r == MAP_FAILED) {
        /* the kernel may have unmapped dst before failing: map it again (its contents are
         * the caller's to overwrite) */
        mmap((void *)dst, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED,
             -1, 0);
        return -1;
    }
    if (mmap((void *)src, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED,
             -1, 0) == MAP_FAILED) {
        /* src must stay mapped (its block goes back to the allocator): the pages go back */
        if (mremap((void *)dst, bytes, bytes, MREMAP_MAYMOVE | MREMAP_FIXED, (void *)src) ==
            MAP_FAILED)
            return -2;
        mmap((void *)dst, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS | MAP_FIXED,
             -1, 0);
        return -1;
    }
    return 0;
}
#endif

long mx_pages_move(void *from, size_t fbytes, void *to, size_t tbytes)
{
#if defined(__linux__) && defined(MREMAP_FIXED)
    long sz = sysconf(_SC_PAGESIZE);
    if (sz <= 0 || (sz & (sz - 1))) return 0;
    const uintptr_t pg = (uintptr_t)sz;
    uintptr_t fa, ta;
    size_t nf = inner_pages(from, fbytes, pg, &fa), nt = inner_pages(to, tbytes, pg, &ta);
    if (!nf || !nt) return 0;
    unsigned char *vf = malloc(nf), *vt = malloc(nt);
    long moved = 0;
    if (!vf || !vt || mincore((void *)fa, nf * pg, vf) != 0 ||
        mincore((void *)ta, nt * pg, vt) != 0)
        goto done;
    for (size_t i = 0, j = 0;;) {
        while (i < nf && !(vf[i] & 1)) i++;   /* the next written page of `from` */
        while (j < nt && (vt[j] & 1)) j++;    /* the next page of `to` never written */
        if (i >= nf || j >= nt) break;
        size_t k = 1;
        while (i + k < nf && j + k < nt && (vf[i + k] & 1) && !(vt[j + k] & 1)) k++;
        int r = move_run(fa + i * pg, ta + j * pg, k * pg);
        if (r == -2) moved = -1;
        if (r != 0) break;
        moved += (long)k;
        i += k;
        j += k;
    }
done:
    free(vf);
    free(vt);
    return moved;
#else
    (void)from;
    (void)fbytes;
    (void)to;
    (void)tbytes;
    return 0;
#endif
}
