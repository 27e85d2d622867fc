/* opts.c -- the CLI's one option parser and the help drawn from the same tables (cli.h).
 *
 * Matching rules, the same for every command: an argument equal to an option's name (or its
 * alias) is that option; a value option takes the next argument whatever it looks like, and
 * a long name (starting "--") also takes "--name=value".  Any other argument that starts with
 * '-' and is longer than "-" is an unknown option; the rest are the positionals, in order.
 * "--" ends the options: every argument after it is a positional (a file named "-p.xyz"), as
 * POSIX utilities and getopt take it.
 * The first problem met, left to right, is the one reported (exit CLI_USAGE); a repeated
 * option keeps its last value.
 */
#include "cli.h"

#include <stdio.h>
#include <string.h>

/* Print a usage error from a message template: "{opt}", "{value}", "{arg}" and "{first}" are
 * replaced by the strings passed for them (NULL: left as written). */
static int usage_from(const char *tpl, const char *opt, const char *value, const char *arg,
                      const char *first)
{
    static const char *const keys[] = {"{opt}", "{value}", "{arg}", "{first}"};
    const char *vals[] = {opt, value, arg, first};
    char msg[1024];
    size_t at = 0;
    while (*tpl && at + 1 < sizeof msg) {
        int k = 0;
        while (k < 4 && !(vals[k] && !strncmp(tpl, keys[k], strlen(keys[k])))) k++;
        if (k == 4) {
            msg[at++] = *tpl++;
            continue;
        }
        for (const char *v = vals[k]; *v && at + 1 < sizeof msg; v++) msg[at++] = *v;
        tpl += strlen(keys[k]);
    }
    msg[at] = '\0';
    return cli_usage("%s", msg);
}

/* The option argv[*i] names, or NULL; *val is set for "--name=value". */
static const cli_opt *match(const cli_opt *opts, const char *a, const char **val)
{
    *val = NULL;
    for (const cli_opt *o = opts; o->name; o++) {
        const char *names[2] = {o->name, o->alias};
        for (int k = 0; k < 2 && names[k]; k++) {
            size_t l = strlen(names[k]);
            if (strncmp(a, names[k], l) != 0) continue;
            if (a[l] == '\0') return o;
            if (a[l] == '=' && o->kind != CLI_OPT_FLAG && names[k][1] == '-') {
                *val = a + l + 1;
                return o;
            }
        }
    }
    return NULL;
}

/* Store the value of option o (given as `typed`) into args. */
static int store(const cli_opt *o, const char *typed, const char *val, void *args)
{
    char *field = (char *)args + o->off;
    if (o->kind == CLI_OPT_FLAG) {
        *(unsigned *)(void *)field |= o->bits;
        return CLI_OK;
    }
    if (!val) return usage_from(o->missing, typed, NULL, NULL, NULL);
    if (o->kind == CLI_OPT_STRING) {
        *(const char **)(void *)field = val;
        return CLI_OK;
    }
    if (!cli_parse_u64(val, o->max, (uint64_t *)(void *)field))
        return usage_from(o->invalid ? o->invalid : o->missing, typed, val, NULL, NULL);
    return CLI_OK;
}

int cli_parse(const cli_command *cmd, int argc, char **argv, void *args, unsigned *given)
{
    int npos = 0, rc;
    const char **first = NULL;
    int opts_end = 0;   /* after "--" */
    if (given) *given = 0;
    for (int i = 0; i < argc; i++) {
        const char *a = argv[i], *val = NULL;
        if (!opts_end && !strcmp(a, "--")) {
            opts_end = 1;
            continue;
        }
        const cli_opt *o = opts_end ? NULL : match(cmd->opts, a, &val);
        if (o) {
            if (o->kind != CLI_OPT_FLAG && !val && i + 1 < argc) val = argv[++i];
            if ((rc = store(o, a, val, args)) != CLI_OK) return rc;
            if (given) *given |= o->mark;
        } else if (!opts_end && a[0] == '-' && a[1] != '\0') {
            return cli_usage("%s: unknown option '%s'", cmd->name, a);
        } else if (cmd->pos[npos].name) {
            const char **slot = (const char **)(void *)((char *)args + cmd->pos[npos++].off);
            *slot = a;
            if (!first) first = slot;
        } else {
            return usage_from(cmd->extra, NULL, NULL, a, first ? *first : "");
        }
    }
    if (cmd->pos[npos].name) return cli_usage("%s", cmd->missing);
    return CLI_OK;
}

/* ---- help -------------------------------------------------------------------------------- */

/* Text whose lines after the first start at column `indent`. */
static void put_indented(FILE *f, const char *text, int indent)
{
    for (const char *p = text; *p; p++) {
        fputc(*p, f);
        if (*p == '\n' && p[1]) fprintf(f, "%*s", indent, "");
    }
    fputc('\n', f);
}

void cli_print_synopsis(FILE *f, const cli_command *cmd)
{
    enum { WIDTH = 95 };
    int col = fprintf(f, "  gigatet %s", cmd->name), indent = col + 1;
    char item[128];
    for (const cli_positional *p = cmd->pos; p->name; p++) col += fprintf(f, " %s", p->name);
    for (const cli_opt *o = cmd->opts; o->name; o++) {
        const char *arg = o->kind == CLI_OPT_FLAG ? "" : o->arg;
        snprintf(item, sizeof item, o->required ? "%s%s%s" : "[%s%s%s]", o->name,
                 *arg ? " " : "", arg);
        int w = (int)strlen(item);
        if (col + 1 + w > WIDTH) col = fprintf(f, "\n%*s", indent - 1, "") - 1;
        col += fprintf(f, " %s", item);
    }
    fputc('\n', f);
}

void cli_print_command_help(FILE *f, const cli_command *cmd)
{
    enum { NAME = 12, HELP = 15 };
    fprintf(f, "%-*s", HELP - 2, cmd->name);
    put_indented(f, cmd->summary, HELP - 2);
    char item[128];
    for (const cli_opt *o = cmd->opts; o->name; o++) {
        snprintf(item, sizeof item, "%s%s%s", o->name, o->kind == CLI_OPT_FLAG ? "" : " ",
                 o->kind == CLI_OPT_FLAG ? "" : o->arg);
        if ((int)strlen(item) <= NAME) fprintf(f, "  %-*s ", NAME, item);
        else fprintf(f, "  %s\n%*s", item, HELP, "");
        put_indented(f, o->help, HELP);
    }
}
