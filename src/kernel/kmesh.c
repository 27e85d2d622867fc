/* kmesh.c -- the kernel mesh's storage: the tet arrays, their growth (with the memory guard's
 * second check, NOTES.md E17), and the per-thread insertion contexts.  The insertion itself,
 * which reads and writes these arrays, is in insert.c. */
#include "kmesh.h"

#include "../base/base.h"

#include <stdlib.h>
#include <string.h>

/* The arrays' first capacity, exactly the slots asked for (the memory guard counted them),
 * on 2 MiB boundaries with huge pages asked for (NOTES.md E19): the insertion reads them at
 * random, so with 4 KiB pages nearly every tet it visits is a TLB miss.  Aligned so that the
 * huge pages start at the arrays' first slot; untouched pages stay unmapped either way.  A
 * later growth (km_reserve) is a realloc: a move by mremap to an address that is not 2 MiB
 * aligned splits the huge pages (1M -t 2 peaked at 412 MB RSS instead of 290, NOTES.md Q7),
 * which is why build.c asks, with threads, for the capacity the parallel rounds' reserve
 * will want. */
/* bytes allocated for each of tv and tn with room for `slots` slots (kmesh.wide: twice) */
static size_t array_bytes(const kmesh *m, size_t slots)
{
    const size_t bytes = 4 * slots * sizeof *m->tv;
    return m->wide ? 2 * bytes + 2 * sizeof(uint64_t) : bytes;
}

static gtet_status first_arrays(kmesh *m, size_t slots)
{
    const size_t bytes = array_bytes(m, slots);
    uint32_t *tv = base_alloc_huge(bytes);
    uint32_t *tn = tv ? base_alloc_huge(bytes) : NULL;
    if (!tv || !tn) {
        free(tv);
        return GTET_ERR_OUT_OF_MEMORY;
    }
    m->tv = tv;
    m->tn = tn;
    m->cap = slots;
    return GTET_OK;
}

gtet_status km_reserve(kmesh *m, size_t slots)
{
    if (slots <= m->cap) return GTET_OK;
    if (slots > KM_MAX_SLOTS) return GTET_ERR_TOO_LARGE;
    if (!m->cap) return first_arrays(m, slots);
    size_t cap = m->cap;
    while (cap < slots) cap += cap / 2 + 64;
    if (cap > KM_MAX_SLOTS) cap = KM_MAX_SLOTS;
    if (m->grow_guard) {  /* beyond the first capacity, which the first guard counted */
        const size_t slot = 8 * sizeof *m->tv;
        size_t want = cap * slot;
        gtet_status s = m->grow_guard(m->grow_user, m->nt * slot, m->cap * slot, slots * slot,
                                      &want);
        if (s != GTET_OK) return s;
        if (want / slot < cap) cap = want / slot < slots ? slots : want / slot;
    }
    uint32_t *tv = realloc(m->tv, array_bytes(m, cap));
    if (!tv) return GTET_ERR_OUT_OF_MEMORY;
    m->tv = tv;
    uint32_t *tn = realloc(m->tn, array_bytes(m, cap));
    if (!tn) return GTET_ERR_OUT_OF_MEMORY;
    m->tn = tn;
    m->cap = cap;
    return GTET_OK;
}

gtet_status km_init(kmesh *m, const double *v, size_t nv, size_t slots_hint, int threads,
                    int wide)
{
    memset(m, 0, sizeof *m);
    m->wide = wide;
    m->v = v;
    m->nv = nv;
    pred_static_init_mt(v, 3, nv, threads, &m->ps, m->box);  /* every point tested is a vertex */
    m->vloc = base_alloc_big(nv ? nv : 1);  /* NOTES.md E110 */
    if (!m->vloc) return GTET_ERR_OUT_OF_MEMORY;
    memset(m->vloc, 0xff, nv);
    return km_reserve(m, slots_hint);
}

void km_free(kmesh *m)
{
    free(m->tv);
    free(m->tn);
    free(m->vloc);
    memset(m, 0, sizeof *m);
}

void kctx_init(kctx *c, kmesh *m, uint64_t seed)
{
    memset(c, 0, sizeof *c);
    c->m = m;
    c->rng = seed * 0x9e3779b97f4a7c15ULL + 1;
    c->last_ghost = UINT32_MAX;
#if defined(GTET_AVX2_TU)
    /* the AVX2 instances of km_insert when the CPU has AVX2 (the same answers either way) */
    __builtin_cpu_init();
    c->avx2 = __builtin_cpu_supports("avx2") != 0;
#endif
}

void kctx_free(kctx *c)
{
    free(c->cav);
    free(c->bnd);
    free(c->freelist);
    free(c->htab);
    c->cav = NULL;
    c->bnd = NULL;
    c->freelist = NULL;
    c->htab = NULL;
}
