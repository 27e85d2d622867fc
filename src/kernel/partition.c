/* partition.c -- the slices and colours of a parallel pass (parallel.c pass_parallel; proofs/
 * parallel.md O1): a round's first pass cuts the Moore keys (slices.c) or, where the mesh's tets
 * cross those far less, median slabs (slabs.c, NOTES.md E70); its retries cut slabs across the
 * axis where their points crowd least (E40, E178), or the keys again on an enlarged, shifted
 * box where slabs cannot be balanced (paper section 4.2). */
#include "parallel.h"

#include <omp.h>
#include <string.h>

#include "../base/base.h"
#include "../sort/sort.h"

#define KEY_BITS KPAR_KEY_BITS  /* per axis: 63-bit Moore keys (slices.h) */

static uint64_t mix64(uint64_t z)
{
    return sort_hash64(z + 0x9e3779b97f4a7c15ULL);  /* splitmix64 */
}

/* The box of pass `pass`: the tight box for pass 0; then enlarged by 1.5x-2.5x and shifted by
 * a pseudo-random fraction of the growth on each axis, so that the slice boundaries move
 * away from where the last pass's conflicts were (paper Fig. 2). */
static void pass_box(const double tight[6], unsigned pass, double out[6])
{
    memcpy(out, tight, 6 * sizeof *out);
    if (pass == 0) return;
    uint64_t h = mix64(0x6b6579ULL + pass);
    double f = 1.5 + (double)(pass % 3) * 0.5;
    for (int d = 0; d < 3; d++) {
        double e = tight[3 + d] - tight[d];
        if (!(e > 0)) e = 1.0;
        double shift = (double)((h >> (16 * d)) & 0xffff) / 65536.0;
        out[d] = tight[d] - shift * (f - 1.0) * e;
        out[3 + d] = out[d] + f * e;
    }
}

/* A pass's slabs and colours (O1): slabs between median planes across `axis`, or across the
 * axis where the pending points crowd least at the cuts (-1) (slabs.c, NOTES.md E40, E178), or
 * at the `given` cuts (a sample's, E70); 0, with nothing changed, when the coordinates do not
 * allow balanced slabs (the caller then cuts on keys).  The np doubles of scratch are the radix
 * scratch P->tk (malloc'ed for the round's pending points, 8 bytes each, >= np; unused by a
 * pass that cuts slabs): no allocation in the pass, and the memory guard's count of the
 * round's arrays holds. */
static int pass_slabs(kpar *P, uint32_t *pts, size_t np, size_t nmesh, int nth, int axis,
                      const kpar_slab_cuts *given, size_t begin[], size_t end[])
{
    const kmesh *m = P->m;
    kpar_slab_cuts s;
    double *scratch = (double *)(void *)P->tk;  /* allocated storage: its type is the last store's */
    if (given) {
        if (!kpar_slabs_at(m->v, pts, np, given, P->ti, begin, end, &P->runs)) return 0;
        s = *given;
    } else {
        if (!kpar_slab_cuts_on(m->v, pts, np, nth, axis, scratch, &s)) return 0;
        kpar_slab_split(m->v, pts, np, &s, P->ti, begin, end, &P->runs);
    }
    uint8_t *col = P->colour;
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t v = 0; v < nmesh; v++) col[v] = (uint8_t)kpar_slab_of(m->v[3 * v + s.axis], &s);
    return 1;
}

/* A round's first pass: the axis whose median-plane slabs the mesh's tets cross least, when
 * they cross fewer than 3/4 of those the Moore slices just cut in P->colour cross (kpar_crossing,
 * kpar_first_axis in slabs.c, NOTES.md E70); else -1: keep the Moore slices (E12, E21).  The
 * candidates' cuts are taken on every (np / SLAB_SAMPLE + 1)-th pending point, in the scratch
 * P->ti, P->tk (free after the Moore cut); only every cross_stride-th tet slot is looked at,
 * about CROSS_SAMPLE of them (all of a small mesh's every CROSS_STRIDE_MIN-th).
 * Deterministic, like everything the partition reads.  *chosen: the chosen axis's cuts (the
 * sample's quantiles: within ~1/256 of the median, no selection over all np points). */
#define SLAB_SAMPLE 65536
#define CROSS_SAMPLE 32768
#define CROSS_STRIDE_MIN 8
/* Which tets a stride samples must not depend on the threads' timing: a parallel pass's fresh
 * slots come in blocks of KM_SLOT_BLOCK claimed from the pass's first free slot in whatever
 * order the threads get there, so a tet's slot moves by whole blocks between runs, and keeps
 * its residue modulo the stride (free lists are per thread and filled in its own order).  So
 * the stride is a power of two from CROSS_STRIDE_MIN to KM_SLOT_BLOCK, which divides the
 * block, chosen from the vertices the mesh holds at the round's start (P->done: the earlier
 * rounds are whole), not from the slots in use, which the block claims make depend on timing.
 * (A fixed stride of 8 read ~550k tets in the 4M run's last round, scattered reads of their
 * vertices: 1 % of the run at `-t 2`, NOTES.md E255.) */
_Static_assert((KM_SLOT_BLOCK & (KM_SLOT_BLOCK - 1)) == 0 && KM_SLOT_BLOCK >= CROSS_STRIDE_MIN,
               "the crossing stride must divide a block");
static size_t cross_stride(size_t vertices)
{
    const size_t want = vertices / 2 * 13 / CROSS_SAMPLE;  /* about 6.5 tets a vertex */
    size_t s = CROSS_STRIDE_MIN;
    while (2 * s <= want && 2 * s <= KM_SLOT_BLOCK) s *= 2;
    return s;
}
static int first_pass_axis(kpar *P, const uint32_t *pts, size_t np, int nth,
                           kpar_slab_cuts *chosen)
{
    const size_t stride = np / SLAB_SAMPLE + 1;
    size_t ns = 0;
    for (size_t i = 0; i < np; i += stride) P->ti[ns++] = pts[i];
    kpar_slab_cuts s[3];
    for (int d = 0; d < 3; d++)
        if (!kpar_slab_cuts_on(P->m->v, P->ti, ns, nth, d, (double *)(void *)P->tk, &s[d]))
            return -1;
    size_t cross[4];
    kpar_crossing(P->m->tv, P->m->nt, cross_stride(P->done), P->m->v, P->colour, s, nth, cross);
    const int axis = kpar_first_axis(cross);
    if (axis >= 0) *chosen = s[axis];
    return axis;
}

/* The slices and colours of a pass (O1): thread k's slice is pts[begin[k] .. end[k]), and the
 * vertices 0..nmesh-1 get the colours of its regions.  A round's first pass cuts keys:
 * kpar.keys (the BRIO's, or the tight box's computed once; kpar_slices), then takes median
 * slabs across one axis instead when the mesh's tets cross those far less (first_pass_axis,
 * NOTES.md E70: the Bunny scan, flat shells and sheets).  Its retries cut
 * slabs (pass_slabs, NOTES.md E40); where slabs are refused, the first retry cuts the same
 * keys between the first pass's cuts (P->cuts, E20) and later ones re-key the vertices in the
 * mesh on an enlarged, shifted box (paper section 4.2). */
void kpar_pass_partition(kpar *P, uint32_t *pts, size_t np, size_t nmesh, int nth, unsigned pass,
                         size_t begin[], size_t end[], const uint64_t **keys_out, int *sh_out)
{
    kmesh *m = P->m;
    memset(P->runs.n, 0, sizeof P->runs.n);  /* Moore slices: no runs (pass_slabs fills them) */
    P->slab_first = 0;
    *keys_out = NULL;
    if (pass > 0 && pass_slabs(P, pts, np, nmesh, nth, -1, NULL, begin, end)) {
        for (int k = 0; GTET_DEBUG_ON && k < nth; k++)  /* O1: slice k is of colour k */
            for (size_t i = begin[k]; i < end[k]; i++) GTET_DEBUG_ASSERT(P->colour[pts[i]] == k);
        return;
    }
    const uint64_t *keys;
    int sh = 0;  /* a vertex's 63-bit key: (keys[v] << sh) & KPAR_KEY_MASK (kpar.keys) */
    double box[6];  /* the keys' box */
    memcpy(box, m->box, sizeof box);
    if (pass > 1) {
        pass_box(m->box, pass, box);
        sort_moore_keys(m->v, 3, nmesh, box, KEY_BITS, P->skeys, nth);
        keys = P->skeys;
    } else {
        if (!P->have_keys) {
            sort_moore_keys(m->v, 3, m->nv, m->box, KEY_BITS, P->keys, nth);
            P->have_keys = 1;
        }
        keys = P->keys;
        sh = P->key_shift;
    }
    /* a round's points come in BRIO order, which with the BRIO's keys is key order (so is the
     * first retry's, a subsequence): the sort is then skipped */
    uint64_t *pk = P->pk;
    int unsorted = 0;
#pragma omp parallel for num_threads(nth) schedule(static) reduction(| : unsorted)
    for (size_t i = 0; i < np; i++) {
        pk[i] = (keys[pts[i]] << sh) & KPAR_KEY_MASK;
        if (i > 0) unsorted |= ((keys[pts[i - 1]] << sh) & KPAR_KEY_MASK) > pk[i];
    }
    /* unsorted only with the kernel's own keys (the BRIO's crowded one key, E7), inside the
     * cells the BRIO refined on their own boxes: sorted there only (NOTES.md E101) */
    if (unsorted) sort_radix_pairs_grouped(pk, pts, np, 3 * KEY_BITS, P->tk, P->ti, nth);
    uint64_t rel[256], bound0;
    kpar_slices(pk, pts, np, nth, pass == 0 ? 2 : pass == 1, pass == 1 ? &P->cuts : NULL, P->tk,
                P->ti, begin, end, rel, &bound0);
    memcpy(P->cuts.rel, rel, (size_t)nth * sizeof *rel);
    P->cuts.bound0 = bound0;
    P->cuts.nth = nth;
    uint8_t *col = P->colour;
#pragma omp parallel for num_threads(nth) schedule(static)
    for (size_t v = 0; v < nmesh; v++) {
        col[v] = (uint8_t)kpar_colour_of((keys[v] << sh) & KPAR_KEY_MASK, rel, bound0, nth);
    }
    *keys_out = keys;
    *sh_out = sh;
    kpar_slab_cuts chosen;  /* the sample's cuts: balanced enough, and no select over np */
    if (pass == 0 && first_pass_axis(P, pts, np, nth, &chosen) >= 0 &&
        pass_slabs(P, pts, np, nmesh, nth, chosen.axis, &chosen, begin, end)) {
        P->cuts.nth = 0;  /* no Moore ranges for the retry's E20 cuts (it falls back) */
        P->slab = chosen;  /* the rebalancing's cuts (E258) */
        P->slab_first = 1;
        *keys_out = NULL;
    }
    for (int k = 0; GTET_DEBUG_ON && k < nth; k++)  /* O1: slice k is of colour k */
        for (size_t i = begin[k]; i < end[k]; i++) GTET_DEBUG_ASSERT(col[pts[i]] == k);
}
