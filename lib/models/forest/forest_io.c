/* meristem — the forest's state in a checkpoint, and its copy (forest.h): the
 * definition, the sites, and each member's maps and whole scene (mer_scene_save,
 * length-prefixed). The forest nodes' maps back to members are rebuilt from the
 * members' maps. */
#include "config.h"

#include <assert.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "models/forest/forest.h"
#include "scene_private.h"

void merp_forest_save(const merp_model *f, merp_bytes_out *out)
{
    merp_put_u64(out, f->len);
    merp_put(out, f->text, f->len);
    merp_put_u32(out, f->nsites);
    merp_put(out, f->sites, (size_t)f->nsites * 2 * sizeof *f->sites);
    merp_put_u32(out, f->nmembers);
    for (uint32_t k = 0; k < f->nmembers; k++) {
        const merp_forest_member *m = &f->m[k];
        merp_put(out, m->offset, sizeof m->offset);
        merp_put_u32(out, m->preset);
        merp_put_u32(out, m->mapped);
        merp_put(out, m->outer, (size_t)m->mapped * sizeof *m->outer);
        merp_put_u32(out, m->nplants);
        merp_put(out, m->plant, (size_t)m->nplants * sizeof *m->plant);
        uint8_t *bytes = NULL;
        size_t size = 0;
        if (mer_scene_save(m->scene, &bytes, &size, NULL) != MER_OK) {
            out->oom = 1; /* every member model saves: only memory can fail */
            return;
        }
        merp_put_u64(out, size);
        merp_put(out, bytes, size);
        merp_free(bytes);
    }
}

/* The forest nodes' maps back to the members, for `nodes` forest nodes: 0, or -1
 * when a member maps a node past them (damage) or out of memory. */
static int rebuild_maps(merp_model *f, uint32_t nodes)
{
    f->mem = merp_malloc(((size_t)nodes + 1) * sizeof *f->mem);
    f->mid = merp_malloc(((size_t)nodes + 1) * sizeof *f->mid);
    if (f->mem == NULL || f->mid == NULL)
        return -1;
    f->cap_out = f->nout = nodes;
    for (uint32_t o = 0; o < nodes; o++)
        f->mem[o] = f->mid[o] = MER_NO_NODE;
    for (uint32_t k = 0; k < f->nmembers; k++)
        for (uint32_t i = 0; i < f->m[k].mapped; i++) {
            uint32_t o = f->m[k].outer[i];
            if (o >= nodes)
                return -1;
            f->mem[o] = k;
            f->mid[o] = i;
        }
    return 0;
}

static int load_member(merp_bytes_in *in, merp_forest_member *m, uint32_t npresets,
                       mer_error *err)
{
    merp_get(in, m->offset, sizeof m->offset);
    m->preset = merp_get_u32(in);
    m->mapped = m->cap = merp_get_u32(in);
    if (!MERP_GET_ARRAY(in, m->outer, m->mapped))
        return -1;
    m->nplants = m->cap_plants = merp_get_u32(in);
    if (!MERP_GET_ARRAY(in, m->plant, m->nplants))
        return -1;
    uint64_t size = merp_get_u64(in);
    if (in->bad || m->preset >= npresets || size > in->n - in->at)
        return in->bad = 1, -1;
    mer_result rc = mer_scene_load(in->p + in->at, (size_t)size, &m->scene, err);
    in->at += (size_t)size;
    return rc == MER_OK && m->scene->sk.n >= m->mapped ? 0 : -1;
}

mer_result merp_forest_load(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err)
{
    merp_model *f = NULL;
    mer_result rc = merp_forest_create_empty(&f, err);
    if (rc != MER_OK)
        return rc;
    uint64_t len = merp_get_u64(in);
    if (!in->bad && len <= in->n - in->at && (f->text = merp_malloc(len + 1)) != NULL) {
        merp_get(in, f->text, len);
        f->text[len] = '\0';
        f->len = len;
    }
    f->nsites = merp_get_u32(in);
    int ok = f->text != NULL && merp_sow_parse(f->text, f->len, &f->sow, NULL) == MER_OK &&
             f->nsites <= f->sow.count && merp_get_array(in, &f->sites, 2 * (size_t)f->nsites,
                                                         sizeof *f->sites);
    uint32_t nm = ok ? merp_get_u32(in) : 0;
    ok = ok && !in->bad && nm <= f->nsites && (f->m = merp_calloc(nm ? nm : 1, sizeof *f->m));
    for (uint32_t k = 0; ok && k < nm; k++) {
        f->nmembers = k + 1;
        ok = load_member(in, &f->m[k], f->sow.npresets, err) == 0;
    }
    ok = ok && rebuild_maps(f, nodes) == 0;
    if (!ok) {
        merp_forest_free(f);
        return in->bad == 2 ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest")
                            : mer_error_set(err, MER_ERR_FORMAT, "model", "a damaged forest");
    }
    *out = f;
    return MER_OK;
}

/* A copy of n elements of `src` into *dst (NULL for 0): 0, or -1 out of memory. */
static int dup(void *dst, const void *src, size_t n, size_t size)
{
    void *q = NULL;
    if (n > 0 && (q = merp_malloc(n * size)) == NULL)
        return -1;
    if (n > 0)
        memcpy(q, src, n * size);
    memcpy(dst, &q, sizeof q);
    return 0;
}

mer_result merp_forest_clone(const merp_model *f, merp_model **out, mer_error *err)
{
    merp_model *c = NULL;
    mer_result rc = merp_forest_create_empty(&c, err);
    if (rc != MER_OK)
        return rc;
    c->len = f->len;
    c->sow = f->sow;
    c->nsites = f->nsites;
    c->nout = c->cap_out = f->nout;
    int ok = dup(&c->text, f->text, f->text ? f->len + 1 : 0, 1) == 0 &&
             dup(&c->sites, f->sites, 2 * (size_t)f->nsites, sizeof *f->sites) == 0 &&
             dup(&c->mem, f->mem, f->nout, sizeof *f->mem) == 0 &&
             dup(&c->mid, f->mid, f->nout, sizeof *f->mid) == 0 &&
             (c->m = merp_calloc(f->nmembers ? f->nmembers : 1, sizeof *c->m)) != NULL;
    for (uint32_t k = 0; ok && k < f->nmembers; k++) {
        const merp_forest_member *m = &f->m[k];
        merp_forest_member *d = &c->m[k];
        c->nmembers = k + 1;
        *d = *m;
        d->outer = NULL;
        d->plant = NULL;
        d->scene = NULL;
        d->cap = d->mapped;
        d->cap_plants = d->nplants;
        ok = dup(&d->outer, m->outer, m->mapped, sizeof *m->outer) == 0 &&
             dup(&d->plant, m->plant, m->nplants, sizeof *m->plant) == 0 &&
             mer_scene_clone(m->scene, &d->scene, err) == MER_OK;
    }
    if (!ok) {
        merp_forest_free(c);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
    }
    *out = c;
    return MER_OK;
}
