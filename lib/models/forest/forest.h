/* meristem — a sown forest (issue 17, the survey's §VII-B): plants placed by
 * Poisson-disk sampling, each of a preset of its own, each bounded by its
 * Voronoi cell. Private to lib (merp_forest_ names).
 *
 * A scene holds one model and one parameter set, so the forest is a composite
 * model: its state holds member scenes, each grown by its own preset's model
 * and parameters.
 *  - P09 and Runions 2007 plants of one preset share one member scene, planted
 *    where they were sown: same-species neighbours share light (the shadow grid)
 *    and markers, so crown shyness emerges as P09 §4.1 describes.
 *  - A plant of any other model (L-systems, guiding vectors, the inverse model:
 *    each grows one tree at the origin) is a member of its own, grown at the
 *    origin and moved to its place when mirrored.
 * Members of different presets do not see each other (no shared light).
 *
 * The members' skeletons are mirrored into the forest scene's skeleton after
 * every step and edit (mirror.c): member node i is forest node outer[i] of that
 * member, created the first time member i exists; a member whose skeleton
 * shrank (an L-system renumbers its drawing every step) leaves the forest nodes
 * past its end dead, to be brought back when it grows again. So the mesher,
 * the snapshot, the summary, node ids and the skeleton export read the forest
 * scene as any other; a prune or bend of a forest node is made on its member
 * (forest.c) and mirrored back.
 *
 * Markers: each plant's marker volume is its preset's, centred over the plant,
 * clipped to the plant's Voronoi cell (mer_voronoi_clip), so no two plants'
 * markers overlap. The definition (the sow text, sow_text.c) is what the
 * journal replays and the checkpoint keeps. */
#ifndef MERISTEM_MODELS_FOREST_H
#define MERISTEM_MODELS_FOREST_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include "models/model.h"

#define MERP_FOREST_PRESETS_MAX 16u
#define MERP_FOREST_NAME_MAX 64u

/* A sow request, as its definition text holds it. */
typedef struct merp_sow {
    float lo[2], hi[2]; /* area: x then z */
    uint32_t count;
    float r;            /* min_distance */
    uint64_t seed;
    uint32_t npresets;
    char presets[MERP_FOREST_PRESETS_MAX][MERP_FOREST_NAME_MAX];
} merp_sow;

typedef struct merp_forest_member {
    mer_scene *scene;
    float offset[3];   /* added to its nodes' bases in the forest */
    uint32_t preset;   /* index into the sow's presets */
    uint32_t *outer;   /* member node id -> forest node id, `mapped` of them */
    uint32_t mapped, cap;
    uint32_t *plant;   /* member plant -> forest plant, `nplants` of them */
    uint32_t nplants, cap_plants;
} merp_forest_member;

struct merp_model {
    char *text; /* the definition, NUL-terminated; NULL before it is given */
    size_t len;
    merp_sow sow;
    uint32_t nsites;
    float *sites;   /* (x, z) of every plant, in the order they were sown */
    uint32_t nmembers;
    merp_forest_member *m;
    /* forest node id -> its member and member node (MER_NO_NODE: none), for
     * the `nout` forest nodes the mirror made */
    uint32_t *mem, *mid;
    uint32_t nout, cap_out;
};

/* sow_text.c: parses a definition text into *out: lines `area x0 z0 x1 z1`,
 * `count N`, `min_distance r`, `seed s`, `presets NAME...` ('#' starts a comment).
 * MER_ERR_INVALID with the line and column of the fault. O(len). */
mer_result merp_sow_parse(const char *text, size_t len, merp_sow *out, mer_error *err);
/* The canonical text of `sow` into buf (NUL-terminated); its length, or the
 * length it would need when cap is too small (as snprintf). */
size_t merp_sow_format(const merp_sow *sow, char *buf, size_t cap);

/* sow.c: places the plants of f->sow and makes the member scenes.
 * MER_ERR_LIMIT naming how many plants fit; MER_ERR_INVALID for an unknown
 * preset or one that does not grow over the area; MER_ERR_NOMEM. */
mer_result merp_forest_sow(merp_model *f, mer_error *err);

/* mirror.c: copies every member's skeleton into `sk` (the forest scene's),
 * new forest nodes born at `step`. MER_ERR_NOMEM, MER_ERR_LIMIT. O(nodes). */
mer_result merp_forest_mirror(merp_model *f, merp_skeleton *sk, uint32_t step, mer_error *err);
/* The member and member node of forest node `id`: 0 and *member, *node set, or
 * -1 when no member node is mirrored there now. O(1). */
int merp_forest_member_of(const merp_model *f, uint32_t id, uint32_t *member, uint32_t *node);
/* Sets the forest's d^n of every mirrored node from its member's diameter. */
void merp_forest_diameters(const merp_model *f, merp_skeleton *sk);
/* Frees the members' maps and scenes. */
void merp_forest_members_free(merp_model *f);

/* forest.c: an empty state (no definition yet); and its release. */
mer_result merp_forest_create_empty(merp_model **out, mer_error *err);
void merp_forest_free(merp_model *f);

/* forest_io.c: save, load and clone of the state. */
void merp_forest_save(const merp_model *f, merp_bytes_out *out);
mer_result merp_forest_load(merp_bytes_in *in, uint32_t nodes, merp_model **out, mer_error *err);
mer_result merp_forest_clone(const merp_model *f, merp_model **out, mer_error *err);

#endif
