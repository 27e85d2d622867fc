/* testutil.c -- see testutil.h. */
#include "testutil.h"

#include <stdarg.h>

int tu_current_failed;
static int tu_passed, tu_failed;
static const char *tu_name = "(none)";

void tu_fail(const char *file, int line, const char *fmt, ...)
{
    va_list ap;
    if (tu_current_failed < 20) {
        fprintf(stderr, "FAIL %s (%s:%d): ", tu_name, file, line);
        va_start(ap, fmt);
        vfprintf(stderr, fmt, ap);
        va_end(ap);
        fputc('\n', stderr);
    }
    tu_current_failed++;
}

void tu_run(const char *name, void (*fn)(void))
{
    tu_name = name;
    tu_current_failed = 0;
    fn();
    if (tu_current_failed) {
        tu_failed++;
        fprintf(stderr, "FAILED %s (%d checks)\n", name, tu_current_failed);
    } else {
        tu_passed++;
        printf("ok %s\n", name);
    }
}

int tu_finish(void)
{
    printf("%d passed, %d failed\n", tu_passed, tu_failed);
    fflush(stdout);
    return tu_failed ? 1 : 0;
}
