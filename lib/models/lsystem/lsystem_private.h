/* meristem — the rules of an L-system as parse.c builds them and derive.c reads
 * them (ABOP §1.7 stochastic, §1.8 context-sensitive, §1.10 parametric
 * productions). Private to lib/models/lsystem. */
#ifndef MERISTEM_LSYSTEM_PRIVATE_H
#define MERISTEM_LSYSTEM_PRIVATE_H

#include "models/lsystem/lsystem.h"

#define MERP_LS_MAXVARS 64 /* formal parameters of one production */
#define MERP_LS_MAXARGS 32 /* parameters of one module */

/* A module of a predecessor or context: its formal parameters occupy variable
 * slots slot .. slot + nf - 1. */
typedef struct merp_ls_pat {
    merp_sym sym;
    uint16_t nf, slot;
} merp_ls_pat;

/* A module of a successor: its parameters are prod->args[arg0 .. arg0+nargs-1]. */
typedef struct merp_ls_out {
    merp_sym sym;
    uint16_t nargs;
    uint32_t arg0;
} merp_ls_out;

typedef struct merp_ls_prod {
    merp_ls_pat pred;
    merp_ls_pat *lc, *rc; /* lc[nlc-1] is next to the predecessor */
    int nlc, nrc;
    merp_expr *cond;      /* NULL: always */
    merp_ls_out *succ;
    int nsucc;
    merp_expr **args;
    int nargs;
    double prob;          /* weight, when has_prob */
    int has_prob, nvars, line;
    int section;          /* MERP_LS_PRODUCTIONS, _DECOMPOSITION, _HOMOMORPHISM */
} merp_ls_prod;

/* The productions of one section, grouped by predecessor symbol (in text order
 * within a group), and the section's maximum depth of recursion (cpfg's
 * "maximum depth:"; unused by the L-system's own productions). */
typedef struct merp_ls_table {
    int *by_head;   /* production indices */
    int *head_off;  /* MERP_LS_NSYM + 1 offsets into by_head */
    int nprod, depth;
} merp_ls_table;

struct merp_lsys {
    merp_ls_prod *prods;
    int nprod, pcap;
    merp_ls_table tab[MERP_LS_SECTIONS];
    int queries;    /* a query module (?P ?H ?L ?U ?E) in the axiom or a successor of
                     * the productions or the decomposition */
    merp_lstr axiom;
    int dlen;
    uint8_t skip[MERP_LS_NSYM]; /* ignored by context matching (ABOP §1.8) */
    merp_ls_name *defs;
    int ndefs, dcap;
    /* What the text gets away with (merp_lsys_warnings): the first
     * MERP_LS_WARN_MAX kept, nwarn counts them all. */
    merp_ls_error warn[MERP_LS_WARN_MAX];
    int nwarn;
};

#endif
