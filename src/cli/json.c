/* json.c -- JSON writers of the CLI's reports (see json.h). */
#include "json.h"

#include <stddef.h>
#include <stdint.h>

/* The one list of the predicate counters' fields: --stats and --degeneracies print it. */
#define PRED_FIELD(f) \
    {#f, offsetof(gtet_pred_counters, f), sizeof(((gtet_pred_counters *)0)->f) / sizeof(uint64_t)}
static const struct pred_field {
    const char *name;
    size_t off, count;   /* count > 1: a JSON array */
} pred_fields[] = {
    PRED_FIELD(orient_calls),   PRED_FIELD(orient_exact),   PRED_FIELD(orient_int),
    PRED_FIELD(orient_gmp),     PRED_FIELD(orient_zero),    PRED_FIELD(insphere_calls),
    PRED_FIELD(insphere_exact), PRED_FIELD(insphere_int),   PRED_FIELD(insphere_gmp),
    PRED_FIELD(insphere_zero),  PRED_FIELD(sos_calls),      PRED_FIELD(sos_depth),
    PRED_FIELD(insphere_int122),
};
#undef PRED_FIELD
/* Every uint64_t of the struct is in the list: a field added to gigatet.h fails here (the
 * array sos_depth is one entry for its 4 values). */
_Static_assert(sizeof(gtet_pred_counters) ==
                   (sizeof pred_fields / sizeof pred_fields[0] + 3) * sizeof(uint64_t),
               "pred_fields must list every field of gtet_pred_counters");

void cli_json_pred_counters(FILE *f, const gtet_pred_counters *p)
{
    size_t n = sizeof pred_fields / sizeof pred_fields[0];
    for (size_t i = 0; i < n; i++) {
        const struct pred_field *d = &pred_fields[i];
        const uint64_t *v = (const uint64_t *)(const void *)((const char *)p + d->off);
        fprintf(f, "%s\"%s\":%s", i ? "," : "{", d->name, d->count > 1 ? "[" : "");
        for (size_t k = 0; k < d->count; k++)
            fprintf(f, "%s%llu", k ? "," : "", (unsigned long long)v[k]);
        if (d->count > 1) fputc(']', f);
    }
    fputc('}', f);
}

/* The length (2-4) of the well-formed UTF-8 sequence at p, or 0 (RFC 3629: no overlong
 * forms, no surrogates, nothing past U+10FFFF). */
static int utf8_len(const unsigned char *p)
{
    const unsigned c = p[0];
    int n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    if (!n) return 0;
    for (int i = 1; i < n; i++)
        if ((p[i] & 0xC0) != 0x80) return 0;   /* the NUL ends it too */
    if ((c == 0xE0 && p[1] < 0xA0) || (c == 0xED && p[1] > 0x9F) || (c == 0xF0 && p[1] < 0x90) ||
        (c == 0xF4 && p[1] > 0x8F))
        return 0;
    return n;
}

/* A JSON string; bytes that are not UTF-8 (a file name is any bytes) become U+FFFD, so that
 * the output stays JSON, which is UTF-8 (NOTES.md E159g). */
void cli_json_str(FILE *f, const char *s)
{
    if (!s) {
        fputs("null", f);
        return;
    }
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        int n;
        if (*p == '"' || *p == '\\') fprintf(f, "\\%c", *p);
        else if (*p < 0x20) fprintf(f, "\\u%04x", *p);
        else if (*p < 0x80) fputc(*p, f);
        else if ((n = utf8_len(p)) != 0) {
            fwrite(p, 1, (size_t)n, f);
            p += n - 1;
        } else {
            fputs("\\ufffd", f);
        }
    }
    fputc('"', f);
}

void cli_json_point(FILE *f, const double p[3])
{
    fprintf(f, "[%.17g,%.17g,%.17g]", p[0], p[1], p[2]);
}

void cli_json_violation(FILE *f, const gtet_check_violation *v, int failed)
{
    if (!failed) {
        fputs("null", f);
        return;
    }
    fputs("{\"stage\":", f);
    cli_json_str(f, v->stage);
    fprintf(f, ",\"tie\":%s,\"group_size\":%llu,\"tets\":[", v->tie ? "true" : "false",
            (unsigned long long)v->group_size);
    for (int i = 0, k = 0; i < 2; i++)
        if (v->tet[i] != GTET_CHECK_NONE) fprintf(f, "%s%llu", k++ ? "," : "", (unsigned long long)v->tet[i]);
    fputs("],\"vertices\":[", f);
    for (int i = 0; i < v->nvertices && i < 5; i++) {
        fprintf(f, "%s{\"id\":%u,\"point\":", i ? "," : "", v->vertex[i]);
        cli_json_point(f, v->point[i]);
        fputc('}', f);
    }
    fputs("]}", f);
}

void cli_json_check_members(FILE *f, const gtet_check_report *r, int failed)
{
    fprintf(f, "\"ok\":%s,\"mode\":\"%s\",\"tets\":%llu,\"facets_checked\":%llu,"
            "\"hull_facets\":%llu,\"duplicates\":%llu,\"negative_tets\":%llu,"
            "\"unused_vertices\":%llu,\"cospherical_facets\":%llu,\"coplanar_hull_edges\":%llu,"
            "\"euler\":%d,\"message\":",
            failed ? "false" : "true",
            (r->mode & (unsigned)GTET_CHECK_DELAUNAY) ? "delaunay" : "canonical",
            (unsigned long long)r->tets, (unsigned long long)r->facets_checked,
            (unsigned long long)r->hull_facets, (unsigned long long)r->duplicates,
            (unsigned long long)r->negative_tets, (unsigned long long)r->unused_vertices,
            (unsigned long long)r->cospherical_facets, (unsigned long long)r->coplanar_hull_edges,
            r->euler);
    cli_json_str(f, r->message);
    fputs(",\"violation\":", f);
    cli_json_violation(f, &r->violation, failed);
}
