/* meristem — a scene: plants growing in one shared environment (P09 §3, §4, §6).
 *
 * A scene holds one or more plants (trees of metamers), the environment they share
 * (marker set for space colonization, shadow grid for shadow propagation, box,
 * sphere and triangle-mesh obstacles, the ground plane), the parameters and developmental schedule,
 * and one deterministic random generator. Same parameters, seed and sequence of
 * calls give bit-identical scenes (mer_scene_hash).
 *
 * Threads: a scene must not be used from two threads at once (the server holds a
 * lock per session); distinct scenes share nothing, and the library has no global
 * mutable state (but the allocator hook of meristem/alloc.h, set before use), so
 * they may step in parallel.
 *
 * Structure. A node is a metamer: an internode from `base` along `dir` for
 * `length`, with a leaf and one or two lateral buds (buds_per_node) at its top
 * end. The node whose main child is absent carries its axis's terminal bud, also at
 * its top end. Node ids are indices in creation order: they are stable and never
 * reused in a scene (pruned and shed nodes become tombstones, alive = 0). A
 * parent's id is always lower than its children's.
 *
 * Axis order: a plant's trunk is order 0; the shoot from a lateral bud on an axis of
 * order n is order n + 1 (P09 §3).
 *
 * Buds have a state: DORMANT buds are alive and compete; a bud that grows a shoot
 * becomes that shoot (state NONE); FLOWER and ABORTED buds never grow.
 *
 * One step (P09 Fig. 3 right): environment (Q, V per dormant bud) → basipetal
 * light → shedding → acropetal resource (BH or priority) → new shoots → in
 * sylleptic mode, a second round for the lateral buds made in this step → pipe-model
 * diameters. Choices where the paper is open, each tested:
 *  - Proleptic (default): a bud formed in step m first competes in step m + 1.
 *    Sylleptic: after the shoots of a step are made, the environment and resource
 *    passes run once more in which only the lateral buds formed in that step may
 *    grow (their shoots count as the same season).
 *  - Sympodial: a terminal bud that has grown its shoot ends it with a flower (or
 *    aborts with sympodial_abort); growth passes to lateral buds.
 *  - All n metamers of a shoot use the bud's V of that step; each new metamer's
 *    direction is normalize(previous + ξV + ηT), the first one's "previous" being
 *    the bud direction (P09 §4.3).
 *  - A lateral bud points at branch_angle from its internode, towards the node's
 *    phyllotactic side vector; each metamer's side vector is its predecessor's,
 *    carried onto the new internode's normal plane and turned by the divergence
 *    angle. With two buds per node the second points the opposite way.
 *  - A new metamer whose end would lie below the ground or inside an obstacle is not
 *    made; the shoot stops there and its bud stays dormant.
 *  - Shedding (P09 §4.4) looks at each lateral branch: if its light (the sum of its
 *    buds' Q) divided by its internode count is below shed_threshold, the branch is
 *    removed; the bud it came from does not regrow (state NONE). Shedding pauses
 *    while growth is constrained to a bud (edit.h), as the other buds' Q is then
 *    held at 0.
 *  - The priority model's light per bud divides a branch's Q by its number of
 *    living (dormant) buds, lit or not.
 *  - Pipe model (P09 §4.5): an axis tip internode has the leaf diameter; going
 *    down, d^n = d_main^n + Σ d_lat^n, and no internode ever gets thinner
 *    (memory of shed and pruned branches).
 *  - Shadow: dormant buds cast shadow; flowers, aborted buds and grown-out buds do
 *    not. Obstacles shade their own voxels fully and cast a bud's pyramid from every
 *    voxel of their top surface.
 */
#ifndef MERISTEM_SCENE_H
#define MERISTEM_SCENE_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/params.h>
#include <meristem/result.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct mer_scene mer_scene;

#define MER_NO_NODE UINT32_MAX

typedef enum mer_bud_state {
    MER_BUD_NONE = 0,    /* no bud: it grew into a shoot, or was cut */
    MER_BUD_DORMANT = 1, /* alive; grows when it receives resource */
    MER_BUD_FLOWER = 2,
    MER_BUD_ABORTED = 3
} mer_bud_state;

/* Limits, in one place. */
#define MER_NODES_MAX (UINT32_C(50) * 1000 * 1000)
#define MER_PLANTS_MAX 10000u
#define MER_OBSTACLES_MAX 1000u
#define MER_MESH_TRIANGLES_MAX 1000000u  /* triangles in one mesh obstacle or volume */
#define MER_MESH_COORD_MAX 1e6f          /* |coordinate| of a mesh vertex */
#define MER_MESH_FILL_MAX 20000000u      /* markers one mer_scene_fill_mesh_markers makes */
#define MER_MESH_FILL_TRIES 64u          /* draws allowed per marker, on average... */
#define MER_MESH_FILL_TRIES_MIN 4096u    /* ...plus these, per call */

/* Creates a scene from `params` (NULL or all-zero: defaults) and `seed`, running
 * the growth model params->model names (P09 by default): validates
 * the parameters, builds the grids, places params->seedlings seedlings along x
 * (centred on the origin, on the ground) and, under space colonization, fills the
 * initial marker volume. `*out` is owned by the caller (mer_scene_free). Cost
 * O(voxels + markers). Errors: those of mer_params_validate, MER_ERR_NOMEM. */
mer_result mer_scene_new(const mer_params *params, uint64_t seed, mer_scene **out,
                         mer_error *err);

/* Frees `s` and everything it owns (NULL is fine). */
void mer_scene_free(mer_scene *s);

/* A deep copy of `s` into `*out` (owned by the caller): it hashes, meshes and
 * grows on exactly as `s` does, and shares nothing with it, so a caller can keep
 * one to undo a sequence of calls. Errors (nothing made): MER_ERR_NOMEM,
 * MER_ERR_INVALID for a growth model that cannot be copied. Cost O(nodes + markers +
 * shadow voxels + mesh obstacles' triangles and cells), far below regrowing. */
mer_result mer_scene_clone(const mer_scene *s, mer_scene **out, mer_error *err);

/* A checkpoint: the whole of `s` as versioned bytes (a magic, a version, the
 * byte order, the length and a digest, then the state) in `*bytes` (`*size`
 * of them; the caller frees them with the free function of meristem/alloc.h,
 * free() unless mer_set_alloc_funcs changed it). mer_scene_load of them gives a
 * scene that hashes, meshes and grows on exactly as `s`. Errors (nothing
 * made): MER_ERR_NOMEM, MER_ERR_INVALID for a growth model that cannot be
 * saved. Cost O(nodes + markers + voxels + mesh obstacles' triangles). */
mer_result mer_scene_save(const mer_scene *s, uint8_t **bytes, size_t *size, mer_error *err);

/* The scene of a checkpoint mer_scene_save wrote, in `*out` (owned by the
 * caller). Everything is checked before it is used: MER_ERR_FORMAT for bytes
 * that are not a checkpoint of this version and byte order, cut short, damaged
 * (the digest) or inconsistent (links, counts, parameters), that name a
 * parameter or model this build does not know, or hold a model's state of
 * another version; MER_ERR_NOMEM. Parameters are stored by name: one that a
 * checkpoint of an older build lacks takes its default.
 * Cost O(size + voxels). */
mer_result mer_scene_load(const uint8_t *bytes, size_t size, mer_scene **out, mer_error *err);

/* The scene's resolved parameters (borrowed; valid until the next set_params). */
const mer_params *mer_scene_params(const mer_scene *s);

/* Replaces the parameters (and with them the schedule) between steps. Grids are
 * rebuilt when their geometry changes; the tree is kept. A ground raised (or
 * turned on) removes the markers now below it. A scene keeps its growth model:
 * parameters naming another are refused (MER_ERR_INVALID, "model"). On error
 * nothing changes.
 * Cost O(voxels + buds·q_max² + markers) when grids are rebuilt, else O(1). */
mer_result mer_scene_set_params(mer_scene *s, const mer_params *params, mer_error *err);

/* Gives the scene's growth model its definition: a text the model reads, `len`
 * bytes (need not be NUL-terminated). An L-system scene (MER_MODEL_LSYSTEM)
 * takes its cpfg source this way: the first definition sets the axiom as its
 * string and draws it; a later one replaces the productions and keeps the
 * current string (ABOP's derivation goes on under the new rules). Errors
 * (nothing changes): MER_ERR_INVALID "definition" for a model that takes no
 * definition, or a text that does not parse (err->line and err->column give
 * the 1-based position), MER_ERR_NOMEM. Cost O(len + the string). */
mer_result mer_scene_set_definition(mer_scene *s, const char *text, size_t len,
                                    mer_error *err);

/* The definition the scene's model holds (borrowed, NUL-terminated, valid until
 * the next mer_scene_set_definition), its length in `*len` (may be NULL); NULL
 * when there is none. O(1). */
const char *mer_scene_definition(const mer_scene *s, size_t *len);

/* Something a definition gets away with: where (1-based line and column of the
 * text) and what. */
typedef struct mer_warning {
    unsigned line, column;
    char message[MER_ERROR_MESSAGE_MAX]; /* one sentence, no trailing newline */
} mer_warning;

/* The warnings about the definition the scene's model holds (an L-system's
 * unbalanced brackets, which cpfg tolerates and so does meristem): up to `cap`
 * into `out` (may be NULL when cap is 0); returns how many there are (0 when
 * none, or for a model without a definition). O(warnings). */
size_t mer_scene_definition_warnings(const mer_scene *s, mer_warning *out, size_t cap);

/* A named number about the model's own state. */
typedef struct mer_model_stat {
    char name[24];  /* "derivation_step", "string_length", "modules.F", ... */
    double value;
} mer_model_stat;

/* Up to `cap` of the model's numbers into `out` (may be NULL when cap is 0);
 * returns how many it has (0 for P09). An L-system gives derivation_step,
 * derivation_length (0: none set), string_length, segments (the internodes its
 * turtle drew at the last drawing, joints not counted), and modules.X, the count of
 * module X, for each module in the string in symbol order. O(string). */
size_t mer_scene_model_stats(const mer_scene *s, mer_model_stat *out, size_t cap);

/* Shows the tree of a model that grows continuously (the inverse model) at time
 * t, in steps (years), fractional allowed: the tree is rebuilt as it stands at
 * t; the step count stays and the next step grows its whole step. Meant for a
 * clone that is meshed and dropped. MER_ERR_INVALID (field "t") for a model that
 * grows in whole steps only (P09, L-systems), MER_ERR_RANGE (field "t") for t
 * outside the model's time; as a step otherwise. O(nodes). */
mer_result mer_scene_show_time(mer_scene *s, double t, mer_error *err);

/* Replaces only the developmental schedule (apical control per order, λ and η
 * keyframes, η per order), between steps; the rest of the parameters stay.
 * `schedule` not NULL. Validated as by mer_params_validate (fields are named
 * "schedule.lambda_keys", "schedule.eta_keys", ...); on error nothing changes.
 * O(1). */
mer_result mer_scene_set_schedule(mer_scene *s, const mer_schedule *schedule, mer_error *err);

/* Adds a seedling (one internode of length l0 pointing up, with its terminal bud
 * and lateral buds, turned about the vertical by an angle drawn from the scene's
 * generator) whose base is at `base`. Its root id goes to `*root` (may be
 * NULL). MER_ERR_RANGE if the base is below the ground or inside an obstacle;
 * MER_ERR_LIMIT past MER_PLANTS_MAX. O(q_max²). */
mer_result mer_scene_add_plant(mer_scene *s, const float base[3], uint32_t *root,
                               mer_error *err);

/* Number of plants ever added (a plant whose root was pruned stays counted). */
uint32_t mer_scene_plant_count(const mer_scene *s);

/* Obstacles (P09 §4.4 Fig. 11, §6): an axis-aligned box [min, max] or a sphere.
 * They remove the markers inside them, shade (see above) and block shoots.
 * MER_ERR_INVALID for a coordinate that is not finite (nothing added);
 * MER_ERR_RANGE for an empty box or a radius not finite and > 0; MER_ERR_LIMIT past
 * MER_OBSTACLES_MAX. O(markers + voxels covered·q_max²). */
mer_result mer_scene_add_box(mer_scene *s, const float min[3], const float max[3],
                             mer_error *err);
mer_result mer_scene_add_sphere(mer_scene *s, const float center[3], float radius,
                                mer_error *err);

/* Triangle meshes (a glTF/GLB via mer_gltf_read_triangles, or built by hand):
 * `xyz` holds `triangles` triangles, 9 floats each (three world-space vertices),
 * caller-owned and copied. The mesh's inside is solid:
 *
 *   a point is inside when it lies in the mesh's bounding box and at least two of
 *   the three axis rays from it (+x, +y, +z) cross the triangles an odd number of
 *   times.
 *
 * For a closed mesh that is exactly its interior, whatever the winding (flipped
 * or mixed windings give the same solid). A slightly open mesh (a missing
 * triangle, a crack) still works: a hole misleads only the rays through it, and
 * the majority vote outweighs one misled axis. Rays through shared edges and
 * vertices count once (a consistent tie rule), rays grazing a face count none.
 * Points exactly on the surface may fall either way.
 *
 * Cost: the inside is voxelized once when the mesh is given, into a cache grid of
 * its own (up to 128 cells along its longest side, independent of the scene's
 * grids), so a point query is O(1) away from the surface and O(the triangles in a
 * few cells) near it. For a closed mesh the cache changes no answer; for an open
 * one, rays are judged from cell centres (lib/env/solid.c says how), a close
 * approximation. Building costs O(triangles + cells + triangle-cell pairs), the
 * pairs bounded (the cache coarsens for huge triangles): about 0.4 s for a
 * million triangles. Memory: 36 bytes per triangle, a byte per cell, 4 bytes per
 * triangle-cell pair.
 *
 * Errors (nothing changes): MER_ERR_INVALID "triangles" when there is none (or
 * `xyz` is NULL), MER_ERR_LIMIT "triangles" past MER_MESH_TRIANGLES_MAX,
 * MER_ERR_INVALID "xyz" for a coordinate that is not finite, MER_ERR_RANGE "xyz"
 * for one past ±MER_MESH_COORD_MAX or a mesh that is flat along an axis,
 * MER_ERR_RANGE "xyz" for a mesh too coarse for the scene (its cache cells
 * thousands of voxels wide where the scene asks: a mesh in raw quantized units,
 * say), whose inside tests would cost more than a fixed bound of triangle tests,
 * MER_ERR_NOMEM. mer_scene_set_params refuses (MER_ERR_RANGE "voxel") finer
 * grids that would take a mesh obstacle past that bound. */

/* Adds a mesh obstacle: like a box or sphere it removes the markers inside it,
 * shades (its voxels fully, and a pyramid from each voxel of its top surface) and
 * blocks shoots. MER_ERR_LIMIT "obstacles" past MER_OBSTACLES_MAX; the other
 * errors as above. It counts in mer_scene_hash (by a digest of its triangles).
 * O(build + markers + voxels in its box · q_max²). */
mer_result mer_scene_add_mesh(mer_scene *s, const float *xyz, size_t triangles, mer_error *err);

/* Adds `count` markers uniformly distributed inside the mesh (a marker volume),
 * drawn from the scene's generator: deterministic. Rejection sampling: a cache
 * cell that may hold inside points is drawn uniformly, then a point uniform in
 * it, kept if inside. At most count·MER_MESH_FILL_TRIES + MER_MESH_FILL_TRIES_MIN
 * draws; past that (a mesh with almost no inside, e.g. an open sheet)
 * MER_ERR_RANGE "xyz", no marker is added and the generator is left as it was.
 * As with mer_scene_add_markers, markers inside obstacles (this mesh too, if it
 * was added as one) or below the ground are dropped. MER_ERR_LIMIT "count" past
 * MER_MESH_FILL_MAX; the other errors as above. O(build + count). */
mer_result mer_scene_fill_mesh_markers(mer_scene *s, const float *xyz, size_t triangles,
                                       uint32_t count, mer_error *err);

/* Adds `count` markers (xyz triples, caller-owned) to the set S. Markers inside
 * obstacles or below the ground are dropped. MER_ERR_INVALID "points" if any
 * coordinate is not finite (NaN or ±inf), and then none is added. O(count). */
mer_result mer_scene_add_markers(mer_scene *s, const float *xyz, size_t count, mer_error *err);

/* Adds `count` markers uniformly distributed in a volume (params.h
 * mer_volume_kind; `size` as documented there), drawn from the scene's generator.
 * MER_ERR_RANGE for a bad kind or size. O(count). */
mer_result mer_scene_fill_markers(mer_scene *s, uint32_t kind, const float center[3],
                                  const float size[3], uint32_t count, mer_error *err);

/* Live markers, and a copy of their positions (see mer_markers_positions). */
size_t mer_scene_marker_count(const mer_scene *s);
size_t mer_scene_markers(const mer_scene *s, float *out, size_t cap);

/* Called after each step with the number of steps done and asked for. */
typedef void (*mer_progress_fn)(void *ctx, uint32_t done, uint32_t total);

/* Runs `count` steps. `progress` (may be NULL) is called after each step. `cancel`
 * (may be NULL) is read before each step; when it is non-zero the run stops there,
 * leaving whole steps only. `*done` (may be NULL) gets the steps completed.
 * Returns MER_OK when stopped by `cancel` too (compare *done with count);
 * MER_ERR_LIMIT if the tree would pass MER_NODES_MAX (the steps before stay);
 * MER_ERR_NOMEM (the scene stays consistent; the failing step may be partial).
 * Cost per step O(nodes + buds · environment query). */
mer_result mer_scene_step(mer_scene *s, uint32_t count, mer_progress_fn progress, void *ctx,
                          const volatile int *cancel, uint32_t *done, mer_error *err);

/* Steps completed so far. */
uint32_t mer_scene_step_index(const mer_scene *s);

/* Why a step grew nothing (mer_step_report.stall), most telling first: a user
 * can lift a constraint, but not bring dead buds back. */
typedef enum mer_stall {
    MER_STALL_NONE = 0,         /* it grew, or no step has run */
    MER_STALL_CONSTRAINED = 1,  /* growth is constrained to a bud (mer_scene_constrain)
                                   and nothing at or above it grew */
    MER_STALL_ALL_BUDS_DEAD = 2, /* no dormant bud is left on any plant */
    MER_STALL_NO_MARKERS = 3,   /* space colonization: no bud had a free marker in reach */
    MER_STALL_NO_LIGHT = 4,     /* shadow propagation: no bud got light enough for an internode */
    MER_STALL_DONE = 5          /* the model has grown all it will: its iterations (guiding)
                                   or derivation length (L-system) are used up */
} mer_stall;

/* What the scene's last step did. */
typedef struct mer_step_report {
    uint32_t step;  /* mer_scene_step_index after that step; 0: no step has run */
    uint32_t grown; /* internodes it made (shed ones not subtracted) */
    uint32_t stall; /* mer_stall: why `grown` is 0; MER_STALL_NONE when it is not */
    uint32_t node;  /* the constrained node for MER_STALL_CONSTRAINED, else MER_NO_NODE */
} mer_step_report;

/* Fills `*out` (not NULL) with the report of the last completed step of this
 * scene (or of the scene it was cloned from). The report is not part of the
 * scene's state: not hashed, not in a checkpoint (a loaded scene has none). O(1). */
void mer_scene_step_report(const mer_scene *s, mer_step_report *out);

/* "constrained", "all-buds-dead", "no-markers", "no-light", "done"; NULL for
 * MER_STALL_NONE or an unknown value. */
const char *mer_stall_name(uint32_t stall);

typedef struct mer_summary {
    uint32_t step;
    uint32_t plants;
    uint32_t internodes;   /* alive */
    uint32_t buds;         /* dormant buds */
    uint32_t flowers;
    uint32_t markers;      /* live markers */
    uint32_t node_bound;   /* ids ever issued */
    float height;          /* highest internode end above the lowest plant base */
    float crown_width;     /* larger horizontal extent (x or z) of the internodes */
    float crown_base;      /* lowest base of a living lateral branch, above the lowest plant base (height if none) */
    float crown_depth;     /* height − crown_base */
    float bbox_min[3];     /* of all live internodes (zeros when none) */
    float bbox_max[3];
} mer_summary;

/* Fills `*out` (not NULL). O(nodes). */
void mer_scene_summary(const mer_scene *s, mer_summary *out);

/* Read-only view of one node (metamer). */
typedef struct mer_node {
    uint32_t id;
    uint32_t parent;       /* MER_NO_NODE for a plant's root */
    uint32_t plant;        /* index in creation order */
    uint32_t order;        /* axis order, trunk 0 */
    uint32_t alive;        /* 0: pruned or shed */
    uint32_t born;         /* step in which it was made */
    uint32_t main_child;   /* MER_NO_NODE if none */
    uint32_t lateral_child[2];
    uint32_t terminal_bud; /* mer_bud_state */
    uint32_t lateral_bud[2];
    float base[3];
    float dir[3];          /* unit */
    float bud_dir[2][3];   /* unit directions of the lateral buds (phyllotaxis, branch angle) */
    float length;
    float diameter;
    float q;               /* light collected by the buds of the subtree at the last step (BH Q) */
    /* Its leaf, when its model sizes leaves per node (the inverse model's G_l,
     * G04 §4.3): > 0 one leaf this long; < 0 none; 0 the model leaves it to the
     * mesher (mer_mesh_options' leaf_size and leaf_age). */
    float leaf;
} mer_node;

/* One past the highest node id issued. */
uint32_t mer_scene_node_bound(const mer_scene *s);

/* Fills `*out` for node `id`; dead nodes are reported with alive = 0.
 * MER_ERR_RANGE (field "node") if id >= mer_scene_node_bound. O(1). */
mer_result mer_scene_node(const mer_scene *s, uint32_t id, mer_node *out, mer_error *err);

/* A 64-bit FNV-1a hash of the step, every node's data, bud states, obstacles and markers:
 * equal hashes for equal scenes, for determinism checks. O(nodes + markers). */
uint64_t mer_scene_hash(const mer_scene *s);

#ifdef __cplusplus
}
#endif

#endif
