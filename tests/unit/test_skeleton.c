/* Unit tests for the parts every growth model shares, through their private
 * interfaces: the skeleton (lib/skeleton/), the pipe model, the environment
 * (lib/env/env.c), brush symmetry (lib/symmetry.c) and the one hash (core/hash.h). */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "core/hash.h"
#include "env/env.h"
#include "skeleton/skeleton.h"
#include "symmetry.h"

#define assert_close(a, b) assert_true(fabsf((float)(a) - (float)(b)) < 1e-5f)

/* Counts the dormant buds the skeleton reports coming (+1) and going (-1). */
static void count_buds(void *ctx, const float p[3], int sign)
{
    (void)p;
    *(int *)ctx += sign;
}

/* A skeleton with one plant and a chain of `n` more internodes on its main axis. */
static void chain(merp_skeleton *sk, const mer_params *p, int *buds, uint32_t n)
{
    mer_rng rng;
    mer_rng_seed(&rng, 1);
    merp_skel_init(sk, p, count_buds, buds);
    const float base[3] = {0, 0, 0};
    uint32_t root;
    assert_int_equal(merp_skel_add_plant(sk, p, 0, base, &rng, &root, NULL), MER_OK);
    uint32_t cur = root;
    for (uint32_t j = 0; j < n; j++) {
        uint32_t c;
        assert_int_equal(merp_skel_node_new(sk, 1, &c, NULL), MER_OK);
        sk->parent[c] = cur;
        sk->child[3 * cur] = c;
        merp_skel_node_end(sk, cur, sk->pos + 3 * c);
        sk->dir[3 * c + 1] = 1.0f;
        sk->len[c] = p->internode_length;
        merp_skel_bud_set(sk, cur, 0, MER_BUD_NONE);
        merp_skel_bud_set(sk, c, 0, MER_BUD_DORMANT);
        cur = c;
    }
}

static void test_nodes_subtrees_and_kill(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    merp_skeleton sk;
    int buds = 0;
    chain(&sk, &p, &buds, 3);
    assert_int_equal(sk.n, 4);
    assert_int_equal(sk.nplants, 1);
    assert_int_equal(buds, 2); /* the root's lateral bud and the tip's */
    assert_int_equal(sk.born[0], 0);
    assert_int_equal(sk.born[3], 1);
    float e[3];
    merp_skel_node_end(&sk, 3, e);
    assert_close(e[1], 4.0f);
    size_t cnt;
    assert_int_equal(merp_skel_subtree(&sk, 1, &cnt, NULL), MER_OK);
    assert_int_equal(cnt, 3);
    assert_int_equal(sk.stack[0], 1);
    sk.con_node = 2;
    assert_int_equal(merp_skel_kill(&sk, 2, NULL), MER_OK);
    assert_false(sk.alive[2]);
    assert_false(sk.alive[3]);
    assert_int_equal(sk.child[3], MER_NO_NODE); /* unlinked from node 1 */
    assert_int_equal(sk.con_node, MER_NO_NODE); /* the constraint went with it */
    assert_int_equal(buds, 1);                  /* the tip's bud went */
    merp_skel_free(&sk);
}

static void test_bud_directions(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    p.branch_angle = 90.0f;
    merp_skeleton sk;
    int buds = 0;
    chain(&sk, &p, &buds, 0);
    float d0[3], d1[3], d2[3];
    merp_skel_bud_dir(&sk, 0, 0, d0);
    merp_skel_bud_dir(&sk, 0, 1, d1);
    merp_skel_bud_dir(&sk, 0, 2, d2);
    assert_close(d0[1], 1.0f);
    for (int a = 0; a < 3; a++) {
        assert_close(d1[a], sk.side[a]); /* at 90° the lateral bud faces the side */
        assert_close(d2[a], -sk.side[a]);
    }
    float next[3];
    merp_side_next(sk.side, sk.dir, 180.0f, next);
    for (int a = 0; a < 3; a++)
        assert_close(next[a], -sk.side[a]);
    merp_skel_free(&sk);
}

/* A new node in lateral slot 1 of node `on`: a leaf-bearing tip. */
static uint32_t lateral_tip(merp_skeleton *sk, uint32_t on)
{
    uint32_t c;
    assert_int_equal(merp_skel_node_new(sk, 2, &c, NULL), MER_OK);
    sk->parent[c] = on;
    sk->slot[c] = 1;
    sk->child[3 * on + 1] = c;
    return c;
}

static void test_pipe_model(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    merp_skeleton sk;
    int buds = 0;
    chain(&sk, &p, &buds, 2);
    merp_pipe_update(&sk, &p);
    float leaf = merp_pipe_leaf(&sk, &p);
    for (uint32_t i = 0; i < 3; i++)
        assert_close(sk.dn[i], leaf); /* one tip: d^n is the leaf's all the way down */
    assert_close(merp_pipe_diameter(&sk, 0), p.leaf_diameter);
    /* Memory (P09 §4.5): a lateral tip on node 1 adds its pipes down to the base... */
    uint32_t lat = lateral_tip(&sk, 1);
    merp_pipe_update(&sk, &p);
    assert_close(sk.dn[0], 2.0f * leaf);
    float d = merp_pipe_diameter(&sk, 0);
    /* ...and keeps them there once it is removed, at every ancestor, through
     * later updates, while the remaining tip's pipe goes on alone above it. */
    assert_int_equal(merp_skel_kill(&sk, lat, NULL), MER_OK);
    for (int round = 0; round < 3; round++) {
        merp_pipe_update(&sk, &p);
        assert_close(sk.dn[0], 2.0f * leaf);
        assert_close(sk.dn[1], 2.0f * leaf);
        assert_close(sk.dn[2], leaf);
    }
    assert_close(merp_pipe_diameter(&sk, 0), d);
    /* The remembered term stays in the sum when the survivors grow: a second
     * tip on node 2 adds its own pipe on top of the removed one's. */
    lateral_tip(&sk, 2);
    merp_pipe_update(&sk, &p);
    assert_close(sk.dn[0], 3.0f * leaf);
    d = merp_pipe_diameter(&sk, 0);
    /* A new exponent keeps the diameters. */
    merp_pipe_set_n(&sk, 3.0f);
    assert_close(sk.pipe_n, 3.0f);
    assert_true(fabsf(merp_pipe_diameter(&sk, 0) - d) < 1e-4f * d);
    merp_skel_free(&sk);
}

static void test_environment(void **state)
{
    (void)state;
    mer_params p = mer_params_default();
    merp_env e;
    assert_int_equal(merp_env_init(&e, &p, NULL), MER_OK);
    const float below[3] = {0, -1, 0}, above[3] = {0, 5, 0};
    assert_true(merp_env_blocked(&e, below));
    assert_false(merp_env_blocked(&e, above));
    const float lo[3] = {-1, 4, -1}, hi[3] = {1, 6, 1};
    assert_int_equal(merp_env_add_box(&e, lo, hi, NULL), MER_OK);
    assert_true(merp_env_blocked(&e, above));
    /* Blocked markers are dropped; any added bumps the epoch. */
    uint32_t epoch = merp_env_epoch(&e);
    const float pts[9] = {0, -1, 0, 0, 5, 0, 3, 5, 3};
    assert_int_equal(merp_env_add_markers(&e, pts, 3, NULL), MER_OK);
    assert_int_equal(mer_markers_count(e.markers), 1);
    assert_int_equal(merp_env_epoch(&e), epoch + 1);
    /* Shadow propagation: what a bud perceives is the grid's light there. */
    const float at[3] = {0.5f, 2.5f, 0.5f}, up[3] = {0, 1, 0};
    float q, v[3];
    assert_int_equal(merp_env_perceive(&e, 1, at, up, &q, v, NULL, NULL), MER_OK);
    assert_close(q, mer_shadow_light(e.shadow, at, p.shadow_c));
    float q_lit = q;
    merp_env_bud_changed(&e, above, 1); /* a bud overhead shades it */
    assert_int_equal(merp_env_perceive(&e, 1, at, up, &q, v, NULL, NULL), MER_OK);
    assert_true(q < q_lit);
    merp_env_buds_moved(&e);
    assert_int_equal(merp_env_epoch(&e), epoch + 2);
    merp_env_free(&e);
}

static void test_symmetry_copies(void **state)
{
    (void)state;
    mer_symmetry sym;
    memset(&sym, 0, sizeof sym);
    sym.rotational = 4;
    sym.mirror = 1;
    sym.mirror_normal[0] = 2.0f; /* normalized: the plane x = 0 */
    merp_symmetry y;
    assert_int_equal(merp_symmetry_resolve(&sym, &y, NULL), MER_OK);
    assert_int_equal(merp_symmetry_copies(&y), 8);
    float out[24];
    const float p[3] = {1, 2, 0};
    merp_symmetry_apply(&y, p, out);
    assert_close(out[0], 1.0f); /* the point itself, then its mirror image */
    assert_close(out[3], -1.0f);
    assert_close(out[4], 2.0f);
    assert_close(out[6], 0.0f); /* a quarter turn about y */
    assert_close(fabsf(out[8]), 1.0f);
    mer_error err;
    sym.rotational = 65;
    assert_int_equal(merp_symmetry_resolve(&sym, &y, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "rotational");
    assert_int_equal(merp_symmetry_resolve(NULL, &y, NULL), MER_OK);
    assert_int_equal(merp_symmetry_copies(&y), 1);
}

static void test_fnv(void **state)
{
    (void)state;
    /* FNV-1a 64 rounds: xor the byte, multiply by the prime. (The start value is
     * the one recorded hashes were made with; see core/hash.h.) */
    assert_true(merp_fnv(MERP_FNV_OFFSET, "", 0) == MERP_FNV_OFFSET);
    assert_true(merp_fnv(UINT64_C(0xcbf29ce484222325), "a", 1) == UINT64_C(0xaf63dc4c8601ec8c));
    assert_true(merp_fnv(MERP_FNV_OFFSET, "a", 1) == (MERP_FNV_OFFSET ^ 0x61u) * MERP_FNV_PRIME);
    const unsigned char le[4] = {0x78, 0x56, 0x34, 0x12};
    assert_true(merp_fnv_u32le(MERP_FNV_OFFSET, 0x12345678u) == merp_fnv(MERP_FNV_OFFSET, le, 4));
    assert_true(merp_fnv_word(MERP_FNV_OFFSET, 0x61u) == merp_fnv(MERP_FNV_OFFSET, "a", 1));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nodes_subtrees_and_kill),
        cmocka_unit_test(test_bud_directions),
        cmocka_unit_test(test_pipe_model),
        cmocka_unit_test(test_environment),
        cmocka_unit_test(test_symmetry_copies),
        cmocka_unit_test(test_fnv),
    };
    return cmocka_run_group_tests_name("skeleton", tests, NULL, NULL);
}
