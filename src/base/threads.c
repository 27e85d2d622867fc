/* threads.c -- base_threads_available: how many threads this process may run right now;
 * base_team_size: how many a parallel region started here gets from OpenMP.
 *
 * libgomp starts a parallel region's threads with pthread_create and, when one cannot be
 * created (EAGAIN: the user's process limit `ulimit -u`, a cgroup's pids.max, or no address
 * space left for its stack under `ulimit -v`), prints "libgomp: Thread creation failed" and
 * calls exit(1): no status reaches the caller, and a Python interpreter ends with it (NOTES.md
 * E183).  The probe starts the threads a run would ask libgomp for, with the same attributes
 * (the default ones: libgomp sets a stack size only for OMP_STACKSIZE), keeps them all alive at
 * once as libgomp's team does, then lets them end and joins them.
 */
#include <limits.h>
#include <omp.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>

#include "base.h"

typedef struct probe {
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int release;
} probe;

static void *wait_release(void *arg)
{
    probe *p = arg;
    pthread_mutex_lock(&p->mu);
    while (!p->release) pthread_cond_wait(&p->cv, &p->mu);
    pthread_mutex_unlock(&p->mu);
    return NULL;
}

/* The largest count a probe of this process found available, and whether a probe found the
 * limit (with pthread_create's error): asked for no more, or once the limit is known, there is
 * no probe.  libgomp keeps the threads it started in its pool, idle, and starts none while a
 * team fits in it; a second probe would count them twice and find fewer (at the limit, none). */
static atomic_int known_available = 1, limit_error;

int base_threads_available(int want, int *error)
{
    *error = 0;
    int known = atomic_load(&known_available);
    if (want <= known) return want;
    if ((*error = atomic_load(&limit_error)) != 0) return known;
    pthread_t *t = malloc((size_t)(want - 1) * sizeof *t);
    if (!t) return want;  /* nothing known; the run's own allocations will say more */
    probe p = {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0};
    int made = 0;
    while (made < want - 1) {
        int e = pthread_create(&t[made], NULL, wait_release, &p);
        if (e) {
            *error = e;
            break;
        }
        made++;
    }
    pthread_mutex_lock(&p.mu);
    p.release = 1;
    pthread_cond_broadcast(&p.cv);
    pthread_mutex_unlock(&p.mu);
    for (int k = 0; k < made; k++) pthread_join(t[k], NULL);
    free(t);
    int have = made + 1;  /* the calling thread is the team's first */
    while (have > known && !atomic_compare_exchange_weak(&known_available, &known, have)) {
    }
    if (*error) {
        int none = 0;
        atomic_compare_exchange_strong(&limit_error, &none, *error);
    }
    /* fewer than a count found before: libgomp's pool holds that many already */
    return have > known ? have : known;
}

int base_team_size(int want)
{
    if (want <= 1) return 1;
    /* a region at this nesting level would be inactive: one thread (called from inside a
     * user's parallel region with nesting off, or OMP_MAX_ACTIVE_LEVELS=0) */
    const int level = omp_get_active_level();
    if (level >= omp_get_max_active_levels()) return 1;
    /* OMP_THREAD_LIMIT counts every thread of the contention group: at top level this one is
     * the only busy thread; nested, the other teams' are unknown here, so one thread */
    const int limit = omp_get_thread_limit();
    if (limit < INT_MAX && level > 0) return 1;
    return want < limit ? want : limit;
}
