/* test_status.c -- every status has its own non-empty description; option defaults. */
#include <string.h>

#include "gigatet.h"
#include "testutil.h"

static void test_every_status_has_a_distinct_description(void)
{
    for (int s = GTET_OK; s <= GTET_ERR_CANCELLED; s++) {
        const char *d = gtet_status_str((gtet_status)s);
        TEST_CHECK(d && *d, "status %d has no description", s);
        for (int t = GTET_OK; t < s; t++)
            TEST_CHECK(strcmp(d, gtet_status_str((gtet_status)t)) != 0,
                       "statuses %d and %d share a description", s, t);
    }
    TEST_CHECK(strcmp(gtet_status_str((gtet_status)999), "unknown status") == 0,
               "an out-of-range status is not called unknown");
}

static void test_options_init_gives_documented_defaults(void)
{
    gtet_options o;
    memset(&o, 0x5a, sizeof o);
    gtet_options_init(&o);
    TEST_CHECK(o.threads == 0 && o.verbosity == 0 && o.check == 0, "defaults differ");
    TEST_CHECK(o.progress == NULL && o.message == NULL && o.error == NULL, "callbacks not NULL");
}

int main(void)
{
    TU_RUN(test_every_status_has_a_distinct_description);
    TU_RUN(test_options_init_gives_documented_defaults);
    return tu_finish();
}
