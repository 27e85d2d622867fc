/* base.h -- what every stage of the library may include (prefix base_): filling a gtet_error,
 * and GTET_DEBUG_ASSERT.  It depends on gigatet.h only.
 *
 * GTET_DEBUG_ASSERT(cond) states an invariant the code relies on and that nothing else checks
 * at run time (a neighbour's back link, ownership before a write, room after a claim).  In
 * builds with GTET_DEBUG defined -- CMake defines it for GTET_SANITIZE, GTET_TSAN and the
 * GTET_DEBUG option -- a false cond calls abort(): those builds exist to stop at the first
 * broken invariant, and the sanitizers' runtime shows where.  The library still prints nothing.
 * Elsewhere (Release) it compiles to nothing and cond is not evaluated; it must have no side
 * effects.
 */
#ifndef GTET_BASE_H
#define GTET_BASE_H

#include <stddef.h>

#include "gigatet.h"

#ifdef GTET_DEBUG
#include <stdlib.h>
#define GTET_DEBUG_ASSERT(cond) ((cond) ? (void)0 : abort())
#define GTET_DEBUG_ON 1
#else
#define GTET_DEBUG_ASSERT(cond) ((void)sizeof((cond) ? 1 : 0))
#define GTET_DEBUG_ON 0
#endif

/* Fill err (if not NULL) with status, index, dimension and a printf-style message. */
void base_error(gtet_error *err, gtet_status status, size_t index, int dimension,
                const char *fmt, ...) __attribute__((format(printf, 5, 6)));

/* Returns s; unless err is NULL or already holds s (a stage said more), fills err with
 * "what: <gtet_status_str(s)>". */
gtet_status base_fail(gtet_error *err, gtet_status s, const char *what);

/* Ask for transparent huge pages on the 2 MiB pages inside [p, p + bytes) (hugepages.c): a
 * hint for the big randomly-read arrays; no effect on anything but speed, none off Linux. */
void base_hugepages(void *p, size_t bytes);

/* The pages base_hugepages asks for: BASE_PAGES_HUGE (MADV_HUGEPAGE) or BASE_PAGES_SMALL
 * (MADV_NOHUGEPAGE).  Decided at the first call of a process and kept: GTET_HUGEPAGES=on / off,
 * else (auto) small pages on a virtual machine that reports its free memory to its host and
 * faults a 4 KiB page cheaply (measured once, ~2 ms), huge pages elsewhere (hugepages.c). */
enum { BASE_PAGES_HUGE = 1, BASE_PAGES_SMALL = 2 };
int base_page_mode(void);

/* The measured cost of a 4 KiB page fault in microseconds, or a negative value when the
 * decision did not measure it (an explicit GTET_HUGEPAGES, or a host that reports nothing). */
double base_small_fault_us(void);

/* A run that will touch about peak_bytes starts: with the automatic choice of 4 KiB pages it
 * switches the big arrays to huge pages when peak_bytes exceeds the memory the guest can
 * fault without its host (base_page_pool_bytes); base_page_mode says so until the next call. */
void base_page_run(size_t peak_bytes);

/* Free memory in blocks below the balloon's reporting order plus the page cache, in bytes
 * (UINT64_MAX when unknown): what 4 KiB faults take without the host (hugepages.c). */
uint64_t base_page_pool_bytes(void);

/* Forget the decision (tests: the next base_page_mode decides again from the environment). */
void base_page_mode_reset(void);

/* malloc for a big array (free/realloc as usual): from 4 MiB on it starts on a 2 MiB boundary
 * and has huge pages asked for (base_hugepages), so that they begin at its first byte; below,
 * plain malloc.  NULL when out of memory (bytes 0: a valid pointer). */
void *base_alloc_huge(size_t bytes);

/* malloc for an array of one entry a point or more: from BASE_BIG_MIN (32 MiB, glibc's largest
 * mmap threshold: from there malloc maps fresh memory anyway) it is base_alloc_huge's block;
 * below, plain malloc, which can reuse what the run freed without raising its peak (NOTES.md
 * E110).  free/realloc as usual. */
#define BASE_BIG_MIN ((size_t)32 << 20)
void *base_alloc_big(size_t bytes);

/* Map [p, p + bytes) now, as if written (MADV_POPULATE_WRITE, Linux 5.14 on; elsewhere
 * nothing): the whole 4 KiB pages inside it, so never memory the caller does not own.  For an
 * array about to be written whose pages are better faulted here (several threads at once, right
 * after memory was freed) than one by one later; the contents do not change.  Returns 0 when
 * the pages are mapped, -1 when the system cannot do it (nothing changed). */
int base_populate(void *p, size_t bytes);

/* The most threads a run uses: the kernel's colours are bytes (build.c, proofs/parallel.md),
 * and validate, sort and the memory guard count no more (NOTES.md E159c). */
#define BASE_MAX_THREADS 255

/* How many threads, the calling one included, of `want` (>= 1) this process can run at once
 * now: it starts want - 1 threads that wait until all are started, then ends and joins them
 * (threads.c).  want when all started; else 1 + those started, with pthread_create's error
 * number in *error (0 otherwise).  Once per process: a count found before is taken as it is
 * (libgomp keeps the threads it started; a probe would count them twice), and once a probe has
 * met the limit every larger request gets the largest count found, with that error.  For the
 * runs' thread counts: libgomp ends the process when it cannot start a parallel region's
 * threads (NOTES.md E183). */
int base_threads_available(int want, int *error);

/* The threads a parallel region with num_threads(want) started by the calling thread gets,
 * dyn-var off (the caller turns it off: with it on, OpenMP may give fewer as it likes): 1 when
 * the region would be inactive (nested inside a parallel region beyond max-active-levels),
 * at most OMP_THREAD_LIMIT at top level, and 1 nested under a thread limit.  The stages split
 * their work by thread number and need every thread they ask for (NOTES.md E184). */
int base_team_size(int want);

#endif
