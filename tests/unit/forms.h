/* Measures of a tree's form, as a botanist reads the paper's figures (P09 Figs. 7,
 * 9, 10, 14), for the form tests (test_forms.c). Each reads plant 0 of a scene
 * through the public API. O(nodes) each. Include after <cmocka.h>. */
#ifndef MERISTEM_TEST_FORMS_H
#define MERISTEM_TEST_FORMS_H

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include <meristem/scene.h>

static inline float form_tip_y(const mer_node *n) { return n->base[1] + n->dir[1] * n->length; }

/* Leader margin: (trunk top − highest tip of any lateral) / height. Positive when
 * the leader overtops the crown (excurrent), negative when a lateral has overtopped
 * it (the leader is lost). */
static inline float form_leader_margin(const mer_scene *s)
{
    float trunk = 0.0f, lateral = 0.0f, base = 0.0f;
    int first = 1;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node n;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0)
            continue;
        if (first) {
            base = n.base[1];
            first = 0;
        }
        float y = form_tip_y(&n) - base;
        if (n.order == 0 && y > trunk)
            trunk = y;
        else if (n.order > 0 && y > lateral)
            lateral = y;
    }
    float h = trunk > lateral ? trunk : lateral;
    return h > 0.0f ? (trunk - lateral) / h : 0.0f;
}

/* Leader height: the trunk's top over the tree's height (1 while the leader leads;
 * the lower, the earlier a lateral took over). */
static inline float form_leader_height(const mer_scene *s)
{
    float m = form_leader_margin(s);
    return m < 0.0f ? 1.0f + m : 1.0f;
}

/* Share of the internodes in the order-k axes (k = 1: the first-order branches). */
static inline float form_order_share(const mer_scene *s, uint32_t k)
{
    uint32_t all = 0, in_k = 0;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node n;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0)
            continue;
        all++;
        in_k += n.order == k;
    }
    return all > 0 ? (float)in_k / (float)all : 0.0f;
}

/* Share of the internodes in the largest first-order branch (with all it bears):
 * near 1 when one lateral has taken the tree over (decurrent). */
static inline float form_largest_branch_share(const mer_scene *s)
{
    uint32_t bound = mer_scene_node_bound(s);
    uint32_t *branch = calloc(bound, sizeof *branch); /* base id + 1 of its order-1 branch */
    uint32_t *count = calloc(bound, sizeof *count);
    assert_non_null(branch);
    assert_non_null(count);
    uint32_t all = 0, best = 0;
    for (uint32_t id = 0; id < bound; id++) {
        mer_node n;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0)
            continue;
        all++;
        if (n.order == 0 || n.parent == MER_NO_NODE)
            continue;
        /* Parents have lower ids: the parent's branch is known. */
        branch[id] = branch[n.parent] != 0 ? branch[n.parent] : id + 1;
        uint32_t c = ++count[branch[id] - 1];
        if (c > best)
            best = c;
    }
    free(branch);
    free(count);
    return all > 0 ? (float)best / (float)all : 0.0f;
}

/* Height over crown width of the silhouette (mer_summary). */
static inline float form_slenderness(const mer_scene *s)
{
    mer_summary m;
    mer_scene_summary(s, &m);
    return m.crown_width > 0.0f ? m.height / m.crown_width : 0.0f;
}

/* Height of the lowest living lateral branch's base above the ground (mer_summary's
 * crown base): a bole is as tall as this. */
static inline float form_lowest_branch(const mer_scene *s)
{
    mer_summary m;
    mer_scene_summary(s, &m);
    return m.crown_base;
}

/* Mean vertical component of the direction of the internodes made from step `from`
 * on: below 0 when the new growth droops (P09 Fig. 13). */
static inline float form_new_dir_y(const mer_scene *s, uint32_t from)
{
    double sum = 0.0;
    uint32_t count = 0;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node n;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0 ||
            n.born < from)
            continue;
        sum += (double)n.dir[1];
        count++;
    }
    return count > 0 ? (float)(sum / count) : 0.0f;
}

/* Gnarl: the mean angle in degrees between an internode and the next one of its axis
 * (its main child): near 0 for straight axes, large for the strongly gnarled branches
 * of P09 Fig. 12c, d. */
static inline float form_gnarl(const mer_scene *s)
{
    double sum = 0.0;
    uint32_t count = 0;
    for (uint32_t id = 0; id < mer_scene_node_bound(s); id++) {
        mer_node n, c;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0 ||
            n.main_child == MER_NO_NODE ||
            mer_scene_node(s, n.main_child, &c, NULL) != MER_OK || !c.alive)
            continue;
        float dot = n.dir[0] * c.dir[0] + n.dir[1] * c.dir[1] + n.dir[2] * c.dir[2];
        sum += (double)acosf(dot > 1.0f ? 1.0f : dot < -1.0f ? -1.0f : dot) * (180.0 / 3.14159265358979);
        count++;
    }
    return count > 0 ? (float)(sum / count) : 0.0f;
}

/* Fork height: where, walking up the trunk, a lateral first carries at least as
 * many internodes as the trunk above it (the trunk divides into limbs), over the
 * tree's height; 1 when the trunk stays the dominant axis to its top. The
 * botanist's excurrent (a main axis that dominates through the crown) against
 * decurrent (a trunk that breaks up into roughly equal limbs). */
static inline float form_fork_height(const mer_scene *s)
{
    uint32_t bound = mer_scene_node_bound(s);
    uint32_t *size = calloc(bound, sizeof *size);
    assert_non_null(size);
    /* Children have higher ids: sizes accumulate from the last node down. */
    uint32_t root = MER_NO_NODE;
    float top = 0.0f, base = 0.0f;
    for (uint32_t id = bound; id-- > 0;) {
        mer_node n;
        if (mer_scene_node(s, id, &n, NULL) != MER_OK || !n.alive || n.plant != 0)
            continue;
        size[id] += 1;
        if (n.parent != MER_NO_NODE)
            size[n.parent] += size[id];
        else
            root = id;
        if (form_tip_y(&n) > top)
            top = form_tip_y(&n);
    }
    float fork = 0.0f;
    if (root != MER_NO_NODE) {
        mer_node n;
        mer_scene_node(s, root, &n, NULL);
        base = n.base[1];
        for (uint32_t id = root;;) {
            mer_scene_node(s, id, &n, NULL);
            fork = form_tip_y(&n) - base;
            if (n.main_child == MER_NO_NODE)
                break;
            uint32_t lat = 0;
            for (int k = 0; k < 2; k++)
                if (n.lateral_child[k] != MER_NO_NODE && size[n.lateral_child[k]] > lat)
                    lat = size[n.lateral_child[k]];
            if (lat >= size[n.main_child])
                break;
            id = n.main_child;
        }
    }
    free(size);
    return top > base ? fork / (top - base) : 0.0f;
}

#endif
