/* test_io_formats.c -- the table of file formats (io_formats in src/io/io.h) and what is
 * drawn from it: io_format_of, io_format_can, io_format_list, io_ele_node_path. */
#include <stdlib.h>
#include <string.h>

#include "io/io.h"
#include "testutil.h"

static void test_table_is_indexed_by_format_and_every_extension_maps_back(void)
{
    for (int k = 0; k < IO_FMT_COUNT; k++) {
        const io_format_info *f = &io_formats[k];
        TEST_CHECK(f->fmt == (io_format)(k + 1), "io_formats[%d].fmt is %d", k, (int)f->fmt);
        char name[32], upper[32];
        snprintf(name, sizeof name, "dir.x/a%s", f->ext);
        snprintf(upper, sizeof upper, "A%s", f->ext);
        for (char *p = upper; *p; p++)
            if (*p >= 'a' && *p <= 'z') *p = (char)(*p - 'a' + 'A');
        TEST_CHECK(io_format_of(name) == f->fmt, "%s", name);
        TEST_CHECK(io_format_of(upper) == f->fmt, "%s", upper);
        TEST_CHECK(io_format_of(f->ext) == IO_FMT_UNKNOWN, "a bare extension %s names no file", f->ext);
        TEST_CHECK(f->description && *f->description, "%s has no description", f->ext);
        int points = (f->can & (IO_READ_POINTS | IO_WRITE_POINTS)) != 0;
        int mesh = (f->can & (IO_READ_MESH | IO_WRITE_MESH)) != 0;
        TEST_CHECK(points != mesh, "%s is a point format or a mesh format, not both", f->ext);
    }
    TEST_CHECK(io_format_of("a.stl") == IO_FMT_UNKNOWN && io_format_of(NULL) == IO_FMT_UNKNOWN,
               "unknown extensions");
    TEST_CHECK(!io_format_can(IO_FMT_UNKNOWN, 0) && !io_format_can(IO_FMT_UNKNOWN, IO_READ_MESH),
               "the unknown format can nothing");
}

static void test_capabilities_and_lists(void)
{
    TEST_CHECK(io_format_can(IO_FMT_XYZ, IO_READ_POINTS | IO_WRITE_POINTS), ".xyz");
    TEST_CHECK(!io_format_can(IO_FMT_XYZ, IO_READ_MESH), ".xyz is no mesh");
    TEST_CHECK(io_format_can(IO_FMT_VTU, IO_READ_MESH | IO_WRITE_MESH), ".vtu");
    char b[128];
    TEST_CHECK(!strcmp(io_format_list(IO_READ_POINTS, 0, b, sizeof b),
                       ".xyz, .node, .ply, .bin or .off"), "%s", b);
    TEST_CHECK(!strcmp(io_format_list(IO_READ_SURFACE, 0, b, sizeof b), ".ply or .off"), "%s", b);
    TEST_CHECK(!io_format_can(IO_FMT_OFF, IO_WRITE_POINTS), ".off is not written");
    TEST_CHECK(!strcmp(io_format_list(IO_WRITE_MESH, 0, b, sizeof b), ".ele, .msh or .vtu"), "%s", b);
    TEST_CHECK(!strcmp(io_format_list(IO_READ_MESH, 1, b, sizeof b),
                       ".ele (with its .node), .msh or .vtu"), "%s", b);
    char small[8];
    io_format_list(IO_READ_POINTS, 0, small, sizeof small);
    TEST_CHECK(strlen(small) < sizeof small, "a short buffer is cut and terminated: %s", small);
}

static void test_ele_companion_path(void)
{
    /* the companion's case follows an upper-case extension (NOTES.md E241), else lower */
    static const char *const cases[][2] = {
        {"out/m.ELE", "out/m.NODE"}, {"out/m.ele", "out/m.node"}, {"out/M.Ele", "out/M.node"}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        char *p = io_ele_node_path(cases[i][0]);
        TEST_CHECK(p && !strcmp(p, cases[i][1]), "%s -> %s", cases[i][0], p ? p : "(null)");
        free(p);
    }
    TEST_CHECK(io_ele_node_path("m.vtu") == NULL, "only .ele has a companion");
}

int main(void)
{
    TU_RUN(test_table_is_indexed_by_format_and_every_extension_maps_back);
    TU_RUN(test_capabilities_and_lists);
    TU_RUN(test_ele_companion_path);
    return tu_finish();
}
