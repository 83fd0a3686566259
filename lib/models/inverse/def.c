/* meristem — an inverse-model tree's definition (G04 §4): its functions, known by
 * their symbols in G04, and its scalars, with the checks across them. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "core/alloc.h"
#include "models/inverse/inverse.h"

const char *const merp_inv_fn_names[MERP_G_COUNT] = {
    "G_h", "G_s1", "G_s2", "G_o1", "G_o2", "G_bs", "G_ss",
    "G_a", "G_m",  "G_l",  "G_e",  "G_lg", "G_bg", "G_r",
};

static int in(float v, float lo, float hi) { return isfinite(v) && v >= lo && v <= hi; }

static mer_result check_scalars(const merp_inv_def *d, mer_error *err)
{
    static const struct {
        const char *name;
        size_t at;
        float lo, hi;
    } rows[] = {
        {"h_max", offsetof(merp_inv_def, h_max), 0.01f, 200.0f},
        {"l_min", offsetof(merp_inv_def, l_min), 0.001f, 10.0f},
        {"l_max", offsetof(merp_inv_def, l_max), 0.01f, 200.0f},
        {"ls_max", offsetof(merp_inv_def, ls_max), 0.001f, 20.0f},
        {"a_max", offsetof(merp_inv_def, a_max), 0.0f, 1000.0f},
        {"s_min", offsetof(merp_inv_def, s_min), 0.0f, 10.0f},
        {"theta_max", offsetof(merp_inv_def, theta_max), 0.0f, 180.0f},
        {"beta_short", offsetof(merp_inv_def, beta_short), 0.0f, 180.0f},
        {"beta_long", offsetof(merp_inv_def, beta_long), 0.0f, 180.0f},
        {"leaf_size", offsetof(merp_inv_def, leaf_size), 0.0f, 10.0f},
        {"span", offsetof(merp_inv_def, span), 0.0f, 0.95f},
        {"jitter", offsetof(merp_inv_def, jitter), 0.0f, 45.0f},
        {"r_max", offsetof(merp_inv_def, r_max), 0.0001f, 10.0f},
    };
    for (size_t i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        float v;
        memcpy(&v, (const char *)d + rows[i].at, sizeof v);
        if (!in(v, rows[i].lo, rows[i].hi))
            return mer_error_set(err, MER_ERR_INVALID, rows[i].name, "%s must be in [%g, %g]",
                                 rows[i].name, (double)rows[i].lo, (double)rows[i].hi);
    }
    if (d->y_max < 1 || d->y_max > MERP_INV_YEARS_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "y_max", "y_max must be in 1..%u",
                             MERP_INV_YEARS_MAX);
    if (d->m_max < 1 || d->m_max > 1000)
        return mer_error_set(err, MER_ERR_INVALID, "m_max", "m_max must be in 1..1000");
    if (d->order_max < 1 || d->order_max > MERP_INV_ORDER_MAX)
        return mer_error_set(err, MER_ERR_INVALID, "order_max", "order_max must be in 1..%u",
                             MERP_INV_ORDER_MAX);
    return MER_OK;
}

mer_result merp_inv_def_check(const merp_inv_def *d, mer_error *err)
{
    assert(d != NULL);
    for (uint32_t i = 0; i < MERP_G_COUNT; i++) {
        merp_gfunc copy = d->g[i];
        if (strcmp(copy.name, merp_inv_fn_names[i]) != 0)
            return mer_error_set(err, MER_ERR_INVALID, "functions",
                                 "function %u must be %s, not \"%s\"", i,
                                 merp_inv_fn_names[i], copy.name);
        mer_result rc = merp_gfunc_prepare(&copy, err);
        if (rc != MER_OK)
            return rc;
    }
    return check_scalars(d, err);
}

/* The functions of a .fset into d by name; with `all`, every one must be there
 * but G_r, which a text written before it existed lacks: it gets the default. */
static mer_result read_functions(merp_inv_def *d, const char *fset, size_t len, int all,
                                 mer_error *err)
{
    assert(d != NULL && fset != NULL);
    enum { CAP = 2 * MERP_G_COUNT };
    merp_gfunc *fs = merp_malloc(CAP * sizeof *fs);
    if (fs == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for functions");
    uint32_t n = 0;
    mer_result rc = merp_fset_read(fset, len, fs, CAP, &n, err);
    uint32_t seen = 0, at[CAP];
    for (uint32_t i = 0; i < n && rc == MER_OK; i++) {
        uint32_t k = 0;
        while (k < MERP_G_COUNT && strcmp(fs[i].name, merp_inv_fn_names[k]) != 0)
            k++;
        if (k == MERP_G_COUNT)
            rc = mer_error_set(err, MER_ERR_INVALID, "functions",
                               "unknown function \"%s\"", fs[i].name);
        else if (seen & (1u << k))
            rc = mer_error_set(err, MER_ERR_INVALID, "functions", "%s given twice",
                               fs[i].name);
        seen |= 1u << k;
        at[i] = k;
    }
    for (uint32_t k = 0; k < MERP_G_COUNT && rc == MER_OK && all; k++)
        if (!(seen & (1u << k)) && k != MERP_G_R)
            rc = mer_error_set(err, MER_ERR_INVALID, "functions", "%s is missing",
                               merp_inv_fn_names[k]);
    if (rc == MER_OK && all && !(seen & (1u << MERP_G_R)))
        rc = merp_inv_radius_default(&d->g[MERP_G_R], err);
    for (uint32_t i = 0; i < n && rc == MER_OK; i++)
        d->g[at[i]] = fs[i];
    merp_free(fs);
    return rc;
}

mer_result merp_inv_def_functions(merp_inv_def *d, const char *fset, size_t len,
                                  mer_error *err)
{
    return read_functions(d, fset, len, 1, err);
}

mer_result merp_inv_def_replace(merp_inv_def *d, const char *fset, size_t len, mer_error *err)
{
    return read_functions(d, fset, len, 0, err);
}
