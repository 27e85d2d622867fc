/* decode.c -- the byte-level helpers of the mesh readers: little-endian loads, base64, zlib.
 *
 * zlib is used here only, so it is a dependency of the I/O library (gigatet_io), never of
 * the core library.
 */
#include "io_internal.h"

#include <limits.h>
#include <string.h>
#define ZLIB_CONST   /* next_in is a pointer to const */
#include <zlib.h>

uint64_t io_load_le(const unsigned char *p, size_t width)
{
    uint64_t v = 0;
    for (size_t i = width; i-- > 0;) v = v << 8 | p[i];
    return v;
}

size_t io_line_of(const char *buf, const char *p)
{
    size_t l = 1;
    for (const char *q = buf; q < p; q++) l += *q == '\n';
    return l;
}

/* The 6-bit value of a base64 character, 64 for '=', 65 for anything else. */
static unsigned b64_value(unsigned char c)
{
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    if (c == '=') return 64;
    return 65;
}

static int b64_space(unsigned char c)
{
    return c == ' ' || c == '\n' || c == '\r' || c == '\t' || c == '\v' || c == '\f';
}

void io_b64_init(io_b64 *s, const char *p, const char *e)
{
    s->p = p;
    s->e = e;
    s->nq = s->qi = 0;
    s->bad = 0;
}

/* Decode the next group into s->q: 1 when it gave at least one byte. */
static int b64_group(io_b64 *s)
{
    unsigned v[4], k = 0;
    while (k < 4 && s->p < s->e) {
        unsigned char c = (unsigned char)*s->p++;
        if (b64_space(c)) continue;
        v[k] = b64_value(c);
        if (v[k] == 65) {
            s->bad = 1;
            return 0;
        }
        k++;
    }
    if (k < 2) {          /* the end, or one lone character (not a whole byte) */
        if (k == 1) s->bad = 1;
        return 0;
    }
    while (k < 4) v[k++] = 64;               /* unpadded last group */
    /* padding only in the last two places, and a '=' in the third needs one in the fourth */
    if (v[0] == 64 || v[1] == 64 || (v[2] == 64 && v[3] != 64)) {
        s->bad = 1;
        return 0;
    }
    uint32_t w = (uint32_t)v[0] << 18 | (uint32_t)v[1] << 12 |
                 (uint32_t)(v[2] & 63) << 6 | (uint32_t)(v[3] & 63);
    s->q[0] = (unsigned char)(w >> 16);
    s->q[1] = (unsigned char)(w >> 8);
    s->q[2] = (unsigned char)w;
    s->nq = v[2] == 64 ? 1 : v[3] == 64 ? 2 : 3;
    s->qi = 0;
    return 1;
}

int io_b64_read(io_b64 *s, unsigned char *dst, size_t n)
{
    while (n > 0) {
        if (s->qi == s->nq && !b64_group(s)) return 0;
        size_t k = s->nq - s->qi < n ? s->nq - s->qi : n;
        if (dst) {
            memcpy(dst, s->q + s->qi, k);
            dst += k;
        }
        s->qi += (unsigned)k;
        n -= k;
    }
    return 1;
}

size_t io_b64_bound(const io_b64 *s)
{
    return (s->nq - s->qi) + (size_t)(s->e - s->p) / 4 * 3 + 3;
}

int io_inflate(const unsigned char *src, size_t slen, unsigned char *dst, size_t dlen)
{
    z_stream z;
    memset(&z, 0, sizeof z);
    if (inflateInit(&z) != Z_OK) return 0;
    int ok = 1, r = Z_OK;
    /* zlib counts in uInt: feed and drain in pieces that fit */
    while (ok && r != Z_STREAM_END) {
        if (z.avail_in == 0 && slen > 0) {
            z.next_in = src;
            z.avail_in = slen > UINT_MAX ? UINT_MAX : (uInt)slen;
            src += z.avail_in;
            slen -= z.avail_in;
        }
        if (z.avail_out == 0 && dlen > 0) {
            z.next_out = dst;
            z.avail_out = dlen > UINT_MAX ? UINT_MAX : (uInt)dlen;
            dst += z.avail_out;
            dlen -= z.avail_out;
        }
        uInt in0 = z.avail_in, out0 = z.avail_out;
        r = inflate(&z, Z_NO_FLUSH);
        if (r != Z_OK && r != Z_STREAM_END && r != Z_BUF_ERROR) ok = 0;
        /* no progress possible: input used up, or output full before the stream's end */
        else if (r != Z_STREAM_END && z.avail_in == in0 && z.avail_out == out0) ok = 0;
    }
    /* the stream must fill the destination exactly */
    if (ok && (z.avail_out != 0 || dlen != 0)) ok = 0;
    inflateEnd(&z);
    return ok;
}
