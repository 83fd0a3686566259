/* meristem — arithmetic expressions of parametric L-systems (ABOP §1.10, the
 * conditions and successor parameters; cpfg's operators and functions).
 *
 * An expression is compiled once, by recursive descent, into postfix code for a
 * small stack machine, then evaluated once per module that a production rewrites.
 * Precedence, loosest first: || ; && ; == != < <= > >= ; + - ; * / ; unary - ! ;
 * ^ (right-associative). Comparisons and logic give 1 or 0. Angles of sin, cos,
 * tan and atan2 are in degrees, as everywhere in cpfg. ran(x) is uniform in
 * [0, x); nran(m, s) is normal with mean m and deviation s.
 */
#include "config.h"

#include "models/lsystem/lsystem.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"

enum {
    OP_NUM, OP_VAR, OP_ADD, OP_SUB, OP_MUL, OP_DIV, OP_POW, OP_NEG, OP_NOT,
    OP_AND, OP_OR, OP_EQ, OP_NE, OP_LT, OP_LE, OP_GT, OP_GE, OP_FN
};
enum { FN_SQRT, FN_SIN, FN_COS, FN_TAN, FN_ATAN2, FN_EXP, FN_LOG, FN_FLOOR,
       FN_RAN, FN_NRAN, FN_ABS };

static const struct { const char *name; int argc; } fns[] = {
    [FN_SQRT] = {"sqrt", 1}, [FN_SIN] = {"sin", 1},   [FN_COS] = {"cos", 1},
    [FN_TAN] = {"tan", 1},   [FN_ATAN2] = {"atan2", 2}, [FN_EXP] = {"exp", 1},
    [FN_LOG] = {"log", 1},   [FN_FLOOR] = {"floor", 1}, [FN_RAN] = {"ran", 1},
    [FN_NRAN] = {"nran", 2}, [FN_ABS] = {"abs", 1},
};
#define NFNS ((int)(sizeof fns / sizeof fns[0]))
#define MAX_CODE 256
#define MAX_STACK 64

typedef struct ins {
    uint8_t op, fn;
    uint16_t slot;
    double num;
} ins;

struct merp_expr {
    int n, depth, pure;
    ins code[];
};

typedef struct cc {
    const char *s, *end, *p;
    const merp_ls_name *names;
    int nnames, line, col0, depth, maxdepth, pure, n;
    ins code[MAX_CODE];
    merp_ls_error *err;
    int failed;
} cc;

static void fail(cc *c, const char *at, const char *msg)
{
    if (c->failed)
        return;
    c->failed = 1;
    c->err->line = c->line;
    c->err->col = c->col0 + (int)(at - c->s);
    snprintf(c->err->msg, sizeof c->err->msg, "%s", msg);
}

/* Appends one instruction; `effect` is its change of the stack depth. */
static void emit(cc *c, int op, int fn, int slot, double num, int effect)
{
    if (c->n >= MAX_CODE) {
        fail(c, c->p, "expression too long");
        return;
    }
    c->code[c->n++] = (ins){(uint8_t)op, (uint8_t)fn, (uint16_t)slot, num};
    c->depth += effect;
    if (c->depth > c->maxdepth)
        c->maxdepth = c->depth;
}

static void skip(cc *c)
{
    while (c->p < c->end && (*c->p == ' ' || *c->p == '\t'))
        c->p++;
}

/* Consumes `tok` when it comes next (after blanks). */
static int eat(cc *c, const char *tok)
{
    skip(c);
    size_t k = strlen(tok);
    if ((size_t)(c->end - c->p) >= k && memcmp(c->p, tok, k) == 0) {
        c->p += k;
        return 1;
    }
    return 0;
}

static void parse_or(cc *c);

static int ident_char(char ch, int first)
{
    return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || ch == '_' ||
           (!first && ch >= '0' && ch <= '9');
}

static void parse_call(cc *c, const char *at, int fn)
{
    int argc = 0;
    if (!eat(c, ")")) {
        do {
            parse_or(c);
            argc++;
        } while (!c->failed && eat(c, ","));
        if (!eat(c, ")"))
            fail(c, c->p, "expected ')' after the arguments");
    }
    if (!c->failed && argc != fns[fn].argc)
        fail(c, at, "wrong number of arguments");
    if (fn == FN_RAN || fn == FN_NRAN)
        c->pure = 0;
    emit(c, OP_FN, fn, 0, 0, 1 - argc);
}

static void parse_name(cc *c)
{
    const char *at = c->p;
    while (c->p < c->end && ident_char(*c->p, 0))
        c->p++;
    size_t len = (size_t)(c->p - at);
    if (eat(c, "(")) {
        for (int f = 0; f < NFNS; f++)
            if (strlen(fns[f].name) == len && memcmp(fns[f].name, at, len) == 0) {
                parse_call(c, at, f);
                return;
            }
        fail(c, at, "unknown function");
        return;
    }
    for (int i = c->nnames - 1; i >= 0; i--) {
        const merp_ls_name *nm = &c->names[i];
        if (strlen(nm->name) == len && memcmp(nm->name, at, len) == 0) {
            if (nm->slot >= 0) {
                c->pure = 0;
                emit(c, OP_VAR, 0, nm->slot, 0, 1);
            } else {
                emit(c, OP_NUM, 0, 0, nm->value, 1);
            }
            return;
        }
    }
    fail(c, at, "unknown name");
}

static void parse_primary(cc *c)
{
    skip(c);
    if (c->p >= c->end) {
        fail(c, c->p, "expression expected");
    } else if (*c->p == '(') {
        c->p++;
        parse_or(c);
        if (!eat(c, ")"))
            fail(c, c->p, "expected ')'");
    } else if ((*c->p >= '0' && *c->p <= '9') || *c->p == '.') {
        char buf[64];
        size_t k = (size_t)(c->end - c->p) < sizeof buf - 1 ? (size_t)(c->end - c->p)
                                                            : sizeof buf - 1;
        memcpy(buf, c->p, k);
        buf[k] = '\0';
        char *e;
        double v = strtod(buf, &e);
        if (e == buf)
            fail(c, c->p, "bad number");
        c->p += e - buf;
        emit(c, OP_NUM, 0, 0, v, 1);
    } else if (ident_char(*c->p, 1)) {
        parse_name(c);
    } else {
        fail(c, c->p, "unexpected character in expression");
    }
}

static void parse_unary(cc *c);

/* ^ binds tighter than unary minus (-2^2 = -4) and groups to the right. */
static void parse_power(cc *c)
{
    parse_primary(c);
    if (eat(c, "^")) {
        parse_unary(c);
        emit(c, OP_POW, 0, 0, 0, -1);
    }
}

static void parse_unary(cc *c)
{
    if (eat(c, "-")) {
        parse_unary(c);
        emit(c, OP_NEG, 0, 0, 0, 0);
    } else if (eat(c, "+")) {
        parse_unary(c);
    } else if (skip(c), c->p < c->end && *c->p == '!' &&
               !(c->p + 1 < c->end && c->p[1] == '=')) {
        c->p++;
        parse_unary(c);
        emit(c, OP_NOT, 0, 0, 0, 0);
    } else {
        parse_power(c);
    }
}

/* The binary operators by precedence, loosest first; all group to the left. A
 * longer token comes before its prefix ("<=" before "<"). */
static const struct {
    const char *tok[7];
    uint8_t op[7];
} levels[] = {
    {{"||"}, {OP_OR}},
    {{"&&"}, {OP_AND}},
    {{"==", "!=", "<=", ">=", "<", ">", "="},
     {OP_EQ, OP_NE, OP_LE, OP_GE, OP_LT, OP_GT, OP_EQ}},
    {{"+", "-"}, {OP_ADD, OP_SUB}},
    {{"*", "/"}, {OP_MUL, OP_DIV}},
};
#define NLEVELS ((int)(sizeof levels / sizeof levels[0]))

static void parse_level(cc *c, int lv)
{
    if (lv == NLEVELS) {
        parse_unary(c);
        return;
    }
    parse_level(c, lv + 1);
    for (int again = 1; again && !c->failed;) {
        again = 0;
        for (int k = 0; k < 7 && levels[lv].tok[k]; k++)
            if (eat(c, levels[lv].tok[k])) {
                parse_level(c, lv + 1);
                emit(c, levels[lv].op[k], 0, 0, 0, -1);
                again = 1;
                break;
            }
    }
}

static void parse_or(cc *c)
{
    parse_level(c, 0);
}

merp_expr *merp_expr_compile(const char *src, size_t len, const merp_ls_name *names,
                             int nnames, int line, int col0, merp_ls_error *err)
{
    assert(src && err && (names || nnames == 0));
    static cc zero;
    cc *c = merp_malloc(sizeof *c);
    if (!c) {
        snprintf(err->msg, sizeof err->msg, "out of memory");
        err->line = line, err->col = col0;
        return NULL;
    }
    *c = zero;
    c->s = c->p = src;
    c->end = src + len;
    c->names = names, c->nnames = nnames;
    c->line = line, c->col0 = col0, c->err = err, c->pure = 1;
    parse_or(c);
    skip(c);
    if (!c->failed && c->p != c->end)
        fail(c, c->p, "unexpected text after the expression");
    if (!c->failed && c->maxdepth > MAX_STACK)
        fail(c, src, "expression nested too deeply");
    merp_expr *e = NULL;
    if (!c->failed) {
        e = merp_malloc(sizeof *e + (size_t)c->n * sizeof(ins));
        if (e) {
            e->n = c->n, e->depth = c->maxdepth, e->pure = c->pure;
            memcpy(e->code, c->code, (size_t)c->n * sizeof(ins));
        } else {
            fail(c, src, "out of memory");
        }
    }
    merp_free(c);
    return e;
}

static double deg(double x) { return x * (M_PI / 180.0); }

static double call(int fn, const double *a, merp_ls_rand *rnd)
{
    switch (fn) {
    case FN_SQRT: return sqrt(a[0]);
    case FN_SIN: return sin(deg(a[0]));
    case FN_COS: return cos(deg(a[0]));
    case FN_TAN: return tan(deg(a[0]));
    case FN_ATAN2: return atan2(a[0], a[1]) * (180.0 / M_PI);
    case FN_EXP: return exp(a[0]);
    case FN_LOG: return log(a[0]);
    case FN_FLOOR: return floor(a[0]);
    case FN_ABS: return fabs(a[0]);
    case FN_RAN: return rnd ? a[0] * merp_ls_uniform(rnd) : 0.0;
    case FN_NRAN: {
        if (!rnd)
            return a[0];
        /* Box–Muller from two uniforms of the module's own counter. */
        double u = 1.0 - merp_ls_uniform(rnd), v = merp_ls_uniform(rnd);
        return a[0] + a[1] * sqrt(-2.0 * log(u)) * cos(2.0 * M_PI * v);
    }
    default: return 0.0;
    }
}

static double binary(int op, double x, double y)
{
    switch (op) {
    case OP_ADD: return x + y;
    case OP_SUB: return x - y;
    case OP_MUL: return x * y;
    case OP_DIV: return x / y;
    case OP_POW: return pow(x, y);
    case OP_AND: return (x != 0.0) && (y != 0.0);
    case OP_OR: return (x != 0.0) || (y != 0.0);
    case OP_EQ: return x == y;
    case OP_NE: return x != y;
    case OP_LT: return x < y;
    case OP_LE: return x <= y;
    case OP_GT: return x > y;
    default: return x >= y;
    }
}

double merp_expr_eval(const merp_expr *e, const double *vars, merp_ls_rand *rnd)
{
    assert(e);
    double st[MAX_STACK];
    int sp = 0;
    for (int i = 0; i < e->n; i++) {
        const ins *in = &e->code[i];
        switch (in->op) {
        case OP_NUM: st[sp++] = in->num; break;
        case OP_VAR: st[sp++] = vars[in->slot]; break;
        case OP_NEG: st[sp - 1] = -st[sp - 1]; break;
        case OP_NOT: st[sp - 1] = st[sp - 1] == 0.0; break;
        case OP_FN: {
            int argc = fns[in->fn].argc;
            sp -= argc;
            st[sp] = call(in->fn, &st[sp], rnd);
            sp++;
            break;
        }
        default:
            sp--;
            st[sp - 1] = binary(in->op, st[sp - 1], st[sp]);
        }
    }
    return sp > 0 ? st[sp - 1] : 0.0;
}

int merp_expr_is_constant(const merp_expr *e)
{
    assert(e);
    return e->pure;
}

void merp_expr_free(merp_expr *e)
{
    merp_free(e);
}

static uint64_t mix(uint64_t z)
{
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

uint64_t merp_ls_key(uint64_t seed, uint32_t step, uint64_t index)
{
    uint64_t k = mix(seed + UINT64_C(0x9E3779B97F4A7C15));
    k = mix(k ^ ((uint64_t)step + UINT64_C(0x632BE59BD9B4E019)));
    return mix(k ^ (index * UINT64_C(0xD6E8FEB86659FD93)));
}

double merp_ls_uniform(merp_ls_rand *rnd)
{
    assert(rnd);
    uint64_t z = mix(rnd->key ^ mix((uint64_t)++rnd->count));
    return (double)(z >> 11) * 0x1.0p-53;
}
