/* thread_shim.c -- an LD_PRELOAD stand-in for a process limit on threads, for the tests of
 * NOTES.md E183 (tests/threads.cmake): without root, `ulimit -u` cannot be tested (root's
 * processes ignore it), and a real limit cannot fail one chosen pthread_create.
 *
 *   GTET_SHIM_MAX_LIVE=L   pthread_create fails with EAGAIN while L threads it started are
 *                          alive (as RLIMIT_NPROC does; a thread counts until its start
 *                          routine returns -- libgomp's pool threads never return)
 *   GTET_SHIM_FAIL_FROM=K  the K-th call (from 1) and every later one fail with EAGAIN
 *
 * Every call goes to the next pthread_create (glibc's) otherwise.
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>

typedef int (*create_fn)(pthread_t *, const pthread_attr_t *, void *(*)(void *), void *);

static atomic_int live, calls;

typedef struct start {
    void *(*fn)(void *);
    void *arg;
} start;

static void *run(void *p)
{
    start s = *(start *)p;
    free(p);
    void *r = s.fn(s.arg);
    atomic_fetch_sub(&live, 1);
    return r;
}

static long env(const char *name)
{
    const char *v = getenv(name);
    return v && *v ? strtol(v, NULL, 10) : -1;
}

int pthread_create(pthread_t *t, const pthread_attr_t *attr, void *(*fn)(void *), void *arg)
{
    static create_fn next;
    if (!next) {  /* ISO C has no cast from an object pointer to a function pointer */
        void *sym = dlsym(RTLD_NEXT, "pthread_create");
        memcpy(&next, &sym, sizeof next);
    }
    if (!next) return EAGAIN;
    const long max_live = env("GTET_SHIM_MAX_LIVE"), fail_from = env("GTET_SHIM_FAIL_FROM");
    const int call = atomic_fetch_add(&calls, 1) + 1;
    if (fail_from > 0 && call >= fail_from) return EAGAIN;
    if (max_live >= 0 && atomic_fetch_add(&live, 1) >= max_live) {
        atomic_fetch_sub(&live, 1);
        return EAGAIN;
    }
    if (max_live < 0) atomic_fetch_add(&live, 1);
    start *s = malloc(sizeof *s);
    if (!s) {
        atomic_fetch_sub(&live, 1);
        return EAGAIN;
    }
    s->fn = fn;
    s->arg = arg;
    int e = next(t, attr, run, s);
    if (e) {
        free(s);
        atomic_fetch_sub(&live, 1);
    }
    return e;
}
