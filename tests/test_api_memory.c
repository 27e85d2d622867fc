/* test_api_memory.c -- the memory guard (src/api/memory.c): the estimate's shape (per point,
 * more with threads, the checker and degeneracy records, a small fixed part that never refuses
 * a small run), the decision against each limit and the limit it names, the limits read from
 * a fake /proc and /sys tree (cgroup v2 with ancestors and "max", cgroup v1 with its
 * "unlimited" value, MemAvailable), and gtet_triangulate refusing at once through
 * gtet_options.memory_limit (or running with the guard off); the big arrays' pages
 * (src/base/hugepages.c): huge pages asked for from a block's first byte, and pages mapped ahead
 * of use exactly inside the range given (NOTES.md E110, E111); gtet_triangulate_wide's arrays
 * (the distributed mode's hook, src/mesh/mesh.h) with room for 64-bit rows (NOTES.md E130). */
#define _DEFAULT_SOURCE /* madvise, mincore, MAP_ANONYMOUS */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <stdint.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "../src/api/memory.h"
#include "../src/base/base.h"
#include "../src/mesh/mesh.h"
#include "gigatet.h"
#include "testutil.h"

#define MIB (UINT64_C(1) << 20)
#define GIB (UINT64_C(1) << 30)

static void estimate_shape(void)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 1;
    const size_t small = gtet_estimate_memory(1000, &o);
    TEST_CHECK(small > 1 * MIB && small < 64 * MIB, "1000 points: %zu bytes", small);
    const size_t big = gtet_estimate_memory(100000000, &o);
    /* per point at 100M, one thread: between 250 and 400 bytes (the kernel's 7 slots of 32 B) */
    TEST_CHECK(big / 100000000 >= 250 && big / 100000000 <= 400, "100M points: %zu B/pt",
               big / 100000000);
    o.threads = 2;
    const size_t big2 = gtet_estimate_memory(100000000, &o);
    TEST_CHECK(big2 > big, "two threads need more: %zu <= %zu", big2, big);
    o.check = 1;
    TEST_CHECK(gtet_estimate_memory(100000000, &o) >= big2, "the check never lowers it");
    o.check = 0;
    o.degeneracies = 1;
    o.degeneracy_limit = SIZE_MAX;
    const size_t rec = gtet_estimate_memory(1000000, &o);
    o.degeneracies = 0;
    TEST_CHECK(rec > gtet_estimate_memory(1000000, &o) && rec < SIZE_MAX,
               "records add a bounded amount: %zu", rec);
    TEST_CHECK(gtet_estimate_memory(SIZE_MAX / 2, &o) == SIZE_MAX, "saturates");
    TEST_CHECK(gtet_estimate_memory(0, NULL) > 0, "NULL options: the defaults");
}

/* NOTES.md E159c: more threads than the kernel's 255 are not counted (100000 threads made 100
 * points "need" 97.7 GiB, refused), and such a run meshes with at most 255 */
static void thread_count_capped(void)
{
    gtet_options o;
    gtet_options_init(&o);
    o.threads = 255;
    const size_t at255 = gtet_estimate_memory(100, &o);
    o.threads = 100000;
    TEST_CHECK(gtet_estimate_memory(100, &o) == at255, "100000 threads: %zu bytes, 255: %zu",
               gtet_estimate_memory(100, &o), at255);
    TEST_CHECK(gtet_memory_guard(100, &o) == GTET_OK, "100 points with 100000 threads refused");
    double xyz[3 * 100];
    uint64_t s = 7;
    for (int i = 0; i < 300; i++) {
        s = s * 6364136223846793005u + 1442695040888963407u;
        xyz[i] = (double)(s >> 11) * 0x1p-53;
    }
    gtet_mesh *m = NULL;
    gtet_error err;
    o.error = &err;
    TEST_CHECK(gtet_triangulate(xyz, 100, &o, &m) == GTET_OK, "100000 threads: %s", err.message);
    if (m) {
        gtet_stats st;
        gtet_mesh_stats(m, &st);
        TEST_CHECK(st.threads >= 1 && st.threads <= 255, "threads used: %d", st.threads);
    }
    gtet_mesh_free(&m);
}

static gtet_status guard(size_t n, const mem_room *room, size_t limit, gtet_error *err)
{
    gtet_options o;
    gtet_options_init(&o);
    o.memory_limit = limit;
    memset(err, 0, sizeof *err);
    return mem_guard_room(n, 1, &o, room, err);
}

static void guard_names_the_limit(void)
{
    const mem_room none = {UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX};
    gtet_error err;
    TEST_CHECK(guard(10000000, &none, 0, &err) == GTET_OK, "no limit: fits");
    mem_room r = none;
    r.mem_available = 20 * GIB;
    TEST_CHECK(guard(10000000, &r, 0, &err) == GTET_OK, "10M in 20 GiB");
    TEST_CHECK(guard(100000000, &r, 0, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   err.status == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "out of memory: needs about ") &&
                   strstr(err.message, "GiB, 20.0 GiB available (MemAvailable)"),
               "100M in 20 GiB: %s", err.message);
    r.cgroup = 1 * GIB;
    TEST_CHECK(guard(10000000, &r, 0, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "1.0 GiB available (cgroup memory limit)"),
               "cgroup: %s", err.message);
    r = none;
    r.rlimit_as = 100 * MIB;
    TEST_CHECK(guard(1000000, &r, 0, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "of address space, 100.0 MiB available (RLIMIT_AS"),
               "ulimit -v: %s", err.message);
    r.rlimit_data = 50 * MIB;
    TEST_CHECK(guard(1000000, &r, 0, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(RLIMIT_DATA"), "ulimit -d: %s", err.message);
    /* the option: a value replaces the machine's limits, SIZE_MAX turns the guard off */
    TEST_CHECK(guard(1000000, &r, 64 * (size_t)GIB, &err) == GTET_OK, "a value overrides");
    TEST_CHECK(guard(1000, &none, 1 * MIB, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "1.0 MiB available (the memory_limit option)"),
               "1M: %s", err.message);
    r.mem_available = 0;
    TEST_CHECK(guard(100000000, &r, SIZE_MAX, &err) == GTET_OK, "off");
    /* never refuses a small run on a machine with normal memory */
    r = none;
    r.mem_available = 256 * MIB;
    TEST_CHECK(guard(100000, &r, 0, &err) == GTET_OK, "100k points in 256 MiB");
}

static void input_freed(void *user) { (void)user; }

/* A caller that frees its points at input_done gets their 24 bytes a point back before the
 * peak: the guard counts them as available (the 80M-point CLI run needs it). */
static void guard_credits_the_freed_input(void)
{
    const size_t n = 10000000;
    gtet_options o;
    gtet_options_init(&o);
    mem_estimate e;
    mem_estimate_run(n, 1, &o, &e);
    mem_room r = {e.resident - 100 * MIB, UINT64_MAX, UINT64_MAX, UINT64_MAX};
    gtet_error err;
    memset(&err, 0, sizeof err);
    TEST_CHECK(mem_guard_room(n, 1, &o, &r, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(MemAvailable)"), "kept input: %s", err.message);
    o.input_done = input_freed;
    TEST_CHECK(mem_guard_room(n, 1, &o, &r, &err) == GTET_OK,
               "freed input (240 MB) covers the missing 100 MiB: %s", err.message);
    r.mem_available = e.resident - 400 * MIB;
    TEST_CHECK(mem_guard_room(n, 1, &o, &r, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(MemAvailable, with the input freed)"),
               "400 MiB short: %s", err.message);
    r.mem_available = 200 * MIB;  /* not even the validate stage's arrays fit beside the input */
    TEST_CHECK(mem_guard_room(n, 1, &o, &r, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(MemAvailable)"), "validate: %s", err.message);
}

/* The second check (mem_grow_room): a mesh that outgrows the estimate grows as far as the
 * limits allow, less what the rest of the run needs (32 B a point + 32 MiB), and is refused,
 * naming the limit, only when even the slots needed now do not fit.  Resident room counts from
 * the slots in use, address space from the capacity mapped. */
static void growth_is_cut_or_refused(void)
{
    const mem_room none = {UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX};
    const size_t n = 1000000, used = 200 * MIB, cap = 224 * MIB, min = 230 * MIB;
    const uint64_t spare = 32 * (uint64_t)n + 32 * MIB;
    gtet_error err;
    memset(&err, 0, sizeof err);
    size_t want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&none, n, used, cap, min, &want, &err) == GTET_OK && want == 336 * MIB,
               "no limit: the whole step (%zu)", want);
    mem_room r = none;
    r.mem_available = 100 * MIB + spare;  /* resident: up to used + 100 MiB */
    want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&r, n, used, cap, min, &want, &err) == GTET_OK && want == 300 * MIB,
               "MemAvailable cuts the step to used + room - spare: %zu MiB", want / MIB);
    r.mem_available = 20 * MIB + spare;  /* used + 20 MiB < min */
    want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&r, n, used, cap, min, &want, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   err.status == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "the mesh outgrew the estimate (6.6 tet slots a point") &&
                   strstr(err.message, "cannot grow by 112.0 MiB") &&
                   strstr(err.message, "(MemAvailable)"),
               "refused: %s", err.message);
    r.cgroup = 20 * MIB + spare;
    r.mem_available = UINT64_MAX;
    want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&r, n, used, cap, min, &want, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(cgroup memory limit)"), "cgroup: %s", err.message);
    r = none;
    r.rlimit_as = 50 * MIB + spare;  /* address: up to cap + 50 MiB = 274 MiB */
    want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&r, n, used, cap, min, &want, &err) == GTET_OK && want == 274 * MIB,
               "ulimit -v cuts the step to cap + room - spare: %zu MiB", want / MIB);
    r.rlimit_as = 5 * MIB + spare;
    want = 336 * MIB;
    TEST_CHECK(mem_grow_room(&r, n, used, cap, min, &want, &err) == GTET_ERR_OUT_OF_MEMORY &&
                   strstr(err.message, "(RLIMIT_AS, ulimit -v)"), "ulimit -v: %s", err.message);
}

static void put(const char *root, const char *rel, const char *text)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", root, rel);
    for (char *s = p + strlen(root) + 1; (s = strchr(s, '/')); s++) {
        *s = '\0';
        mkdir(p, 0700);
        *s = '/';
    }
    FILE *f = fopen(p, "w");
    if (!f) return;
    fputs(text, f);
    fclose(f);
}

static void probe_fake_tree(void)
{
    char root[] = "/tmp/gtet-memory-XXXXXX";
    TEST_REQUIRE(mkdtemp(root) != NULL, "mkdtemp");
    char proc[256], sys[256];
    snprintf(proc, sizeof proc, "%s/proc", root);
    snprintf(sys, sizeof sys, "%s/sys", root);
    put(root, "proc/meminfo", "MemTotal:  32000000 kB\nMemFree: 1000 kB\nMemAvailable:  2000000 kB\n");
    /* v2: /a has 1000 MB with 600 MB used of which 100 MB inactive cache; /a/b "max" */
    put(root, "proc/self/cgroup", "0::/a/b\n");
    put(root, "sys/fs/cgroup/a/memory.max", "1000000000\n");
    put(root, "sys/fs/cgroup/a/memory.current", "600000000\n");
    put(root, "sys/fs/cgroup/a/memory.stat", "anon 500000000\ninactive_file 100000000\n");
    put(root, "sys/fs/cgroup/a/b/memory.max", "max\n");
    put(root, "sys/fs/cgroup/a/b/memory.current", "400000000\n");
    mem_room room;
    mem_probe(proc, sys, &room);
    TEST_CHECK(room.mem_available == UINT64_C(2000000) * 1024, "MemAvailable %llu",
               (unsigned long long)room.mem_available);
    TEST_CHECK(room.cgroup == 500000000, "v2: %llu", (unsigned long long)room.cgroup);
    /* v1: the memory line among others; the child's unlimited value, the parent's limit */
    put(root, "proc/self/cgroup", "9:pids:/x\n4:cpu,memory:/p/c\n0::/\n");
    put(root, "sys/fs/cgroup/memory/p/memory.limit_in_bytes", "300000000\n");
    put(root, "sys/fs/cgroup/memory/p/memory.usage_in_bytes", "100000000\n");
    put(root, "sys/fs/cgroup/memory/p/memory.stat", "cache 0\ntotal_inactive_file 0\n");
    put(root, "sys/fs/cgroup/memory/p/c/memory.limit_in_bytes", "9223372036854771712\n");
    mem_probe(proc, sys, &room);
    TEST_CHECK(room.cgroup == 200000000, "v1: %llu", (unsigned long long)room.cgroup);
    /* nothing readable: no limit */
    put(root, "proc/self/cgroup", "0::/nowhere\n");
    mem_probe(proc, sys, &room);
    TEST_CHECK(room.cgroup == UINT64_MAX, "no cgroup files: %llu", (unsigned long long)room.cgroup);
    char cmd[512];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    TEST_CHECK(system(cmd) == 0, "cleanup");
    /* the real machine: MemAvailable is there on Linux */
    mem_probe("/proc", "/sys", &room);
    TEST_CHECK(room.mem_available > 0 && room.mem_available < UINT64_MAX, "real MemAvailable");
}

static void triangulate_refuses(void)
{
    const size_t n = 5000;
    double *xyz = malloc(3 * n * sizeof *xyz);
    TEST_REQUIRE(xyz != NULL, "allocation");
    tu_rng rng = {11};
    for (size_t i = 0; i < 3 * n; i++) xyz[i] = tu_uniform(&rng);
    gtet_options o;
    gtet_error err;
    gtet_options_init(&o);
    TEST_CHECK(o.memory_limit == 0, "default: against the machine");
    o.error = &err;
    o.memory_limit = 1024;
    gtet_mesh *mesh = (gtet_mesh *)&o;  /* set to NULL on failure */
    gtet_status s = gtet_triangulate(xyz, n, &o, &mesh);
    TEST_CHECK(s == GTET_ERR_OUT_OF_MEMORY && mesh == NULL && strstr(err.message, "needs about"),
               "1 KiB: status %d, %s", (int)s, err.message);
    o.memory_limit = SIZE_MAX;
    s = gtet_triangulate(xyz, n, &o, &mesh);
    TEST_CHECK(s == GTET_OK && mesh && gtet_mesh_num_tets(mesh) > 0, "off: status %d", (int)s);
    gtet_mesh_free(&mesh);
    o.memory_limit = 0;
    s = gtet_triangulate(xyz, n, &o, &mesh);
    TEST_CHECK(s == GTET_OK, "the machine: status %d, %s", (int)s, err.message);
    gtet_mesh_free(&mesh);
    free(xyz);
}

/* With threads the working mesh gets, at once, the capacity the last BRIO round's parallel
 * reserve asks for (build.c kbuild_start: 8 slots a point): growing there would move its
 * arrays off the huge pages they were aligned to (kmesh.c first_arrays; 1M -t 2 peaked at
 * 412 MB RSS instead of 290).  The stats' kernel_peak_bytes is the capacity's 32 B a slot plus
 * 29 B a point, so it tells whether the arrays grew: they did at 1.5x when the first capacity
 * was 7 slots a point. */
static void capacity_slots(const double *xyz, size_t n, int threads, size_t *slots)
{
    *slots = SIZE_MAX;
    gtet_options o;
    gtet_options_init(&o);
    o.threads = threads;
    gtet_mesh *mesh = NULL;
    gtet_status s = gtet_triangulate(xyz, n, &o, &mesh);
    TEST_REQUIRE(s == GTET_OK, "status %d", (int)s);
    gtet_stats st;
    gtet_mesh_stats(mesh, &st);
    const size_t nv = gtet_mesh_num_vertices(mesh);
    gtet_mesh_free(&mesh);
    *slots = (st.peak_bytes - 29 * nv) / 32;
}

static void parallel_run_does_not_grow(void)
{
    const size_t n = 100000;
    double *xyz = malloc(3 * n * sizeof *xyz);
    TEST_REQUIRE(xyz != NULL, "allocation");
    tu_rng rng = {5};
    const size_t first = 8 * n + 64 + 2 * 2 * 4096;
    for (int kind = 0; kind < 3; kind++) {
        for (size_t i = 0; i < n; i++) {
            double *p = xyz + 3 * i;
            for (int k = 0; k < 3; k++) p[k] = tu_uniform(&rng);
            if (kind == 1 && i % 2)  /* half the points in a 1e-3 cube */
                for (int k = 0; k < 3; k++) p[k] = 0.5 + 1e-3 * p[k];
            if (kind == 2) {  /* on a sphere: scaled to radius 1 (rounding keeps most off it) */
                const double r = sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
                for (int k = 0; k < 3; k++) p[k] = r > 0 ? p[k] / r : 1.0;
            }
        }
        size_t cap;
        capacity_slots(xyz, n, 2, &cap);
        TEST_CHECK(cap <= first, "kind %d: the mesh grew to %.2f slots a point (first %.2f)",
                   kind, (double)cap / n, (double)first / n);
    }
    free(xyz);
}

/* The VmFlags of the mapping holding p (/proc/self/smaps), or "" when not found. */
static void vm_flags(const void *p, char *flags, size_t size)
{
    flags[0] = 0;
    FILE *f = fopen("/proc/self/smaps", "r");
    if (!f) return;
    char line[512];
    int inside = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned long lo, hi;
        if (sscanf(line, "%lx-%lx ", &lo, &hi) == 2 && strchr(line, '-') < strchr(line, ' '))
            inside = (uintptr_t)p >= lo && (uintptr_t)p < hi;
        else if (inside && strncmp(line, "VmFlags:", 8) == 0) {
            const size_t len = strlen(line + 8);
            memcpy(flags, line + 8, len < size ? len + 1 : size);
            flags[size - 1] = 0;
            break;
        }
    }
    fclose(f);
}

/* base_alloc_huge: from 4 MiB on, a 2 MiB boundary and huge pages asked for over the whole
 * block (smaps flag "hg"); below, plain memory. */
static void big_blocks_ask_for_huge_pages(void)
{
    if (access("/sys/kernel/mm/transparent_hugepage/enabled", F_OK) != 0) {
        printf("  (no transparent huge pages here: skipped)\n");
        return;
    }
    setenv("GTET_HUGEPAGES", "on", 1);  /* the automatic choice is tested below */
    base_page_mode_reset();
    const size_t big = (size_t)9 << 20;
    char *p = base_alloc_huge(big);
    TEST_REQUIRE(p != NULL, "allocation");
    TEST_CHECK((uintptr_t)p % ((uintptr_t)2 << 20) == 0, "not on a 2 MiB boundary: %p", (void *)p);
    char flags[256];
    vm_flags(p, flags, sizeof flags);
    TEST_CHECK(strstr(flags, " hg") != NULL, "first byte: VmFlags%s", flags);
    vm_flags(p + big - 1, flags, sizeof flags);
    TEST_CHECK(strstr(flags, " hg") != NULL, "last byte: VmFlags%s", flags);
    free(p);
    /* base_alloc_big: the same block from BASE_BIG_MIN on, plain malloc below */
    p = base_alloc_big(BASE_BIG_MIN);
    TEST_REQUIRE(p != NULL, "allocation");
    TEST_CHECK((uintptr_t)p % ((uintptr_t)2 << 20) == 0, "big: not on a 2 MiB boundary");
    vm_flags(p, flags, sizeof flags);
    TEST_CHECK(strstr(flags, " hg") != NULL, "big: VmFlags%s", flags);
    free(p);
    /* GTET_HUGEPAGES=off: the same blocks advised against huge pages (NOTES.md E162) */
    setenv("GTET_HUGEPAGES", "off", 1);
    base_page_mode_reset();
    p = base_alloc_huge(big);
    TEST_REQUIRE(p != NULL, "allocation");
    vm_flags(p, flags, sizeof flags);
    TEST_CHECK(strstr(flags, " hg") == NULL && strstr(flags, " nh") != NULL,
               "GTET_HUGEPAGES=off: VmFlags%s", flags);
    free(p);
    /* the decision is kept: changing the environment afterwards changes nothing */
    setenv("GTET_HUGEPAGES", "on", 1);
    TEST_CHECK(base_page_mode() == BASE_PAGES_SMALL, "the decision was not kept");
    /* unset (auto): small pages exactly when a 4 KiB fault was measured cheap (hugepages.c;
     * measured only on a guest that reports free memory to its host), and the blocks advised
     * as decided (NOTES.md E163) */
    unsetenv("GTET_HUGEPAGES");
    base_page_mode_reset();
    const int mode = base_page_mode();
    const double us = base_small_fault_us();
    printf("  auto: %s pages (4 KiB fault %.2f us%s)\n", mode == BASE_PAGES_SMALL ? "4 KiB" : "huge",
           us, us < 0 ? ": not measured, no free page reporting seen" : "");
    TEST_CHECK(mode == (us >= 0 && us < 5.0 ? BASE_PAGES_SMALL : BASE_PAGES_HUGE),
               "auto chose %d with a 4 KiB fault of %.2f us", mode, us);
    p = base_alloc_huge(big);
    TEST_REQUIRE(p != NULL, "allocation");
    vm_flags(p, flags, sizeof flags);
    TEST_CHECK(strstr(flags, mode == BASE_PAGES_SMALL ? " nh" : " hg") != NULL,
               "auto (%d): VmFlags%s", mode, flags);
    free(p);
    /* a run larger than the memory 4 KiB faults take without the host switches an automatic
     * choice of 4 KiB pages to huge pages, and the next small run back (NOTES.md E168) */
    const uint64_t pool = base_page_pool_bytes();
    printf("  pool of never-reported free memory and page cache: %.2f GiB\n",
           pool == UINT64_MAX ? -1.0 : (double)pool / 1073741824.0);
    base_page_run(SIZE_MAX / 2);
    TEST_CHECK(base_page_mode() == BASE_PAGES_HUGE, "a run past every pool: mode %d", base_page_mode());
    if (mode == BASE_PAGES_SMALL) {
        TEST_CHECK(pool > 0 && pool != UINT64_MAX, "the pool was not read: %llu",
                   (unsigned long long)pool);
        p = base_alloc_huge(big);
        TEST_REQUIRE(p != NULL, "allocation");
        vm_flags(p, flags, sizeof flags);
        TEST_CHECK(strstr(flags, " hg") != NULL, "a big run's block: VmFlags%s", flags);
        free(p);
    }
    base_page_run(0);
    TEST_CHECK(base_page_mode() == mode, "a small run after it: mode %d, not %d", base_page_mode(),
               mode);
    /* a forced choice is never switched */
    setenv("GTET_HUGEPAGES", "off", 1);
    base_page_mode_reset();
    base_page_run(SIZE_MAX / 2);
    TEST_CHECK(base_page_mode() == BASE_PAGES_SMALL, "GTET_HUGEPAGES=off switched by a big run");
    unsetenv("GTET_HUGEPAGES");
    base_page_mode_reset();
}

/* base_populate maps the whole pages inside its range, and only those. */
static void populate_maps_whole_pages(void)
{
    const size_t page = 4096, n = 64;
    unsigned char *p = mmap(NULL, n * page, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                            -1, 0);
    TEST_REQUIRE(p != MAP_FAILED, "mmap");
    (void)madvise(p, n * page, MADV_NOHUGEPAGE);  /* so that residency is per 4 KiB page */
    unsigned char in[64];
    TEST_REQUIRE(mincore(p, n * page, in) == 0, "mincore");
    size_t before = 0;
    for (size_t i = 0; i < n; i++) before += in[i] & 1;
    TEST_CHECK(before == 0, "%zu pages resident before", before);
    if (base_populate(p + 100, n * page - 200) != 0) {
        printf("  (MADV_POPULATE_WRITE not supported here: skipped)\n");
        munmap(p, n * page);
        return;
    }
    TEST_REQUIRE(mincore(p, n * page, in) == 0, "mincore");
    for (size_t i = 0; i < n; i++) {
        const int want = i > 0 && i + 1 < n;  /* the partial first and last pages are not whole */
        TEST_CHECK((in[i] & 1) == want, "page %zu resident %d, want %d", i, in[i] & 1, want);
    }
    TEST_CHECK(p[page] == 0 && p[(n - 1) * page - 1] == 0, "populated pages not zero");
    munmap(p, n * page);
}

/* gtet_triangulate_wide (src/mesh/mesh.h): the same mesh as gtet_triangulate, its tet and
 * neighbour arrays handed over with room for 8 * (4 * n_tets + 1) bytes each, which the
 * distributed mode widens its result into where they lie (src/mpi/mpi_output.c, NOTES.md
 * E130); gtet_triangulate's own stay shrunk to the tets (16 B a tet).  Uniform points fit the
 * first capacity (7 slots a point); points on a paraboloid (~15 tets a point) grow the arrays
 * (kmesh.c km_reserve), which must keep the room too.  gtet_triangulate_wide_distinct on the
 * uniform (distinct) points: the same mesh, vertex i = point i. */
static void wide_arrays_keep_room(void)
{
    const size_t n = 20000;
    double *xyz = malloc(3 * n * sizeof *xyz);
    TEST_REQUIRE(xyz != NULL, "allocation");
    tu_rng rng = {11};
    for (int kind = 0; kind < 2; kind++) {
        for (size_t i = 0; i < n; i++) {
            double *p = xyz + 3 * i;
            for (int k = 0; k < 3; k++) p[k] = tu_uniform(&rng);
            if (kind == 1) {  /* on the paraboloid z = x^2 + y^2, exactly: integers */
                p[0] = floor(p[0] * 1024);
                p[1] = floor(p[1] * 1024);
                p[2] = p[0] * p[0] + p[1] * p[1];
            }
        }
        gtet_options o;
        gtet_options_init(&o);
        o.threads = 1;
        gtet_mesh *plain = NULL, *wide = NULL;
        TEST_REQUIRE(gtet_triangulate(xyz, n, &o, &plain) == GTET_OK, "kind %d: plain", kind);
        TEST_REQUIRE(gtet_triangulate_wide(xyz, n, &o, &wide) == GTET_OK, "kind %d: wide", kind);
        const size_t nt = gtet_mesh_num_tets(plain);
        TEST_REQUIRE(nt > 0 && gtet_mesh_num_tets(wide) == nt, "kind %d: %zu and %zu tets", kind,
                     nt, gtet_mesh_num_tets(wide));
        TEST_CHECK(kind == 0 || nt > 8 * n, "kind %d: %zu tets do not grow the arrays", kind, nt);
        TEST_CHECK(memcmp(gtet_mesh_tets(plain), gtet_mesh_tets(wide), 16 * nt) == 0 &&
                       memcmp(gtet_mesh_neighbors(plain), gtet_mesh_neighbors(wide), 16 * nt) == 0,
                   "kind %d: the meshes differ", kind);
#if defined(__GLIBC__)
        const size_t room = 8 * (4 * nt + 1);
        TEST_CHECK(malloc_usable_size(wide->tets) >= room &&
                       malloc_usable_size(wide->neighbors) >= room,
                   "kind %d: wide arrays of %zu and %zu bytes, %zu needed", kind,
                   malloc_usable_size(wide->tets), malloc_usable_size(wide->neighbors), room);
        TEST_CHECK(malloc_usable_size(plain->tets) < room / 2 + 4096 &&
                       malloc_usable_size(plain->neighbors) < room / 2 + 4096,
                   "kind %d: plain arrays of %zu and %zu bytes for %zu tets", kind,
                   malloc_usable_size(plain->tets), malloc_usable_size(plain->neighbors), nt);
#endif
        if (kind == 0) {  /* distinct points: gtet_triangulate_wide_distinct, the same mesh */
            gtet_mesh *dist = NULL;
            TEST_REQUIRE(gtet_triangulate_wide_distinct(xyz, n, &o, &dist) == GTET_OK &&
                             gtet_mesh_num_tets(dist) == nt &&
                             gtet_mesh_num_vertices(dist) == n,
                         "distinct: a mesh of %zu tets", nt);
            const uint32_t *map = gtet_mesh_input_map(dist);
            size_t bad = 0;
            for (size_t i = 0; i < n; i++) bad += map[i] != i;
            TEST_CHECK(bad == 0 && memcmp(gtet_mesh_vertices(dist), xyz, 24 * n) == 0,
                       "distinct: %zu input map entries not the identity, or other vertices", bad);
            TEST_CHECK(memcmp(gtet_mesh_tets(plain), gtet_mesh_tets(dist), 16 * nt) == 0 &&
                           memcmp(gtet_mesh_neighbors(plain), gtet_mesh_neighbors(dist),
                                  16 * nt) == 0,
                       "distinct: the meshes differ");
            gtet_mesh_free(&dist);
        }
        gtet_mesh_free(&plain);
        gtet_mesh_free(&wide);
    }
    free(xyz);
}

/* A block the readers are about to fill (a text file read whole, a pipe's next doubling) fits
 * only within every limit; the refusal names the tightest (NOTES.md E161). */
static void block_fits_names_the_limit(void)
{
    const mem_room none = {UINT64_MAX, UINT64_MAX, UINT64_MAX, UINT64_MAX};
    char why[96] = "";
    TEST_CHECK(mem_block_fits(&none, (uint64_t)1 << 50, why, sizeof why), "no limit: fits");
    mem_room r = none;
    r.mem_available = 512 * MIB;
    TEST_CHECK(mem_block_fits(&r, 512 * MIB, why, sizeof why), "exactly MemAvailable fits");
    TEST_CHECK(!mem_block_fits(&r, 513 * MIB, why, sizeof why) &&
                   strcmp(why, "512.0 MiB available (MemAvailable)") == 0, "MemAvailable: '%s'", why);
    r.cgroup = 100 * MIB;
    TEST_CHECK(!mem_block_fits(&r, 200 * MIB, why, sizeof why) &&
                   strcmp(why, "100.0 MiB available (cgroup memory limit)") == 0, "cgroup: '%s'", why);
    r.rlimit_as = 80 * MIB;
    TEST_CHECK(!mem_block_fits(&r, 90 * MIB, why, sizeof why) &&
                   strcmp(why, "80.0 MiB available (RLIMIT_AS, ulimit -v)") == 0, "as: '%s'", why);
    r.rlimit_data = 70 * MIB;
    TEST_CHECK(!mem_block_fits(&r, 90 * MIB, why, sizeof why) &&
                   strcmp(why, "70.0 MiB available (RLIMIT_DATA, ulimit -d)") == 0, "data: '%s'", why);
    TEST_CHECK(mem_block_fits(&r, 70 * MIB, why, sizeof why), "within every limit: fits");
}

int main(void)
{
    TU_RUN(estimate_shape);
    TU_RUN(thread_count_capped);
    TU_RUN(guard_names_the_limit);
    TU_RUN(guard_credits_the_freed_input);
    TU_RUN(growth_is_cut_or_refused);
    TU_RUN(probe_fake_tree);
    TU_RUN(triangulate_refuses);
    TU_RUN(parallel_run_does_not_grow);
    TU_RUN(big_blocks_ask_for_huge_pages);
    TU_RUN(populate_maps_whole_pages);
    TU_RUN(wide_arrays_keep_room);
    TU_RUN(block_fits_names_the_limit);
    return tu_finish();
}
