/* meristem — BH and priority allocation kernels (P09 §4.2). */
#include "config.h"

#include <assert.h>
#include <math.h>
#include <stddef.h>
#include <string.h>

#include <meristem/fate.h>

void mer_bh_split2(float v, float lambda, float q_main, const float q_lat[2], float *v_main,
                   float v_lat[2])
{
    float ql = q_lat[0] + q_lat[1];
    float den = lambda * q_main + (1.0f - lambda) * ql;  /* λQ_m + (1−λ)Q_l */
    if (!(den > 0.0f)) {
        *v_main = 0.0f;
        v_lat[0] = v_lat[1] = 0.0f;
        return;
    }
    *v_main = v * (lambda * q_main) / den;
    float vl = v * ((1.0f - lambda) * ql) / den;
    if (ql > 0.0f) {
        v_lat[0] = vl * (q_lat[0] / ql);
        v_lat[1] = vl * (q_lat[1] / ql);
    } else {
        v_lat[0] = v_lat[1] = 0.0f;
    }
}

void mer_bh_split(float v, float lambda, float q_main, float q_lat, float *v_main, float *v_lat)
{
    float ql[2] = {q_lat, 0.0f}, vl[2];
    mer_bh_split2(v, lambda, q_main, ql, v_main, vl);
    *v_lat = vl[0];
}

uint32_t mer_shoot_size(float v, uint32_t max_n, float l0, float *length)
{
    if (!(v >= 1.0f)) {
        if (length != NULL)
            *length = 0.0f;
        return 0;
    }
    float fl = floorf(v);                       /* n = ⌊v⌋ */
    uint32_t n = fl >= (float)max_n ? max_n : (uint32_t)fl;
    if (length != NULL)
        *length = l0 * (v / fl);                /* l = v/n */
    return n;
}

float mer_priority_weight(uint32_t i, uint32_t n, float w_max, float w_min, float kappa)
{
    float knee = kappa * (float)n;   /* position where w reaches w_min */
    float x = (float)i;
    if (i == 0 || !(knee > 0.0f))
        return i == 0 ? w_max : w_min;
    if (x >= knee)
        return w_min;
    return w_max + (w_min - w_max) * (x / knee);
}

/* Item a goes before item b: higher light per bud (key) first, then lower index. */
static int before(uint32_t a, uint32_t b, const float *key)
{
    if (key[a] != key[b])
        return key[a] > key[b];
    return a < b;
}

/* Below this many items a list without NaN keys is sorted by insertion: most
 * axes list a handful, where the merge sort's passes cost more than the sort. */
#define INSERTION_MAX 16

/* Puts the smaller of a and b in a, the larger in b, without a branch. */
#define ORDER_PAIR(a, b)                       \
    do {                                       \
        uint64_t lo_ = (a) < (b) ? (a) : (b);  \
        uint64_t hi_ = (a) < (b) ? (b) : (a);  \
        (a) = lo_;                             \
        (b) = hi_;                             \
    } while (0)

/* `before` for a short list whose keys are all ≥ 0, on one integer an item:
 * the key's bits inverted above the index. The bits of floats ≥ 0 rise with
 * their value (−0 is made +0 first: `before` takes them as equal), so a larger
 * key makes a smaller integer and equal keys fall to the index. Lists of up to
 * four items (most axes') go through a sorting network, with no branch to
 * mispredict on the keys; longer ones by insertion. */
static void sort_short(uint32_t n, const float *key, uint32_t *rank)
{
    assert(n <= INSERTION_MAX);
    uint64_t item[INSERTION_MAX];
    for (uint32_t i = 0; i < n; i++) {
        float k = key[i] + 0.0f; /* −0 + 0 = +0 */
        uint32_t bits;
        memcpy(&bits, &k, sizeof bits);
        item[i] = (uint64_t)~bits << 32 | i;
    }
    switch (n) {
    case 0:
    case 1:
        break;
    case 2:
        ORDER_PAIR(item[0], item[1]);
        break;
    case 3:
        ORDER_PAIR(item[0], item[1]);
        ORDER_PAIR(item[1], item[2]);
        ORDER_PAIR(item[0], item[1]);
        break;
    case 4:
        ORDER_PAIR(item[0], item[1]);
        ORDER_PAIR(item[2], item[3]);
        ORDER_PAIR(item[0], item[2]);
        ORDER_PAIR(item[1], item[3]);
        ORDER_PAIR(item[1], item[2]);
        break;
    default:
        for (uint32_t i = 1; i < n; i++) {
            uint64_t x = item[i];
            uint32_t j = i;
            for (; j > 0 && x < item[j - 1]; j--)
                item[j] = item[j - 1];
            item[j] = x;
        }
    }
    for (uint32_t i = 0; i < n; i++)
        rank[i] = (uint32_t)item[i];
}

/* Orders rank[0, n) (the identity on entry) by `before`. Without NaN keys
 * `before` is a strict total order (ties go by index), so every sort gives
 * the same list; with one, the merge sort keeps its own answer. */
static void sort_ranks(uint32_t n, const float *key, int has_nan, int has_negative,
                       uint32_t *rank, uint32_t *scratch)
{
    if (n <= INSERTION_MAX && !has_nan && !has_negative) {
        sort_short(n, key, rank);
        return;
    }
    if (n <= INSERTION_MAX && !has_nan) {
        for (uint32_t i = 1; i < n; i++) {
            uint32_t x = rank[i], j = i;
            for (; j > 0 && before(x, rank[j - 1], key); j--)
                rank[j] = rank[j - 1];
            rank[j] = x;
        }
        return;
    }
    /* Bottom-up merge sort: stable and O(n log n), no recursion, no comparator globals. */
    uint32_t *src = rank, *dst = scratch;
    for (uint32_t width = 1; width < n; width *= 2) {
        for (uint32_t lo = 0; lo < n; lo += 2 * width) {
            uint32_t mid = lo + width < n ? lo + width : n;
            uint32_t hi = lo + 2 * width < n ? lo + 2 * width : n;
            uint32_t a = lo, b = mid, o = lo;
            while (a < mid && b < hi)
                dst[o++] = before(src[b], src[a], key) ? src[b++] : src[a++];
            while (a < mid)
                dst[o++] = src[a++];
            while (b < hi)
                dst[o++] = src[b++];
        }
        uint32_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != rank)
        for (uint32_t i = 0; i < n; i++)
            rank[i] = src[i];
}

void mer_priority_allocate(float v, uint32_t n, const float *q, const uint32_t *buds,
                           uint32_t terminal, int apical, const float *weights, float w_max,
                           float w_min, float kappa, uint32_t *rank, uint32_t *scratch,
                           float *out_v)
{
    if (n == 0)
        return;
    /* The sort keys, light per bud, computed once into out_v (written last). */
    float *key = out_v;
    int has_nan = 0, has_negative = 0;
    for (uint32_t i = 0; i < n; i++) {
        rank[i] = i;
        key[i] = q[i] / (float)(buds[i] > 0 ? buds[i] : 1);
        has_nan |= key[i] != key[i];
        has_negative |= key[i] < 0.0f;
    }
    sort_ranks(n, key, has_nan, has_negative, rank, scratch);
    if (apical && terminal < n) {
        /* Apical control: the terminal bud heads the list whatever its light. */
        uint32_t pos = 0;
        while (rank[pos] != terminal)
            pos++;
        for (; pos > 0; pos--)
            rank[pos] = rank[pos - 1];
        rank[0] = terminal;
    }
    float sum = 0.0f;
    for (uint32_t pos = 0; pos < n; pos++) {
        float w = weights != NULL ? weights[pos] : mer_priority_weight(pos, n, w_max, w_min, kappa);
        float qw = q[rank[pos]] * w;
        out_v[rank[pos]] = qw;
        sum += qw;
    }
    for (uint32_t i = 0; i < n; i++)
        out_v[i] = sum > 0.0f ? v * out_v[i] / sum : 0.0f;
}
