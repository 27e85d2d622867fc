/* write.c -- the point writers (.xyz .node .ply .bin) and mesh writers (.ele+.node, .msh, .vtu).
 *
 * Every writer goes through io_out (io_common.c): a temporary beside the destination, renamed
 * into place only when everything was written and closed without error, removed otherwise.
 * Doubles are printed with "%.17g" (17 significant digits identify a binary64 uniquely, so a
 * correctly rounded strtod returns the same bits, -0.0 included); binary formats store the
 * little-endian bytes of the doubles, assembled explicitly.
 *
 * Index bases: TetGen files are 1-based (TetGen's own default; TetGen and meshio take the base
 * from the first node id); Gmsh node tags are 1-based by definition; VTK connectivity is
 * 0-based.  Tets are written as given: gigatet's tets have orient3d > 0, the orientation of
 * Gmsh's and VTK's reference tetrahedron (0,0,0),(1,0,0),(0,1,0),(0,0,1), and of TetGen's output.
 */
#define _POSIX_C_SOURCE 200809L   /* newlocale, uselocale */
#include "io_internal.h"

#include <locale.h>
#include <stdlib.h>
#include <string.h>

/* Numbers are written in the C locale whatever the program set: under a locale with a decimal
 * comma (Python's locale.setlocale(LC_ALL, "de_DE.UTF-8")) "%.17g" wrote 0,5118, a file
 * every reader takes as junk, with success (NOTES.md E159f).  Per thread (uselocale), so
 * other threads of the program keep theirs. */
typedef struct c_numeric {
    locale_t c, old;
} c_numeric;

static void c_numeric_enter(c_numeric *l)
{
    l->c = newlocale(LC_NUMERIC_MASK, "C", (locale_t)0);
    l->old = l->c ? uselocale(l->c) : (locale_t)0;
}

static void c_numeric_leave(c_numeric *l)
{
    if (!l->c) return;
    uselocale(l->old);
    freelocale(l->c);
}

static char *fmt_d(char *p, double v)
{
    return p + snprintf(p, 32, "%.17g", v);
}

static void put_le64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; i++) p[i] = (unsigned char)(v >> (8 * i));
}

static void put_double(unsigned char *p, double d)
{
    uint64_t u;
    memcpy(&u, &d, 8);
    put_le64(p, u);
}

/* "[prefix]x y z\n" into line; returns its length. */
static size_t point_line(char *line, const char *prefix, const double *x)
{
    char *p = line;
    size_t pl = strlen(prefix);
    memcpy(p, prefix, pl);
    p += pl;
    p = fmt_d(p, x[0]);
    *p++ = ' ';
    p = fmt_d(p, x[1]);
    *p++ = ' ';
    p = fmt_d(p, x[2]);
    *p++ = '\n';
    return (size_t)(p - line);
}

/* Vertex lines "ID x y z\n" with ID = i + base. */
static void write_id_points(FILE *f, const double *xyz, size_t n, uint64_t base)
{
    char line[160], id[32];
    for (size_t i = 0; i < n; i++) {
        char *e = io_fmt_u64(id, i + base);
        *e++ = ' ';
        *e = '\0';
        fwrite(line, 1, point_line(line, id, xyz + 3 * i), f);
    }
}

static void write_binary_doubles(FILE *f, const double *xyz, size_t n)
{
    unsigned char b[24 * 256];
    for (size_t i = 0; i < 3 * n;) {
        size_t k = 0;
        for (; k < 3 * 256 && i < 3 * n; k++, i++) put_double(b + 8 * k, xyz[i]);
        fwrite(b, 8, k, f);
    }
}

static io_status write_points(const char *path, const double *xyz, size_t n, io_error *err)
{
    io_format fmt = io_format_of(path);
    char list[128];
    if (!io_format_can(fmt, IO_WRITE_POINTS))
        return io_fail(err, IO_ERR_ARGUMENT, "%s: unknown point file extension (use %s)", path,
                       io_format_list(IO_WRITE_POINTS, 0, list, sizeof list));
    io_out o;
    io_status s = io_out_open(&o, path, err);
    if (s != IO_OK) return s;
    char line[160];
    switch (fmt) {
    case IO_FMT_XYZ:
        fprintf(o.f, "# %zu points written by gigatet (x y z)\n", n);
        for (size_t i = 0; i < n; i++) fwrite(line, 1, point_line(line, "", xyz + 3 * i), o.f);
        break;
    case IO_FMT_NODE:
        fprintf(o.f, "%zu 3 0 0\n", n);
        write_id_points(o.f, xyz, n, 1);
        fprintf(o.f, "# written by gigatet\n");
        break;
    case IO_FMT_PLY:
        fprintf(o.f, "ply\nformat binary_little_endian 1.0\ncomment written by gigatet\n"
                "element vertex %zu\nproperty double x\nproperty double y\nproperty double z\n"
                "end_header\n", n);
        write_binary_doubles(o.f, xyz, n);
        break;
    default: {
        unsigned char h[8];
        put_le64(h, (uint64_t)n);
        fwrite(h, 1, 8, o.f);
        write_binary_doubles(o.f, xyz, n);
        break;
    }
    }
    if ((s = io_out_close(&o, err)) != IO_OK) return s;
    return io_out_commit(&o, err);
}

/* ---- meshes ------------------------------------------------------------------------------ */

char *io_ele_node_path(const char *path)
{
    io_format fmt = io_format_of(path);
    if (fmt != IO_FMT_ELE) return NULL;
    const io_format_info *f = &io_formats[fmt - 1];
    size_t l = strlen(path), le = strlen(f->ext), lc = strlen(f->companion);
    char *p = malloc(l - le + lc + 1);
    if (!p) return NULL;
    memcpy(p, path, l - le);
    memcpy(p + l - le, f->companion, lc + 1);
    /* MESH.ELE's companion is MESH.NODE (tools on case-insensitive file systems write both
     * in capitals; on Linux MESH.node is another name, which failed with "cannot open") */
    int upper = 1;
    for (size_t i = l - le + 1; i < l; i++) upper &= path[i] >= 'A' && path[i] <= 'Z';
    for (size_t i = l - le + 1; upper && i < l - le + lc; i++)
        p[i] = (char)(p[i] - 'a' + 'A');
    return p;
}

/* Tet lines "[ID ]a b c d\n" with vertex ids + base. */
static void write_tets(FILE *f, const uint32_t *tets, size_t nt, int with_id, uint64_t id0,
                       uint64_t base, const char *prefix)
{
    char line[128];
    size_t pl = strlen(prefix);
    for (size_t t = 0; t < nt; t++) {
        char *p = line;
        if (with_id) {
            p = io_fmt_u64(p, t + id0);
            *p++ = ' ';
        }
        memcpy(p, prefix, pl);
        p += pl;
        for (int k = 0; k < 4; k++) {
            p = io_fmt_u64(p, tets[4 * t + (size_t)k] + base);
            *p++ = k < 3 ? ' ' : '\n';
        }
        fwrite(line, 1, (size_t)(p - line), f);
    }
}

static void write_msh(FILE *f, const double *v, size_t nv, const uint32_t *tets, size_t nt)
{
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) {
            double x = v[3 * i + (size_t)c];
            if (i == 0 || x < lo[c]) lo[c] = x;
            if (i == 0 || x > hi[c]) hi[c] = x;
        }
    fprintf(f, "$MeshFormat\n4.1 0 %zu\n$EndMeshFormat\n", sizeof(size_t));
    /* One volume entity (tag 1), no physical tags, no bounding surfaces. */
    fprintf(f, "$Entities\n0 0 0 1\n1 %.17g %.17g %.17g %.17g %.17g %.17g 0 0\n$EndEntities\n",
            lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
    fprintf(f, "$Nodes\n1 %zu 1 %zu\n3 1 0 %zu\n", nv, nv, nv);
    char line[32];
    for (size_t i = 0; i < nv; i++) {
        char *p = io_fmt_u64(line, i + 1);
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), f);
    }
    char pl[160];
    for (size_t i = 0; i < nv; i++) fwrite(pl, 1, point_line(pl, "", v + 3 * i), f);
    fprintf(f, "$EndNodes\n$Elements\n1 %zu 1 %zu\n3 1 4 %zu\n", nt, nt, nt);
    write_tets(f, tets, nt, 1, 1, 1, "");
    fprintf(f, "$EndElements\n");
}

static void write_vtu(FILE *f, const double *v, size_t nv, const uint32_t *tets, size_t nt)
{
    fprintf(f, "<?xml version=\"1.0\"?>\n"
            "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
            "<UnstructuredGrid>\n<Piece NumberOfPoints=\"%zu\" NumberOfCells=\"%zu\">\n"
            "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n",
            nv, nt);
    char pl[160];
    for (size_t i = 0; i < nv; i++) fwrite(pl, 1, point_line(pl, "", v + 3 * i), f);
    fprintf(f, "</DataArray>\n</Points>\n<Cells>\n"
            "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n");
    write_tets(f, tets, nt, 0, 0, 0, "");
    fprintf(f, "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n");
    char line[32];
    for (size_t t = 0; t < nt; t++) {
        char *p = io_fmt_u64(line, 4 * (uint64_t)(t + 1));
        *p++ = '\n';
        fwrite(line, 1, (size_t)(p - line), f);
    }
    fprintf(f, "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n");
    for (size_t t = 0; t < nt; t++) fputs("10\n", f);
    fprintf(f, "</DataArray>\n</Cells>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

static io_status write_mesh(const char *path, const double *vertices, size_t nv,
                            const uint32_t *tets, size_t nt, io_error *err)
{
    io_format fmt = io_format_of(path);
    char list[128];
    if (!io_format_can(fmt, IO_WRITE_MESH))
        return io_fail(err, IO_ERR_ARGUMENT, "%s: unknown mesh file extension (use %s)", path,
                       io_format_list(IO_WRITE_MESH, 0, list, sizeof list));
    io_out o, on = {0};
    io_status s;
    char *node_path = NULL;
    if (fmt == IO_FMT_ELE) {
        node_path = io_ele_node_path(path);
        if (!node_path) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
        if ((s = io_out_open(&on, node_path, err)) != IO_OK) {
            free(node_path);
            return s;
        }
        fprintf(on.f, "%zu 3 0 0\n", nv);
        write_id_points(on.f, vertices, nv, 1);
        fprintf(on.f, "# written by gigatet\n");
        if ((s = io_out_close(&on, err)) != IO_OK) {
            free(node_path);
            return s;
        }
    }
    if ((s = io_out_open(&o, path, err)) != IO_OK) goto fail;
    if (fmt == IO_FMT_ELE) {
        fprintf(o.f, "%zu 4 0\n", nt);
        write_tets(o.f, tets, nt, 1, 1, 1, "");
        fprintf(o.f, "# written by gigatet\n");
    } else if (fmt == IO_FMT_MSH) {
        write_msh(o.f, vertices, nv, tets, nt);
    } else {
        write_vtu(o.f, vertices, nv, tets, nt);
    }
    if ((s = io_out_close(&o, err)) != IO_OK) goto fail;
    if (fmt == IO_FMT_ELE) {
        /* Both files are complete: rename .node, then .ele; if the second rename fails,
         * take the first one back out so that no half mesh is left. */
        if ((s = io_out_commit(&on, err)) != IO_OK) {
            io_out_abort(&o);
            goto fail;
        }
        if ((s = io_out_commit(&o, err)) != IO_OK) {
            remove(node_path);
            goto fail;
        }
        free(node_path);
        return IO_OK;
    }
    return io_out_commit(&o, err);
fail:
    io_out_abort(&on);
    free(node_path);
    return s;
}

io_status io_write_points(const char *path, const double *xyz, size_t n, io_error *err)
{
    c_numeric l;
    c_numeric_enter(&l);
    io_status s = write_points(path, xyz, n, err);
    c_numeric_leave(&l);
    return s;
}

io_status io_write_mesh(const char *path, const double *vertices, size_t nv,
                        const uint32_t *tets, size_t nt, io_error *err)
{
    c_numeric l;
    c_numeric_enter(&l);
    io_status s = write_mesh(path, vertices, nv, tets, nt, err);
    c_numeric_leave(&l);
    return s;
}
