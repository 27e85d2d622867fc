/* json.c -- JSON writers of the CLI's reports (see json.h). */
#include "json.h"

void cli_json_str(FILE *f, const char *s)
{
    if (!s) {
        fputs("null", f);
        return;
    }
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\') fprintf(f, "\\%c", *p);
        else if (*p < 0x20) fprintf(f, "\\u%04x", *p);
        else fputc(*p, f);
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
