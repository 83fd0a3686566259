/* The growth-model seam: a trivial model (a straight stem, one internode per step)
 * plugged in through merp_model_ops runs in a scene, gets the pipe model's
 * diameters, and is meshed and written as GLB like P09's trees. Also the model
 * names and the parameter rows each model reads. */
#include "config.h"

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

#include "scene_private.h"

/* The stem model's state: how many steps it has grown, and how often it was
 * told that nodes changed. */
struct merp_model {
    uint32_t steps, changed;
};

static mer_result stem_create(const mer_params *p, merp_model **out, mer_error *err)
{
    (void)p;
    *out = calloc(1, sizeof **out);
    return *out != NULL ? MER_OK : mer_error_set(err, MER_ERR_NOMEM, NULL, "stem");
}

static void stem_set_params(merp_model *m, const mer_params *p)
{
    (void)m;
    (void)p;
}

/* The tip of the plant whose first internode is `root`: follow main children. */
static uint32_t tip_of(const merp_skeleton *sk, uint32_t root)
{
    uint32_t i = root;
    while (sk->child[3 * i] != MER_NO_NODE)
        i = sk->child[3 * i];
    return i;
}

/* One internode on top of every plant's stem, where the ground and obstacles let it. */
static mer_result stem_step(merp_model *m, const merp_world *w, mer_error *err)
{
    merp_skeleton *sk = w->sk;
    for (uint32_t r = 0; r < sk->nplants; r++) {
        uint32_t tip = tip_of(sk, sk->roots[r]);
        if (!sk->alive[tip] || sk->bud[3 * tip] != MER_BUD_DORMANT)
            continue;
        float start[3], end[3];
        merp_skel_node_end(sk, tip, start);
        memcpy(end, start, sizeof end);
        end[1] += w->p->internode_length;
        if (merp_env_blocked(w->env, end))
            continue;
        uint32_t c;
        mer_result rc = merp_skel_node_new(sk, w->step, &c, err);
        if (rc != MER_OK)
            return rc;
        sk->parent[c] = tip;
        sk->child[3 * tip] = c;
        sk->plant[c] = sk->plant[tip];
        memcpy(sk->pos + 3 * c, start, sizeof start);
        sk->dir[3 * c + 1] = 1.0f;
        memcpy(sk->side + 3 * c, sk->side + 3 * tip, 3 * sizeof(float));
        sk->len[c] = w->p->internode_length;
        merp_skel_bud_set(sk, tip, 0, MER_BUD_NONE);
        merp_skel_bud_set(sk, c, 0, MER_BUD_DORMANT);
    }
    m->steps++;
    return MER_OK;
}

static void stem_nodes_changed(merp_model *m, const merp_world *w)
{
    (void)w;
    m->changed++;
}

static uint64_t stem_hash(const merp_model *m, uint64_t h)
{
    return h ^ m->steps;
}

static void stem_free(merp_model *m) { free(m); }

static const merp_model_ops stem_ops = {
    .name = "stem",
    .param_rows = 0,
    .validate = NULL,
    .create = stem_create,
    .set_params = stem_set_params,
    .step = stem_step,
    .nodes_changed = stem_nodes_changed,
    .hash = stem_hash,
    .free = stem_free,
};

static mer_scene *stem_scene(uint64_t seed)
{
    mer_scene *s = NULL;
    mer_error err;
    if (merp_scene_new_with(&stem_ops, NULL, seed, &s, &err) != MER_OK)
        fail_msg("merp_scene_new_with: %s", err.message);
    return s;
}

static void step(mer_scene *s, uint32_t n)
{
    mer_error err;
    uint32_t done = 0;
    assert_int_equal(mer_scene_step(s, n, NULL, NULL, NULL, &done, &err), MER_OK);
    assert_int_equal(done, n);
}

/* session → step: the stem grows one internode a step, straight up, with pipe
 * diameters that grow from the leaf's towards the base. */
static void test_stem_grows_through_the_seam(void **state)
{
    (void)state;
    mer_scene *s = stem_scene(7);
    step(s, 5);
    assert_int_equal(mer_scene_step_index(s), 5);
    assert_int_equal(mer_scene_node_bound(s), 6);
    mer_summary sum;
    mer_scene_summary(s, &sum);
    assert_int_equal(sum.internodes, 6);
    assert_int_equal(sum.buds, 2); /* the tip's, and the seedling's lateral one */
    assert_float_equal(sum.height, 6.0f, 1e-5f);
    float below = 1e9f;
    for (uint32_t i = 0; i < 6; i++) {
        mer_node n;
        assert_int_equal(mer_scene_node(s, i, &n, NULL), MER_OK);
        assert_int_equal(n.parent, i == 0 ? MER_NO_NODE : i - 1);
        assert_float_equal(n.base[1], (float)i, 1e-5f);
        assert_true(n.diameter > 0.0f && n.diameter <= below);
        below = n.diameter;
    }
    assert_true(s->model->steps == 5);
    mer_scene_free(s);
}

/* The scene hash folds the model's state, and two runs of one seed agree. */
static void test_stem_is_deterministic(void **state)
{
    (void)state;
    mer_scene *a = stem_scene(3), *b = stem_scene(3);
    step(a, 4);
    step(b, 4);
    assert_true(mer_scene_hash(a) == mer_scene_hash(b));
    b->model->steps++;
    assert_true(mer_scene_hash(a) != mer_scene_hash(b));
    mer_scene_free(a);
    mer_scene_free(b);
}

/* Edits of the skeleton work whatever model grew it, and the model hears of them;
 * the environment still blocks growth. */
static void test_edits_reach_the_model(void **state)
{
    (void)state;
    mer_scene *s = stem_scene(1);
    step(s, 4);
    mer_error err;
    assert_int_equal(mer_scene_prune(s, 3, &err), MER_OK);
    assert_int_equal(s->model->changed, 1);
    const float ax[3] = {0, 0, 1};
    assert_int_equal(mer_scene_bend(s, 1, ax, 10.0f, &err), MER_OK);
    assert_int_equal(s->model->changed, 2);
    assert_int_equal(mer_scene_prune(s, 3, &err), MER_ERR_GONE);
    mer_scene_free(s);

    s = stem_scene(1);
    const float lo[3] = {-1, 3.5f, -1}, hi[3] = {1, 4, 1};
    assert_int_equal(mer_scene_add_box(s, lo, hi, &err), MER_OK);
    step(s, 6);
    assert_int_equal(mer_scene_node_bound(s), 3); /* the box stops the fourth */
    mer_scene_free(s);
}

/* session → step → GLB: the stem meshes and writes like any tree. */
static void test_stem_meshes_to_glb(void **state)
{
    (void)state;
    mer_scene *s = stem_scene(5);
    step(s, 6);
    mer_mesh *m = NULL;
    mer_error err;
    assert_int_equal(mer_mesh_build(s, NULL, &m, &err), MER_OK);
    assert_int_equal(m->internodes, 7);
    assert_int_equal(m->axes, 1);
    assert_true(m->bark.vertex_count > 0 && m->bark.index_count > 0);
    uint8_t *glb = NULL;
    size_t size = 0;
    assert_int_equal(mer_gltf_write_tree(m, NULL, NULL, &glb, &size, &err), MER_OK);
    assert_true(size > 12);
    assert_memory_equal(glb, "glTF", 4);
    uint32_t version, length;
    memcpy(&version, glb + 4, 4);
    memcpy(&length, glb + 8, 4);
    assert_int_equal(version, 2);
    assert_int_equal(length, size);
    mer_gltf_free(glb);
    mer_mesh_free(m);
    mer_scene_free(s);
}

/* Model names: "p09" is model 0, the default of all-zero parameters. */
static void test_model_names(void **state)
{
    (void)state;
    uint32_t k = 99;
    mer_error err;
    assert_int_equal(mer_model_parse("p09", &k, &err), MER_OK);
    assert_int_equal(k, MER_MODEL_P09);
    assert_string_equal(mer_model_name(MER_MODEL_P09), "p09");
    assert_null(mer_model_name(1000));
    assert_int_equal(mer_model_parse("no-such-model", &k, &err), MER_ERR_INVALID);
    assert_string_equal(err.field, "model");
    assert_non_null(strstr(err.message, "p09"));
    assert_int_equal(mer_model_parse(NULL, &k, &err), MER_ERR_INVALID);
    assert_int_equal(mer_params_default().model, MER_MODEL_P09);
    mer_params p = mer_params_default();
    p.model = 1000;
    assert_int_equal(mer_params_validate(&p, &err), MER_ERR_RANGE);
    assert_string_equal(err.field, "model");
    mer_scene *s = NULL;
    assert_int_equal(mer_scene_new(&p, 1, &s, &err), MER_ERR_RANGE);
    assert_null(s);
}

/* Each row says which model reads it: λ and κ are P09's, d_i is Runions', the
 * bounds and the noise everyone's; a summary lists the noise only while it is on. */
static void test_rows_per_model(void **state)
{
    (void)state;
    size_t p09 = 0, world = 0, runions = 0, ls = 0, gv = 0;
    for (size_t i = 0; i < mer_params_field_count(); i++) {
        const char *m = mer_params_field_model(i);
        assert_non_null(m);
        const char *name = mer_params_field_name(i);
        if (strcmp(name, "lambda") == 0 || strcmp(name, "kappa") == 0)
            assert_string_equal(m, "p09");
        if (strcmp(name, "bounds_min.x") == 0 || strcmp(name, "pipe_n") == 0)
            assert_string_equal(m, "");
        if (strcmp(name, "ls_delta") == 0)
            assert_string_equal(m, "lsystem");
        if (strcmp(name, "d_i") == 0)
            assert_string_equal(m, "runions");
        if (strcmp(name, "gv_epsilon") == 0)
            assert_string_equal(m, "guiding");
        mer_params p = mer_params_default();
        int used = mer_params_field_used(&p, i);
        if (strcmp(name, "noise_scale") == 0) {
            assert_string_equal(m, "");
            assert_false(used);
            p.noise_amplitude = 0.1f;
            assert_true(mer_params_field_used(&p, i));
        } else {
            assert_int_equal(used, strcmp(m, "runions") != 0 && strcmp(m, "lsystem") != 0 &&
                                       strcmp(m, "guiding") != 0 && strncmp(name, "noise_", 6) != 0);
        }
        p09 += strcmp(m, "p09") == 0;
        ls += strcmp(m, "lsystem") == 0;
        world += m[0] == '\0';
        runions += strcmp(m, "runions") == 0;
        gv += strcmp(m, "guiding") == 0;
    }
    assert_true(p09 > 0 && world > 0 && ls > 0);
    assert_int_equal(runions, 3);
    assert_int_equal(gv, 13);
    assert_int_equal(p09 + world + runions + ls + gv, mer_params_field_count());
    assert_null(mer_params_field_model(mer_params_field_count()));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_stem_grows_through_the_seam),
        cmocka_unit_test(test_stem_is_deterministic),
        cmocka_unit_test(test_edits_reach_the_model),
        cmocka_unit_test(test_stem_meshes_to_glb),
        cmocka_unit_test(test_model_names),
        cmocka_unit_test(test_rows_per_model),
    };
    return cmocka_run_group_tests_name("model", tests, NULL, NULL);
}
