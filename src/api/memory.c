/* memory.c -- the memory guard: a run that cannot fit is refused before it allocates.
 *
 * On Linux with overcommit, malloc does not fail when memory runs out: the kernel's OOM
 * killer ends the process later (exit 137, no message).  So gtet_triangulate estimates its
 * peak from the point count before any big allocation and returns GTET_ERR_OUT_OF_MEMORY at
 * once when the machine cannot give it (mem_guard, called from triangulate.c: prepare).
 *
 * The estimate (mem_estimate_run) is the largest of the phases below, each a sum of per-point
 * and per-tet-slot terms, plus a fixed part.  v = the distinct points, taken as n (duplicates
 * only lower it).  Counted: every array the library allocates.  Not counted: the caller's
 * input array (it is already resident, so MemAvailable and VmSize have seen it).
 *
 *   dedup   (validate.c kval_dedup*): result vertices 24 + input map 4 + duplicate marks 1
 *   sort    (triangulate.c order_points, brio.c sort_brio_keys): result 28, order 4, and the
 *           BRIO's keys 8 + radix scratch 8 + 4 + round 1
 *   insert  (build.c kbuild_start, kmesh.c km_init, parallel.c kpar_init/kpar_round): input
 *           map 4 (from KBUILD_HOLD_ONCE_MIN points on the result's vertices are freed while
 *           the sorted copy exists, NOTES.md E14; below it the result's 28), order 4, the sorted copy sv 24, round ids 4, vloc 1, and the working mesh:
 *           tv + tn = 32 bytes per tet slot, MEM_SLOTS_TOUCHED slots per point touched (the
 *           pages RSS counts) of the capacity build.c reserves; with threads, colour 1, keys
 *           8, shifted keys 8, hints 4, and the pending keys pk 8 + tk 8 + ti 4 of the last
 *           BRIO round (5/6 of the points: the rounds grow by 6, brio.c brio_rounds)
 *   finish  (build.c kbuild_finish: the parallel state and vloc freed, finalize.c compacts in
 *           place and shrinks to the finite tets, then restore_vertices allocates the result's
 *           vertices again while sv still exists): result 28, order 4, sv 24 and 32 bytes per
 *           finite tet.  With one thread this is the run's peak (uniform 4M: 1211 MB RSS,
 *           279 bytes a point less the input), with two the insertion's is as high
 *   check   (opts.check; src/check): result 28 + 32 per finite tet, plus the checker's arrays
 *           (MEM_CHECK_PER_TET, MEM_CHECK_PER_POINT, measured)
 *   records (opts.degeneracies): the threads' logs and their merged copy, 36 bytes a record,
 *           at most limit per thread and MEM_DEGEN_PER_POINT per point
 *
 * Address space (RLIMIT_AS, RLIMIT_DATA) counts what is mapped, touched or not: the mesh
 * arrays at their capacity (build.c's hint: 7 slots per point, 8 with threads so that the
 * last parallel round's reserve of 8 slots per pending point fits without growing),
 * every array malloc'ed even when a serial run never writes it, and per extra thread a glibc
 * malloc arena (64 MiB reserved) and a stack.
 *
 * The constants are calibrated against the peak RSS of `gigatet triangulate` (the table is in
 * NOTES.md; tests/test_api_memory.c and tests/cli/test_memory_guard.sh check them).  When the
 * kernel's memory per tet changes (tv/tn layout, the slots reserved per point, per-point
 * arrays), update MEM_SLOT_BYTES / MEM_SLOTS_TOUCHED / MEM_SLOTS_CAPACITY and the per-point
 * sums here, and re-measure.
 */
#include "memory.h"

#include <omp.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#include "../base/base.h"
#include "../kernel/build.h"

#define MIB (UINT64_C(1) << 20)
#define GIB (UINT64_C(1) << 30)

/* the working mesh (kmesh.h): tv and tn, 4 uint32 each per slot */
#define MEM_SLOT_BYTES 32
/* slots touched per point at the end of the insertion, in tenths: finite tets, ghosts,
 * deleted slots and the threads' partly used slot blocks (uniform 1M: 6.75) */
#define MEM_SLOTS_TOUCHED_X10 70
/* slots allocated per point: build.c kbuild_start's hint, 7 per point with one thread and 8
 * with more (the last parallel round's reserve, so that it does not grow), in tenths */
#define MEM_SLOTS_CAPACITY_X10 70
#define MEM_SLOTS_CAPACITY_PAR_X10 80
/* finite tets per point in the result (uniform: 6.5-6.7) */
#define MEM_TETS_PER_POINT_X10 70
/* per point, in every phase from dedup on: result vertices (3 doubles) + input map */
#define MEM_PT_RESULT 28
#define MEM_PT_CALLER_INPUT 24  /* the caller's points (3 doubles), freed at input_done */
#define MEM_PT_INPUT_MAP 4    /* the result's input map, alone during the insertion */
#define MEM_PT_DEDUP 1        /* validate.c: one duplicate mark per point */
#define MEM_PT_ORDER 4        /* triangulate.c: the insertion order */
#define MEM_PT_SORT 21        /* brio.c: keys 8, radix scratch tk 8 + ti 4, round 1 */
#define MEM_PT_KERNEL 29      /* build.c: sv 24, ids 4; insert.c: vloc 1 */
#define MEM_PT_SORTED 24      /* build.c: sv alone (the finish phase) */
/* parallel.c allocates colour 1, keys 8, skeys 8, the deferred points' hints 4 per point and
 * pk 8 + tk 8 + ti 4 per pending point of the last round (5/6 of them): 37.7 mapped; measured
 * touched, two threads against one: 17 (uniform, grid, sphere) to 26 (cauchy: the keys on the
 * tight box) per point before the hints (E177: written for the deferred points, a few in
 * each page); in tenths */
#define MEM_PT_PARALLEL_X10 320
#define MEM_PT_PARALLEL_MAPPED_X10 377
/* the checker (src/check), measured (uniform 1M: peak RSS 694 MB with --check, 304 MB
 * without): per finite tet and per point beyond the result */
#define MEM_CHECK_PER_TET 56
#define MEM_CHECK_PER_POINT 48
#define MEM_DEGEN_RECORD 36   /* sizeof(gtet_degeneracy) */
#define MEM_DEGEN_COPIES 3    /* a log grown by doubling (up to 2x) + the merged copy */
#define MEM_DEGEN_PER_POINT 16  /* decisions per point at most (an integer grid: about 15) */
/* fixed: per-thread contexts (a 32 KiB adjacency table each), thread stacks, the BRIO's and
 * radix's small tables, GMP */
#define MEM_FIXED (8 * MIB)
#define MEM_FIXED_PER_THREAD (1 * MIB)
/* address space per extra thread: a glibc malloc arena (64 MiB reserved) and a stack */
#define MEM_ADDR_PER_THREAD (72 * MIB)

/* a * b / 10, saturating */
static uint64_t mul10(uint64_t a, uint64_t b)
{
    if (b && a > UINT64_MAX / b) return UINT64_MAX;
    return a * b / 10;
}

static uint64_t add(uint64_t a, uint64_t b)
{
    return a > UINT64_MAX - b ? UINT64_MAX : a + b;
}

static uint64_t max2(uint64_t a, uint64_t b) { return a > b ? a : b; }

/* the degeneracy records' peak (opts.degeneracies) */
static uint64_t degen_bytes(uint64_t n, int threads, const gtet_options *o)
{
    if (!o->degeneracies) return 0;
    uint64_t stored = mul10(n, 10 * MEM_DEGEN_PER_POINT);
    const uint64_t cap = mul10(o->degeneracy_limit, 10 * (uint64_t)threads);
    if (cap < stored) stored = cap;
    return mul10(stored, 10 * MEM_DEGEN_RECORD * MEM_DEGEN_COPIES);
}

void mem_estimate_run(size_t n_in, int threads, const gtet_options *opts, mem_estimate *e)
{
    const uint64_t n = n_in;
    const int T = threads < 1 ? 1 : threads > BASE_MAX_THREADS ? BASE_MAX_THREADS : threads;
    const uint64_t base = mul10(n, 10 * (MEM_PT_RESULT + MEM_PT_ORDER));
    const uint64_t dedup = mul10(n, 10 * (MEM_PT_RESULT + MEM_PT_DEDUP));
    const uint64_t sort = add(base, mul10(n, 10 * MEM_PT_SORT));
    const uint64_t par = T > 1 ? mul10(n, MEM_PT_PARALLEL_X10) : 0;
    /* the result's vertices are held through the insertion below KBUILD_HOLD_ONCE_MIN */
    const uint64_t held = n < KBUILD_HOLD_ONCE_MIN ? MEM_PT_RESULT : MEM_PT_INPUT_MAP;
    const uint64_t kernel = add(mul10(n, 10 * (held + MEM_PT_ORDER + MEM_PT_KERNEL)), par);
    uint64_t insert = add(kernel, mul10(n, MEM_SLOTS_TOUCHED_X10 * MEM_SLOT_BYTES));
    insert = add(insert, degen_bytes(n, T, opts));
    const uint64_t tets = mul10(n, MEM_TETS_PER_POINT_X10);
    const uint64_t finish = add(mul10(n, 10 * (MEM_PT_RESULT + MEM_PT_ORDER + MEM_PT_SORTED)),
                                mul10(tets, 10 * MEM_SLOT_BYTES));
    uint64_t peak = max2(max2(max2(dedup, sort), insert), finish);
    if (opts->check) {
        uint64_t chk = add(mul10(n, 10 * (MEM_PT_RESULT + MEM_CHECK_PER_POINT)),
                           mul10(tets, 10 * (MEM_SLOT_BYTES + MEM_CHECK_PER_TET)));
        peak = max2(peak, chk);
    }
    const uint64_t fixed = MEM_FIXED + (uint64_t)T * MEM_FIXED_PER_THREAD;
    e->resident = add(peak, fixed);
    /* address space: every per-point array of the kernel is mapped whatever the thread count,
     * and the mesh arrays at their capacity */
    const uint64_t cap10 = T > 1 ? MEM_SLOTS_CAPACITY_PAR_X10 : MEM_SLOTS_CAPACITY_X10;
    uint64_t addr = add(mul10(n, 10 * (MEM_PT_INPUT_MAP + MEM_PT_ORDER + MEM_PT_KERNEL) +
                                     MEM_PT_PARALLEL_MAPPED_X10),
                        mul10(n, cap10 * MEM_SLOT_BYTES));
    addr = add(addr, degen_bytes(n, T, opts));
    addr = max2(max2(addr, sort), e->resident - fixed);
    e->address = add(add(addr, fixed), (uint64_t)(T - 1) * MEM_ADDR_PER_THREAD);
}

/* ---- what the machine can give ----------------------------------------------------------- */

#define MEM_PATH 4096

/* out = a followed by b; 0 (and nothing read) when the path would not fit */
static int join(char out[MEM_PATH], const char *a, const char *b)
{
    const size_t la = strlen(a), lb = strlen(b);
    if (la + lb >= MEM_PATH) return 0;
    memcpy(out, a, la);
    memcpy(out + la, b, lb + 1);
    return 1;
}

/* The number after "key" (a line "key: N [kB]") in a file; *v in bytes when the line says kB. */
static int read_key(const char *path, const char *key, uint64_t *v)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char line[512];
    const size_t kl = strlen(key);
    int found = 0;
    while (!found && fgets(line, sizeof line, f)) {
        if (strncmp(line, key, kl) != 0 || (line[kl] != ':' && line[kl] != ' ')) continue;
        char *end;
        const unsigned long long x = strtoull(line + kl + 1, &end, 10);
        if (end == line + kl + 1) continue;
        *v = strstr(end, "kB") ? (uint64_t)x * 1024 : (uint64_t)x;
        found = 1;
    }
    fclose(f);
    return found;
}

/* A file holding one number, or "max" (UINT64_MAX). */
static int read_value(const char *path, uint64_t *v)
{
    FILE *f = fopen(path, "r");
    if (!f) return 0;
    char buf[64];
    int ok = 0;
    if (fgets(buf, sizeof buf, f)) {
        char *end;
        if (!strncmp(buf, "max", 3)) {
            *v = UINT64_MAX;
            ok = 1;
        } else {
            const unsigned long long x = strtoull(buf, &end, 10);
            ok = end != buf;
            *v = x;
        }
    }
    fclose(f);
    return ok;
}

/* One cgroup directory: limit - working set (usage less the inactive page cache, which the
 * kernel reclaims before it kills), or UINT64_MAX without a limit.  v2: memory.max,
 * memory.current, memory.stat inactive_file; v1: memory.limit_in_bytes (2^62 and above mean
 * none), memory.usage_in_bytes, memory.stat total_inactive_file. */
static uint64_t cgroup_left(const char *dir, int v2)
{
    char p[MEM_PATH];
    uint64_t limit, usage = 0, cache = 0;
    if (!join(p, dir, v2 ? "/memory.max" : "/memory.limit_in_bytes") || !read_value(p, &limit) ||
        limit >= (UINT64_C(1) << 62))
        return UINT64_MAX;
    if (join(p, dir, v2 ? "/memory.current" : "/memory.usage_in_bytes")) read_value(p, &usage);
    if (join(p, dir, "/memory.stat"))
        read_key(p, v2 ? "inactive_file" : "total_inactive_file", &cache);
    if (cache > usage) cache = usage;
    usage -= cache;
    return usage >= limit ? 0 : limit - usage;
}

/* The tightest limit of cgroup `path` (as /proc/self/cgroup names it) and its ancestors under
 * the hierarchy mounted at `mount`. */
static uint64_t cgroup_walk(const char *mount, const char *path, int v2)
{
    char rel[MEM_PATH], dir[MEM_PATH];
    uint64_t best = UINT64_MAX;
    if (!join(rel, "", path)) return best;
    for (;;) {
        if (join(dir, mount, rel)) {
            const uint64_t left = cgroup_left(dir, v2);
            if (left < best) best = left;
        }
        char *slash = strrchr(rel, '/');
        if (!slash || rel[0] == '\0') break;
        *slash = '\0';  /* "/a/b" -> "/a" -> "" (the root) */
    }
    return best;
}

/* 1 when the comma-separated list has `name`. */
static int has_controller(const char *list, const char *name)
{
    const size_t l = strlen(name);
    for (const char *p = list; *p;) {
        const char *c = strchr(p, ',');
        const size_t len = c ? (size_t)(c - p) : strlen(p);
        if (len == l && !strncmp(p, name, l)) return 1;
        if (!c) break;
        p = c + 1;
    }
    return 0;
}

/* The process's memory cgroups from <proc>/self/cgroup: "0::PATH" (v2, mounted at
 * <sys>/fs/cgroup or, on a hybrid system, <sys>/fs/cgroup/unified) and "N:...memory...:PATH"
 * (v1, <sys>/fs/cgroup/memory). */
static uint64_t cgroup_room(const char *proc, const char *sys)
{
    char p[MEM_PATH], line[MEM_PATH];
    FILE *f = join(p, proc, "/self/cgroup") ? fopen(p, "r") : NULL;
    if (!f) return UINT64_MAX;
    uint64_t best = UINT64_MAX;
    while (fgets(line, sizeof line, f)) {
        line[strcspn(line, "\n")] = '\0';
        char *c1 = strchr(line, ':');
        char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
        if (!c2) continue;
        *c2 = '\0';
        const char *ctl = c1 + 1, *path = c2 + 1;
        uint64_t left = UINT64_MAX;
        if (!strncmp(line, "0:", 2) && *ctl == '\0') {
            if (join(p, sys, "/fs/cgroup")) left = cgroup_walk(p, path, 1);
            if (join(p, sys, "/fs/cgroup/unified")) {
                const uint64_t l2 = cgroup_walk(p, path, 1);
                if (l2 < left) left = l2;
            }
        } else if (has_controller(ctl, "memory") && join(p, sys, "/fs/cgroup/memory")) {
            left = cgroup_walk(p, path, 0);
        }
        if (left < best) best = left;
    }
    fclose(f);
    return best;
}

/* limit - what is mapped (a <proc>/self/status field), or UINT64_MAX without a limit. */
static uint64_t rlimit_room(int resource, const char *status, const char *field)
{
    struct rlimit rl;
    if (getrlimit(resource, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY) return UINT64_MAX;
    uint64_t used = 0;
    read_key(status, field, &used);
    return used >= (uint64_t)rl.rlim_cur ? 0 : (uint64_t)rl.rlim_cur - used;
}

void mem_probe(const char *proc, const char *sys, mem_room *room)
{
    char p[MEM_PATH];
    room->mem_available = UINT64_MAX;
    if (join(p, proc, "/meminfo")) read_key(p, "MemAvailable", &room->mem_available);
    room->cgroup = cgroup_room(proc, sys);
    if (!join(p, proc, "/self/status")) p[0] = '\0';
    room->rlimit_as = rlimit_room(RLIMIT_AS, p, "VmSize");
    room->rlimit_data = rlimit_room(RLIMIT_DATA, p, "VmData");
}

/* ---- the guard --------------------------------------------------------------------------- */

/* "23.4 GiB", "512.0 MiB", "12 KiB" */
static void fmt_bytes(char *out, size_t size, uint64_t b)
{
    if (b >= GIB) snprintf(out, size, "%.1f GiB", (double)b / (double)GIB);
    else if (b >= MIB) snprintf(out, size, "%.1f MiB", (double)b / (double)MIB);
    else snprintf(out, size, "%.0f KiB", (double)b / 1024.0);
}

static gtet_status refuse(gtet_error *err, uint64_t need, uint64_t have, const char *what,
                          const char *bound)
{
    char a[32], b[32];
    fmt_bytes(a, sizeof a, need);
    fmt_bytes(b, sizeof b, have);
    base_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
               "out of memory: needs about %s%s, %s available (%s)", a, what, b, bound);
    return GTET_ERR_OUT_OF_MEMORY;
}

int mem_block_fits(const mem_room *room, uint64_t bytes, char *why, size_t why_size)
{
    const int cg = room->cgroup < room->mem_available;
    const uint64_t res = cg ? room->cgroup : room->mem_available;
    const int data = room->rlimit_data < room->rlimit_as;
    const uint64_t addr = data ? room->rlimit_data : room->rlimit_as;
    if (bytes <= res && bytes <= addr) return 1;
    char have[32];
    const int addr_bound = addr < res;
    fmt_bytes(have, sizeof have, addr_bound ? addr : res);
    snprintf(why, why_size, "%s available (%s)", have,
             addr_bound ? (data ? "RLIMIT_DATA, ulimit -d" : "RLIMIT_AS, ulimit -v")
                        : (cg ? "cgroup memory limit" : "MemAvailable"));
    return 0;
}

gtet_status mem_guard_room(size_t n, int threads, const gtet_options *opts,
                           const mem_room *room, gtet_error *err)
{
    if (opts->memory_limit == SIZE_MAX) return GTET_OK;
    mem_estimate e;
    mem_estimate_run(n, threads, opts, &e);
    if (opts->memory_limit) {
        if (e.resident <= opts->memory_limit) return GTET_OK;
        return refuse(err, e.resident, opts->memory_limit, "", "the memory_limit option");
    }
    /* a caller that frees its points at opts->input_done (after the validate stage, whose
     * arrays are far below the peak) gives their pages and address space back before the
     * insertion: the limits, which count them now, are that much larger for the peak */
    const uint64_t credit = opts->input_done ? mul10(n, 10 * MEM_PT_CALLER_INPUT) : 0;
    const uint64_t validate = mul10(n, 10 * (MEM_PT_RESULT + MEM_PT_DEDUP));
    const int cg = room->cgroup < room->mem_available;
    const uint64_t res = cg ? room->cgroup : room->mem_available;
    const char *res_name = cg ? (credit ? "cgroup memory limit, with the input freed"
                                        : "cgroup memory limit")
                              : (credit ? "MemAvailable, with the input freed" : "MemAvailable");
    if (validate > res) return refuse(err, validate, res, "", cg ? "cgroup memory limit" : "MemAvailable");
    if (e.resident > add(res, credit)) return refuse(err, e.resident, add(res, credit), "", res_name);
    const int data = room->rlimit_data < room->rlimit_as;
    const uint64_t addr = data ? room->rlimit_data : room->rlimit_as;
    if (e.address > add(addr, credit))
        return refuse(err, e.address, add(addr, credit), " of address space",
                      data ? "RLIMIT_DATA, ulimit -d" : "RLIMIT_AS, ulimit -v");
    return GTET_OK;
}

gtet_status mem_guard(size_t n, int threads, const gtet_options *opts, gtet_error *err)
{
    if (opts->memory_limit == SIZE_MAX) return GTET_OK;
    mem_room room;
    mem_probe("/proc", "/sys", &room);
    return mem_guard_room(n, threads, opts, &room, err);
}

/* what the second check keeps free for the rest of the run: the finish phase allocates the
 * result's vertices again (from KBUILD_HOLD_ONCE_MIN points on: 24 bytes a point) and a few
 * small arrays; the margin is for the rest of the machine */
#define MEM_GROW_SPARE_PER_POINT 32
#define MEM_GROW_SPARE (32 * MIB)

gtet_status mem_grow_room(const mem_room *room, size_t n, size_t used_bytes, size_t cap_bytes,
                          size_t min_bytes, size_t *want_bytes, gtet_error *err)
{
    /* resident: the slots not touched yet will be; address: the growth is mapped at once */
    const int cg = room->cgroup < room->mem_available;
    const uint64_t res = cg ? room->cgroup : room->mem_available;
    const int data = room->rlimit_data < room->rlimit_as;
    const uint64_t addr = data ? room->rlimit_data : room->rlimit_as;
    const uint64_t spare = add(mul10(n, 10 * MEM_GROW_SPARE_PER_POINT), MEM_GROW_SPARE);
    const uint64_t res_left = res > spare ? res - spare : 0;
    const uint64_t addr_left = addr > spare ? addr - spare : 0;
    const uint64_t by_res = add(used_bytes, res_left), by_addr = add(cap_bytes, addr_left);
    const uint64_t grant = by_res < by_addr ? by_res : by_addr;
    if (*want_bytes <= grant) return GTET_OK;
    if (min_bytes <= grant) {
        *want_bytes = (size_t)grant;
        return GTET_OK;
    }
    const int addr_bound = by_addr < by_res;
    char step[32], have[32], keep[32];
    fmt_bytes(step, sizeof step, *want_bytes - cap_bytes);
    fmt_bytes(have, sizeof have, addr_bound ? addr : res);
    fmt_bytes(keep, sizeof keep, spare);
    base_error(err, GTET_ERR_OUT_OF_MEMORY, SIZE_MAX, -1,
               "out of memory: the mesh outgrew the estimate (%.1f tet slots a point so far, "
               "7 estimated) and cannot grow by %s and keep %s for the rest of the run: "
               "%s available (%s)",
               n ? (double)used_bytes / MEM_SLOT_BYTES / (double)n : 0.0, step, keep, have,
               addr_bound ? (data ? "RLIMIT_DATA, ulimit -d" : "RLIMIT_AS, ulimit -v")
                          : (cg ? "cgroup memory limit" : "MemAvailable"));
    return GTET_ERR_OUT_OF_MEMORY;
}

gtet_status mem_grow_guard(void *user, size_t used_bytes, size_t cap_bytes, size_t min_bytes,
                           size_t *want_bytes)
{
    const mem_grow *g = user;
    mem_room room;
    mem_probe(g->proc, g->sys, &room);
    return mem_grow_room(&room, g->n, used_bytes, cap_bytes, min_bytes, want_bytes, g->err);
}

size_t gtet_estimate_memory(size_t n, const gtet_options *opts)
{
    gtet_options o;
    if (opts) o = *opts;
    else gtet_options_init(&o);
    const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
    mem_estimate e;
    mem_estimate_run(n, threads, &o, &e);
    return e.resident > SIZE_MAX ? SIZE_MAX : (size_t)e.resident;
}

gtet_status gtet_memory_guard(size_t n, const gtet_options *opts)
{
    gtet_options o;
    if (opts) o = *opts;
    else gtet_options_init(&o);
    if (o.error) {
        memset(o.error, 0, sizeof *o.error);
        o.error->index = SIZE_MAX;
        o.error->dimension = -1;
    }
    const int threads = o.threads > 0 ? o.threads : omp_get_max_threads();
    return mem_guard(n, threads, &o, o.error);
}
