/* meristem — the parameter table: names, paper symbols, defaults, ranges, and
 * which growth model reads each field. The listing order is a contract (the CLI's
 * help, the HTTP API's params objects and /v1/presets list fields in it), so the
 * rows of every model share one table, each tagged with its group (models/model.h).
 * The checks across one model's fields are that model's (its ops' validate). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include <meristem/params.h>

#include "models/model.h"

typedef enum { F_FLOAT, F_U32 } field_kind;

typedef struct field {
    const char *name;
    const char *symbol;
    size_t offset;
    field_kind kind;
    double def, min, max;
    int min_open; /* 1: the range excludes min */
    uint32_t rows; /* MERP_ROWS_*: who reads it */
} field;

/* W: read by every model (the world: skeleton, environment, initial scene);
 * P: read by P09 alone; R: by the Runions 2007 model alone; L: by the L-system
 * model alone; G: by the guiding-vector model alone; N: the Perlin noise every
 * model reads. */
#define W MERP_ROWS_WORLD
#define P MERP_ROWS_P09
#define R MERP_ROWS_RUNIONS
#define N MERP_ROWS_NOISE
#define L MERP_ROWS_LSYSTEM
#define G MERP_ROWS_GUIDING
#define FF(rows, name, sym, member, def, lo, hi, open) \
    { name, sym, offsetof(mer_params, member), F_FLOAT, def, lo, hi, open, rows }
#define FU(rows, name, sym, member, def, lo, hi) \
    { name, sym, offsetof(mer_params, member), F_U32, def, lo, hi, 0, rows }
#define NEVER_D 4294967295.0

static const field fields[] = {
    FU(W, "environment", "", environment, MER_ENV_SHADOW, 0, 1),
    FU(P, "fate", "", fate, MER_FATE_BH, 0, 1),
    FF(W, "internode_length", "l0", internode_length, 1.0, 0.0, 100.0, 1),
    FU(P, "max_shoot", "", max_shoot, 16, 1, 1000),
    FF(W, "rho", "ρ", rho, 2.0, 0.0, 100.0, 1),
    FF(W, "theta", "θ", theta, 90.0, 0.0, 360.0, 1),
    FF(W, "r", "r", r, 4.0, 0.0, 100.0, 1),
    FF(W, "marker_cell", "", marker_cell, 4.0, 0.05, 1000.0, 0),
    FF(W, "shadow_a", "a", shadow_a, 0.1, 0.0, 1000.0, 1),
    FF(W, "shadow_b", "b", shadow_b, 2.0, 1.0, 1000.0, 1),
    FF(W, "shadow_c", "C", shadow_c, 1.0, 0.0, 1e6, 0),
    FU(W, "q_max", "q_max", q_max, 6, 0, 32),
    FF(W, "voxel", "", voxel, 1.0, 0.01, 1000.0, 0),
    FU(W, "shadow_dir", "", shadow_dir, MER_SHADOW_DIR_NEIGHBOUR, 0, 1),
    FF(W, "bounds_min.x", "", bounds_min[0], -50.0, -1e5, 1e5, 0),
    FF(W, "bounds_min.y", "", bounds_min[1], 0.0, -1e5, 1e5, 0),
    FF(W, "bounds_min.z", "", bounds_min[2], -50.0, -1e5, 1e5, 0),
    FF(W, "bounds_max.x", "", bounds_max[0], 50.0, -1e5, 1e5, 0),
    FF(W, "bounds_max.y", "", bounds_max[1], 100.0, -1e5, 1e5, 0),
    FF(W, "bounds_max.z", "", bounds_max[2], 50.0, -1e5, 1e5, 0),
    FF(W, "ground", "", ground, 0.0, -1e5, 1e5, 0),
    FU(W, "ground_enabled", "", ground_enabled, 1, 0, 1),
    FF(P, "alpha", "α", alpha, 2.0, 0.0, 1e6, 1),
    FF(P, "lambda", "λ", lambda, 0.5, 0.0, 1.0, 0),
    FF(P, "w_max", "w_max", w_max, 1.0, 0.0, 1e6, 1),
    FF(P, "w_min", "w_min", w_min, 0.006, 0.0, 1e6, 1),
    FF(P, "kappa", "κ", kappa, 0.5, 0.0, 1.0, 1),
    FU(P, "sylleptic", "", sylleptic, 0, 0, 1),
    FU(P, "sympodial", "", sympodial, 0, 0, 1),
    FU(P, "sympodial_abort", "", sympodial_abort, 0, 0, 1),
    FF(P, "divergence", "", divergence, 137.5, 0.0, 360.0, 0),
    FU(W, "buds_per_node", "", buds_per_node, 1, 1, 2),
    FF(W, "branch_angle", "", branch_angle, 45.0, 0.0, 180.0, 0),
    FF(P, "xi", "ξ", xi, 0.3, 0.0, 100.0, 0),
    FF(P, "eta", "η", eta, 0.05, -100.0, 100.0, 0),
    FF(P, "shed_threshold", "", shed_threshold, 0.0, 0.0, 1e6, 0),
    FF(W, "pipe_n", "n", pipe_n, 2.5, 1.0, 10.0, 0),
    FF(W, "leaf_diameter", "d_leaf", leaf_diameter, 0.05, 0.0, 100.0, 1),
    FF(R, "d_i", "d_i", d_i, 6.0, 0.0, 1000.0, 1),
    FF(R, "d_k", "d_k", d_k, 2.0, 0.0, 1000.0, 1),
    FF(R, "D", "D", D, 1.0, 0.0, 100.0, 1),
    FF(N, "noise_amplitude", "A", noise_amplitude, 0.0, 0.0, 2.0, 0),
    FF(N, "noise_scale", "", noise_scale, 0.2, 0.0, 100.0, 1),
    FU(N, "noise_octaves", "", noise_octaves, 3, 1, 8),
    FU(N, "noise_targets", "", noise_targets, 7, 0, 7),
    FF(L, "ls_delta", "δ", ls_delta, 90.0, 0.0, 360.0, 0),
    FF(L, "ls_step", "", ls_step, 1.0, 0.0, 1e4, 1),
    FF(L, "ls_width", "", ls_width, 0.0, 0.0, 1e4, 0),
    FF(L, "ls_width_scale", "", ls_width_scale, 1.0, 0.0, 1e4, 1),
    FF(L, "ls_elasticity", "e", ls_elasticity, 0.0, -10.0, 10.0, 0),
    FU(L, "ls_blocking", "", ls_blocking, 0, 0, 1),
    FF(G, "gv_density", "", gv_density, 1.0, 0.0, 1000.0, 1),
    FU(G, "gv_cones", "", gv_cones, 14, 4, 64),
    FF(G, "gv_rotation", "δ", gv_rotation, 4.0, 0.0, 180.0, 0),
    FF(G, "gv_rotation_falloff", "", gv_rotation_falloff, 1.0, 0.0, 2.0, 0),
    FU(G, "gv_early_endpoints", "", gv_early_endpoints, 1, 1, 100000),
    FU(G, "gv_endpoints", "", gv_endpoints, 200, 1, 100000),
    FU(G, "gv_endpoints_total", "", gv_endpoints_total, 0, 0, 1000000),
    FU(G, "gv_k_hops", "k", gv_k_hops, 3, 1, 1000),
    FF(G, "gv_t", "t", gv_t, 0.5, 0.0, 1.0, 1),
    FU(G, "gv_bound", "", gv_bound, 0, 0, 1),
    FU(G, "gv_iterations", "", gv_iterations, 4, 1, 1000),
    FF(G, "gv_epsilon", "ε", gv_epsilon, 0.05, 0.0, 10.0, 1),
    FF(G, "gv_p", "p", gv_p, 2.0, 0.1, 16.0, 0),
    FU(W, "seedlings", "", seedlings, 1, 0, 1000),
    FF(W, "seedling_spacing", "", seedling_spacing, 10.0, 0.0, 1e4, 0),
    FU(W, "marker_volume", "", marker_volume, MER_VOLUME_ELLIPSOID, 0, 5),
    FU(W, "marker_count", "|S|", marker_count, 20000, 0, 20000000),
    FF(W, "marker_center.x", "", marker_center[0], 0.0, -1e5, 1e5, 0),
    FF(W, "marker_center.y", "", marker_center[1], 12.0, -1e5, 1e5, 0),
    FF(W, "marker_center.z", "", marker_center[2], 0.0, -1e5, 1e5, 0),
    FF(W, "marker_size.x", "", marker_size[0], 10.0, 0.0, 1e5, 0),
    FF(W, "marker_size.y", "", marker_size[1], 10.0, 0.0, 1e5, 0),
    FF(W, "marker_size.z", "", marker_size[2], 10.0, 0.0, 1e5, 0),
    FU(P, "apical_off.0", "", schedule.apical_off[0], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.1", "", schedule.apical_off[1], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.2", "", schedule.apical_off[2], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.3", "", schedule.apical_off[3], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.4", "", schedule.apical_off[4], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.5", "", schedule.apical_off[5], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.6", "", schedule.apical_off[6], NEVER_D, 0, NEVER_D),
    FU(P, "apical_off.7", "", schedule.apical_off[7], NEVER_D, 0, NEVER_D),
    FF(P, "eta_order_scale.0", "", schedule.eta_order_scale[0], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.1", "", schedule.eta_order_scale[1], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.2", "", schedule.eta_order_scale[2], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.3", "", schedule.eta_order_scale[3], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.4", "", schedule.eta_order_scale[4], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.5", "", schedule.eta_order_scale[5], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.6", "", schedule.eta_order_scale[6], 1.0, -100.0, 100.0, 0),
    FF(P, "eta_order_scale.7", "", schedule.eta_order_scale[7], 1.0, -100.0, 100.0, 0),
};

#undef W
#undef P
#undef R
#undef N
#undef L
#undef G

#define NFIELDS (sizeof fields / sizeof fields[0])

static void field_store(mer_params *p, const field *f, double v)
{
    char *base = (char *)p + f->offset;
    if (f->kind == F_FLOAT) {
        float x = (float)v;
        memcpy(base, &x, sizeof x);
    } else {
        uint32_t x = (uint32_t)v;
        memcpy(base, &x, sizeof x);
    }
}

static double field_load(const mer_params *p, const field *f)
{
    const char *base = (const char *)p + f->offset;
    if (f->kind == F_FLOAT) {
        float x;
        memcpy(&x, base, sizeof x);
        return (double)x;
    }
    uint32_t x;
    memcpy(&x, base, sizeof x);
    return (double)x;
}

mer_params mer_params_default(void)
{
    mer_params p;
    memset(&p, 0, sizeof p);
    for (size_t i = 0; i < NFIELDS; i++)
        field_store(&p, &fields[i], fields[i].def);
    return p;
}

static int is_all_zero(const mer_params *p)
{
    static const mer_params zero;
    return memcmp(p, &zero, sizeof zero) == 0;
}

void mer_params_resolve(const mer_params *in, mer_params *out)
{
    assert(out != NULL);
    if (in == NULL || is_all_zero(in))
        *out = mer_params_default();
    else if (in != out)
        *out = *in;
}

static mer_result check_field(const field *f, double v, mer_error *err)
{
    int bad = isnan(v) || v > f->max || (f->min_open ? v <= f->min : v < f->min);
    if (!bad && f->kind == F_U32 && floor(v) != v)
        bad = 1;
    if (!bad)
        return MER_OK;
    if (f->kind == F_U32)
        return mer_error_set(err, MER_ERR_RANGE, f->name,
                             "%s must be an integer from %.0f to %.0f, got %g",
                             f->name, f->min, f->max, v);
    return mer_error_set(err, MER_ERR_RANGE, f->name, "%s must be in %s%g, %g], got %g",
                         f->name, f->min_open ? "(" : "[", f->min, f->max, v);
}

mer_result mer_params_validate(const mer_params *in, mer_error *err)
{
    mer_params p;
    mer_params_resolve(in, &p);
    for (size_t i = 0; i < NFIELDS; i++) {
        mer_result rc = check_field(&fields[i], field_load(&p, &fields[i]), err);
        if (rc != MER_OK)
            return rc;
    }
    static const char *const axes[3] = {"bounds_max.x", "bounds_max.y", "bounds_max.z"};
    double cells_v = 1.0, cells_m = 1.0;
    for (int a = 0; a < 3; a++) {
        double ext = (double)p.bounds_max[a] - (double)p.bounds_min[a];
        if (!(ext > 0.0))
            return mer_error_set(err, MER_ERR_RANGE, axes[a],
                                 "%s must exceed the matching bounds_min", axes[a]);
        cells_v *= ceil(ext / (double)p.voxel);
        cells_m *= ceil(ext / (double)p.marker_cell);
    }
    if (cells_v > (double)MER_GRID_CELLS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "voxel",
                             "the shadow grid would have %.0f voxels, more than %u; raise voxel or shrink bounds",
                             cells_v, (unsigned)MER_GRID_CELLS_MAX);
    if (cells_m > (double)MER_GRID_CELLS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "marker_cell",
                             "the marker grid would have %.0f cells, more than %u; raise marker_cell",
                             cells_m, (unsigned)MER_GRID_CELLS_MAX);
    const merp_model_ops *ops = merp_model_ops_of(p.model);
    if (ops == NULL)
        return mer_error_set(err, MER_ERR_RANGE, "model", "there is no model %u",
                             (unsigned)p.model);
    return ops->validate != NULL ? ops->validate(&p, err) : MER_OK;
}

static const field *find(const char *name)
{
    if (name == NULL)
        return NULL;
    for (size_t i = 0; i < NFIELDS; i++)
        if (strcmp(fields[i].name, name) == 0)
            return &fields[i];
    return NULL;
}

mer_result mer_params_set(mer_params *p, const char *name, double value, mer_error *err)
{
    assert(p != NULL);
    const field *f = find(name);
    if (f == NULL)
        return mer_error_set(err, MER_ERR_INVALID, name, "unknown parameter '%s'",
                             name != NULL ? name : "(null)");
    mer_result rc = check_field(f, value, err);
    if (rc != MER_OK)
        return rc;
    mer_params_resolve(p, p);
    field_store(p, f, value);
    return MER_OK;
}

mer_result mer_params_get(const mer_params *in, const char *name, double *value, mer_error *err)
{
    assert(value != NULL);
    const field *f = find(name);
    if (f == NULL)
        return mer_error_set(err, MER_ERR_INVALID, name, "unknown parameter '%s'",
                             name != NULL ? name : "(null)");
    mer_params p;
    mer_params_resolve(in, &p);
    *value = field_load(&p, f);
    return MER_OK;
}

size_t mer_params_field_count(void) { return NFIELDS; }

const char *mer_params_field_name(size_t i) { return i < NFIELDS ? fields[i].name : NULL; }

const char *mer_params_field_symbol(size_t i) { return i < NFIELDS ? fields[i].symbol : NULL; }

const char *mer_params_field_model(size_t i)
{
    if (i >= NFIELDS)
        return NULL;
    for (uint32_t k = 0; merp_model_ops_of(k) != NULL; k++)
        if (merp_model_ops_of(k)->param_rows & fields[i].rows)
            return merp_model_ops_of(k)->name;
    return "";
}

int mer_params_field_used(const mer_params *p, size_t i)
{
    assert(p != NULL);
    if (i >= NFIELDS)
        return 0;
    if (fields[i].rows & MERP_ROWS_WORLD)
        return 1;
    if (fields[i].rows & MERP_ROWS_NOISE)
        return p->noise_amplitude > 0.0f;
    const merp_model_ops *ops = merp_model_ops_of(p->model);
    return ops != NULL && (ops->param_rows & fields[i].rows) != 0;
}

void mer_params_field_range(size_t i, double *min, double *max)
{
    assert(min != NULL && max != NULL);
    *min = i < NFIELDS ? fields[i].min : 0.0;
    *max = i < NFIELDS ? fields[i].max : 0.0;
}

float mer_keyframes_eval(const mer_keyframe *keys, uint32_t n, float step, float fallback)
{
    assert(n == 0 || keys != NULL);
    if (n == 0)
        return fallback;
    if (step <= keys[0].step)
        return keys[0].value;
    for (uint32_t i = 1; i < n; i++) {
        if (step <= keys[i].step) {
            float t = (step - keys[i - 1].step) / (keys[i].step - keys[i - 1].step);
            return keys[i - 1].value + t * (keys[i].value - keys[i - 1].value);
        }
    }
    return keys[n - 1].value;
}
