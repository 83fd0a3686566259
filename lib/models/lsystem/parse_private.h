/* meristem — what the two halves of the cpfg reader share: parse.c reads the
 * text (lines, directives, sections) and parse_production.c the productions and
 * the modules and expressions in them. Private to lib/models/lsystem. */
#ifndef MERISTEM_LSYSTEM_PARSE_PRIVATE_H
#define MERISTEM_LSYSTEM_PARSE_PRIVATE_H

#include "models/lsystem/lsystem_private.h"

#include <stdio.h>

/* A span of one line: [b, e), column of b. */
typedef struct merp_ls_span {
    const char *b, *e;
    int line, col;
} merp_ls_span;

/* The parser's state: the rules being built, the error to fill, and the names
 * an expression may use (the defines, then the production's formal
 * parameters). */
typedef struct merp_ls_pctx {
    merp_lsys *ls;
    merp_ls_error *err;
    merp_ls_name names[MERP_LS_MAXVARS + 256];
    int nnames;
    int sect; /* the section the lines belong to */
} merp_ls_pctx;

/* Fills the error at line, col; returns -1. */
static inline int merp_ls_error_at(merp_ls_pctx *c, int line, int col, const char *msg)
{
    c->err->line = line;
    c->err->col = col;
    snprintf(c->err->msg, sizeof c->err->msg, "%s", msg);
    return -1;
}

/* [b, e) of s, b and e inside s. */
static inline merp_ls_span merp_ls_sub(merp_ls_span s, const char *b, const char *e)
{
    return (merp_ls_span){b, e, s.line, s.col + (int)(b - s.b)};
}

/* s without leading and trailing blanks. */
merp_ls_span merp_ls_trim(merp_ls_span s);

/* 1 when s is a C identifier. */
int merp_ls_identifier(merp_ls_span s);

/* Reads one module symbol at *p; 0 at the end of s. */
merp_sym merp_ls_symbol(merp_ls_span s, const char **p);

/* Evaluates s as a constant expression (the defines only); *ok is 0 and the
 * error filled when it does not compile. */
double merp_ls_const_expr(merp_ls_pctx *c, merp_ls_span s, int *ok);

/* Reads a successor (or the axiom, with `nnames` = the defines only) into pr's
 * succ and args; 0 or -1 with the error filled. Unbalanced brackets are
 * accepted, as cpfg does, with a warning. */
int merp_ls_successor(merp_ls_pctx *c, merp_ls_span s, merp_ls_prod *pr, int nnames);

/* Reads one production line, arrow at `arrow` (`alen` bytes), and appends it
 * to the rules; 0 or -1 with the error filled. */
int merp_ls_production(merp_ls_pctx *c, merp_ls_span s, const char *arrow, int alen);

/* Frees what pr holds (not pr). */
void merp_ls_prod_free(merp_ls_prod *pr);

#endif
