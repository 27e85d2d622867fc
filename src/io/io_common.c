/* io_common.c -- the table of formats, errors, whole-file loading, text tokens, atomic
 * output files and the point readers' dispatch of io.h.
 *
 * Atomic output: io_out_open creates "PATH.tmp-PID-N" with O_CREAT|O_EXCL (never reusing or
 * following an existing file; the process umask applies as to any new file), io_out_close
 * flushes and closes it and reports any write error (a full disk shows up at the latest in
 * fclose), io_out_commit renames it onto PATH (rename within one directory is atomic on
 * POSIX).  Any failure unlinks the temporary, so the destination is either the complete new
 * file or untouched.
 */
#define _POSIX_C_SOURCE 200809L
#include "io_internal.h"

#include "../api/memory.h"

#include <ctype.h>
#include <errno.h>
#include <stdatomic.h>
#include <fcntl.h>
#include <limits.h>
#include <math.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

io_status io_fail(io_error *err, io_status status, const char *fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
        err->status = status;
    }
    return status;
}

/* ---- the formats ------------------------------------------------------------------------- */

const io_format_info io_formats[IO_FMT_COUNT] = {
    {IO_FMT_XYZ, ".xyz", IO_READ_POINTS | IO_WRITE_POINTS, NULL,
     "points: x y z per line, '#' comments"},
    {IO_FMT_NODE, ".node", IO_READ_POINTS | IO_WRITE_POINTS, NULL,
     "points: TetGen, 0- or 1-based (written 1-based)"},
    {IO_FMT_PLY, ".ply", IO_READ_POINTS | IO_WRITE_POINTS | IO_READ_SURFACE, NULL,
     "points or surface: PLY ascii or binary, either endian (written little-endian, double x y z)"},
    {IO_FMT_BIN, ".bin", IO_READ_POINTS | IO_WRITE_POINTS, NULL,
     "points: little-endian uint64 count, then count*3 little-endian doubles"},
    {IO_FMT_ELE, ".ele", IO_READ_MESH | IO_WRITE_MESH, ".node",
     "mesh: TetGen, NAME.ele with NAME.node, 0- or 1-based (written 1-based)"},
    {IO_FMT_MSH, ".msh", IO_READ_MESH | IO_WRITE_MESH, NULL,
     "mesh: Gmsh 4.1 or 2.2, ASCII or binary (written 4.1 ASCII)"},
    {IO_FMT_VTU, ".vtu", IO_READ_MESH | IO_WRITE_MESH, NULL,
     "mesh: VTK XML UnstructuredGrid, ascii, base64, appended, zlib (written ascii)"},
    {IO_FMT_OFF, ".off", IO_READ_POINTS | IO_READ_SURFACE, NULL,
     "points or surface: Geomview OFF, text (as points: its vertices)"},
};

static int ext_is(const char *path, const char *ext)
{
    size_t lp = strlen(path), le = strlen(ext);
    if (lp <= le) return 0;
    for (size_t i = 0; i < le; i++)
        if (tolower((unsigned char)path[lp - le + i]) != ext[i]) return 0;
    return 1;
}

io_format io_format_of(const char *path)
{
    if (!path) return IO_FMT_UNKNOWN;
    for (int k = 0; k < IO_FMT_COUNT; k++)
        if (ext_is(path, io_formats[k].ext)) return io_formats[k].fmt;
    return IO_FMT_UNKNOWN;
}

int io_format_can(io_format fmt, unsigned can)
{
    if (fmt <= IO_FMT_UNKNOWN || fmt > IO_FMT_COUNT) return 0;
    return (io_formats[fmt - 1].can & can) == can;
}

const char *io_format_list(unsigned can, int companions, char *buf, size_t size)
{
    int n = 0, k = 0;
    for (int i = 0; i < IO_FMT_COUNT; i++) n += (io_formats[i].can & can) == can;
    size_t at = 0;
    buf[0] = '\0';
    for (int i = 0; i < IO_FMT_COUNT && at < size; i++) {
        const io_format_info *f = &io_formats[i];
        if ((f->can & can) != can) continue;
        const char *sep = k == 0 ? "" : k == n - 1 ? " or " : ", ";
        int w = companions && f->companion
                    ? snprintf(buf + at, size - at, "%s%s (with its %s)", sep, f->ext, f->companion)
                    : snprintf(buf + at, size - at, "%s%s", sep, f->ext);
        if (w < 0) break;
        at += (size_t)w;
        k++;
    }
    return buf;
}

io_status io_load_file(const char *path, char **buf, size_t *len, io_error *err)
{
    *buf = NULL;
    *len = 0;
    int fd = open(path, O_RDONLY);
    if (fd < 0) return io_fail(err, IO_ERR_INPUT, "%s: cannot open: %s", path, strerror(errno));
    return io_load_fd(fd, path, buf, len, err);
}

/* A file is loaded whole: before a buffer of IO_ROOM_MIN bytes or more is allocated (a regular
 * file's size, or a pipe's next doubling), the machine's limits are read (mem_probe), so that
 * an input larger than the memory (a 30 GB .xyz, an endless pipe) ends in IO_ERR_NOMEM with
 * the limit named, not in the OOM killer's SIGKILL: with overcommit the allocation itself
 * succeeds and the process dies while the read touches the pages (NOTES.md E161). */
#define IO_ROOM_MIN ((size_t)64 << 20)
static io_status input_room(const char *path, size_t bytes, int regular, size_t got,
                            io_error *err)
{
    if (bytes < IO_ROOM_MIN) return IO_OK;
    mem_room room;
    mem_probe("/proc", "/sys", &room);
    char why[96];
    if (mem_block_fits(&room, bytes, why, sizeof why)) return IO_OK;
    const double gib = (double)((size_t)1 << 30);
    if (regular)
        return io_fail(err, IO_ERR_NOMEM,
                       "%s: out of memory: the file (%.2f GiB) is read whole, and %s", path,
                       (double)bytes / gib, why);
    return io_fail(err, IO_ERR_NOMEM,
                   "%s: out of memory: the input (not a regular file: a pipe, a device) has "
                   "sent %.2f GiB so far and is read whole; its buffer cannot double: %s", path,
                   (double)got / gib, why);
}

io_status io_load_fd(int fd, const char *path, char **buf, size_t *len, io_error *err)
{
    *buf = NULL;
    *len = 0;
    struct stat st;
    if (fstat(fd, &st) != 0) {
        int e = errno;
        close(fd);
        return io_fail(err, IO_ERR_INPUT, "%s: cannot stat: %s", path, strerror(e));
    }
    if (S_ISDIR(st.st_mode)) {
        close(fd);
        return io_fail(err, IO_ERR_INPUT, "%s: is a directory, not a file", path);
    }
    /* Regular files: one allocation of the known size; pipes etc.: grow by doubling. */
    size_t cap = S_ISREG(st.st_mode) ? (size_t)st.st_size + 1 : 65536, n = 0;
    io_status room = input_room(path, cap, 1, 0, err);
    if (room != IO_OK) {
        close(fd);
        return room;
    }
    char *b = malloc(cap);
    if (!b) {
        close(fd);
        return io_fail(err, IO_ERR_NOMEM, "%s: out of memory reading %zu bytes", path, cap);
    }
    for (;;) {
        if (n + 1 >= cap) {
            /* Full: probe one byte before growing, so that a regular file of the size
             * fstat reported is read with one allocation. */
            char probe;
            ssize_t r = read(fd, &probe, 1);
            if (r < 0 && errno == EINTR) continue;
            if (r == 0) break;
            if (r > 0 && cap <= SIZE_MAX / 2) {
                room = input_room(path, 2 * cap, 0, n + 1, err);
                if (room != IO_OK) {
                    free(b);
                    close(fd);
                    return room;
                }
            }
            char *nb = (r < 0 || cap > SIZE_MAX / 2) ? NULL : realloc(b, cap * 2);
            if (!nb) {
                int e = errno;
                free(b);
                close(fd);
                if (r < 0) return io_fail(err, IO_ERR_INPUT, "%s: read error: %s", path, strerror(e));
                return io_fail(err, IO_ERR_NOMEM, "%s: out of memory reading the file", path);
            }
            b = nb;
            cap *= 2;
            b[n++] = probe;
            continue;
        }
        ssize_t r = read(fd, b + n, cap - 1 - n);
        if (r < 0) {
            if (errno == EINTR) continue;
            int e = errno;
            free(b);
            close(fd);
            return io_fail(err, IO_ERR_INPUT, "%s: read error: %s", path, strerror(e));
        }
        if (r == 0) break;
        n += (size_t)r;
    }
    close(fd);
    b[n] = '\0';
    *buf = b;
    *len = n;
    return IO_OK;
}

/* ---- text -------------------------------------------------------------------------------- */

static int is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

size_t io_bom_length(const char *buf, size_t len)
{
    return len >= 3 && memcmp(buf, "\xEF\xBB\xBF", 3) == 0 ? 3 : 0;
}

io_status io_text_encoding(const char *name, const char *buf, size_t len, io_error *err)
{
    const char *enc = NULL;
    if (len >= 4 && memcmp(buf, "\xFF\xFE\0\0", 4) == 0) enc = "UTF-32LE";
    else if (len >= 4 && memcmp(buf, "\0\0\xFE\xFF", 4) == 0) enc = "UTF-32BE";
    else if (len >= 2 && memcmp(buf, "\xFF\xFE", 2) == 0) enc = "UTF-16LE";
    else if (len >= 2 && memcmp(buf, "\xFE\xFF", 2) == 0) enc = "UTF-16BE";
    if (!enc) return IO_OK;
    /* iconv's "UTF-16" / "UTF-32" read the mark and drop it */
    return io_fail(err, IO_ERR_INPUT, "%s: the file is %s text (it starts with a %s byte order "
                   "mark); ASCII or UTF-8 is read: convert it, e.g. iconv -f %.6s -t UTF-8", name,
                   enc, enc, enc);
}

void io_text_init(io_text *t, const char *name, const char *buf, size_t len)
{
    t->name = name;
    t->p = buf + io_bom_length(buf, len);
    t->end = buf + len;
    t->line = 0;
    t->lp = t->le = buf;
}

int io_text_next_line(io_text *t)
{
    while (t->p < t->end) {
        const char *nl = memchr(t->p, '\n', (size_t)(t->end - t->p));
        const char *le = nl ? nl : t->end;
        const char *hash = memchr(t->p, '#', (size_t)(le - t->p));
        t->line++;
        t->lp = t->p;
        t->le = hash ? hash : le;
        t->p = nl ? nl + 1 : t->end;
        while (t->lp < t->le && is_blank(*t->lp)) t->lp++;
        if (t->lp < t->le) return 1;
    }
    return 0;
}

int io_text_token(io_text *t, const char **ts, const char **te)
{
    const char *q = t->lp;
    while (q < t->le && is_blank(*q)) q++;
    if (q >= t->le) {
        t->lp = q;
        return 0;
    }
    *ts = q;
    while (q < t->le && !is_blank(*q)) q++;
    *te = q;
    t->lp = q;
    return 1;
}

size_t io_text_count_tokens(const io_text *t)
{
    size_t k = 0;
    const char *q = t->lp;
    while (q < t->le) {
        while (q < t->le && is_blank(*q)) q++;
        if (q >= t->le) break;
        k++;
        while (q < t->le && !is_blank(*q)) q++;
    }
    return k;
}

/* At most 40 bytes of a token, with non-printable bytes shown as '?', for messages. */
static void token_excerpt(const char *ts, const char *te, char out[48])
{
    size_t k = 0;
    for (const char *q = ts; q < te && k < 40; q++)
        out[k++] = isprint((unsigned char)*q) ? *q : '?';
    if (ts + k < te) { out[k++] = '.'; out[k++] = '.'; out[k++] = '.'; }
    out[k] = '\0';
}

io_status io_text_double(const io_text *t, const char *ts, const char *te, const char *what,
                         double *v, io_error *err)
{
    char *ep;
    char ex[48];
    errno = 0;
    double x = strtod(ts, &ep);
    if (ep != te) {
        token_excerpt(ts, te, ex);
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: %s is not a number: '%s'", t->name, t->line,
                       what, ex);
    }
    if (!isfinite(x)) {
        token_excerpt(ts, te, ex);
        return io_fail(err, IO_ERR_INPUT, "%s:%zu: %s is not finite: '%s'%s", t->name, t->line,
                       what, ex, errno == ERANGE ? " (overflows a double)" : "");
    }
    *v = x;
    return IO_OK;
}

io_status io_text_uint(const io_text *t, const char *ts, const char *te, const char *what,
                       uint64_t max, uint64_t *v, io_error *err)
{
    char ex[48];
    uint64_t x = 0;
    const char *q = ts;
    if (q < te && *q == '+') q++;
    if (q >= te) goto bad;
    for (; q < te; q++) {
        if (*q < '0' || *q > '9') goto bad;
        unsigned d = (unsigned)(*q - '0');
        if (d > max || x > (max - d) / 10) {
            token_excerpt(ts, te, ex);
            return io_fail(err, IO_ERR_INPUT, "%s:%zu: %s is too large: '%s' (at most %llu)",
                           t->name, t->line, what, ex, (unsigned long long)max);
        }
        x = x * 10 + d;
    }
    *v = x;
    return IO_OK;
bad:
    token_excerpt(ts, te, ex);
    return io_fail(err, IO_ERR_INPUT, "%s:%zu: %s is not a non-negative integer: '%s'", t->name,
                   t->line, what, ex);
}

io_status io_dvec_push3(io_dvec *v, const double x[3], const char *name, io_error *err)
{
    if (v->n + 3 > v->cap) {
        size_t nc = v->cap ? v->cap * 2 : 3 * 1024;
        double *na = nc > SIZE_MAX / sizeof(double) ? NULL : realloc(v->a, nc * sizeof(double));
        if (!na) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory after %zu points", name,
                                v->n / 3);
        v->a = na;
        v->cap = nc;
    }
    memcpy(v->a + v->n, x, 3 * sizeof(double));
    v->n += 3;
    return IO_OK;
}

/* ---- dispatch ---------------------------------------------------------------------------- */

static io_status unknown_points(io_error *err, const char *name)
{
    char list[128];
    return io_fail(err, IO_ERR_INPUT, "%s: unknown point file extension (expected %s)", name,
                   io_format_list(IO_READ_POINTS, 0, list, sizeof list));
}

static io_status parse_nul(io_format fmt, const char *name, const char *buf, size_t len,
                           double **xyz, size_t *n, io_error *err)
{
    long first;
    io_status es;
    if (fmt != IO_FMT_BIN && (es = io_text_encoding(name, buf, len, err)) != IO_OK) return es;
    switch (fmt) {
    case IO_FMT_XYZ: return io_parse_xyz(name, buf, len, xyz, n, err);
    case IO_FMT_NODE: return io_parse_node(name, buf, len, xyz, n, &first, err);
    case IO_FMT_PLY: return io_parse_ply(name, buf, len, xyz, n, err);
    case IO_FMT_BIN: return io_parse_bin(name, (const unsigned char *)buf, len, xyz, n, err);
    case IO_FMT_OFF: {
        io_surface s = {0};
        io_status st = io_parse_off(name, buf, len, &s, err);
        free(s.tris);
        if (st != IO_OK) {
            free(s.vertices);
            return st;
        }
        *xyz = s.vertices;
        *n = s.nv;
        return IO_OK;
    }
    default:
        return unknown_points(err, name);
    }
}

io_status io_parse_points(io_format fmt, const char *name, const void *data, size_t len,
                          double **xyz, size_t *n, io_error *err)
{
    *xyz = NULL;
    *n = 0;
    char *copy = malloc(len + 1);
    if (!copy) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", name);
    if (len) memcpy(copy, data, len);
    copy[len] = '\0';
    io_status s = parse_nul(fmt, name, copy, len, xyz, n, err);
    free(copy);
    return s;
}

io_status io_read_points(const char *path, double **xyz, size_t *n, io_error *err)
{
    *xyz = NULL;
    *n = 0;
    io_format fmt = io_format_of(path);
    if (!io_format_can(fmt, IO_READ_POINTS)) return unknown_points(err, path);
    if (fmt == IO_FMT_BIN) return io_read_bin_file(path, xyz, n, err);
    char *buf;
    size_t len;
    io_status s = io_load_file(path, &buf, &len, err);
    if (s != IO_OK) return s;
    s = parse_nul(fmt, path, buf, len, xyz, n, err);
    free(buf);
    return s;
}

/* ---- atomic output ----------------------------------------------------------------------- */

/* The temporaries between io_out_open and their commit or abort, for io_out_unlink_all (a
 * signal handler): a slot holds the path while the file may exist, and is cleared before the
 * path is freed.  More than IO_OUT_LIVE at once are not listed (the CLI has at most three). */
#define IO_OUT_LIVE 16
static _Atomic(char *) out_live[IO_OUT_LIVE];

static void live_add(char *tmp)
{
    for (int i = 0; i < IO_OUT_LIVE; i++) {
        char *none = NULL;
        if (atomic_compare_exchange_strong(&out_live[i], &none, tmp)) return;
    }
}

static void live_remove(char *tmp)
{
    for (int i = 0; i < IO_OUT_LIVE; i++) {
        char *was = tmp;
        if (atomic_compare_exchange_strong(&out_live[i], &was, NULL)) return;
    }
}

void io_out_unlink_all(void)
{
    for (int i = 0; i < IO_OUT_LIVE; i++) {
        char *t = atomic_load(&out_live[i]);
        if (t) unlink(t);
    }
}

/* The handler: the temporaries removed, then the signal re-raised with its default action
 * (SA_RESETHAND has already restored it), so the process dies of it as without the handler. */
static void on_fatal_signal(int sig)
{
    io_out_unlink_all();
    signal(sig, SIG_DFL);
    raise(sig);
}

void io_out_catch_signals(void)
{
    static const int sigs[] = {SIGINT, SIGTERM, SIGHUP};
    for (size_t i = 0; i < sizeof sigs / sizeof sigs[0]; i++) {
        struct sigaction sa, old;
        if (sigaction(sigs[i], NULL, &old) == 0 && old.sa_handler == SIG_IGN) continue;
        memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_fatal_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESETHAND;
        sigaction(sigs[i], &sa, NULL);
    }
}

io_status io_out_open(io_out *o, const char *path, io_error *err)
{
    o->f = NULL;
    o->path = path;
    size_t cap = strlen(path) + 64;
    o->tmp = malloc(cap);
    if (!o->tmp) return io_fail(err, IO_ERR_NOMEM, "%s: out of memory", path);
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    unsigned long salt = (unsigned long)ts.tv_nsec;
    /* the temporary's name keeps at most 200 bytes of the final name's last component, so
     * that its suffix (".tmp-PID-N", up to 47 bytes) never takes a valid name past NAME_MAX
     * (255): a 244-byte name failed with "File name too long" (NOTES.md E159e) */
    const char *slash = strrchr(path, '/');
    const size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    const size_t baselen = strlen(path + dirlen) < 200 ? strlen(path + dirlen) : 200;
    if (strlen(path + dirlen) > NAME_MAX) {   /* refused now, not at the rename after the work */
        free(o->tmp);
        o->tmp = NULL;
        return io_fail(err, IO_ERR_WRITE, "%s: cannot create the output file: %s (its name "
                       "has %zu bytes, at most %d)", path, strerror(ENAMETOOLONG),
                       strlen(path + dirlen), NAME_MAX);
    }
    for (int attempt = 0; attempt < 100; attempt++) {
        snprintf(o->tmp, cap, "%.*s%.*s.tmp-%ld-%lu", (int)dirlen, path, (int)baselen,
                 path + dirlen, (long)getpid(), salt + (unsigned long)attempt);
        live_add(o->tmp);   /* before the file exists: a signal at any time after finds it */
        int fd = open(o->tmp, O_WRONLY | O_CREAT | O_EXCL, 0666);
        if (fd < 0) {
            int e = errno;
            live_remove(o->tmp);
            if (e == EEXIST) continue;
            free(o->tmp);
            o->tmp = NULL;
            return io_fail(err, IO_ERR_WRITE, "%s: cannot create the output file: %s", path,
                           strerror(e));
        }
        o->f = fdopen(fd, "wb");
        if (!o->f) {
            int e = errno;
            close(fd);
            unlink(o->tmp);
            live_remove(o->tmp);
            free(o->tmp);
            o->tmp = NULL;
            return io_fail(err, IO_ERR_WRITE, "%s: cannot open the output file: %s", path,
                           strerror(e));
        }
        setvbuf(o->f, NULL, _IOFBF, (size_t)1 << 20); /* large writes: meshes run to GBs */
        return IO_OK;
    }
    free(o->tmp);
    o->tmp = NULL;
    return io_fail(err, IO_ERR_WRITE, "%s: cannot create a temporary file beside it", path);
}

io_status io_out_close(io_out *o, io_error *err)
{
    if (!o->f) return IO_OK;
    int bad = fflush(o->f) != 0 || ferror(o->f);
    int e = errno;
    if (fclose(o->f) != 0 && !bad) {
        bad = 1;
        e = errno;
    }
    o->f = NULL;
    if (bad) {
        io_out_abort(o);
        return io_fail(err, IO_ERR_WRITE, "%s: write error: %s", o->path, strerror(e));
    }
    return IO_OK;
}

io_status io_out_commit(io_out *o, io_error *err)
{
    if (rename(o->tmp, o->path) != 0) {
        int e = errno;
        io_out_abort(o);
        return io_fail(err, IO_ERR_WRITE, "%s: cannot rename the finished output into place: %s",
                       o->path, strerror(e));
    }
    live_remove(o->tmp);
    free(o->tmp);
    o->tmp = NULL;
    return IO_OK;
}

void io_out_abort(io_out *o)
{
    if (o->f) {
        fclose(o->f);
        o->f = NULL;
    }
    if (o->tmp) {
        unlink(o->tmp);
        live_remove(o->tmp);
        free(o->tmp);
        o->tmp = NULL;
    }
}

io_status io_check_writable(const char *path, io_error *err)
{
    struct stat st;  /* the rename onto a directory would fail, but only after the work */
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
        return io_fail(err, IO_ERR_WRITE, "%s: is a directory; give a file name for the output",
                       path);
    io_out o;
    io_status s = io_out_open(&o, path, err);
    if (s == IO_OK) io_out_abort(&o);
    return s;
}

char *io_fmt_u64(char *p, uint64_t v)
{
    char tmp[24];
    int k = 0;
    do {
        tmp[k++] = (char)('0' + v % 10);
        v /= 10;
    } while (v);
    while (k) *p++ = tmp[--k];
    return p;
}
