/* slices.c -- the cuts of a parallel pass (parallel.c) into one slice per thread, and the
 * colour ranges of the vertices (obligation O1 of proofs/parallel.md: every point of slice k
 * gets colour k from the ranges, and equal keys are never split).  Cuts lie on Moore-cell
 * boundaries where the data allows (NOTES.md E12: cut_on_cells), else at equal counts with the
 * boundary halfway along the curve between two slices' neighbouring points (kpar_slices).
 */
#include "slices.h"

#include <math.h>
#include <string.h>

#define KEY_BITS KPAR_KEY_BITS
_Static_assert(KPAR_KEY_MASK == (UINT64_C(1) << (3 * KEY_BITS)) - 1, "key mask");

/* A key strictly after x and at most y, about halfway along the (looping) curve from x to y
 * (x itself when x == y). */
static uint64_t key_mid(uint64_t x, uint64_t y)
{
    const uint64_t d = (y - x) & KPAR_KEY_MASK;
    return (x + (d + 1) / 2) & KPAR_KEY_MASK;
}

/* pk and pts become their cyclic order starting at index off (0 < off < np). */
static void rotate_pending(uint64_t *pk, uint32_t *pts, size_t np, size_t off, uint64_t *tk,
                           uint32_t *ti)
{
    memcpy(tk, pk, off * sizeof *tk);
    memcpy(ti, pts, off * sizeof *ti);
    memmove(pk, pk + off, (np - off) * sizeof *pk);
    memmove(pts, pts + off, (np - off) * sizeof *pts);
    memcpy(pk + (np - off), tk, off * sizeof *pk);
    memcpy(pts + (np - off), ti, off * sizeof *pts);
}

/* Cuts on Moore cells (NOTES.md E12).  An aligned range of 8^j keys is one cube of the curve,
 * so a cut at a key that is a multiple of 8^j leaves whole cubes of side 2^j cells on both
 * sides.  The gap before sorted position i (gap 0: between the last key and the first, across
 * the loop's origin) gets the level of the coarsest such key B in it: x < B <= y for the keys
 * x, y on either side, B = y with the bits below the highest 3-bit digit where x and y differ
 * cleared, level = that digit's rank from the bottom (0..20); 21 at the origin (B = 0); -1
 * between equal keys (never a cut). */
#define CUT_TOL 64   /* a cut moves at most slice / CUT_TOL points off the equal-count one */
static int gap_level(const uint64_t *pk, size_t np, size_t i, uint64_t *bound)
{
    const uint64_t x = pk[i ? i - 1 : np - 1], y = pk[i];
    if (x == y) return -1;
    if (y < x) {  /* only at i == 0: the loop's origin */
        *bound = 0;
        return KEY_BITS;
    }
    const int h = 63 - __builtin_clzll(x ^ y);
    *bound = y & ~((UINT64_C(1) << (h / 3 * 3)) - 1);
    return h / 3;
}

/* The gap within tol of position t (cyclically) with the highest level, the nearest to t
 * among those; -1 when every gap there lies between equal keys. */
static long snap_cut(const uint64_t *pk, size_t np, size_t t, size_t tol)
{
    long best = -1;
    int level = -1;
    uint64_t b;
    for (size_t d = 0; d <= tol; d++)
        for (int side = 0; side < 2 - (d == 0); side++) {
            const size_t i = side ? (t + np - d) % np : (t + d) % np;
            const int l = gap_level(pk, np, i, &b);
            if (l > level) level = l, best = (long)i;
        }
    return best;
}

#define BEST_ORIGIN_PARALLEL 65536  /* fewer pending points: the origin's search on one thread */

/* The rebalancing's cut of a rest pk[lo..hi) (rebalance.c; lo < hi <= np, hi - lo >= 2): the
 * gap of the coarsest level (gap_level) within (hi - lo) / REST_TOL of the middle and inside
 * the rest, the nearest to the middle among those (a coarse cell's faces meet fewer tets than
 * a fine staircase: fewer points deferred at the cut), with its cell's key in *bound; hi when
 * every gap there lies between equal keys (O1: never cut between them). */
#define REST_TOL 16
size_t kpar_rest_cut(const uint64_t *pk, size_t np, size_t lo, size_t hi, uint64_t *bound)
{
    const size_t t = lo + (hi - lo) / 2, tol = (hi - lo) / REST_TOL;
    size_t best = hi;
    int level = -1;
    uint64_t b;
    for (size_t d = 0; d <= tol; d++)
        for (int side = 0; side < 2 - (d == 0); side++) {
            const size_t i = side ? t - d : t + d;
            if (i <= lo || i >= hi) continue;
            const int l = gap_level(pk, np, i, &b);
            if (l > level) level = l, best = i, *bound = b;
        }
    return best;
}

/* Equal counts: goal[j] (j < nth), the points before cut j measured from the origin.  (Cuts
 * weighted by an estimated cost, E21 and E187, balanced the static filter's dearer calls on
 * points finer than its scale; since the level filter, E188, those points cost what the others
 * do, and the first pass's rebalancing, E186, takes up what the counts miss.) */
static void cut_goals(size_t np, int nth, uint64_t goal[])
{
    for (int j = 0; j < nth; j++) goal[j] = (uint64_t)(np / (size_t)nth) * (uint64_t)j;
}

/* The cut targets tgt[j] = pos[j] mod np for the origin r: pos[j] is the position goal[j]
 * points on from r (counted on, unwrapped).  acc and pos are the sweep's state: from origin
 * r to r + 1 the caller passes them on (each pos[j] only moves forward), or acc zeros and
 * pos[j] = r to start. */
static void cut_targets(size_t np, int nth, const uint64_t goal[], uint64_t acc[], size_t pos[],
                        size_t tgt[])
{
    for (int j = 0; j < nth; j++) {
        pos[j] += (size_t)(goal[j] - acc[j]);
        acc[j] = goal[j];
        tgt[j] = pos[j] % np;
    }
}

/* The origin r of the equal-count cuts (cut_targets) whose worst snapped cut is coarsest, the
 * nearest to 0 on the loop among r in [0, pos[1] of origin 0).  Origin 0 when its cuts reach level
 * KEY_BITS - 1 (octant faces: only the origin's gap is coarser, so nothing beats it; uniform
 * points with 2 or 4 threads), without the search.  The search: the highest level within tol
 * of every gap x at once (van Herk / Gil-Werman: block-wise prefix and suffix maxima over the
 * gaps x - tol .. x + tol, blocks of w = 2 tol + 1), then each origin's worst cut; scratch
 * holds 3 np + 4 tol bytes.  The cuts of origin r are at r + goal[j], so every step
 * is a loop over independent positions or blocks, run on `threads` threads; the best origin
 * is the one of the greatest score, then the least distance to 0, then the least r -- the
 * one an ascending scan keeping strict improvements finds -- whatever the thread count. */
/* The gap of extended index k (0 <= k < np + 2 tol, tol < np): (k - tol) mod np, without a
 * division (a loop over every extended index takes one per index otherwise). */
static inline size_t ext_gap(size_t k, size_t tol, size_t np)
{
    return k < tol ? k + np - tol : k - tol < np ? k - tol : k - tol - np;
}

static size_t best_origin(const uint64_t *pk, size_t np, int nth, size_t tol,
                          const uint64_t goal[], int8_t *scratch, int threads)
{
    uint64_t b, acc[256] = {0};
    size_t pos[256] = {0}, tgt[256];
    int worst0 = KEY_BITS;
    cut_targets(np, nth, goal, acc, pos, tgt);
    for (int j = 1; j < nth; j++) {
        const long g = snap_cut(pk, np, tgt[j], tol);
        const int l = g < 0 ? -1 : gap_level(pk, np, (size_t)g, &b);
        if (l < worst0) worst0 = l;
    }
    if (worst0 >= KEY_BITS - 1) return 0;
    const size_t w = 2 * tol + 1, n2 = np + 2 * tol, rend = nth > 1 ? pos[1] : np;
    const size_t nblocks = (n2 + w - 1) / w;
    int8_t *lev = scratch, *pre = scratch + np, *suf = pre + n2;
    const int T = threads > 1 && np > BEST_ORIGIN_PARALLEL ? threads : 1;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        uint64_t bi;
#pragma omp for schedule(static)
        for (size_t i = 0; i < np; i++) lev[i] = (int8_t)gap_level(pk, np, i, &bi);
#pragma omp for schedule(static)
        for (size_t blk = 0; blk < nblocks; blk++) {
            /* extended index k is gap (k - tol) mod np; block blk is k in [blk w, blk w + w) */
            const size_t k0 = blk * w, k1 = k0 + w < n2 ? k0 + w : n2;
            for (size_t k = k0; k < k1; k++) {
                const int8_t e = lev[ext_gap(k, tol, np)];
                pre[k] = (k == k0 || e > pre[k - 1]) ? e : pre[k - 1];
            }
            for (size_t k = k1; k-- > k0;) {
                const int8_t e = lev[ext_gap(k, tol, np)];
                suf[k] = (k == k1 - 1 || e > suf[k + 1]) ? e : suf[k + 1];
            }
        }
    }
    size_t best = 0, bdist = 0;
    int best_score = -2;
#pragma omp parallel num_threads(T) if (T > 1)
    {
        size_t my = 0, mydist = 0;
        int my_score = -2;
#pragma omp for schedule(static) nowait
        for (size_t r = 0; r < rend; r++) {
            int score = KEY_BITS + 1;
            for (int j = 0; j < nth && score >= my_score; j++) {
                size_t x = r + (size_t)goal[j];  /* < 2 np; window: extended x .. x + 2 tol */
                if (x >= np) x -= np;
                const int8_t a = suf[x], c = pre[x + w - 1];
                const int m = a > c ? a : c;
                if (m < score) score = m;
            }
            const size_t dist = r < rend - r ? r : rend - r;
            if (score > my_score || (score == my_score && dist < mydist))
                my_score = score, my = r, mydist = dist;
        }
#pragma omp critical(gtet_best_origin)
        if (my_score > best_score ||
            (my_score == best_score && (mydist < bdist || (mydist == bdist && my < best))))
            best_score = my_score, best = my, bdist = mydist;
    }
    return best;
}

/* The first retry's cut targets from the previous pass's colour ranges (NOTES.md E20): old
 * slice j's deferred points form one arc of the loop (its colour range), and the new cut j
 * goes to the middle of that arc (by count), as far as it can be from the old boundaries,
 * where the deferred points crowd.  (A rotation by half a slice of pending points does this
 * only when the old cuts started at the loop's origin, key 0: after a free origin, best_origin,
 * it put the new cuts on the old boundaries, and the retry failed.)  0 when some old slice has
 * no deferred point, or every point has one old colour. */
static int retry_targets(const uint64_t *pk, size_t np, int nth, const kpar_cuts *prev,
                         size_t tgt[])
{
    size_t o = np, cnt[256] = {0};
    int before = kpar_colour_of(pk[np - 1], prev->rel, prev->bound0, nth);
    for (size_t i = 0; i < np; i++) {
        const int c = kpar_colour_of(pk[i], prev->rel, prev->bound0, nth);
        cnt[c]++;
        if (c == 0 && before != 0 && o == np) o = i;  /* where old colour 0's arc starts */
        before = c;
    }
    if (o == np) return 0;
    size_t at = o;
    for (int j = 0; j < nth; j++) {
        if (cnt[j] == 0) return 0;
        tgt[j] = (at + cnt[j] / 2) % np;
        at += cnt[j];
    }
    return 1;
}

/* Slices cut at the coarsest Moore-cell boundaries within slice / CUT_TOL points of the cut
 * targets (E12): equal counts from origin 0 (mode 0) or from the origin whose equal-count
 * cuts are coarsest (mode 2, a round's first pass: the cuts of a dense cluster that holds a
 * slice's worth of points are its cube's faces), or the first retry's targets (mode 1, equal counts: the
 * middles of the previous pass's slices' deferred points when prev is given for as many
 * threads, retry_targets; else half a slice in, E6).  The colour boundaries are the cells'
 * keys B of the gaps (gap_level), so colour regions are unions of cubes.  0 (nothing changed)
 * when a slice is too small for any freedom or a window holds only equal keys: the caller
 * then cuts by equal counts. */
static int cut_on_cells(uint64_t *pk, uint32_t *pts, size_t np, int nth, int mode,
                        const kpar_cuts *prev, uint64_t *tk, uint32_t *ti, size_t begin[],
                        size_t end[], uint64_t rel[], uint64_t *bound0)
{
    const size_t s = np / (size_t)nth, tol = s / CUT_TOL;
    if (tol == 0) return 0;
    size_t tgt[256];
    if (!(mode == 1 && prev && prev->nth == nth && retry_targets(pk, np, nth, prev, tgt))) {
        uint64_t goal[256] = {0}, acc[256] = {0};
        cut_goals(np, nth, goal);
        const size_t r = mode == 2 ? best_origin(pk, np, nth, tol, goal, (int8_t *)tk, nth)
                                   : mode == 1 ? s / 2 : 0;
        size_t pos[256];
        for (int j = 0; j < nth; j++) pos[j] = r;
        cut_targets(np, nth, goal, acc, pos, tgt);
    }
    size_t gap[256];
    for (int j = 0; j < nth; j++) {
        const long g = snap_cut(pk, np, tgt[j], tol);
        if (g < 0) return 0;
        gap[j] = (size_t)g;
    }
    const size_t off = gap[0];
    uint64_t b0 = 0, bk = 0;
    gap_level(pk, np, off, &b0);
    for (int j = 0; j < nth; j++) {  /* positions after the rotation by off, increasing */
        const size_t at = (gap[j] + np - off) % np;
        if (j > 0 && at <= begin[j - 1]) return 0;
        begin[j] = at;
        gap_level(pk, np, gap[j], &bk);
        rel[j] = (bk - b0) & KPAR_KEY_MASK;
    }
    for (int j = 0; j < nth; j++) end[j] = j + 1 < nth ? begin[j + 1] : np;
    if (off > 0) rotate_pending(pk, pts, np, off, tk, ti);
    *bound0 = b0;
    return 1;
}

/* Slices and colour ranges of a pass (O1).  pk[0..np) sorted, pts alongside.  First the cuts
 * on Moore cells (cut_on_cells; rotate: 0 origin at the first key, 1 the middles of the
 * previous pass's slices' deferred points, or half a slice in, 2 the coarsest origin); when
 * they are not possible, equal counts as follows.
 * The first retry of a round (rotate) keeps the tight box's keys -- no re-keying of the mesh --
 * and moves every cut by half a slice along the loop: pk and pts become the cyclic order
 * starting half a slice in (never between equal keys).  The deferred points lie near the last
 * pass's region boundaries; the new regions are unions of halves of old ones, and on the
 * looping curve with two threads the new boundary is the other symmetry plane of the loop,
 * which crosses the old one only along a line (most of the deferred points then go in parallel: NOTES.md E6).
 * Slices of (nearly) equal counts, each cut moved forward past equal keys.  Colour boundaries:
 * halfway along the curve between the last point of the previous slice and the first of this
 * one (cyclically), strictly after the former, so that every point's colour is its own slice's.
 * rel[k] is slice k's boundary measured from slice 0's (the curve is a loop); a vertex's colour
 * is the largest k with rel[k] <= its key so measured (kpar_colour_of).  An empty slice (equal
 * keys moved its points to the previous one) takes the next non-empty slice's boundary, or one
 * past every key when none follows, so that it never wins.  Ranges are measured from the first
 * non-empty slice's boundary (slice 0 is empty when np < nth: the kernel never cuts so few
 * points; test_parallel_slices covers it). */
void kpar_slices(uint64_t *pk, uint32_t *pts, size_t np, int nth, int rotate,
                 const kpar_cuts *prev, uint64_t *tk, uint32_t *ti,
                 size_t begin[], size_t end[], uint64_t rel[], uint64_t *bound0)
{
    if (cut_on_cells(pk, pts, np, nth, rotate, prev, tk, ti, begin, end, rel, bound0))
        return;
    if (rotate == 1) {
        size_t off = np / (2 * (size_t)nth);
        while (off > 0 && off < np && pk[off] == pk[off - 1]) off++;
        if (off > 0 && off < np) rotate_pending(pk, pts, np, off, tk, ti);
    }
    size_t at = 0;
    for (int k = 0; k < nth; k++) {
        size_t b = at, e = (k == nth - 1) ? np : np / (size_t)nth * (size_t)(k + 1);
        if (e < b) e = b;
        while (e < np && e > 0 && pk[e] == pk[e - 1]) e++;
        begin[k] = b;
        end[k] = e;
        at = e;
    }
    uint64_t b0 = 0;
    for (int k = nth - 1; k >= 0; k--) {
        if (begin[k] >= end[k]) {
            rel[k] = k == nth - 1 ? KPAR_KEY_MASK + 1 : rel[k + 1];
            continue;
        }
        const size_t before = begin[k] ? begin[k] - 1 : np - 1;
        rel[k] = key_mid(pk[before], pk[begin[k]]);  /* absolute for now */
        b0 = rel[k];  /* ends as the first non-empty slice's boundary (measured from it, the
                       * empty slices before it get 0 and never win against it) */
    }
    for (int k = 0; k < nth; k++)
        if (rel[k] <= KPAR_KEY_MASK) rel[k] = (rel[k] - b0) & KPAR_KEY_MASK;
    *bound0 = b0;
}
