/* meristem — the brush (P09 §5): a dab scatters markers in a ball whose size and
 * density grow with pressure, copied under symmetry; space colonization then grows
 * towards them. */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>

#include <meristem/edit.h>

#include "core/alloc.h"
#include "scene_private.h"
#include "symmetry.h"

#define MERP_BRUSH_RADIUS_MAX 1000.0f  /* ball radius at full pressure */
#define MERP_BRUSH_COUNT_DEFAULT 50u   /* max_count 0 means this */
#define MERP_BRUSH_COUNT_MAX 100000u   /* markers at full pressure */
#define MERP_BRUSH_SPREAD_MIN 0.1f     /* ball radius at zero pressure, as a fraction */
#define MERP_BRUSH_SPREAD_GAIN 0.9f    /* 1 - MERP_BRUSH_SPREAD_MIN: full size at pressure 1 */

static mer_result check_brush(const mer_brush *brush, uint32_t *max_count, mer_error *err)
{
    if (!(brush->radius > 0.0f && brush->radius <= MERP_BRUSH_RADIUS_MAX))
        return mer_error_set(err, MER_ERR_RANGE, "radius", "radius must be in (0, %g], got %g",
                             (double)MERP_BRUSH_RADIUS_MAX, (double)brush->radius);
    if (!(brush->pressure > 0.0f && brush->pressure <= 1.0f))
        return mer_error_set(err, MER_ERR_RANGE, "pressure", "pressure must be in (0, 1], got %g",
                             (double)brush->pressure);
    *max_count = brush->max_count ? brush->max_count : MERP_BRUSH_COUNT_DEFAULT;
    if (*max_count > MERP_BRUSH_COUNT_MAX)
        return mer_error_set(err, MER_ERR_RANGE, "max_count",
                             "max_count must be from 1 to %u, got %u", MERP_BRUSH_COUNT_MAX,
                             (unsigned)*max_count);
    return MER_OK;
}

mer_result mer_scene_brush(mer_scene *s, const mer_brush *brush, const mer_symmetry *sym,
                           size_t *added, mer_error *err)
{
    assert(s != NULL && brush != NULL);
    if (added != NULL)
        *added = 0;
    uint32_t max_count = 0;
    mer_result rc = check_brush(brush, &max_count, err);
    merp_symmetry y;
    if (rc == MER_OK)
        rc = merp_symmetry_resolve(sym, &y, err);
    if (rc != MER_OK)
        return rc;
    float pr = brush->pressure;
    uint32_t count = 1 + (uint32_t)lroundf((float)(max_count - 1) * pr * pr);
    float spread = brush->radius * (MERP_BRUSH_SPREAD_MIN + MERP_BRUSH_SPREAD_GAIN * pr);
    size_t copies = merp_symmetry_copies(&y);
    size_t total = (size_t)count * copies;
    if (total > MER_BRUSH_MARKERS_MAX)
        return mer_error_set(err, MER_ERR_LIMIT, "max_count",
                             "a dab would make %zu markers with its copies, more than %u",
                             total, (unsigned)MER_BRUSH_MARKERS_MAX);
    float *xyz = merp_malloc(total * 3 * sizeof *xyz);
    if (xyz == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for brush markers");
    /* A refused dab draws nothing: the generator goes back to where it was. */
    const mer_rng drawn_from = s->rng;
    for (uint32_t c = 0; c < count; c++) {
        float u[3];
        merp_unit_ball(&s->rng, u);
        float p0[3];
        for (int a = 0; a < 3; a++)
            p0[a] = brush->center[a] + spread * u[a];
        merp_symmetry_apply(&y, p0, xyz + 3 * copies * c);
    }
    size_t before = mer_scene_marker_count(s);
    rc = mer_scene_add_markers(s, xyz, total, err);
    merp_free(xyz);
    if (rc != MER_OK)
        s->rng = drawn_from;
    if (rc == MER_OK && added != NULL)
        *added = mer_scene_marker_count(s) - before;
    return rc;
}
