/* The inverse model of G04 §4 as a tree: built at whole and fractional years on
 * the shared skeleton, run as a growth model through merp_scene_new_with (it is
 * not registered yet), deterministic from the seed, and meshed to GLB; and the
 * Populus deltoides of G04 §5 measured over its 27 years — height per year after
 * G_h, a crown that goes from broom to round, order-1 branches that rise in
 * number and then fall as the lower ones are shed. */
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
#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/scene.h>

#include "core/bytes.h"
#include "models/inverse/inverse.h"
#include "scene_private.h"

#include "inverse_helpers.h"
#include "scene_helpers.h"

/* What the tree measures: trunk length, height, the crown's extent, branches. */
typedef struct measure {
    float trunk, top, height, crown_low, width; /* top: the trunk's */
    uint32_t order1, nodes, max_order;
} measure;

static measure measure_of(const merp_skeleton *sk)
{
    measure m = {0};
    m.crown_low = 1e9f;
    float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        m.nodes++;
        float end[3];
        merp_skel_node_end(sk, i, end);
        if (end[1] > m.height)
            m.height = end[1];
        if (sk->order[i] > m.max_order)
            m.max_order = sk->order[i];
        if (sk->order[i] == 0) {
            m.trunk += sk->len[i];
            m.top = end[1] > m.top ? end[1] : m.top;
            continue;
        }
        uint32_t p = sk->parent[i];
        if (sk->order[i] == 1 && sk->order[p] == 0) {
            m.order1++;
            if (sk->pos[3 * i + 1] < m.crown_low)
                m.crown_low = sk->pos[3 * i + 1];
        }
        for (int a = 0; a < 2; a++) {
            float v = end[a == 0 ? 0 : 2];
            lo[a] = v < lo[a] ? v : lo[a];
            hi[a] = v > hi[a] ? v : hi[a];
        }
    }
    float w0 = hi[0] - lo[0], w1 = hi[1] - lo[1];
    m.width = m.order1 > 0 ? 0.5f * (w0 + w1) : 0.0f;
    return m;
}

/* A hand-built definition: the trunk alone (no lateral reaches s_min), straight. */
static merp_inv_def *trunk_only(void)
{
    merp_inv_def *d = malloc(sizeof *d);
    mer_error err;
    assert_int_equal(merp_inv_populus(d, &err), MER_OK);
    d->s_min = 5.0f;
    d->jitter = 0.0f;
    return d;
}

/* At every whole year the trunk is l_y = h_max · G_h(t_y) (eq (7) applied)
 * long, standing straight up; between years it grows without a jump. */
static void test_trunk_follows_G_h(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(1);
    merp_inv_def *d = trunk_only();
    mer_error err;
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    float l[28];
    merp_inv_trunk_lengths(d, l);
    for (uint32_t y = 1; y <= 27; y++) {
        step(s, 1);
        measure m = measure_of(&s->sk);
        assert_float_equal(m.trunk, l[y], 1e-3f * l[y]);
        assert_float_equal(m.top, l[y], 1e-3f * l[y]);
        assert_int_equal(m.max_order, 0);
    }
    float before = 0.0f;
    for (int i = 0; i <= 40; i++) {
        double t = 11.0 + (double)i / 40.0;
        assert_int_equal(merp_inverse_show(s, t, &err), MER_OK);
        float now = measure_of(&s->sk).trunk;
        assert_true(now >= before - 1e-5f);
        if (i == 0)
            assert_float_equal(now, l[11], 1e-3f * l[11]);
        if (i == 40)
            assert_float_equal(now, l[12], 1e-3f * l[12]);
        before = now;
    }
    assert_int_equal(merp_inverse_show(s, 28.0, &err), MER_ERR_RANGE);
    /* A new G_h regrows the tree shown (year 12) at once. */
    const float taller[][2] = {{0, 0}, {1, 1}};
    assert_int_equal(merp_gfunc_make(&d->g[MERP_G_H], "G_h", MERP_GF_LINEAR, 2, taller, 2, &err),
                     MER_OK);
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    assert_float_equal(measure_of(&s->sk).trunk, d->h_max * 12.0f / 27.0f, 1e-3f);
    d->y_max = 11;
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "y_max");
    free(d);
    mer_scene_free(s);
}

/* Eq (11) in the tree: with every lateral of lifespan 3 years (G_a flat), the
 * order-1 branches made in year b are gone from year b + 3 on. */
static void test_branches_are_shed_at_their_age(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(2);
    merp_inv_def *d = malloc(sizeof *d);
    mer_error err;
    assert_int_equal(merp_inv_populus(d, &err), MER_OK);
    const float flat[][2] = {{0, 0.1f}, {1, 0.1f}};
    assert_int_equal(merp_gfunc_make(&d->g[MERP_G_A], "G_a", MERP_GF_LINEAR, 2, flat, 2, &err),
                     MER_OK);
    d->order_max = 1;
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    step(s, 12);
    const merp_skeleton *sk = &s->sk;
    uint32_t seen = 0;
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i] && sk->order[i] == 1 && sk->order[sk->parent[i]] == 0) {
            assert_true(sk->born[i] > 12 - 3); /* born 10, 11 or 12 */
            seen++;
        }
    assert_true(seen > 0);
    /* With a longer life, older ones stand too. */
    d->a_max = 100.0f;
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    uint32_t old = 0;
    for (uint32_t i = 0; i < sk->n; i++)
        old += sk->alive[i] && sk->order[i] == 1 && sk->born[i] <= 9;
    assert_true(old > 0);
    free(d);
    mer_scene_free(s);
}

/* The Populus of G04 §5 over 27 years: the trunk follows G_h; the crown turns
 * from a broom (tall, narrow) to round; order-1 branches rise in number, then
 * fall as the lower ones are shed; higher orders appear. */
static void test_populus_over_its_years(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(7);
    const merp_inv_def *d = merp_inverse_def(s);
    float l[28];
    merp_inv_trunk_lengths(d, l);
    measure by_year[28];
    for (uint32_t y = 1; y <= 27; y++) {
        step(s, 1);
        by_year[y] = measure_of(&s->sk);
        assert_float_equal(by_year[y].trunk, l[y], 1e-3f * l[y]);
        assert_true(by_year[y].top > 0.97f * l[y] && by_year[y].top <= l[y] * 1.001f);
    }
    uint32_t peak = 1;
    for (uint32_t y = 1; y <= 27; y++) {
        if (by_year[y].order1 > by_year[peak].order1)
            peak = y;
    }
    float early = by_year[4].height / by_year[4].width;
    float late = (by_year[27].height - by_year[27].crown_low) / by_year[27].width;
    print_message("populus: h/w year 4 %.2f, crown h/w year 27 %.2f; order-1 branches "
                  "3:%u 8:%u peak %u:%u 27:%u; nodes 27:%u\n",
                  (double)early, (double)late, by_year[3].order1, by_year[8].order1, peak,
                  by_year[peak].order1, by_year[27].order1, by_year[27].nodes);
    assert_true(early > 2.5f); /* a broom stick */
    assert_true(late < 1.6f);  /* a rounded crown */
    assert_true(peak > 4 && peak < 27);
    assert_true(by_year[peak].order1 > by_year[3].order1);
    assert_true(by_year[27].order1 < by_year[peak].order1);
    assert_true(by_year[27].max_order >= 2);
    mer_error err;
    uint32_t done = 0;
    assert_int_equal(mer_scene_step(s, 1, NULL, NULL, NULL, &done, &err), MER_ERR_LIMIT);
    assert_int_equal(done, 0);
    mer_scene_free(s);
}

/* The same seed gives the same tree, at whole and fractional years; another
 * seed gives another. */
static void test_deterministic_from_the_seed(void **state)
{
    (void)state;
    mer_scene *a = inverse_scene(11), *b = inverse_scene(11), *c = inverse_scene(12);
    step(a, 9);
    step(b, 9);
    step(c, 9);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(mer_scene_hash(a) != mer_scene_hash(c));
    mer_error err;
    assert_int_equal(merp_inverse_show(a, 12.25, &err), MER_OK);
    assert_int_equal(merp_inverse_show(b, 12.25, &err), MER_OK);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    assert_true(merp_inverse_time(a) == 12.25);
    /* A fresh scene shown at 12.25 has the same live tree as one stepped first. */
    mer_scene *d = inverse_scene(11);
    assert_int_equal(merp_inverse_show(d, 12.25, &err), MER_OK);
    measure ma = measure_of(&a->sk), md = measure_of(&d->sk);
    assert_int_equal(ma.nodes, md.nodes);
    assert_float_equal(ma.height, md.height, 1e-6f);
    assert_float_equal(ma.width, md.width, 1e-6f);
    mer_scene_free(a);
    mer_scene_free(b);
    mer_scene_free(c);
    mer_scene_free(d);
}

/* A branch keeps its place and shape while the year turns: between 12 and 13
 * the tree at 12 + ε is the tree at 12 but for tiny new growth. */
static void test_fractional_years_are_continuous(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(5);
    mer_error err;
    assert_int_equal(merp_inverse_show(s, 12.0, &err), MER_OK);
    measure whole = measure_of(&s->sk);
    assert_int_equal(merp_inverse_show(s, 12.001, &err), MER_OK);
    measure just_after = measure_of(&s->sk);
    assert_float_equal(just_after.height, whole.height, 0.01f);
    assert_float_equal(just_after.width, whole.width, 0.05f * whole.width);
    assert_int_equal(merp_inverse_show(s, 12.25, &err), MER_OK);
    measure quarter = measure_of(&s->sk);
    assert_int_equal(merp_inverse_show(s, 13.0, &err), MER_OK);
    measure next = measure_of(&s->sk);
    assert_true(quarter.trunk > whole.trunk && quarter.trunk < next.trunk);
    assert_true(quarter.nodes > whole.nodes);
    mer_scene_free(s);
}

/* The live nodes of the subtree of id. */
static uint32_t subtree_size(const merp_skeleton *sk, uint32_t id)
{
    uint32_t n = 1;
    for (uint32_t k = 0; k < 3; k++) {
        uint32_t c = sk->child[3 * id + k];
        if (c != MER_NO_NODE && sk->alive[c])
            n += subtree_size(sk, c);
    }
    return n;
}

/* A prune outlives the yearly rebuilds: the branch stays cut in later years
 * (and in a copy of the scene), and the rest of the tree is as it would be. */
static void test_prunes_outlive_rebuilds(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(4), *twin = inverse_scene(4);
    step(s, 10);
    step(twin, 10);
    const merp_skeleton *sk = &s->sk;
    uint32_t cut = MER_NO_NODE, most = 0; /* the biggest order-1 branch: it lives on */
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i] && sk->order[i] == 1 && sk->order[sk->parent[i]] == 0 &&
            subtree_size(sk, i) > most) {
            cut = i;
            most = subtree_size(sk, i);
        }
    assert_int_not_equal(cut, MER_NO_NODE);
    uint64_t key = merp_inverse_node_key(s, cut);
    assert_true(key != 0);
    mer_error err;
    assert_int_equal(mer_scene_prune(s, cut, &err), MER_OK);
    mer_scene *copy = NULL;
    assert_int_equal(mer_scene_clone(s, &copy, &err), MER_OK);
    step(s, 3);
    step(twin, 3);
    step(copy, 3);
    assert_true(mer_scene_hash(copy) == mer_scene_hash(s));
    assert_int_equal(node_of_key(s, key), MER_NO_NODE);
    uint32_t there = node_of_key(twin, key);
    assert_int_not_equal(there, MER_NO_NODE);
    assert_int_equal(measure_of(&s->sk).nodes + subtree_size(&twin->sk, there),
                     measure_of(&twin->sk).nodes);
    mer_scene_free(s);
    mer_scene_free(twin);
    mer_scene_free(copy);
}

/* Leaves (G04 §4.3): this year's metamers bear them, sized by G_l(x_s) once
 * grown; last year's have none; early in the year they are still small. */
static void test_leaves_grow_within_the_year(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(6);
    mer_error err;
    assert_int_equal(merp_inverse_show(s, 12.0, &err), MER_OK);
    const merp_skeleton *sk = &s->sk;
    const merp_inv_def *d = merp_inverse_def(s);
    uint32_t leafy = 0;
    double full = 0.0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i])
            continue;
        float leaf = merp_inverse_leaf_size(s, i);
        if (sk->born[i] == 12) {
            assert_true(leaf > 0.0f && leaf <= d->leaf_size);
            leafy++;
            full += (double)leaf;
        } else {
            assert_float_equal(leaf, 0.0f, 0.0f);
        }
    }
    assert_true(leafy > 50);
    assert_int_equal(merp_inverse_show(s, 11.3, &err), MER_OK);
    double early = 0.0;
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i] && sk->born[i] == 12)
            early += (double)merp_inverse_leaf_size(s, i);
    assert_true(early > 0.0 && early < 0.5 * full);
    mer_scene_free(s);
}

/* The model's state round-trips through its checkpoint bytes, cuts and all,
 * and grows on as before; damaged bytes are refused. */
static void test_checkpoint_state(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(8), *twin = inverse_scene(8);
    step(s, 9);
    step(twin, 9);
    mer_error err;
    uint32_t cut = s->sk.n - 1;
    while (!s->sk.alive[cut] || s->sk.order[cut] == 0)
        cut--;
    assert_int_equal(mer_scene_prune(s, cut, &err), MER_OK);
    assert_int_equal(mer_scene_prune(twin, cut, &err), MER_OK);
    merp_bytes_out out = {0};
    merp_inverse_ops.save(s->model, &out);
    assert_false(out.oom);
    merp_bytes_in in = {out.buf, out.n, 0, 0};
    merp_model *back = NULL;
    assert_int_equal(merp_inverse_ops.load(&in, s->sk.n, &back, &err), MER_OK);
    assert_int_equal(in.at, out.n);
    assert_true(merp_inverse_ops.hash(back, 1) == merp_inverse_ops.hash(s->model, 1));
    merp_inverse_ops.free(s->model);
    s->model = back;
    step(s, 4);
    step(twin, 4);
    assert_true(mer_scene_hash(s) == mer_scene_hash(twin));
    /* Cut short, or with a node count it cannot fit, it is refused. */
    merp_bytes_in shortened = {out.buf, out.n - 3, 0, 0};
    assert_int_equal(merp_inverse_ops.load(&shortened, s->sk.n, &back, &err), MER_ERR_FORMAT);
    merp_bytes_in few = {out.buf, out.n, 0, 0};
    assert_int_equal(merp_inverse_ops.load(&few, 5, &back, &err), MER_ERR_FORMAT);
    assert_null(back);
    free(out.buf);
    mer_scene_free(s);
    mer_scene_free(twin);
}

/* Of the order-1 branches longer than 1.5 m, the fraction whose tip hangs
 * below their base. */
static float hanging(const merp_skeleton *sk)
{
    uint32_t long_ones = 0, below = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        if (!sk->alive[i] || sk->order[i] != 1 || sk->order[sk->parent[i]] != 0)
            continue;
        float len = sk->len[i], tip[3];
        uint32_t j = i;
        while (sk->child[3 * j] != MER_NO_NODE && sk->alive[sk->child[3 * j]]) {
            j = sk->child[3 * j];
            len += sk->len[j];
        }
        merp_skel_node_end(sk, j, tip);
        if (len > 1.5f) {
            long_ones++;
            below += tip[1] < sk->pos[3 * i + 1];
        }
    }
    return long_ones > 0 ? (float)below / (float)long_ones : 0.0f;
}

/* The widest spread of order >= 1 wood between heights lo and hi. */
static float width_between(const merp_skeleton *sk, float lo, float hi)
{
    float w = 0.0f;
    for (uint32_t i = 0; i < sk->n; i++) {
        float e[3];
        merp_skel_node_end(sk, i, e);
        if (sk->alive[i] && sk->order[i] >= 1 && e[1] >= lo && e[1] < hi) {
            float r = sqrtf(e[0] * e[0] + e[2] * e[2]);
            w = r > w ? r : w;
        }
    }
    return 2.0f * w;
}

/* The two other species show the model's range: the conifer is a spire, wide
 * at the base and narrow at the top; the weeping form's long branches hang,
 * where the Populus's turn up. */
static void test_species_range(void **state)
{
    (void)state;
    mer_error err;
    merp_inv_def *d = malloc(sizeof *d);
    mer_scene *s = inverse_scene(9);
    assert_int_equal(merp_inv_conifer(d, &err), MER_OK);
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    step(s, 27);
    measure m = measure_of(&s->sk);
    float third = (m.height - m.crown_low) / 3.0f;
    float base = width_between(&s->sk, m.crown_low, m.crown_low + third);
    float top = width_between(&s->sk, m.crown_low + 2.0f * third, m.height + 1.0f);
    print_message("conifer: crown h/w %.2f, widths base %.2f top %.2f\n",
                  (double)((m.height - m.crown_low) / m.width), (double)base, (double)top);
    assert_true((m.height - m.crown_low) / m.width > 1.5f);
    assert_true(base > 1.5f * top);
    mer_scene_free(s);

    s = inverse_scene(9);
    step(s, 20);
    float populus = hanging(&s->sk);
    assert_int_equal(merp_inv_weeping(d, &err), MER_OK);
    assert_int_equal(merp_inverse_set_def(s, d, &err), MER_OK);
    float weeping = hanging(&s->sk);
    print_message("hanging long branches: populus %.2f, weeping %.2f\n", (double)populus,
                  (double)weeping);
    assert_true(populus < 0.3f);
    assert_true(weeping > 0.6f);
    mer_scene_free(s);
    free(d);
}

/* The tree meshes and writes as GLB like any other. */
/* The radius of G04 §4.1: along the trunk each node's diameter is
 * 2 · r_max · L / h_max · G_r(x) at its base, x its place over the trunk's
 * length L; no branch starts thicker than the node it grows from. */
static void test_radius_follows_G_r(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(5);
    step(s, 10);
    const merp_skeleton *sk = &s->sk;
    const merp_inv_def *d = merp_inverse_def(s);
    float L = 0.0f;
    uint32_t root = sk->roots[0];
    for (uint32_t i = root; i != MER_NO_NODE; i = sk->child[3 * i])
        L += sk->len[i];
    float r_b = d->r_max * L / d->h_max, along = 0.0f;
    uint32_t checked = 0;
    mer_error err;
    for (uint32_t i = root; i != MER_NO_NODE; i = sk->child[3 * i], checked++) {
        mer_node n;
        assert_int_equal(mer_scene_node(s, i, &n, &err), MER_OK);
        float want = 2.0f * r_b * merp_gfunc_eval(&d->g[MERP_G_R], along / L);
        assert_float_equal(n.diameter, want, 1e-4f * want + 1e-7f);
        along += sk->len[i];
    }
    assert_true(checked > 20);
    uint32_t laterals = 0;
    for (uint32_t i = 0; i < sk->n; i++) {
        uint32_t p = sk->parent[i];
        if (!sk->alive[i] || p == MER_NO_NODE || sk->slot[i] == 0)
            continue;
        assert_true(merp_pipe_diameter(sk, i) <= merp_pipe_diameter(sk, p) * 1.0001f);
        laterals++;
    }
    assert_true(laterals > 20);
    mer_scene_free(s);
}

static void test_meshes_to_glb(void **state)
{
    (void)state;
    mer_scene *s = inverse_scene(3);
    mer_error err;
    assert_int_equal(merp_inverse_show(s, 8.5, &err), MER_OK);
    mer_mesh *m = NULL;
    assert_int_equal(mer_mesh_build(s, NULL, &m, &err), MER_OK);
    assert_true(m->internodes > 100);
    assert_true(m->axes > 10);
    uint8_t *glb = NULL;
    size_t size = 0;
    assert_int_equal(mer_gltf_write_tree(m, NULL, NULL, &glb, &size, &err), MER_OK);
    assert_memory_equal(glb, "glTF", 4);
    mer_gltf_free(glb);
    mer_mesh_free(m);
    mer_scene_free(s);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_trunk_follows_G_h),
        cmocka_unit_test(test_branches_are_shed_at_their_age),
        cmocka_unit_test(test_populus_over_its_years),
        cmocka_unit_test(test_deterministic_from_the_seed),
        cmocka_unit_test(test_fractional_years_are_continuous),
        cmocka_unit_test(test_prunes_outlive_rebuilds),
        cmocka_unit_test(test_leaves_grow_within_the_year),
        cmocka_unit_test(test_checkpoint_state),
        cmocka_unit_test(test_species_range),
        cmocka_unit_test(test_radius_follows_G_r),
        cmocka_unit_test(test_meshes_to_glb),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
