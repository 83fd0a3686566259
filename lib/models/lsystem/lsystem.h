/* meristem — L-systems after Prusinkiewicz & Lindenmayer, "The Algorithmic Beauty
 * of Plants" (ABOP, 1990), chapters 1 and 2, in the syntax of cpfg: the private
 * interface of lib/models/lsystem. Not installed.
 *
 * Four parts, one file each: expr.c (the arithmetic of ABOP §1.10 parametric
 * L-systems, compiled once), string.c (the module string, linear memory), parse.c
 * (cpfg text -> rules) and derive.c (one parallel rewriting step, ABOP §1.2, §1.7,
 * §1.8, §1.10), and turtle.c (the interpretation into segments). The growth model
 * built on them (model.c, draw.c) is in model_private.h.
 */
#ifndef MERISTEM_LSYSTEM_H
#define MERISTEM_LSYSTEM_H

#include <stddef.h>
#include <stdint.h>

/* Where and why a text was refused: 1-based line and column of the offending
 * character. */
typedef struct merp_ls_error {
    int line, col;
    char msg[120];
} merp_ls_error;

/* ---- expressions (expr.c) ---- */

/* A name an expression may use: a formal parameter (slot >= 0, read from the
 * variables at evaluation) or a #define constant (slot < 0, `value`). */
typedef struct merp_ls_name {
    char name[32];
    int slot;
    double value;
} merp_ls_name;

/* The random draws of ran() and nran(): counter-based, so a value depends only on
 * `key` (seed, step, module) and how many draws came before in the same module. */
typedef struct merp_ls_rand {
    uint64_t key;
    uint32_t count;
} merp_ls_rand;

typedef struct merp_expr merp_expr;

/* Compiles `len` bytes at `src` (one expression; identifiers resolved through
 * `names`, `nnames` entries, may be 0). On error returns NULL and fills `err`
 * with the column counted from `col0` (the column of src[0]) on `line`. Cost
 * O(len). */
merp_expr *merp_expr_compile(const char *src, size_t len, const merp_ls_name *names,
                             int nnames, int line, int col0, merp_ls_error *err);

/* Evaluates `e` with formal parameters `vars` (indexed by slot); `rnd` may be NULL
 * when the expression draws no random numbers (then ran() gives 0). Cost O(size
 * of e). */
double merp_expr_eval(const merp_expr *e, const double *vars, merp_ls_rand *rnd);

/* 1 when `e` reads no variable and draws no random number. */
int merp_expr_is_constant(const merp_expr *e);

void merp_expr_free(merp_expr *e);

/* A uniform double in [0, 1) from `rnd` (advances its counter). */
double merp_ls_uniform(merp_ls_rand *rnd);

/* The key of the draws of module `index` in derivation step `step`. */
uint64_t merp_ls_key(uint64_t seed, uint32_t step, uint64_t index);

/* ---- the module string (string.c) ---- */

/* A symbol: a byte, or 256 + c for the two-character query modules ?c (?E, ?P). */
typedef uint16_t merp_sym;
#define MERP_LS_NSYM 512

/* Modules in flat arrays: sym[i], and the parameters of module i at
 * par[poff[i]] .. par[poff[i+1]] - 1. Memory is proportional to the string.
 * The struct is open inside lib/models/lsystem (derivation and interpretation
 * walk it in tight loops). */
typedef struct merp_lstr {
    size_t n, cap;
    merp_sym *sym;
    uint32_t *poff; /* n + 1 entries once n > 0 */
    float *par;
    size_t npar, pcap;
} merp_lstr;

void merp_lstr_init(merp_lstr *s);
void merp_lstr_free(merp_lstr *s);
/* Empties `s`, keeping its memory. */
void merp_lstr_clear(merp_lstr *s);
/* Appends module `sym` with `np` parameters. 0, or -1 when out of memory (then s
 * is unchanged). Amortised O(np). */
int merp_lstr_push(merp_lstr *s, merp_sym sym, const float *par, unsigned np);
/* Makes room for `n` modules and `npar` parameters in all, so that pushes up to
 * those do not reallocate. 0, or -1 when out of memory (s unchanged). */
int merp_lstr_reserve(merp_lstr *s, size_t n, size_t npar);
/* Exchanges the contents of `a` and `b`. O(1). */
void merp_lstr_swap(merp_lstr *a, merp_lstr *b);
/* Copies `src` into `dst` (cleared first). 0, or -1 when out of memory. */
int merp_lstr_copy(merp_lstr *dst, const merp_lstr *src);
/* How many modules have symbol `sym`. O(n). */
size_t merp_lstr_count(const merp_lstr *s, merp_sym sym);
/* Writes the string as text, parameters with %g ("A(1,2.5)B"), NUL-terminated,
 * truncated to `cap`; returns the full length (like snprintf). O(n). */
size_t merp_lstr_format(const merp_lstr *s, char *buf, size_t cap);
/* The index of the ']' closing the branch that holds module i (i itself when
 * it is that ']'), or s->n when i is on the main path. O(length of the rest of
 * the branch). */
size_t merp_lstr_branch_end(const merp_lstr *s, size_t i);
/* Fills match[i] with the index of the bracket matching s->sym[i] for every '['
 * and ']' (SIZE_MAX when unbalanced); other entries are left as SIZE_MAX.
 * `match` has s->n entries. O(n) time, O(depth) extra memory; -1 when out of
 * memory. */
int merp_lstr_brackets(const merp_lstr *s, size_t *match);

static inline unsigned merp_lstr_np(const merp_lstr *s, size_t i)
{
    return s->poff[i + 1] - s->poff[i];
}

/* ---- the rules (parse.c) and derivation (derive.c) ---- */

typedef struct merp_lsys merp_lsys;

/* The sections of a cpfg text: the L-system's productions, then optionally
 * "decomposition" and "homomorphism", each with its "maximum depth:". */
enum { MERP_LS_PRODUCTIONS, MERP_LS_DECOMPOSITION, MERP_LS_HOMOMORPHISM, MERP_LS_SECTIONS };

/* The maximum depth of a section that names none. */
#define MERP_LS_DEPTH_DEFAULT 1
#define MERP_LS_DEPTH_MAX 1000

/* Parses cpfg text: comments, #define, derivation length:, axiom:, ignore: or
 * consider:, productions "lc < pred > rc : cond -> succ : prob" (also "-->"),
 * lsystem:/endlsystem lines, and the sections "decomposition" and
 * "homomorphism" with "maximum depth: n", whose productions are context-free.
 * NULL with `err` filled on error or out of memory. Cost O(length of text). */
merp_lsys *merp_lsys_parse(const char *text, merp_ls_error *err);
void merp_lsys_free(merp_lsys *ls);

/* What a text that parsed gets away with, as cpfg does: a successor or axiom
 * whose brackets do not balance (a ']' with no '[' before it, a '[' never
 * closed: the turtle pops nothing at the one, and the branch runs to the end
 * of the string at the other). Sets *out to the first MERP_LS_WARN_MAX warnings
 * (line and column of the bracket) and returns how many there are. O(1). */
#define MERP_LS_WARN_MAX 8
int merp_lsys_warnings(const merp_lsys *ls, const merp_ls_error **out);

/* The derivation length the text asked for (0 when not given). */
int merp_lsys_derivation_length(const merp_lsys *ls);
/* The axiom, as a string (owned by ls). */
const merp_lstr *merp_lsys_axiom(const merp_lsys *ls);
/* How many productions (of every section). */
int merp_lsys_nprod(const merp_lsys *ls);
/* How many productions section `sect` (MERP_LS_DECOMPOSITION, ...) holds. */
int merp_lsys_section_size(const merp_lsys *ls, int sect);
/* 1 when the axiom or a successor of the productions or the decomposition
 * holds a query module (?P ?H ?L ?U ?E): then the string must be interpreted
 * after every step for the next one to read them. */
int merp_lsys_has_queries(const merp_lsys *ls);

/* One derivation step (ABOP §1.2: every module rewritten in parallel): `out`
 * receives the successor of `in` (out is cleared first and must not be in).
 * Stochastic choices and ran() draw from (seed, step, module index) only, so the
 * result does not depend on evaluation order. 0, or -1 when out of memory.
 * Cost O(|in| + |out|) times the production work per module. */
int merp_lsys_derive(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                     uint64_t seed, uint32_t step);

/* The decomposition of cpfg: every module of `in` that a decomposition
 * production matches is replaced by its successor, whose modules are
 * decomposed in turn, down to the section's maximum depth, where a module is
 * left as it is (truncation, not an error). `out` (cleared first, not in)
 * becomes the string. Draws are keyed by (seed, step, module, depth). 0, or -1
 * when out of memory. Linear in |out| (times the production work). */
int merp_lsys_decompose(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                        uint64_t seed, uint32_t step);

/* Marks in a homomorphism's map a module that a production made. */
#define MERP_LS_PRODUCED UINT32_C(0x80000000)

/* The homomorphism of cpfg: the string the turtle reads instead of `in`,
 * rewritten like merp_lsys_decompose by the homomorphism productions (to the
 * section's maximum depth, then truncated); `in` is not changed. *map
 * (allocated here, |out| entries, freed with merp_free) gives for each module
 * of out the index of the module of `in` that gave it, or'ed with
 * MERP_LS_PRODUCED when a production made it. 0, or -1 when out of memory. */
int merp_lsys_homomorphism(const merp_lsys *ls, const merp_lstr *in, merp_lstr *out,
                           uint32_t **map, uint64_t seed, uint32_t step);

/* Derives `n` steps from the axiom into `out`, steps numbered 0 .. n-1, the
 * decomposition applied to the axiom and after every step. */
int merp_lsys_run(const merp_lsys *ls, int n, uint64_t seed, merp_lstr *out);

/* ---- the turtle (turtle.c) ---- */

/* Defaults of the interpretation: δ in degrees, the step of F without a
 * parameter, the initial width, and tropism (ABOP §2.2): the direction T and
 * the susceptibility e (0: none). */
typedef struct merp_ls_turtle {
    double delta, step, width;
    double tropism[3], elasticity;
} merp_ls_turtle;

/* One drawn internode: from base to tip, the turtle's heading H and left L as
 * it drew it, the segment drawn before it on the same path (parent, UINT32_MAX
 * for the first), its branching order (bracket depth), width and colour index
 * from ! and ', and the module that drew it. */
typedef struct merp_ls_seg {
    float base[3], tip[3];
    float head[3], left[3];
    float width;
    uint32_t parent, module;
    uint16_t order, color;
} merp_ls_seg;

typedef struct merp_ls_segs {
    size_t n, cap;
    merp_ls_seg *seg;
} merp_ls_segs;

/* The answers to query modules while a string is interpreted (cpfg's query
 * and communication modules): ?P(x,y,z) receives the turtle's position plus
 * `origin`, ?H ?L ?U its heading, left and up vectors, ?E whatever `env`
 * writes (NULL: ?E keeps its parameters), each into as many of the module's
 * parameters as it has (at most three for ?P ?H ?L ?U). The values are
 * written into `par`, an array laid out like the string's own parameters. */
typedef struct merp_ls_query {
    float *par;
    double origin[3];
    void (*env)(void *ctx, const double pos[3], const double head[3], float *par,
                unsigned np);
    void *ctx;
} merp_ls_query;

/* ABOP's defaults: δ 90, step 1, width 1, no tropism. */
merp_ls_turtle merp_ls_turtle_default(void);

/* Interprets `s` with the turtle of ABOP §1.5, §1.6, §2.2 into `out` (cleared
 * first): the turtle starts at the origin heading up (+y), its left -x, its up
 * +z. 0, or -1 when out of memory. O(|s|) time; memory O(segments + depth). */
int merp_ls_interpret(const merp_lstr *s, const merp_ls_turtle *tp, merp_ls_segs *out);
/* merp_ls_interpret answering the query modules through `q` (may be NULL). */
int merp_ls_interpret_query(const merp_lstr *s, const merp_ls_turtle *tp,
                            const merp_ls_query *q, merp_ls_segs *out);

void merp_ls_segs_free(merp_ls_segs *segs);

#endif
