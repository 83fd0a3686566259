/* Unit tests for copies of scenes: mer_scene_clone (lib/scene_clone.c) and
 * checkpoints, mer_scene_save and mer_scene_load (lib/scene_io.c). A copy hashes
 * and meshes byte-identically to its original, grows on identically under every
 * preset, and shares nothing with it (the original is freed first: ASan sees any
 * alias). A damaged checkpoint is refused, never loaded, never a crash. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <cmocka.h>

#include <meristem/edit.h>
#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/presets.h>
#include <meristem/scene.h>

#include "scene_helpers.h"

/* The GLB of `s` with default mesh options. */
static uint8_t *glb(const mer_scene *s, size_t *size)
{
    mer_mesh *m = NULL;
    mer_error err;
    if (mer_mesh_build(s, NULL, &m, &err) != MER_OK)
        fail_msg("mesh: %s", err.message);
    uint8_t *bytes = NULL;
    if (mer_gltf_write_tree(m, NULL, NULL, &bytes, size, &err) != MER_OK)
        fail_msg("glTF: %s", err.message);
    mer_mesh_free(m);
    return bytes;
}

/* A scene's hash and GLB, kept to compare later scenes with. */
struct look {
    uint64_t hash;
    uint8_t *glb;
    size_t size;
};

static struct look look_of(const mer_scene *s)
{
    struct look l = {.hash = mer_scene_hash(s)};
    l.glb = glb(s, &l.size);
    return l;
}

static void assert_looks(const struct look *l, const mer_scene *s)
{
    assert_int_equal(mer_scene_hash(s), l->hash);
    size_t n;
    uint8_t *g = glb(s, &n);
    assert_int_equal(n, l->size);
    assert_memory_equal(g, l->glb, n);
    mer_gltf_free(g);
}

static void look_free(struct look *l)
{
    mer_gltf_free(l->glb);
}

/* Two scenes hash and mesh byte-identically. */
static void assert_same(const mer_scene *a, const mer_scene *b)
{
    struct look l = look_of(a);
    assert_looks(&l, b);
    look_free(&l);
}

static mer_scene *copy(const mer_scene *s)
{
    mer_scene *c = NULL;
    mer_error err;
    if (mer_scene_clone(s, &c, &err) != MER_OK)
        fail_msg("clone: %s", err.message);
    return c;
}

/* A tetrahedron beside the trunk: a mesh obstacle. */
static void add_tetrahedron(mer_scene *s)
{
    static const float v[4][3] = {{2, 0.5f, -1}, {4, 0.5f, -1}, {3, 0.5f, 1}, {3, 3, 0}};
    static const int f[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
    float xyz[36];
    for (int t = 0; t < 4; t++)
        for (int k = 0; k < 3; k++)
            memcpy(&xyz[9 * t + 3 * k], v[f[t][k]], sizeof v[0]);
    mer_error err;
    if (mer_scene_add_mesh(s, xyz, 4, &err) != MER_OK)
        fail_msg("mesh obstacle: %s", err.message);
}

/* The edits both copies of a scene get before the clone. */
static void shape(mer_scene *s)
{
    const float lo[3] = {-4, 0, -4}, hi[3] = {-3, 2, -3};
    mer_error err;
    assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
    add_tetrahedron(s);
    step(s, 5);
    uint32_t n = mer_scene_node_bound(s);
    if (n > 4)
        (void)mer_scene_prune(s, n - 2, &err);
}

/* Gives an L-system preset's scenes their source (P09's need none). */
static void define(mer_scene *s, const char *preset)
{
    const char *text = mer_preset_definition(preset);
    mer_error err;
    if (text != NULL && mer_scene_set_definition(s, text, strlen(text), &err) != MER_OK)
        fail_msg("%s: %s", preset, err.message);
}

static void test_copy_of_a_copy_is_independent(void **state)
{
    (void)state;
    mer_scene *a = make(NULL, 3);
    step(a, 4);
    mer_scene *c = copy(a);
    mer_scene *d = copy(c);
    step(c, 3); /* grows the copy only */
    assert_same(a, d);
    step(a, 3);
    assert_same(a, c);
    mer_scene_free(a);
    mer_scene_free(c);
    mer_scene_free(d);
}

static uint8_t *save(const mer_scene *s, size_t *size)
{
    uint8_t *bytes = NULL;
    mer_error err;
    if (mer_scene_save(s, &bytes, size, &err) != MER_OK)
        fail_msg("save: %s", err.message);
    return bytes;
}

static mer_scene *load(const uint8_t *bytes, size_t size)
{
    mer_scene *s = NULL;
    mer_error err;
    if (mer_scene_load(bytes, size, &s, &err) != MER_OK)
        fail_msg("load: %s %s", err.field, err.message);
    return s;
}

/* Under every preset, a copy (mer_scene_clone) and a checkpoint loaded back
 * (mer_scene_save, mer_scene_load) of a shaped scene equal a scene that went
 * the same way, and grow on as it does. Both are taken from one original,
 * which is then freed: neither may lean on it. */
static void test_presets_clone_and_checkpoint_identically(void **state)
{
    (void)state;
    for (size_t i = 0; i < mer_preset_count(); i++) {
        mer_params p;
        mer_error err;
        assert_int_equal(mer_preset_params(mer_preset_name(i), &p, &err), MER_OK);
        mer_scene *a = new_scene(&p, 7 + i), *b = new_scene(&p, 7 + i);
        define(a, mer_preset_name(i));
        define(b, mer_preset_name(i));
        shape(a);
        shape(b);
        mer_scene *c = copy(a);
        size_t size;
        uint8_t *bytes = save(a, &size);
        mer_scene_free(a); /* the copy and the checkpoint must not lean on it */
        mer_scene *l = load(bytes, size);
        assert_same(b, c);
        assert_same(b, l);
        /* Nothing is lost on the way: saving the loaded scene gives the same bytes. */
        size_t again_size;
        uint8_t *again = save(l, &again_size);
        assert_int_equal(again_size, size);
        assert_memory_equal(again, bytes, size);
        free(again);
        free(bytes);
        step(b, 4);
        step(c, 4);
        step(l, 4);
        assert_same(b, c);
        assert_same(b, l);
        mer_scene_free(b);
        mer_scene_free(c);
        mer_scene_free(l);
    }
}

/* A small scene under space colonization, with markers and obstacles: cheap to
 * load many times. */
static mer_scene *small_scene(void)
{
    mer_params p = mer_params_default();
    p.environment = MER_ENV_MARKERS;
    p.marker_count = 2000;
    p.bounds_min[0] = p.bounds_min[2] = -8.0f;
    p.bounds_max[0] = p.bounds_max[2] = 8.0f;
    p.bounds_max[1] = 16.0f;
    mer_scene *s = new_scene(&p, 5);
    shape(s);
    return s;
}

static void refused(const uint8_t *bytes, size_t size)
{
    mer_scene *s = (mer_scene *)1;
    mer_error err;
    assert_int_equal(mer_scene_load(bytes, size, &s, &err), MER_ERR_FORMAT);
    assert_null(s);
}

static void test_damaged_checkpoints_are_refused(void **state)
{
    (void)state;
    mer_scene *s = small_scene();
    size_t size;
    uint8_t *bytes = save(s, &size);
    mer_scene_free(s);
    refused(NULL, 0);
    /* Cut anywhere: each a fresh block of exactly that length, for ASan. */
    for (size_t n = 0; n < size; n += n < 64 ? 1 : 1 + size / 300) {
        uint8_t *cut = malloc(n ? n : 1);
        memcpy(cut, bytes, n);
        refused(cut, n);
        free(cut);
    }
    /* A flipped bit anywhere: the header's checks or the digest see it. */
    for (size_t at = 0; at < size; at += at < 64 ? 1 : 1 + size / 300) {
        bytes[at] ^= 0x10;
        refused(bytes, size);
        bytes[at] ^= 0x10;
    }
    free(bytes);
}

/* Flips bits all over the checkpoint of s (freed) and steps whatever loads. */
static void flips_never_crash(mer_scene *s)
{
    size_t size;
    uint8_t *bytes = save(s, &size);
    mer_scene_free(s);
    const size_t header = 32;
    uint8_t *copy = malloc(size);
    size_t loaded = 0, refusals = 0;
    for (size_t at = header; at < size; at += 1 + size / 400) {
        for (int bit = 0; bit < 8; bit += 3) {
            memcpy(copy, bytes, size);
            copy[at] ^= (uint8_t)(1u << bit);
            uint64_t h = UINT64_C(1469598103934665603) /* MERP_FNV_OFFSET */;
            for (size_t k = header; k < size; k++)
                h = (h ^ copy[k]) * UINT64_C(1099511628211);
            memcpy(copy + 24, &h, sizeof h);
            mer_scene *t = NULL;
            mer_error err;
            mer_result rc = mer_scene_load(copy, size, &t, &err);
            if (rc == MER_OK) {
                uint32_t done;
                (void)mer_scene_step(t, 1, NULL, NULL, NULL, &done, &err);
                mer_scene_free(t);
                loaded++;
            } else {
                assert_int_equal(rc, MER_ERR_FORMAT);
                refusals++;
            }
        }
    }
    /* The digest was recomputed right: some damage passes it and loads. */
    assert_true(loaded > 0 && refusals > 0);
    free(copy);
    free(bytes);
}

/* Damage the digest does not see (it is recomputed): every field is checked
 * before it is used, so a load either refuses or gives a scene that can step.
 * Under the priority model too, whose axis lists place each node's items by
 * the counts of the basipetal pass: links that disagree (a child its parent
 * does not list) must not send them out of their arrays. */
static void test_inconsistent_checkpoints_never_crash(void **state)
{
    (void)state;
    flips_never_crash(small_scene());
    mer_params p;
    mer_error err;
    assert_int_equal(mer_preset_params("fig9-priority-k0.5", &p, &err), MER_OK);
    p.bounds_min[0] = p.bounds_min[2] = -8.0f; /* a small grid: loads stay quick */
    p.bounds_max[0] = p.bounds_max[2] = 8.0f;
    p.bounds_max[1] = 16.0f;
    mer_scene *s = new_scene(&p, 3);
    step(s, 8);
    flips_never_crash(s);
}

/* Gives a checkpoint of `size` bytes, its payload edited, the header's payload
 * length and digest (FNV-1a) that fit it. */
static void reseal(uint8_t *bytes, size_t size)
{
    uint64_t payload = size - 32, h = UINT64_C(1469598103934665603) /* MERP_FNV_OFFSET */;
    for (size_t k = 32; k < size; k++)
        h = (h ^ bytes[k]) * UINT64_C(1099511628211);
    memcpy(bytes + 16, &payload, 8);
    memcpy(bytes + 24, &h, 8);
}

/* Every model keeps the skeleton's links agreeing through what users do to
 * it: steps, prunes (a model that rebuilds its skeleton, an L-system or an
 * inverse tree, then renews or renumbers ids) and a definition given again.
 * A checkpoint load refuses links that disagree, so a model that broke them
 * would make its sessions unloadable after a restart: each preset's scene is
 * saved and loaded after each of two such rounds. */
static void test_links_agree_after_edits(void **state)
{
    (void)state;
    for (size_t i = 0; i < mer_preset_count(); i++) {
        const char *name = mer_preset_name(i);
        mer_params p;
        mer_error err;
        assert_int_equal(mer_preset_params(name, &p, &err), MER_OK);
        mer_scene *s = new_scene(&p, 11 + i);
        define(s, name);
        for (int round = 0; round < 2; round++) {
            step(s, 3);
            uint32_t n = mer_scene_node_bound(s);
            for (uint32_t k = 0; k < 2 && n > 6; k++)
                (void)mer_scene_prune(s, n / 2 + k * n / 4, &err); /* a dead node is refused: fine */
            step(s, 2);
            define(s, name);
            size_t size;
            uint8_t *bytes = save(s, &size);
            mer_scene_free(load(bytes, size));
            free(bytes);
        }
        mer_scene_free(s);
    }
}

/* Where the skeleton's node count n lies in a checkpoint (lib/scene_io.c
 * save_skeleton): n, then the parents, the root's none and node 1's the root. */
static size_t skeleton_at(const uint8_t *bytes, size_t size, uint32_t n)
{
    const uint32_t mark[3] = {n, UINT32_MAX, 0};
    for (size_t at = 32; at + sizeof mark <= size; at++)
        if (memcmp(bytes + at, mark, sizeof mark) == 0)
            return at;
    fail_msg("no skeleton in the checkpoint");
    return 0;
}

/* Links that disagree are damage no edit makes: a node that names a parent
 * which does not list it, a dead node its living parent still lists. They
 * are refused when loaded, so the growth passes may trust them (the P09
 * priority model's axis lists place items by them). */
static void test_disagreeing_links_are_refused(void **state)
{
    (void)state;
    mer_params p;
    mer_error err;
    assert_int_equal(mer_preset_params("fig9-priority-k0.5", &p, &err), MER_OK);
    p.bounds_min[0] = p.bounds_min[2] = -8.0f;
    p.bounds_max[0] = p.bounds_max[2] = 8.0f;
    p.bounds_max[1] = 16.0f;
    mer_scene *s = new_scene(&p, 3);
    step(s, 6);
    uint32_t n = mer_scene_node_bound(s);
    assert_true(n > 4);
    size_t size;
    uint8_t *bytes = save(s, &size);
    mer_scene_free(s);
    size_t at = skeleton_at(bytes, size, n);
    uint32_t last = n - 1, parent, root_parent = 0;
    memcpy(&parent, bytes + at + 4 + 4 * (size_t)last, 4);
    assert_true(parent != UINT32_MAX && parent != root_parent);
    uint8_t *copy = malloc(size);
    /* the newest node names the root as its parent: the root does not list it */
    memcpy(copy, bytes, size);
    memcpy(copy + at + 4 + 4 * (size_t)last, &root_parent, 4);
    reseal(copy, size);
    refused(copy, size);
    /* the newest node dead, its living parent still listing it */
    memcpy(copy, bytes, size);
    copy[at + 4 + 20 * (size_t)n + last] = 0;
    reseal(copy, size);
    refused(copy, size);
    /* as saved, it loads: the edits above are what is refused */
    mer_scene *t = load(bytes, size);
    mer_scene_free(t);
    free(copy);
    free(bytes);
}

/* The offset after the parameter entry at `at` (lib/params_io.c): a name, a
 * kind, a number or keyframes. */
static size_t skip_entry(const uint8_t *bytes, size_t at)
{
    at += 1 + bytes[at];
    if (bytes[at++] == 1)
        return at + 8;
    uint32_t n;
    memcpy(&n, bytes + at, 4);
    return at + 4 + 8 * (size_t)n;
}

/* The payload's parameter sections (lib/params_io.c), rewritten as a writer
 * would: the entries named in `drop` left out of both sections (a writer older
 * than those parameters), and an entry `add` (a number, 0) appended to the
 * first (a newer one). Header length and digest recomputed; `*size` updated. */
static uint8_t *rewrite(const uint8_t *bytes, size_t *size, const char *const *drop, size_t ndrop,
                        const char *add)
{
    const size_t header = 32;
    uint8_t *out = malloc(*size + 128);
    assert_non_null(out);
    memcpy(out, bytes, header);
    size_t at = header, o = header;
    for (int section = 0; section < 2; section++) {
        uint32_t count, kept = 0;
        memcpy(&count, bytes + at, 4);
        size_t count_at = o;
        at += 4;
        o += 4;
        for (uint32_t k = 0; k < count; k++) {
            size_t start = at;
            char name[80] = {0};
            memcpy(name, bytes + at + 1, bytes[at]);
            at = skip_entry(bytes, at);
            int dropped = 0;
            for (size_t d = 0; d < ndrop; d++)
                dropped |= strcmp(name, drop[d]) == 0;
            if (!dropped) {
                memcpy(out + o, bytes + start, at - start);
                o += at - start;
                kept++;
            }
        }
        if (section == 0 && add != NULL) {
            uint8_t len = (uint8_t)strlen(add), kind = 1;
            double zero = 0.0;
            out[o++] = len;
            memcpy(out + o, add, len);
            o += len;
            out[o++] = kind;
            memcpy(out + o, &zero, 8);
            o += 8;
            kept++;
        }
        memcpy(out + count_at, &kept, 4);
    }
    memcpy(out + o, bytes + at, *size - at);
    o += *size - at;
    *size = o;
    reseal(out, o);
    return out;
}

/* 1 if every field in `names` holds its default in `p`. */
static int at_defaults(const mer_params *p, const char *const *names, size_t n)
{
    mer_params d = mer_params_default();
    for (size_t i = 0; i < n; i++) {
        double a = 0, b = 0;
        if (strcmp(names[i], "lambda_keys") == 0)
            a = p->schedule.lambda_key_count;
        else if (strcmp(names[i], "eta_keys") == 0)
            a = p->schedule.eta_key_count;
        else if (mer_params_get(p, names[i], &a, NULL) != MER_OK ||
                 mer_params_get(&d, names[i], &b, NULL) != MER_OK)
            fail_msg("no parameter %s", names[i]);
        if (a != b)
            return 0;
    }
    return 1;
}

/* A checkpoint of a writer that predates a group of parameters (the noise, the
 * L-system's, Runions', the keyframe schedules) lacks their entries: it loads
 * with those at their defaults, which keep the behaviour before them, and
 * grows on byte-identically to the scene it came from. */
static void test_older_writers_checkpoints_load(void **state)
{
    (void)state;
    static const char *const groups[][7] = {
        {"noise_amplitude", "noise_scale", "noise_octaves", "noise_targets"},
        {"ls_delta", "ls_step", "ls_width", "ls_width_scale", "ls_elasticity", "ls_blocking"},
        {"d_i", "d_k", "D"},
        {"lambda_keys", "eta_keys"},
    };
    static const size_t sizes[] = {4, 6, 3, 2};
    size_t tried = 0;
    for (size_t i = 0; i < mer_preset_count(); i++) {
        mer_params p;
        mer_error err;
        assert_int_equal(mer_preset_params(mer_preset_name(i), &p, &err), MER_OK);
        /* One checkpoint per preset, rewritten once per group; the scene it came
         * from, as it was then (at3) and three steps on (at6), is what each load
         * must equal. */
        mer_scene *a = new_scene(&p, 13 + i), *b = new_scene(&p, 13 + i);
        define(a, mer_preset_name(i));
        define(b, mer_preset_name(i));
        step(a, 3);
        step(b, 3);
        size_t size;
        uint8_t *bytes = save(a, &size);
        mer_scene_free(a);
        struct look at3 = look_of(b), at6;
        step(b, 3);
        at6 = look_of(b);
        mer_scene_free(b);
        for (size_t g = 0; g < sizeof sizes / sizeof sizes[0]; g++) {
            if (!at_defaults(&p, groups[g], sizes[g]))
                continue;
            size_t old_size = size;
            uint8_t *old = rewrite(bytes, &old_size, groups[g], sizes[g], NULL);
            mer_scene *c = load(old, old_size);
            assert_true(at_defaults(mer_scene_params(c), groups[g], sizes[g]));
            assert_looks(&at3, c);
            step(c, 3);
            assert_looks(&at6, c);
            mer_scene_free(c);
            free(old);
            tried++;
        }
        look_free(&at3);
        look_free(&at6);
        free(bytes);
    }
    assert_true(tried >= mer_preset_count());
}

/* A checkpoint of a default scene two steps old. */
static uint8_t *saved_seedling(size_t *size)
{
    mer_scene *s = new_scene(NULL, 3);
    step(s, 2);
    uint8_t *bytes = save(s, size);
    mer_scene_free(s);
    return bytes;
}

/* A checkpoint of a newer writer, with a parameter this build does not know,
 * is refused: growing on without it could grow another tree. So is a name
 * given twice. */
static void test_unknown_parameters_are_refused(void **state)
{
    (void)state;
    size_t size;
    uint8_t *bytes = saved_seedling(&size);
    size_t n = size;
    uint8_t *newer = rewrite(bytes, &n, NULL, 0, "leaf_wobble");
    mer_scene *t = (mer_scene *)1;
    mer_error err;
    assert_int_equal(mer_scene_load(newer, n, &t, &err), MER_ERR_FORMAT);
    assert_null(t);
    assert_non_null(strstr(err.message, "leaf_wobble"));
    free(newer);
    n = size;
    uint8_t *twice = rewrite(bytes, &n, NULL, 0, "rho");
    assert_int_equal(mer_scene_load(twice, n, &t, &err), MER_ERR_FORMAT);
    assert_non_null(strstr(err.message, "twice"));
    free(twice);
    n = size;
    uint8_t *same = rewrite(bytes, &n, NULL, 0, NULL);
    assert_int_equal(n, size);
    assert_memory_equal(same, bytes, size); /* the rewriting itself changes nothing */
    free(same);
    free(bytes);
}

/* The model's state is versioned by the model: a checkpoint whose state is of
 * another version than the model's is refused, never misread. */
static void test_model_state_of_another_version_is_refused(void **state)
{
    (void)state;
    size_t size;
    uint8_t *bytes = saved_seedling(&size);
    size_t at = 32;
    for (int section = 0; section < 2; section++) {
        uint32_t count;
        memcpy(&count, bytes + at, 4);
        at += 4;
        for (uint32_t k = 0; k < count; k++)
            at = skip_entry(bytes, at);
    }
    assert_int_equal(bytes[at], 3);
    assert_memory_equal(bytes + at + 1, "p09", 3);
    uint32_t version;
    memcpy(&version, bytes + at + 4, 4);
    version++;
    memcpy(bytes + at + 4, &version, 4);
    reseal(bytes, size);
    mer_scene *t = (mer_scene *)1;
    mer_error err;
    assert_int_equal(mer_scene_load(bytes, size, &t, &err), MER_ERR_FORMAT);
    assert_null(t);
    assert_non_null(strstr(err.message, "version"));
    free(bytes);
}

/* A value a grid refuses (found by fuzz_checkpoint; its input, framed as the
 * harness frames it): parameters mer_params_validate lets pass with marker_cell
 * 0, which the marker grid refuses. That is damage too (MER_ERR_FORMAT), never
 * a range error of the caller's. */
static void test_grid_refusals_are_damage(void **state)
{
    (void)state;
    char path[512];
    const char *src = getenv("srcdir");
    snprintf(path, sizeof path, "%s/tests/fuzz/corpus/checkpoint/regress-zero-marker-cell",
             src != NULL ? src : "..");
    FILE *f = fopen(path, "rb");
    assert_non_null(f);
    static uint8_t in[1 << 16];
    size_t n = fread(in, 1, sizeof in, f);
    fclose(f);
    assert_true(n > 1 && (in[0] & 1)); /* a payload: head it */
    mer_scene *s = new_scene(NULL, 3);
    size_t size;
    uint8_t *bytes = save(s, &size);
    mer_scene_free(s);
    uint8_t *framed = malloc(32 + n - 1);
    assert_non_null(framed);
    uint64_t payload = n - 1, h = UINT64_C(1469598103934665603) /* MERP_FNV_OFFSET */;
    for (size_t k = 1; k < n; k++)
        h = (h ^ in[k]) * UINT64_C(1099511628211);
    memcpy(framed, bytes, 16);
    memcpy(framed + 16, &payload, 8);
    memcpy(framed + 24, &h, 8);
    memcpy(framed + 32, in + 1, n - 1);
    refused(framed, 32 + n - 1);
    free(framed);
    free(bytes);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_presets_clone_and_checkpoint_identically),
        cmocka_unit_test(test_copy_of_a_copy_is_independent),
        cmocka_unit_test(test_damaged_checkpoints_are_refused),
        cmocka_unit_test(test_inconsistent_checkpoints_never_crash),
        cmocka_unit_test(test_disagreeing_links_are_refused),
        cmocka_unit_test(test_links_agree_after_edits),
        cmocka_unit_test(test_grid_refusals_are_damage),
        cmocka_unit_test(test_older_writers_checkpoints_load),
        cmocka_unit_test(test_unknown_parameters_are_refused),
        cmocka_unit_test(test_model_state_of_another_version_is_refused),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
