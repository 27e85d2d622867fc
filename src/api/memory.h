/* memory.h -- the memory guard of gtet_triangulate (prefix mem_): an estimate of a run's peak
 * memory from its point count and options, what the machine can give, and the decision to
 * refuse a run that cannot fit (GTET_ERR_OUT_OF_MEMORY before any big allocation) instead of
 * letting the kernel's OOM killer end the process.  See memory.c. */
#ifndef GTET_API_MEMORY_H
#define GTET_API_MEMORY_H

#include <stddef.h>
#include <stdint.h>

#include "gigatet.h"

/* A run's peak, in bytes: resident (the pages it touches; compared with MemAvailable and the
 * cgroup's limit) and address space (what it maps, touched or not; compared with RLIMIT_AS and
 * RLIMIT_DATA).  The caller's input array is in neither. */
typedef struct mem_estimate {
    uint64_t resident;
    uint64_t address;
} mem_estimate;

/* The estimate for n points with `threads` worker threads (>= 1) and the options' check and
 * degeneracy record. */
void mem_estimate_run(size_t n, int threads, const gtet_options *opts, mem_estimate *e);

/* What the machine can give: each field is UINT64_MAX when there is no such limit (or it
 * could not be read). */
typedef struct mem_room {
    uint64_t mem_available;  /* /proc/meminfo MemAvailable */
    uint64_t cgroup;         /* the tightest limit - working set of the process's memory
                                cgroup and its ancestors (v2 memory.max, v1
                                memory.limit_in_bytes) */
    uint64_t rlimit_as;      /* RLIMIT_AS - VmSize (ulimit -v) */
    uint64_t rlimit_data;    /* RLIMIT_DATA - VmData (ulimit -d) */
} mem_room;

/* Read the limits above; proc and sys are the roots of procfs and sysfs ("/proc", "/sys"; a
 * test passes a fake tree). */
void mem_probe(const char *proc, const char *sys, mem_room *room);

/* 1 when one more block of `bytes` fits in what room leaves (resident: MemAvailable and the
 * cgroup's limit; address space: RLIMIT_AS and RLIMIT_DATA); else 0, with `why` (why_size
 * bytes) saying "5.2 GiB available (MemAvailable)".  For the readers of files that are loaded
 * whole (src/io: a text file larger than the machine's memory, an endless pipe), which
 * would otherwise be killed by the OOM killer while reading. */
int mem_block_fits(const mem_room *room, uint64_t bytes, char *why, size_t why_size);

/* GTET_OK when a run of n points fits (opts->memory_limit: 0 = against the machine, SIZE_MAX =
 * no guard, else that many bytes); else GTET_ERR_OUT_OF_MEMORY with err's message saying how
 * much it needs, how much is available and which limit bound it. */
gtet_status mem_guard(size_t n, int threads, const gtet_options *opts, gtet_error *err);

/* As mem_guard, against the limits of `room` (the tests' entry point). */
gtet_status mem_guard_room(size_t n, int threads, const gtet_options *opts,
                           const mem_room *room, gtet_error *err);

/* The second check, while the kernel runs (kmesh.h grow_guard): a mesh with more tets per
 * point than the estimate (points on one sphere: 15-22 against 7) grows its arrays past what
 * the first check counted.  Before each such growth the limits are read again and the growth
 * is cut to what they leave (less what the rest of the run needs), or refused when even the slots needed now
 * do not fit: GTET_ERR_OUT_OF_MEMORY, "the mesh outgrew the estimate", instead of the OOM
 * killer.  Only in the guard's default mode (memory_limit 0): an explicit limit or none is the
 * caller's word.  user: a mem_grow. */
typedef struct mem_grow {
    size_t n;           /* the run's distinct points (for the message) */
    gtet_error *err;
    const char *proc, *sys;  /* "/proc", "/sys" (a test passes a fake tree) */
} mem_grow;
gtet_status mem_grow_guard(void *user, size_t used_bytes, size_t cap_bytes, size_t min_bytes,
                           size_t *want_bytes);

/* The decision of mem_grow_guard against the limits of `room` (the tests' entry point). */
gtet_status mem_grow_room(const mem_room *room, size_t n, size_t used_bytes, size_t cap_bytes,
                          size_t min_bytes, size_t *want_bytes, gtet_error *err);

#endif
