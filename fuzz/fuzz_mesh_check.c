/* fuzz_mesh_check.c -- libFuzzer target: the mesh readers of src/io and then the exact checker
 * on whatever they accept, as `gigatet check` runs them on a file from another tool.
 *
 * data[0] % 3 picks the format (.ele + .node, .msh, .vtu).  For .ele the next two bytes are
 * the little-endian length of the .node part, which follows them; the .ele part is the rest
 * (a length past the end takes everything).  Properties: never a crash, leak or undefined
 * behaviour; io_parse_mesh returns either IO_OK with every vertex id below nv and finite
 * coordinates, or an error status with a message and a zeroed mesh; the checker then gives
 * a verdict (GTET_OK or GTET_ERR_CHECK_FAILED, with a message when it fails) or a clean
 * argument / memory error, with flags 0 and with GTET_CHECK_DELAUNAY |
 * GTET_CHECK_ANY_ORIENTATION.  The readers' allocations are bounded by the input size (and
 * zlib's expansion ratio); meshes above FZ_MAX_TETS tets are read but not checked, so one
 * input cannot run for long.
 */
#include "fuzz_common.h"

#include "gigatet.h"
#include "io/io.h"

#define FZ_MAX_TETS 200000u

static void check_mesh(const io_mesh *m, unsigned flags)
{
    gtet_check_report rep;
    memset(&rep, 0, sizeof rep);
    gtet_status gs = gtet_check_arrays(m->vertices, m->nv, m->tets, m->nt, NULL, NULL, 0, flags,
                                       &rep);
    FZ_ASSERT(gs == GTET_OK || gs == GTET_ERR_CHECK_FAILED || gs == GTET_ERR_ARGUMENT ||
              gs == GTET_ERR_OUT_OF_MEMORY || gs == GTET_ERR_TOO_LARGE,
              "gtet_check_arrays(flags %u) returned %d", flags,
              (int)gs);
    FZ_ASSERT(memchr(rep.message, '\0', sizeof rep.message) != NULL, "report message unterminated");
    if (gs == GTET_ERR_CHECK_FAILED || (gs == GTET_OK && !rep.ok))
        FZ_ASSERT(rep.message[0] != '\0', "a failed check (flags %u) without a message", flags);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1) return 0;
    static const io_format fmts[3] = {IO_FMT_ELE, IO_FMT_MSH, IO_FMT_VTU};
    static const char *const names[3] = {"fuzz.ele", "fuzz.msh", "fuzz.vtu"};
    int f = data[0] % 3;
    const uint8_t *body = data + 1, *node = NULL;
    size_t blen = size - 1, nlen = 0;
    if (fmts[f] == IO_FMT_ELE) {
        size_t want = blen >= 2 ? (size_t)body[0] | (size_t)body[1] << 8 : 0;
        body += blen >= 2 ? 2 : blen;
        blen -= blen >= 2 ? 2 : blen;
        nlen = want < blen ? want : blen;
        node = body;
        body += nlen;
        blen -= nlen;
    }
    io_mesh m;
    io_error err;
    err.message[0] = '\0';
    io_status st = io_parse_mesh(fmts[f], names[f], body, blen, node, nlen, &m, &err);
    if (st != IO_OK) {
        FZ_ASSERT(st == IO_ERR_INPUT || st == IO_ERR_NOMEM, "unexpected status %d", (int)st);
        FZ_ASSERT(err.message[0] != '\0' && memchr(err.message, '\0', sizeof err.message),
                  "status %d without a message", (int)st);
        FZ_ASSERT(!m.vertices && !m.tets && m.nv == 0 && m.nt == 0 && m.skipped_cells == 0,
                  "mesh not cleared on failure");
        return 0;
    }
    /* an empty array may be NULL (a .vtu with NumberOfCells="0" and no <Cells>) */
    FZ_ASSERT((m.vertices != NULL || m.nv == 0) && (m.tets != NULL || m.nt == 0),
              "IO_OK without arrays (nv %zu, nt %zu)", m.nv, m.nt);
    for (size_t i = 0; i < 3 * m.nv; i++)
        FZ_ASSERT(isfinite(m.vertices[i]), "IO_OK with a non-finite coordinate at %zu", i);
    for (size_t i = 0; i < 4 * m.nt; i++)
        FZ_ASSERT(m.tets[i] < m.nv, "tet vertex %u out of range (nv %zu)", m.tets[i], m.nv);
    if (m.nt <= FZ_MAX_TETS) {
        check_mesh(&m, 0);
        check_mesh(&m, GTET_CHECK_DELAUNAY | GTET_CHECK_ANY_ORIENTATION);
    }
    io_mesh_free(&m);
    return 0;
}
