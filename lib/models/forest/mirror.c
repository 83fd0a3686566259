/* meristem — mirroring the members' skeletons into the forest's (forest.h). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <string.h>

#include "core/alloc.h"
#include "models/forest/forest.h"
#include "scene_private.h"

/* Room for `n` entries in *a (of *cap). */
static int grow_u32(uint32_t **a, uint32_t *cap, uint32_t n)
{
    if (n <= *cap)
        return 0;
    uint32_t c = *cap ? *cap : 64;
    while (c < n)
        c = c > UINT32_MAX / 2 ? n : 2 * c;
    uint32_t *b = merp_realloc(*a, (size_t)c * sizeof *b);
    if (b == NULL)
        return -1;
    *a = b;
    *cap = c;
    return 0;
}

/* Room for `n` forest nodes in the maps back to the members. */
static int grow_out(merp_model *f, uint32_t n)
{
    uint32_t c1 = f->cap_out, c2 = f->cap_out;
    if (grow_u32(&f->mem, &c1, n) != 0 || grow_u32(&f->mid, &c2, n) != 0)
        return -1;
    f->cap_out = c1 < c2 ? c1 : c2;
    return 0;
}

/* A forest node for each member node not mapped yet. */
static mer_result map_new(merp_model *f, uint32_t k, merp_skeleton *sk, uint32_t step,
                          mer_error *err)
{
    merp_forest_member *m = &f->m[k];
    const merp_skeleton *ms = &m->scene->sk;
    if (grow_u32(&m->outer, &m->cap, ms->n) != 0)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
    for (uint32_t i = m->mapped; i < ms->n; i++) {
        uint32_t o;
        mer_result rc = merp_skel_node_new(sk, step, &o, err);
        if (rc != MER_OK)
            return rc;
        if (grow_out(f, o + 1) != 0)
            return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
        f->mem[o] = k;
        f->mid[o] = i;
        f->nout = o + 1;
        m->outer[i] = o;
        m->mapped = i + 1;
    }
    return MER_OK;
}

/* The member's plants as forest plants: a new plant for each new one (an
 * L-system keeps no plants: its first node is its one plant's root). */
static mer_result map_plants(merp_forest_member *m, merp_skeleton *sk, mer_error *err)
{
    const merp_skeleton *ms = &m->scene->sk;
    uint32_t n = ms->nplants > 0 ? ms->nplants : ms->n > 0 ? 1 : 0;
    if (grow_u32(&m->plant, &m->cap_plants, n) != 0)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a forest");
    for (uint32_t j = 0; j < n; j++) {
        uint32_t root = m->outer[ms->nplants > 0 ? ms->roots[j] : 0];
        if (j < m->nplants) {
            sk->roots[m->plant[j]] = root;
            continue;
        }
        sk->parent[root] = MER_NO_NODE;
        mer_result rc = merp_skel_add_root(sk, root, err);
        if (rc != MER_OK)
            return rc;
        m->plant[j] = sk->nplants - 1;
        m->nplants = j + 1;
    }
    return MER_OK;
}

static uint32_t outer_of(const merp_forest_member *m, uint32_t id)
{
    return id == MER_NO_NODE ? MER_NO_NODE : m->outer[id];
}

/* Member node i's fields onto forest node o. */
static void copy_node(const merp_forest_member *m, uint32_t i, merp_skeleton *sk, uint32_t o)
{
    const merp_skeleton *ms = &m->scene->sk;
    sk->parent[o] = outer_of(m, ms->parent[i]);
    for (int c = 0; c < 3; c++) {
        sk->child[3 * o + c] = outer_of(m, ms->child[3 * i + c]);
        sk->bud[3 * o + c] = ms->bud[3 * i + c];
        sk->pos[3 * o + c] = ms->pos[3 * i + c] + m->offset[c];
        sk->dir[3 * o + c] = ms->dir[3 * i + c];
        sk->side[3 * o + c] = ms->side[3 * i + c];
    }
    sk->slot[o] = ms->slot[i];
    sk->alive[o] = ms->alive[i];
    sk->plant[o] = m->plant[ms->nplants > 0 ? ms->plant[i] : 0];
    sk->order[o] = ms->order[i];
    sk->born[o] = ms->born[i];
    sk->len[o] = ms->len[i];
    sk->q[o] = ms->q[i];
    sk->dn[o] = powf(merp_pipe_diameter(ms, i), sk->pipe_n);
}

/* Forest node o, mapped past its member's end, dead and unlinked. */
static void unmap_node(merp_skeleton *sk, uint32_t o)
{
    sk->parent[o] = MER_NO_NODE;
    for (int c = 0; c < 3; c++) {
        sk->child[3 * o + c] = MER_NO_NODE;
        sk->bud[3 * o + c] = MER_BUD_NONE;
    }
    sk->alive[o] = 0;
}

mer_result merp_forest_mirror(merp_model *f, merp_skeleton *sk, uint32_t step, mer_error *err)
{
    assert(f != NULL && sk != NULL);
    for (uint32_t k = 0; k < f->nmembers; k++) {
        merp_forest_member *m = &f->m[k];
        mer_result rc = map_new(f, k, sk, step, err);
        if (rc == MER_OK)
            rc = map_plants(m, sk, err);
        if (rc != MER_OK)
            return rc;
        const merp_skeleton *ms = &m->scene->sk;
        for (uint32_t i = 0; i < ms->n; i++)
            copy_node(m, i, sk, m->outer[i]);
        for (uint32_t i = ms->n; i < m->mapped; i++)
            unmap_node(sk, m->outer[i]);
    }
    return MER_OK;
}

int merp_forest_member_of(const merp_model *f, uint32_t id, uint32_t *member, uint32_t *node)
{
    if (id >= f->nout || f->mem[id] == MER_NO_NODE)
        return -1;
    const merp_forest_member *m = &f->m[f->mem[id]];
    if (f->mid[id] >= m->scene->sk.n)
        return -1;
    *member = f->mem[id];
    *node = f->mid[id];
    return 0;
}

void merp_forest_diameters(const merp_model *f, merp_skeleton *sk)
{
    for (uint32_t k = 0; k < f->nmembers; k++) {
        const merp_forest_member *m = &f->m[k];
        const merp_skeleton *ms = &m->scene->sk;
        for (uint32_t i = 0; i < ms->n; i++)
            sk->dn[m->outer[i]] = powf(merp_pipe_diameter(ms, i), sk->pipe_n);
    }
}

void merp_forest_members_free(merp_model *f)
{
    for (uint32_t k = 0; k < f->nmembers; k++) {
        mer_scene_free(f->m[k].scene);
        merp_free(f->m[k].outer);
        merp_free(f->m[k].plant);
    }
    merp_free(f->m);
    merp_free(f->mem);
    merp_free(f->mid);
    f->m = NULL;
    f->mem = f->mid = NULL;
    f->nmembers = f->nout = f->cap_out = 0;
}
