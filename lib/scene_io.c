/* meristem — checkpoints: a whole scene as versioned bytes and back (see
 * mer_scene_save). The layout, in host byte order:
 *   header   "MERSCENE", u32 version (3), u32 0x01020304 (byte order), u64
 *            payload size, u64 FNV-1a of the payload
 *   payload  params      the scene's, then the environment's, each a section of
 *                        named entries (params_io.c): a field this build does not
 *                        know is refused, one the checkpoint lacks takes its
 *                        default, so new parameters do not orphan checkpoints
 *            model       u8 name length, its name ("p09"), u32 the version of
 *                        its state (merp_model_ops.state_version)
 *            rng, seed (u64, the noise permutation's), step, skeleton (nodes
 *            by id, plants, constraint), environment (epoch, markers by
 *            index, the shadow grid's voxels, obstacles with mesh triangles),
 *            the model's state (its ops' save), refused unless its version is
 *            the model's own
 * Version 2 held the parameters as the struct's bytes; it is refused, and the
 * journal, replayed from its start, restores what it held.
 * The shadow grid could be recast from the buds and obstacles exactly (its sums
 * are of integers), but reading it back is O(voxels) where recasting costs
 * O(buds · q_max²), most of a load on a large tree. */
#include "config.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#include "core/alloc.h"
#include "core/bytes.h"
#include "core/hash.h"
#include "params_io.h"
#include "scene_private.h"

#define MAGIC "MERSCENE"
#define CHECKPOINT_VERSION 3u
#define MODEL_NAME_MAX 64u
#define BYTE_ORDER_MARK UINT32_C(0x01020304)
#define HEADER (8 + 4 + 4 + 8 + 8)

static void save_skeleton(const merp_skeleton *sk, merp_bytes_out *o)
{
    merp_put_u32(o, sk->n);
    for (size_t a = 0; a < MERP_SKEL_ARRAYS; a++)
        merp_put(o, merp_skel_array_data(sk, a), (size_t)sk->n * merp_skel_arrays[a].bytes);
    merp_put(o, &sk->pipe_n, sizeof sk->pipe_n);
    merp_put(o, &sk->cos_beta, sizeof sk->cos_beta);
    merp_put(o, &sk->sin_beta, sizeof sk->sin_beta);
    merp_put_u32(o, sk->nplants);
    merp_put(o, sk->roots, sk->nplants * sizeof *sk->roots);
    merp_put_u32(o, sk->con_node);
    merp_put_u32(o, sk->con_slot);
}

static void save_env(const merp_env *e, merp_bytes_out *o)
{
    merp_put_u32(o, e->epoch);
    merp_markers_save(e->markers, o);
    merp_put_u32(o, e->shadow != NULL);
    if (e->shadow != NULL)
        merp_shadow_save(e->shadow, o);
    merp_put_u32(o, e->nobs);
    for (uint32_t k = 0; k < e->nobs; k++) {
        const merp_obstacle *ob = &e->obs[k];
        merp_put_u32(o, ob->kind);
        merp_put(o, ob->a, sizeof ob->a);
        merp_put(o, ob->b, sizeof ob->b);
        merp_put(o, &ob->r, sizeof ob->r);
        size_t ntri = 0;
        const float *tri = ob->solid != NULL ? merp_solid_triangles(ob->solid, &ntri) : NULL;
        merp_put_u64(o, ntri);
        merp_put(o, tri, 9 * ntri * sizeof *tri);
    }
}

mer_result mer_scene_save(const mer_scene *s, uint8_t **bytes, size_t *size, mer_error *err)
{
    assert(s != NULL && bytes != NULL && size != NULL);
    *bytes = NULL;
    *size = 0;
    if (s->ops->save == NULL)
        return mer_error_set(err, MER_ERR_INVALID, "model",
                             "scenes of the model '%s' cannot be saved", s->ops->name);
    merp_bytes_out o = {0};
    uint8_t header[HEADER] = {0};
    merp_put(&o, header, sizeof header); /* filled in below */
    merp_params_save(&s->p, &o);
    merp_params_save(&s->env.p, &o);
    uint8_t name_len = (uint8_t)strlen(s->ops->name);
    assert(name_len > 0 && name_len <= MODEL_NAME_MAX);
    merp_put(&o, &name_len, 1);
    merp_put(&o, s->ops->name, name_len);
    merp_put_u32(&o, s->ops->state_version);
    merp_put(&o, s->rng.s, sizeof s->rng.s);
    merp_put(&o, &s->seed, sizeof s->seed);
    merp_put_u32(&o, s->step);
    save_skeleton(&s->sk, &o);
    save_env(&s->env, &o);
    s->ops->save(s->model, &o);
    if (o.oom) {
        merp_free(o.buf);
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a checkpoint");
    }
    uint64_t payload = o.n - HEADER, digest = merp_fnv(MERP_FNV_OFFSET, o.buf + HEADER, payload);
    uint32_t version = CHECKPOINT_VERSION, order = BYTE_ORDER_MARK;
    memcpy(o.buf, MAGIC, 8);
    memcpy(o.buf + 8, &version, 4);
    memcpy(o.buf + 12, &order, 4);
    memcpy(o.buf + 16, &payload, 8);
    memcpy(o.buf + 24, &digest, 8);
    *bytes = o.buf;
    *size = o.n;
    return MER_OK;
}

/* Whether the links of living node i agree both ways (merp_skeleton's
 * invariant): each child lives and names i as its parent in that slot, and
 * i's parent lives and lists i in i's slot. Ids are checked first. */
static int links_agree(const merp_skeleton *sk, uint32_t i)
{
    for (uint32_t k = 0; k < 3; k++) {
        uint32_t c = sk->child[3 * i + k];
        if (c != MER_NO_NODE && (!sk->alive[c] || sk->parent[c] != i || sk->slot[c] != k))
            return 0;
    }
    uint32_t p = sk->parent[i];
    return p == MER_NO_NODE || (sk->alive[p] && sk->child[3 * p + sk->slot[i]] == i);
}

/* Ids grow from parent to child, so links that point backwards, or forwards
 * from a child, would be cycles or strays: refused. So are living nodes whose
 * links disagree, which no edit makes: the growth passes rely on them (the
 * P09 priority model's axis lists, p09.h). */
static int skeleton_valid(const merp_skeleton *sk)
{
    for (uint32_t i = 0; i < sk->n; i++) {
        if (sk->parent[i] != MER_NO_NODE && sk->parent[i] >= i)
            return 0;
        if (sk->slot[i] > 2 || sk->alive[i] > 1 || sk->plant[i] >= sk->nplants)
            return 0;
        for (int k = 0; k < 3; k++) {
            uint32_t c = sk->child[3 * i + k];
            if ((c != MER_NO_NODE && (c <= i || c >= sk->n)) || sk->bud[3 * i + k] > MER_BUD_ABORTED)
                return 0;
        }
    }
    for (uint32_t i = 0; i < sk->n; i++)
        if (sk->alive[i] && !links_agree(sk, i))
            return 0;
    for (uint32_t j = 0; j < sk->nplants; j++)
        if (sk->roots[j] >= sk->n)
            return 0;
    return sk->con_node == MER_NO_NODE || (sk->con_node < sk->n && sk->con_slot <= 2);
}

static void load_skeleton(merp_skeleton *sk, merp_bytes_in *in)
{
    uint32_t n = merp_get_u32(in);
    if (n > MER_NODES_MAX)
        in->bad = 1;
    for (size_t a = 0; a < MERP_SKEL_ARRAYS; a++)
        if (!merp_get_array(in, merp_skel_array_slot(sk, a), n, merp_skel_arrays[a].bytes))
            break;
    if (in->bad)
        return;
    sk->n = sk->cap = n;
    merp_get(in, &sk->pipe_n, sizeof sk->pipe_n);
    merp_get(in, &sk->cos_beta, sizeof sk->cos_beta);
    merp_get(in, &sk->sin_beta, sizeof sk->sin_beta);
    uint32_t nplants = merp_get_u32(in);
    if (nplants > n)
        in->bad = 1;
    if (!MERP_GET_ARRAY(in, sk->roots, nplants))
        return;
    sk->nplants = sk->cap_plants = nplants;
    sk->con_node = merp_get_u32(in);
    sk->con_slot = merp_get_u32(in);
    if (!in->bad && !skeleton_valid(sk))
        in->bad = 1;
}

static mer_result load_obstacle(merp_env *e, merp_bytes_in *in, mer_error *err)
{
    merp_obstacle ob = {.kind = merp_get_u32(in)};
    merp_get(in, ob.a, sizeof ob.a);
    merp_get(in, ob.b, sizeof ob.b);
    merp_get(in, &ob.r, sizeof ob.r);
    uint64_t ntri = merp_get_u64(in);
    if (ob.kind < MERP_OBS_BOX || ob.kind > MERP_OBS_MESH || (ntri > 0) != (ob.kind == MERP_OBS_MESH) ||
        ntri > MER_MESH_TRIANGLES_MAX)
        in->bad = 1;
    float *tri = NULL;
    if (!MERP_GET_ARRAY(in, tri, 9 * (size_t)ntri))
        return MER_OK; /* the caller reports `in` */
    mer_result rc = MER_OK;
    if (tri != NULL) {
        rc = merp_check_mesh(tri, ntri, err);
        if (rc == MER_OK)
            rc = merp_solid_new(tri, ntri, &ob.solid, err);
        merp_free(tri);
        // No scene this loads into could have taken it (markers aside, which
        // may have come after it): its inside tests would cost unbounded time.
        if (rc == MER_OK && (rc = merp_check_mesh_work(ob.solid, &e->p, 0, NULL, err)) != MER_OK)
            merp_solid_free(ob.solid);
        if (rc != MER_OK)
            return rc == MER_ERR_NOMEM ? rc : mer_error_set(err, MER_ERR_FORMAT, "obstacles",
                                                            "a damaged mesh obstacle");
    }
    e->obs[e->nobs++] = ob;
    return MER_OK;
}

static mer_result load_env(merp_env *e, merp_bytes_in *in, uint32_t *epoch, mer_error *err)
{
    *epoch = merp_get_u32(in);
    if (in->bad)
        return MER_OK;
    mer_result rc = merp_markers_load(e->markers, in, err);
    if (rc == MER_OK && merp_get_u32(in) != (e->shadow != NULL))
        in->bad = 1;
    if (rc == MER_OK && !in->bad && e->shadow != NULL)
        rc = merp_shadow_load(e->shadow, in, err);
    uint32_t nobs = rc == MER_OK ? merp_get_u32(in) : 0;
    if (nobs > MER_OBSTACLES_MAX)
        in->bad = 1;
    if (rc != MER_OK || in->bad || nobs == 0)
        return rc;
    e->obs = merp_calloc(nobs, sizeof *e->obs);
    if (e->obs == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for obstacles");
    for (uint32_t k = 0; k < nobs && rc == MER_OK && !in->bad; k++)
        rc = load_obstacle(e, in, err);
    return rc;
}

/* The header of `bytes`: MER_OK when it is ours, whole and undamaged. */
static mer_result check_header(const uint8_t *bytes, size_t size, mer_error *err)
{
    if (size < HEADER || memcmp(bytes, MAGIC, 8) != 0)
        return mer_error_set(err, MER_ERR_FORMAT, NULL, "not a meristem checkpoint");
    uint32_t version, order;
    uint64_t payload, digest;
    memcpy(&version, bytes + 8, 4);
    memcpy(&order, bytes + 12, 4);
    memcpy(&payload, bytes + 16, 8);
    memcpy(&digest, bytes + 24, 8);
    if (version != CHECKPOINT_VERSION)
        return mer_error_set(err, MER_ERR_FORMAT, "version",
                             "a checkpoint of version %u, not %u", (unsigned)version, CHECKPOINT_VERSION);
    if (order != BYTE_ORDER_MARK)
        return mer_error_set(err, MER_ERR_FORMAT, NULL, "a checkpoint of the other byte order");
    if (payload != size - HEADER)
        return mer_error_set(err, MER_ERR_FORMAT, NULL, "a checkpoint cut short or overlong");
    if (merp_fnv(MERP_FNV_OFFSET, bytes + HEADER, payload) != digest)
        return mer_error_set(err, MER_ERR_FORMAT, NULL, "a damaged checkpoint (digest)");
    return MER_OK;
}

/* The model section: its name, and its state's version, which must be the
 * model's own. */
static mer_result load_model(merp_bytes_in *in, mer_params *p, const merp_model_ops **ops,
                             mer_error *err)
{
    uint8_t len = 0;
    char name[MODEL_NAME_MAX + 1] = {0};
    merp_get(in, &len, 1);
    if (len == 0 || len > MODEL_NAME_MAX)
        in->bad = 1;
    merp_get(in, name, in->bad ? 0 : len);
    uint32_t version = merp_get_u32(in);
    if (in->bad || memchr(name, '\0', len) != NULL || mer_model_parse(name, &p->model, NULL) != MER_OK)
        return mer_error_set(err, MER_ERR_FORMAT, "model", "a model this build does not know");
    *ops = merp_model_ops_of(p->model);
    if (*ops == NULL || (*ops)->load == NULL)
        return mer_error_set(err, MER_ERR_FORMAT, "model", "a model that cannot be loaded");
    if (version != (*ops)->state_version)
        return mer_error_set(err, MER_ERR_FORMAT, "model",
                             "the state of the model '%s' of version %u, not %u", (*ops)->name,
                             (unsigned)version, (unsigned)(*ops)->state_version);
    return MER_OK;
}

/* The parameters of the payload, valid, and the model they name. */
static mer_result load_params(merp_bytes_in *in, mer_params *p, mer_params *env_p,
                              const merp_model_ops **ops, mer_error *err)
{
    mer_result rc = merp_params_load(in, p, err);
    if (rc == MER_OK)
        rc = merp_params_load(in, env_p, err);
    if (rc == MER_OK)
        rc = load_model(in, p, ops, err);
    if (rc != MER_OK)
        return rc;
    env_p->model = p->model; /* the environment reads no model's rows */
    if (mer_params_validate(p, NULL) != MER_OK || mer_params_validate(env_p, NULL) != MER_OK)
        return mer_error_set(err, MER_ERR_FORMAT, "params", "damaged parameters");
    return MER_OK;
}

static mer_result load_body(mer_scene *s, merp_bytes_in *in, const mer_params *env_p,
                            mer_error *err)
{
    merp_get(in, s->rng.s, sizeof s->rng.s);
    merp_get(in, &s->seed, sizeof s->seed);
    merp_perlin_init(&s->noise, s->seed);
    s->step = merp_get_u32(in);
    load_skeleton(&s->sk, in);
    uint32_t epoch = 0;
    mer_result rc = in->bad ? MER_OK : merp_env_init(&s->env, env_p, err);
    if (rc == MER_OK && !in->bad)
        rc = load_env(&s->env, in, &epoch, err);
    if (rc == MER_OK && !in->bad)
        rc = s->ops->load(in, s->sk.n, &s->model, err);
    if (rc == MER_OK && !in->bad && in->at != in->n)
        in->bad = 1;
    if (rc == MER_OK && in->bad)
        rc = in->bad == 2 ? mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a scene")
                          : mer_error_set(err, MER_ERR_FORMAT, NULL, "a damaged checkpoint");
    // A grid or model refusing what the bytes hold (a range, a count) is damage
    // to the caller, who may only tell it from running out of memory.
    if (rc != MER_OK && rc != MER_ERR_NOMEM && rc != MER_ERR_FORMAT) {
        mer_error why = {0};
        if (err != NULL)
            why = *err;
        rc = mer_error_set(err, MER_ERR_FORMAT, why.field, "a damaged checkpoint: %.200s", why.message);
    }
    if (rc != MER_OK)
        return rc;
    s->env.epoch = epoch;
    return MER_OK;
}

mer_result mer_scene_load(const uint8_t *bytes, size_t size, mer_scene **out, mer_error *err)
{
    assert(out != NULL && (bytes != NULL || size == 0));
    *out = NULL;
    mer_result rc = bytes != NULL ? check_header(bytes, size, err)
                                  : mer_error_set(err, MER_ERR_FORMAT, NULL, "no checkpoint");
    if (rc != MER_OK)
        return rc;
    merp_bytes_in in = {bytes + HEADER, size - HEADER, 0, 0};
    mer_params p, env_p;
    const merp_model_ops *ops = NULL;
    rc = load_params(&in, &p, &env_p, &ops, err);
    if (rc != MER_OK)
        return rc;
    mer_scene *s = merp_calloc(1, sizeof *s);
    if (s == NULL)
        return mer_error_set(err, MER_ERR_NOMEM, NULL, "out of memory for a scene");
    s->p = p;
    s->ops = ops;
    merp_skel_init(&s->sk, &s->p, merp_env_bud_changed, &s->env);
    rc = load_body(s, &in, &env_p, err);
    if (rc != MER_OK) {
        mer_scene_free(s);
        return rc;
    }
    *out = s;
    return MER_OK;
}
