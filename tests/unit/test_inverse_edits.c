/* The inverse model's tree across rebuilds and in the mesh: a node keeps its id
 * through steps and function changes; a bend is made again after set_functions
 * where its node still exists, and a prune whose node the new functions do not
 * make is dropped and counted; ids stay bounded however often the functions
 * change; and leaves are drawn by the shared mesher at G_l(x_s) along each
 * shoot, growing by G_lg at fractional years (G04 §4.3, Figs. 12–13). */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/mesh.h>
#include <meristem/scene.h>

#include "core/vec.h"
#include "models/inverse/inverse.h"
#include "scene_private.h"

#include "inverse_helpers.h"
#include "scene_helpers.h"

/* An inverse-model scene from `seed` grown `years` years. */
static mer_scene *grown(uint64_t seed, uint32_t years)
{
    mer_scene *s = inverse_scene(seed);
    step(s, years);
    return s;
}

/* The scene's definition with G_name replaced by the line from (0, y0) to (1, y1). */
static void set_line(mer_scene *s, merp_inv_fn fn, float y0, float y1)
{
    merp_inv_def *d = malloc(sizeof *d);
    *d = *merp_inverse_def(s);
    const float xy[][2] = {{0, y0}, {1, y1}};
    mer_error err;
    assert_int_equal(merp_gfunc_make(&d->g[fn], merp_inv_fn_names[fn], MERP_GF_LINEAR, 2, xy,
                                     2, &err),
                     MER_OK);
    if (merp_inverse_set_def(s, d, &err) != MER_OK)
        fail_msg("set_def: %s", err.message);
    free(d);
}

/* The first node of the order-1 branch with the most nodes. */
static uint32_t big_branch(const merp_skeleton *sk)
{
    uint32_t best = MER_NO_NODE, most = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i] || sk->order[i] != 1 || sk->order[sk->parent[i]] != 0)
            continue;
        uint32_t count = 0;
        for (uint32_t j = i; j != MER_NO_NODE; j = sk->child[3 * j])
            count++;
        if (count > most) {
            most = count;
            best = i;
        }
    }
    assert_int_not_equal(best, MER_NO_NODE);
    return best;
}

/* A node keeps its id through a step and through a change of the silhouette:
 * every key in both trees has the same id in both. */
static void test_ids_stable_across_regrowth(void **state)
{
    (void)state;
    mer_scene *s = grown(2, 10);
    uint32_t n = s->sk.n, same = 0;
    uint64_t *key = calloc(n, sizeof *key);
    for (uint32_t i = 0; i < n; i++)
        key[i] = s->sk.alive[i] ? merp_inverse_node_key(s, i) : 0;
    set_line(s, MERP_G_S2, 0.55f, 0.1f);
    for (uint32_t i = 0; i < n; i++)
        if (key[i] != 0 && node_of_key(s, key[i]) != MER_NO_NODE) {
            assert_int_equal(node_of_key(s, key[i]), i);
            same++;
        }
    assert_true(same > n / 2);
    uint32_t done = 0;
    mer_error err;
    assert_int_equal(mer_scene_step(s, 1, NULL, NULL, NULL, &done, &err), MER_OK);
    for (uint32_t i = 0; i < n; i++)
        if (key[i] != 0 && node_of_key(s, key[i]) != MER_NO_NODE)
            assert_int_equal(node_of_key(s, key[i]), i);
    free(key);
    mer_scene_free(s);
}

/* A bend of a branch, then new functions: the same node, bent by the same angle
 * from where the new functions put it; a clone and a checkpoint agree. */
static void test_bend_survives_set_functions(void **state)
{
    (void)state;
    mer_scene *s = grown(3, 10), *twin = grown(3, 10);
    uint32_t b = big_branch(&s->sk);
    uint64_t key = merp_inverse_node_key(s, b);
    const float up[3] = {0.0f, 1.0f, 0.0f};
    float axis[3];
    v3_cross(s->sk.dir + 3 * b, up, axis);
    mer_error err;
    assert_int_equal(mer_scene_bend(s, b, axis, 25.0f, &err), MER_OK);
    set_line(s, MERP_G_S2, 0.5f, 0.2f);
    set_line(twin, MERP_G_S2, 0.5f, 0.2f);
    uint32_t at = node_of_key(s, key), tw = node_of_key(twin, key);
    assert_int_equal(at, b);
    assert_int_not_equal(tw, MER_NO_NODE);
    float c = v3_dot(s->sk.dir + 3 * at, twin->sk.dir + 3 * tw);
    assert_float_equal(acosf(c > 1.0f ? 1.0f : c) / MER_DEG2RAD, 25.0f, 0.5f);
    assert_int_equal(model_stat(s, "edits.bends"), 1);
    assert_int_equal(model_stat(s, "edits.dropped"), 0);
    /* And again after a step, in a clone and in a checkpoint's copy. */
    mer_scene *copy = NULL;
    assert_int_equal(mer_scene_clone(s, &copy, &err), MER_OK);
    uint32_t done = 0;
    assert_int_equal(mer_scene_step(s, 1, NULL, NULL, NULL, &done, &err), MER_OK);
    assert_int_equal(mer_scene_step(copy, 1, NULL, NULL, NULL, &done, &err), MER_OK);
    assert_true(mer_scene_hash(copy) == mer_scene_hash(s));
    assert_int_equal(node_of_key(s, key), b);
    mer_scene_free(copy);
    mer_scene_free(twin);
    mer_scene_free(s);
}

/* A prune of a metamer that is not the first of its shoot, then G_m = 0 (one
 * metamer a shoot): that metamer is gone, the prune dropped and counted. */
static void test_prune_dropped_when_node_gone(void **state)
{
    (void)state;
    mer_scene *s = grown(4, 8);
    const merp_skeleton *sk = &s->sk;
    uint32_t cut = MER_NO_NODE;
    for (uint32_t i = 0; i < sk->n && cut == MER_NO_NODE; i++) {
        uint32_t p = sk->parent[i];
        if (sk->alive[i] && p != MER_NO_NODE && sk->slot[i] == 0 && sk->order[i] == 1 &&
            sk->born[p] == sk->born[i] && sk->order[p] == 1)
            cut = i;
    }
    assert_int_not_equal(cut, MER_NO_NODE);
    mer_error err;
    assert_int_equal(mer_scene_prune(s, cut, &err), MER_OK);
    assert_int_equal(model_stat(s, "edits.prunes"), 1);
    set_line(s, MERP_G_M, 0.0f, 0.0f);
    assert_int_equal(model_stat(s, "edits.prunes"), 0);
    assert_int_equal(model_stat(s, "edits.dropped"), 1);
    uint32_t done = 0;
    assert_int_equal(mer_scene_step(s, 1, NULL, NULL, NULL, &done, &err), MER_OK);
    assert_int_equal(model_stat(s, "edits.dropped"), 0);
    mer_scene_free(s);
}

/* Functions changed back and forth many times: the ids stay within twice the
 * live tree and a margin, not one tree's worth more per change. */
static void test_ids_bounded(void **state)
{
    (void)state;
    mer_scene *s = grown(5, 12);
    for (int k = 0; k < 24; k++) {
        set_line(s, MERP_G_M, 0.0f, k % 2 ? 0.6f : 0.9f);
        uint32_t live = 0;
        for (uint32_t i = 0; i < s->sk.n; i++)
            live += s->sk.alive[i];
        assert_true(s->sk.n <= 2 * live + 1024);
        for (uint32_t i = 0; i < s->sk.n; i++)
            if (s->sk.alive[i] && s->sk.parent[i] != MER_NO_NODE)
                assert_true(s->sk.parent[i] < i);
    }
    mer_scene_free(s);
}

/* The leaf of each metamer of the trunk's last shoot: leaf_size · G_l(x_s) at
 * the year's end, that much times G_lg's growth at a fractional year; the mesh
 * draws one card of that length at each, and none on older wood. */
static void check_leaves(mer_scene *s, double t)
{
    mer_error err;
    assert_int_equal(merp_inverse_show(s, t, &err), MER_OK);
    const merp_skeleton *sk = &s->sk;
    const merp_inv_def *d = merp_inverse_def(s);
    uint32_t year = (uint32_t)ceil(t), shoot[64], m = 0;
    float f = (float)(t - (double)(year - 1));
    for (uint32_t i = sk->roots[0]; i != MER_NO_NODE; i = sk->child[3 * i])
        if (sk->born[i] == year && m < 64)
            shoot[m++] = i;
    assert_true(m >= 2);
    /* Its metamers that have started; G_m gives the whole shoot's count. */
    float l_s = 0.0f;
    float l[64];
    merp_inv_trunk_lengths(d, l);
    l_s = l[year] - l[year - 1];
    uint32_t whole = merp_inv_phyllo_count(
        merp_inv_metamers(&d->g[MERP_G_M], l_s, d->ls_max, d->m_max), d->m_max);
    mer_mesh_options opt = {.leaves = 1};
    mer_mesh *mesh = NULL;
    assert_int_equal(mer_mesh_build(s, &opt, &mesh, &err), MER_OK);
    for (uint32_t j = 0; j < m; j++) {
        mer_node n;
        assert_int_equal(mer_scene_node(s, shoot[j], &n, &err), MER_OK);
        float want = merp_inv_leaf_size(&d->g[MERP_G_L], merp_inv_x_s(j, whole), d->leaf_size) *
                     merp_inv_growth(&d->g[MERP_G_LG], f, j, whole, d->span);
        assert_float_equal(n.leaf > 0.0f ? n.leaf : 0.0f, want, 1e-5f);
        /* Its card: 4 vertices of this node, base to tip `leaf` long. */
        uint32_t v = 0;
        while (v < mesh->leaves.vertex_count && mesh->leaves.node_ids[v] != shoot[j])
            v++;
        if (want <= 0.0f) {
            assert_int_equal(v, mesh->leaves.vertex_count);
            continue;
        }
        assert_true(v + 4 <= mesh->leaves.vertex_count);
        const float *p = mesh->leaves.positions + 3 * v;
        float len = sqrtf((p[6] - p[0]) * (p[6] - p[0]) + (p[7] - p[1]) * (p[7] - p[1]) +
                          (p[8] - p[2]) * (p[8] - p[2]));
        assert_float_equal(len, want, 1e-4f);
    }
    uint32_t leafy = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        mer_node n;
        assert_int_equal(mer_scene_node(s, i, &n, &err), MER_OK);
        if (n.alive && n.born < year)
            assert_true(n.leaf < 0.0f);
        leafy += n.alive && n.leaf > 0.0f;
    }
    assert_int_equal(mesh->leaves.vertex_count, 4 * leafy);
    mer_mesh_free(mesh);
}

static void test_leaves_follow_G_l(void **state)
{
    (void)state;
    mer_scene *s = grown(6, 0);
    check_leaves(s, 9.0);
    check_leaves(s, 8.4);
    check_leaves(s, 8.75);
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_ids_stable_across_regrowth),
        cmocka_unit_test(test_bend_survives_set_functions),
        cmocka_unit_test(test_prune_dropped_when_node_gone),
        cmocka_unit_test(test_ids_bounded),
        cmocka_unit_test(test_leaves_follow_G_l),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
