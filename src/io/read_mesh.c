/* read_mesh.c -- the mesh readers' entry points: io_parse_mesh on bytes in memory (what the
 * fuzzers call) and io_read_mesh on files, which loads the file(s) and calls it.  The
 * formats themselves are in read_ele.c, read_msh.c and read_vtu.c (what each reads: io.h).
 *
 * Every parser sees a copy of its bytes with a NUL after them, so text scanning (strtod
 * included) can never run past the end.  On failure the mesh is freed and zeroed here, so
 * the parsers may return at any point without cleaning up what they stored in it.
 */
#include "io_internal.h"

#include <stdlib.h>
#include <string.h>

void io_mesh_free(io_mesh *m)
{
    if (!m) return;
    free(m->vertices);
    free(m->tets);
    memset(m, 0, sizeof *m);
}

/* A NUL-terminated copy of len bytes. */
static char *copy_nul(const void *data, size_t len)
{
    char *c = len < SIZE_MAX ? malloc(len + 1) : NULL;
    if (!c) return NULL;
    if (len) memcpy(c, data, len);
    c[len] = '\0';
    return c;
}

static io_status unknown_mesh(io_error *err, const char *name)
{
    char list[128];
    return io_fail(err, IO_ERR_INPUT, "%s: unknown mesh file extension (%s are read)", name,
                   io_format_list(IO_READ_MESH, 0, list, sizeof list));
}

/* The parsers on NUL-terminated buffers; nbuf is the .node of an .ele. */
static io_status parse_nul(io_format fmt, const char *name, const char *buf, size_t len,
                           const char *node_name, const char *nbuf, size_t nlen, io_mesh *m,
                           io_error *err)
{
    io_status s;
    if ((s = io_text_encoding(name, buf, len, err)) != IO_OK) return s;
    if (fmt == IO_FMT_ELE && (s = io_text_encoding(node_name, nbuf, nlen, err)) != IO_OK)
        return s;
    switch (fmt) {
    case IO_FMT_ELE: return io_parse_ele(name, buf, len, node_name, nbuf, nlen, m, err);
    case IO_FMT_MSH: return io_parse_msh(name, buf, len, m, err);
    case IO_FMT_VTU: return io_parse_vtu(name, buf, len, m, err);
    default:
        return unknown_mesh(err, name);
    }
}

io_status io_parse_mesh(io_format fmt, const char *name, const void *data, size_t len,
                        const void *node_data, size_t node_len, io_mesh *m, io_error *err)
{
    memset(m, 0, sizeof *m);
    int ele = fmt == IO_FMT_ELE;
    char *node_name = ele ? io_ele_node_path(name) : NULL;
    char *buf = copy_nul(data, len);
    char *nbuf = ele ? copy_nul(node_data, node_data ? node_len : 0) : NULL;
    io_status s;
    if (!buf || (ele && !nbuf))
        s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory for a copy of %zu bytes", name, len);
    else
        s = parse_nul(fmt, name, buf, len, node_name ? node_name : "(the .node data)", nbuf,
                      node_data ? node_len : 0, m, err);
    free(buf);
    free(nbuf);
    free(node_name);
    if (s != IO_OK) io_mesh_free(m);
    return s;
}

io_status io_read_mesh(const char *path, io_mesh *m, io_error *err)
{
    memset(m, 0, sizeof *m);
    io_format fmt = io_format_of(path);
    if (!io_format_can(fmt, IO_READ_MESH)) return unknown_mesh(err, path);
    char *buf = NULL, *nbuf = NULL, *node_path = NULL;
    size_t len = 0, nlen = 0;
    io_status s;
    /* the .ele first, so that a missing mesh is reported under its own name */
    if ((s = io_load_file(path, &buf, &len, err)) != IO_OK) goto out;
    if (fmt == IO_FMT_ELE) {
        if (!(node_path = io_ele_node_path(path))) {
            s = io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
            goto out;
        }
        if ((s = io_load_file(node_path, &nbuf, &nlen, err)) != IO_OK) goto out;
    }
    s = parse_nul(fmt, path, buf, len, node_path, nbuf, nlen, m, err);
out:
    free(buf);
    free(nbuf);
    free(node_path);
    if (s != IO_OK) io_mesh_free(m);
    return s;
}
