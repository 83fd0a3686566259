/* meristem — graphically defined functions (G04 §4; the function editor of
 * L-studio and lpfg), and their text formats .func and .fset. Private to lib.
 *
 * A function is a named control polygon over x ∈ [0, 1]: the x of its points go
 * from 0 to 1 without decreasing, and a point may count several times (its
 * multiplicity). Two kinds:
 *  - B-spline (lpfg's): the clamped uniform cubic B-spline of the polygon, each
 *    point repeated by its multiplicity, so it passes through the first and the
 *    last point. It is a parametric curve (x(u), y(u)); `samples` points of it
 *    are precomputed, the i-th at x = i / (samples - 1) with u found by
 *    bisection (x(u) never decreases, as the polygon's x do not), and a value
 *    between samples is interpolated linearly, as lpfg does.
 *  - linear: the polygon itself, straight between points (multiplicities do not
 *    matter). Not in lpfg; written as a `kind: linear` line in .func text.
 *
 * Fixed-size by design: a function is a value (copied into a model definition,
 * compared, hashed), so it holds its points and samples inline. */
#ifndef MERISTEM_INVERSE_GFUNC_H
#define MERISTEM_INVERSE_GFUNC_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>

#define MERP_GF_NAME_MAX 48     /* bytes of a name, its terminating 0 included */
#define MERP_GF_POINTS_MAX 32   /* control points of one function */
#define MERP_GF_EXPANDED_MAX 96 /* control points counted with their multiplicities */
#define MERP_GF_SAMPLES_MAX 512 /* lpfg's editor offers far fewer */

typedef enum merp_gf_kind { MERP_GF_BSPLINE = 0, MERP_GF_LINEAR = 1 } merp_gf_kind;

typedef struct merp_gf_point {
    float x, y;
    uint32_t m; /* multiplicity, >= 1 */
} merp_gf_point;

typedef struct merp_gfunc {
    char name[MERP_GF_NAME_MAX];
    merp_gf_kind kind;
    uint32_t samples; /* 2..MERP_GF_SAMPLES_MAX */
    int flip;         /* the editor shows x vertically; in a file, points read "y x" */
    uint32_t npts;
    merp_gf_point pts[MERP_GF_POINTS_MAX];
    /* The B-spline's samples (merp_gfunc_prepare): points (sx[i], sy[i]) of the
     * curve, sx non-decreasing from 0 to 1. */
    float sx[MERP_GF_SAMPLES_MAX], sy[MERP_GF_SAMPLES_MAX];
} merp_gfunc;

/* Checks f's points (x from 0 to 1, non-decreasing, in [0, 1]; multiplicities
 * >= 1; at least 4 counted points for a B-spline, 2 for a linear function;
 * samples in range; a name) and computes its samples. MER_ERR_INVALID with the
 * reason, f unchanged but for its samples. O(samples · log(1/ε) · points). */
mer_result merp_gfunc_prepare(merp_gfunc *f, mer_error *err);
/* f(x) of a prepared function; x is clamped to [0, 1]. O(log samples) for a
 * B-spline, O(points) for a linear function. */
float merp_gfunc_eval(const merp_gfunc *f, float x);
/* The point (x(u), y(u)) of f's B-spline at parameter u ∈ [0, 1] (the whole
 * curve), with no sampling: what the samples are taken from. O(points). */
void merp_gfunc_curve(const merp_gfunc *f, float u, float *x, float *y);
/* A prepared function of the given kind through `n` points (multiplicity 1) with
 * `samples` samples. MER_ERR_INVALID as merp_gfunc_prepare. */
mer_result merp_gfunc_make(merp_gfunc *f, const char *name, merp_gf_kind kind,
                           uint32_t samples, const float (*xy)[2], uint32_t n,
                           mer_error *err);
/* 1 when a and b have the same name, kind, samples, flip and points. */
int merp_gfunc_equal(const merp_gfunc *a, const merp_gfunc *b);

/* funcfile.c: the text formats. `.func`:
 *     fver 1 1
 *     name: NAME
 *     samples: N
 *     flip: on|off
 *     [kind: linear]          (ours; absent means lpfg's B-spline)
 *     points: N
 *     x y [multiplicity]      (N lines; "y x [m]" when flip is on)
 * `.fset`, a gallery: "funcgalleryver 1 1", "items: N", then N functions.
 * Blank lines and spaces around tokens are allowed. */

/* Reads one .func text of `len` bytes (no terminating 0 needed) into a prepared
 * *out. MER_ERR_FORMAT whose message starts "line L, column C: " for text that
 * does not parse; MER_ERR_INVALID (same prefix, at the points line) for points
 * merp_gfunc_prepare refuses. O(len + preparing). */
mer_result merp_func_read(const char *text, size_t len, merp_gfunc *out, mer_error *err);
/* Reads a .fset text: up to `cap` functions into out[0..*count). MER_ERR_FORMAT
 * and MER_ERR_INVALID as merp_func_read, MER_ERR_LIMIT when it holds more than
 * `cap` items. */
mer_result merp_fset_read(const char *text, size_t len, merp_gfunc *out, uint32_t cap,
                          uint32_t *count, mer_error *err);
/* Writes f as .func text into buf (cap bytes, 0-terminated when cap > 0) and
 * returns the length the whole text needs (without its 0), as snprintf does:
 * call with cap 0 to size the buffer. Floats are written with 9 significant
 * digits, so reading the text back gives the same function. O(points). */
size_t merp_func_write(const merp_gfunc *f, char *buf, size_t cap);
/* Writes n functions as one .fset text; as merp_func_write. */
size_t merp_fset_write(const merp_gfunc *fs, uint32_t n, char *buf, size_t cap);

#endif
