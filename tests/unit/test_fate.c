/* Unit tests for lib/models/p09/fate.c: BH split, ⌊v⌋ and l, Fig. 8c weights, priority lists. */
#include "config.h"

#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include <meristem/fate.h>

#define EPS 1e-5f
#define assert_close(a, b) assert_true(fabsf((a) - (b)) < EPS)

static void test_bh_split_hand_computed(void **state)
{
    (void)state;
    float vm, vl;
    /* v = 10, λ = 0.6, Q_m = 2, Q_l = 1: den = 1.2 + 0.4 = 1.6 */
    mer_bh_split(10.0f, 0.6f, 2.0f, 1.0f, &vm, &vl);
    assert_close(vm, 7.5f);
    assert_close(vl, 2.5f);
    /* λ = 0.5 and equal light: an even split */
    mer_bh_split(3.2f, 0.5f, 0.8f, 0.8f, &vm, &vl);
    assert_close(vm, 1.6f);
    assert_close(vl, 1.6f);
    /* λ < 0.5 biases towards the lateral branch */
    mer_bh_split(10.0f, 0.4f, 1.0f, 1.0f, &vm, &vl);
    assert_close(vm, 4.0f);
    assert_close(vl, 6.0f);
    /* no light on either side: nothing flows */
    mer_bh_split(10.0f, 0.5f, 0.0f, 0.0f, &vm, &vl);
    assert_close(vm, 0.0f);
    assert_close(vl, 0.0f);
    /* λ = 1: everything to the main axis */
    mer_bh_split(10.0f, 1.0f, 1.0f, 5.0f, &vm, &vl);
    assert_close(vm, 10.0f);
    assert_close(vl, 0.0f);
}

static void test_bh_split_two_laterals(void **state)
{
    (void)state;
    float vm, vl[2];
    const float ql[2] = {1.0f, 3.0f};
    /* v = 8, λ = 0.5, Q_m = 4, Q_l = 1 + 3: v_m = 4, v_l = 4 shared 1:3 */
    mer_bh_split2(8.0f, 0.5f, 4.0f, ql, &vm, vl);
    assert_close(vm, 4.0f);
    assert_close(vl[0], 1.0f);
    assert_close(vl[1], 3.0f);
}

static void test_shoot_size_floor_and_length(void **state)
{
    (void)state;
    float l;
    assert_int_equal(mer_shoot_size(2.5f, 16, 1.0f, &l), 2);
    assert_close(l, 1.25f);
    assert_int_equal(mer_shoot_size(3.0f, 16, 1.0f, &l), 3);
    assert_close(l, 1.0f);
    assert_int_equal(mer_shoot_size(0.99f, 16, 1.0f, &l), 0);
    assert_close(l, 0.0f);
    assert_int_equal(mer_shoot_size(1.0f, 16, 1.0f, &l), 1);
    assert_close(l, 1.0f);
    assert_int_equal(mer_shoot_size(2.5f, 16, 0.5f, &l), 2);
    assert_close(l, 0.625f);
    /* the cap limits the count, not the length */
    assert_int_equal(mer_shoot_size(20.0f, 16, 1.0f, &l), 16);
    assert_close(l, 1.0f);
    assert_int_equal(mer_shoot_size(-3.0f, 16, 1.0f, NULL), 0);
    assert_int_equal(mer_shoot_size(NAN, 16, 1.0f, NULL), 0);
}

static void test_priority_weights_fig8c(void **state)
{
    (void)state;
    /* w_max 1, w_min 0.1, κ 0.5, N = 10: linear from 1 at i = 0 to 0.1 at i = 5 */
    assert_close(mer_priority_weight(0, 10, 1.0f, 0.1f, 0.5f), 1.0f);
    assert_close(mer_priority_weight(1, 10, 1.0f, 0.1f, 0.5f), 0.82f);
    assert_close(mer_priority_weight(4, 10, 1.0f, 0.1f, 0.5f), 0.28f);
    assert_close(mer_priority_weight(5, 10, 1.0f, 0.1f, 0.5f), 0.1f);
    assert_close(mer_priority_weight(9, 10, 1.0f, 0.1f, 0.5f), 0.1f);
    assert_close(mer_priority_weight(0, 1, 1.0f, 0.1f, 0.5f), 1.0f);
    /* smaller κ: the weights fall sooner */
    assert_true(mer_priority_weight(2, 10, 1.0f, 0.1f, 0.35f) <
                mer_priority_weight(2, 10, 1.0f, 0.1f, 0.5f));
}

/* The worked example in the spirit of Fig. 8b: an axis supporting a lateral bud
 * (Q 0.9), a branch (Q 2.1 over 3 buds: 0.7 per bud) and its terminal bud (Q 0.5),
 * with weights w1 = 2, w2 = 1, w3 = 0.5. */
static void test_priority_fig8b_worked_example(void **state)
{
    (void)state;
    const float q[3] = {0.9f, 2.1f, 0.5f};
    const uint32_t buds[3] = {1, 3, 1};
    const float w[3] = {2.0f, 1.0f, 0.5f};
    uint32_t rank[3], scratch[3];
    float v[3];
    /* Apical control: terminal first, then by light per bud: 0.9, 0.7.
     * Q·w = 1.0, 0.9, 1.05; sum 2.95; v = 5.9 gives 2.0, 1.8, 2.1. */
    mer_priority_allocate(5.9f, 3, q, buds, 2, 1, w, 0, 0, 0, rank, scratch, v);
    assert_int_equal(rank[0], 2);
    assert_int_equal(rank[1], 0);
    assert_int_equal(rank[2], 1);
    assert_close(v[2], 2.0f);
    assert_close(v[0], 1.8f);
    assert_close(v[1], 2.1f);
    /* Without apical control: 0.9, 0.7, 0.5 per bud; Q·w = 1.8, 2.1, 0.25; sum 4.15;
     * v = 8.3 gives 3.6, 4.2, 0.5. */
    mer_priority_allocate(8.3f, 3, q, buds, 2, 0, w, 0, 0, 0, rank, scratch, v);
    assert_int_equal(rank[0], 0);
    assert_int_equal(rank[1], 1);
    assert_int_equal(rank[2], 2);
    assert_close(v[0], 3.6f);
    assert_close(v[1], 4.2f);
    assert_close(v[2], 0.5f);
}

static void test_priority_sort_is_stable_and_complete(void **state)
{
    (void)state;
    /* 7 items, ties broken by index; no terminal. */
    const float q[7] = {1, 3, 3, 0.5f, 2, 3, 0};
    const uint32_t buds[7] = {1, 1, 1, 1, 1, 1, 1};
    uint32_t rank[7], scratch[7];
    float v[7];
    mer_priority_allocate(10.0f, 7, q, buds, UINT32_MAX, 1, NULL, 1.0f, 1.0f, 0.5f, rank,
                          scratch, v);
    const uint32_t want[7] = {1, 2, 5, 4, 0, 3, 6};
    for (int i = 0; i < 7; i++)
        assert_int_equal(rank[i], want[i]);
    /* equal weights: v_i = v·Q_i/ΣQ; ΣQ = 12.5 */
    assert_close(v[1], 10.0f * 3.0f / 12.5f);
    assert_close(v[6], 0.0f);
    float sum = 0;
    for (int i = 0; i < 7; i++)
        sum += v[i];
    assert_close(sum, 10.0f);
}

/* Whether item a goes before item b in a priority list: higher light per bud
 * first, equal keys (−0 and +0 among them) by index (meristem/fate.h). */
static int goes_before(const float *key, uint32_t a, uint32_t b)
{
    return key[a] != key[b] ? key[a] > key[b] : a < b;
}

/* Every list length the short sorts take (networks up to 4, insertion to 16,
 * the merge sort beyond), keys drawn from a few values so that ties are common,
 * −0 among them: each list must come out in `before`'s order, a permutation. */
static void test_priority_sort_orders_every_length(void **state)
{
    (void)state;
    const float values[6] = {0.0f, -0.0f, 0.25f, 1.0f, 1.0f / 3.0f, 2.0f};
    uint32_t seed = 12345;
    for (uint32_t n = 1; n <= 20; n++) {
        for (int trial = 0; trial < 200; trial++) {
            float q[20], v[20], key[20];
            uint32_t buds[20], rank[20], scratch[20], seen[20] = {0};
            for (uint32_t i = 0; i < n; i++) {
                seed = seed * 1103515245u + 12345u;
                q[i] = values[(seed >> 16) % 6];
                buds[i] = 1 + (seed >> 8) % 2;
                key[i] = q[i] / (float)buds[i];
            }
            mer_priority_allocate(1.0f, n, q, buds, UINT32_MAX, 0, NULL, 1.0f, 0.1f, 0.5f, rank,
                                  scratch, v);
            for (uint32_t i = 0; i < n; i++) {
                assert_true(rank[i] < n);
                seen[rank[i]]++;
                if (i > 0)
                    assert_true(goes_before(key, rank[i - 1], rank[i]));
            }
            for (uint32_t i = 0; i < n; i++)
                assert_int_equal(seen[i], 1);
        }
    }
    /* +0 then −0: equal keys keep their index order (the sign bit must not rank −0 first) */
    const float q[2] = {0.0f, -0.0f};
    const uint32_t buds[2] = {1, 1};
    uint32_t rank[2], scratch[2];
    float v[2];
    mer_priority_allocate(1.0f, 2, q, buds, UINT32_MAX, 0, NULL, 1.0f, 0.1f, 0.5f, rank, scratch, v);
    assert_int_equal(rank[0], 0);
    assert_int_equal(rank[1], 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_bh_split_hand_computed),
        cmocka_unit_test(test_bh_split_two_laterals),
        cmocka_unit_test(test_shoot_size_floor_and_length),
        cmocka_unit_test(test_priority_weights_fig8c),
        cmocka_unit_test(test_priority_fig8b_worked_example),
        cmocka_unit_test(test_priority_sort_is_stable_and_complete),
        cmocka_unit_test(test_priority_sort_orders_every_length),
    };
    return cmocka_run_group_tests_name("fate", tests, NULL, NULL);
}
