/* json.h -- the few JSON writers the CLI's reports share (src/cli/).
 *
 * Output is plain ASCII JSON: strings escaped per RFC 8259 (control characters as \u00XX, bytes
 * >= 0x80 passed through, so UTF-8 file names stay UTF-8), doubles printed with %.17g so they
 * read back bit-exact (a finite double only: the checker never reports a non-finite point).
 */
#ifndef GTET_CLI_JSON_H
#define GTET_CLI_JSON_H

#include <stdio.h>

#include "gigatet.h"

/* "s" with escapes, or null for NULL. */
void cli_json_str(FILE *f, const char *s);
/* [x, y, z] */
void cli_json_point(FILE *f, const double p[3]);
/* The violation object of a check report ("violation": {...} or null, without the key). */
void cli_json_violation(FILE *f, const gtet_check_violation *v, int failed);
/* The predicate counters as one object: every field of gtet_pred_counters under its own name
 * (an array for sos_depth), in the struct's order. */
void cli_json_pred_counters(FILE *f, const gtet_pred_counters *p);
/* The counters and verdict of a check report, as members ("key": value, ...) without braces. */
void cli_json_check_members(FILE *f, const gtet_check_report *r, int failed);

#endif
