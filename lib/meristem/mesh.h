/* meristem — tree geometry: the scene's skeleton as meshes an artist accepts.
 *
 * Bark. Each axis (a trunk, or a branch grown from a lateral bud, followed along
 * its main continuations) is ONE generalized cylinder: a ring of `sides` vertices
 * at the base of its first internode and at the end of every internode, joined
 * by quads. Rings are framed by parallel transport (the frame is carried from
 * ring to ring by the rotation between consecutive tangents), so tubes never
 * twist; a ring at a joint is tilted to the mean of the two internodes'
 * directions (a miter). Radii come from the pipe model (P09 §4.5): the ring below
 * internode i has its radius, the tip ring the last internode's. A lateral axis
 * starts at its node on the parent's centre line, i.e. inside the parent's tube,
 * so no gap or crack shows at a fork.
 *
 * Caps. A living tip's last internode is a cone from its lower ring to its end
 * point (but where an implicit junction's patch covers it, Junctions): a twig
 * tapers to its tip, and one apex vertex closes the tube (on a tree of many
 * short twigs this halves the vertex count against a ring and a cap). A cut surface (an axis whose continuation was pruned or shed) keeps its
 * ring and gets a flat disk with its own normals, and so does a trunk's base.
 *
 * Level of detail. `detail` 1..5 sets the sides of the thickest axis (4, 6, 8,
 * 12, 16); an axis gets 3 + round((max − 3)·d / d_max) sides from its base
 * diameter d, so thin twigs are triangular prisms and the trunk is round.
 *
 * UVs (bark). u = j / sides around the circumference, with a duplicated seam
 * vertex at u = 1; v = arc length / circumference, accumulated ring to ring with
 * the segment's mean circumference, so v grows monotonically along an axis and
 * a square tiling bark texture keeps its aspect with no seam between rings.
 *
 * Picking. Every vertex carries the id of the internode it belongs to
 * (`node_ids`, written to glTF as `_NODE_ID`). Ring i of an axis belongs to its
 * i-th internode (the apex, tip ring and cap to the last), and a bark triangle
 * joins one ring to the next, so of its three vertices the one with the SMALLEST
 * id names the internode the triangle covers: an internode is made before its
 * continuation, and ids are issued in order. The rule does not depend on the
 * order of a triangle's corners, so it survives an encoder that rotates them
 * (EXT_meshopt_compression's TRIANGLES mode); in this mesh every bark triangle
 * lists a vertex of its lower ring first, so the first vertex is that one too.
 * An internode of no length has no band: its two rings would lie one on the
 * other, so one ring serves both and belongs to the internode above (but for
 * twigs drawn with twig lines, whose lines run ring to ring); a branch of no
 * length at all has no tube.
 *
 * Leaves. At each living internode made in the last `leaf_age` seasons of
 * growth (counted back from the newest internode, so a tree that has stopped
 * extending still carries its last shoots' leaves), one leaf per lateral bud, pointing the way that bud points (the
 * phyllotaxis of P09 §4.3), as a rhombus card `leaf_size` long and half as wide,
 * turned to face up as far as its direction allows, with UVs of a unit square
 * (base at v = 0, tip at v = 1). Leaves are a separate primitive and material.
 * A model that sizes leaves per node (mer_node.leaf, the inverse model's G_l of
 * G04 §4.3 as grown so far by G_lg) gets instead one such card at each node
 * with a leaf, that long and along its first lateral bud, whatever its age.
 *
 * Twig lines (level of detail). With `twig_lines`, the twigs (axes meshed with
 * 3 sides whose base is at most 1/400 of the tree's largest extent thick, at
 * least 8 units counted) come after every other axis, in bark chunks of their
 * own (`twig` set), and each chunk also lists line segments over its vertices
 * (`line_indices`): one per internode, along the prism's first edge (ring to
 * ring, the last ring to the apex). A viewer looking at the tree from far
 * enough that a twig is under a pixel or so wide draws those lines instead of
 * the twig chunks: the same pixels for a third of the work, no new vertices,
 * and picking still hits the prisms. The fraction fixes how far that is: a
 * viewer that shows the whole tree across W pixels draws a twig at most
 * W / 400 pixels wide, so with the whole tree in view a twig is about a pixel
 * or less on any view up to about 400 px, and under two up to 800.
 * `twig_diameter_max` is the thickest twig's base diameter, for a viewer that
 * decides from its own projection instead. Without the option, axes are meshed
 * in id order and nothing is flagged.
 *
 * Junctions (G04 §3, issue 18). With `junctions` = MER_JUNCTIONS_IMPLICIT, a
 * fork whose parent internode is at least `junction_diameter` thick (0: a fifth
 * of the tree's thickest) and that has a lateral at least a quarter as thick is
 * an implicit surface instead of tubes that pierce each other: the junction's
 * field (summation blend, PCM and generalized bounded blending: the branch bark
 * ridge) is polygonized in a small grid sized to its radii, each shaft's tube
 * ends at an extra ring just outside the other primitives' supports, and the
 * patch is stitched to those rings, so bark is one closed surface there (a
 * tube ring that a cut's tilted ring reaches past along the axis, after an
 * out cut or before an in cut, is left out, the band running past it); a
 * shaft runs across as many short internodes as its cut needs while its axis
 * stays nearly straight, and the tube and the patch share each ring vertex's
 * normal and b; a continuation or lateral may be cut in a growing tip's last
 * internode, whose cone then runs from the cut ring to the apex, and one whose
 * axis ends before its cut would clear the fork (a bush's short axes) ends
 * inside the patch, closed by its field's round end, with no ring and no
 * tube: where laterals leave it on the way, the forks they leave are taken
 * into a run (below), however thin, each short axis ending inside it. The internodes of one axis
 * whose tips are one J (an L-system string that branches at one point more
 * often than an internode holds laterals leaves internodes of no length)
 * are one fork, whose patch takes the laterals of all of them, and so do
 * the laterals of a lateral of no length leaving that J (a guiding-vector
 * shoot's first hop): its fork is the parent's. A fork with
 * no living continuation (its parent ends in its terminal bud, dormant or
 * flowered, or in a cut: a sympodium's forks) is relayed: its thickest
 * lateral goes on from the parent as one solid with it, with the bud scale
 * scar where its shoot began, the other lateral blending in with its ridge,
 * and the parent's tip (a cone, or a disk) lies inside the patch. A fork
 * that does not fit as it grew and whose continuation is thinner than its
 * thickest lateral is relayed the same way, the continuation then one of
 * the patch's laterals (a sylleptic shoot's forks). Forks a few radii
 * apart, whose cuts would fall in each other's patches (a thick axis's
 * short internodes; a fork near the base of another fork's lateral), are
 * patched together as a run: one patch for up to 64 forks (more than
 * eight only on a grid of at most 600,000 cells), each axis through them
 * one solid (with each fork's bud scale scar), every fork's laterals
 * blending in with their ridges, and a lateral that a fork of the run goes
 * on up blending in with all of that fork's surface. A fork
 * whose axes bend too much there, whose cuts would fall in another fork's
 * patch that no run takes in (thickest laterals are served first; a run
 * of more than 64 forks, or whose grid would be too large) or past a
 * growing tip's apex,
 * whose cut ring would be under 0.4 of its grid's cell in radius even on
 * cells four times finer than the fork's own, or whose
 * laterals run nearly along their parent (a lateral within 11.5° of its
 * continuation or of a thicker lateral stays a tube from J instead, the
 * fork patched), stays tubes (`junctions_unfit`
 * counts those). A patch is
 * polygonized by dual contouring, which keeps the ridge's crease sharp, on
 * the fork's grid, else on it moved half a cell, on one 0.7 × as fine or on
 * one half as fine (a thin continuation's); where none closes, by marching
 * tetrahedra on the fork's grid or the one 0.7 × as fine
 * (`junctions_smooth` counts those); a fork whose patch closes on none
 * stays tubes (`junctions_open`). In this mode
 * every lateral that is not in a patch gets a base disk, and every disk's
 * centre (an end's, the trunk's base's too) lies a 32nd of its radius inside
 * its tube, so the whole bark is closed (a 2-manifold once
 * vertices of equal position are welded, unless the skeleton draws two
 * internodes over one another or end to end; the UV seams and disks keep
 * their own vertices). Each bark vertex then carries b = F_b(p), the bounding
 * field's value (0 on tubes, up to 1 on the ridge and on a fresh bud scale
 * scar: the larger of the laterals' F_b and the parent's scar's weighted
 * F_b), in `ridge` (glTF `_RIDGE`); with a colour mode the colour is darkened by it. Patch UVs
 * continue the bark's of the nearest shaft (u by angle in that shaft's ring
 * frame, v by arc length), with seam vertices of their own. The bark ages with
 * the fork's oldest lateral (at a relayed fork, not counting the relay but
 * where it has no other), in years (steps, 1 in the season it appears; G04
 * Fig. 7): the lateral's scar ring round its base moves into the crotch as its
 * bark ridge, and where the fork also ends one season's shoot, the parent's bud
 * scale scar there fades with the years of the parent's next shoot (weight
 * e^(−(y − 1)/3)).
 *
 * Colours. Optionally a COLOR_0 per vertex: by branch order (a fixed palette),
 * by light Q (the subtree's light at the last step, dark blue → yellow, scaled
 * by the largest Q), or by age (young green → old brown, scaled by the step).
 */
#ifndef MERISTEM_MESH_H
#define MERISTEM_MESH_H

#include <stddef.h>
#include <stdint.h>

#include <meristem/result.h>
#include <meristem/scene.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum mer_color_mode {
    MER_COLOR_NONE = 0,
    MER_COLOR_ORDER = 1,
    MER_COLOR_LIGHT = 2,
    MER_COLOR_AGE = 3
} mer_color_mode;

/* All-zero means defaults. */
typedef enum mer_junction_mode {
    MER_JUNCTIONS_TUBES = 0,   /* forks as tubes that pierce each other (default) */
    MER_JUNCTIONS_IMPLICIT = 1 /* forks of thick parents as implicit patches (Junctions) */
} mer_junction_mode;

typedef struct mer_mesh_options {
    uint32_t detail;   /* 1..5; 0: MER_MESH_DETAIL_DEFAULT */
    uint32_t leaves;   /* 1: leaf cards; 0: none */
    uint32_t markers;  /* 1: the scene's markers as points; 0: none */
    uint32_t color;    /* mer_color_mode; 0: none */
    float leaf_size;   /* leaf length in world units; 0: 0.8 × l0 */
    uint32_t leaf_age; /* leaves on the last this many seasons of growth; 0: 3 */
    uint32_t no_uvs;   /* 1: no UVs (both parts' `uvs` NULL), for a viewer that draws
                          no texture, and rings without the seam vertex (a 3-sided
                          twig's ring is 3 vertices, not 4); 0: UVs as above */
    uint32_t twig_lines; /* 1: twig lines and twig chunks (see Twig lines) */
    uint32_t junctions;  /* mer_junction_mode; 0: tubes */
    float junction_diameter; /* implicit junctions where the parent is at least this
                                thick; 0: a fifth of the thickest internode */
    uint32_t threads;    /* implicit junction patches on up to this many threads
                            (started and joined within the call; the bytes do not
                            depend on it); 0 or 1: the caller's only, at most 64 */
} mer_mesh_options;

#define MER_MESH_DETAIL_MAX 5
#define MER_MESH_DETAIL_DEFAULT 3 /* what detail 0 means */

/* Parts are split into chunks of at most MER_MESH_CHUNK_VERTICES vertices, so
 * that indices fit in 16 bits (half the bytes of a big tree's indices); each
 * chunk becomes one glTF primitive. */
#define MER_MESH_CHUNK_VERTICES 65535u

typedef struct mer_mesh_chunk {
    uint32_t first_vertex, vertex_count; /* a run of the part's vertices */
    uint32_t first_index, index_count;   /* a run of the part's indices */
    uint32_t twig;                       /* 1: only twigs' prisms (see Twig lines) */
    uint32_t first_line_index, line_index_count; /* its run of line_indices */
} mer_mesh_chunk;

/* One part's arrays, owned by the mer_mesh. Arrays that an option did not ask
 * for are NULL. */
typedef struct mer_mesh_part {
    uint32_t vertex_count;
    uint32_t index_count;   /* triangles × 3 */
    uint32_t chunk_count;
    mer_mesh_chunk *chunks; /* in order; they tile the vertices and the indices */
    float *positions;       /* 3 per vertex */
    float *normals;         /* 3 per vertex, unit */
    float *uvs;             /* 2 per vertex */
    float *colors;          /* 4 per vertex (linear RGBA) when a colour mode is on */
    uint32_t *node_ids;     /* 1 per vertex */
    uint32_t *indices;      /* relative to their chunk's first vertex; counter-clockwise
                               seen from outside */
    uint32_t line_index_count; /* twig line segments × 2 (see Twig lines); 0 without */
    uint32_t *line_indices;    /* relative to their chunk's first vertex, like indices */
    float *ridge;              /* 1 per vertex with implicit junctions: b (Junctions) */
} mer_mesh_part;

typedef struct mer_mesh {
    mer_mesh_part bark;
    mer_mesh_part leaves;   /* vertex_count 0 unless options.leaves */
    float twig_diameter_max; /* the thickest twig's base diameter; 0: no twigs */
    uint32_t point_count;   /* markers, 0 unless options.markers */
    float *points;          /* 3 per marker */
    uint32_t axes;          /* generalized cylinders in `bark` */
    uint32_t internodes;    /* living internodes meshed */
    uint32_t junctions;     /* forks meshed as implicit patches (a run's
                               patch serves several, thin forks up a
                               short axis among them) */
    uint32_t *junction_forks; /* `junctions` node ids, ascending: the
                                 internodes whose tip is such a fork's J
                                 (a client's way to tell a patched fork
                                 from its neighbours); NULL without */
    uint32_t junctions_open; /* forks chosen for a patch that got none (it closed
                                on neither grid, or its grid would be too
                                large; Junctions): meshed as tubes */
    uint32_t junctions_smooth; /* of `junctions`, the forks whose patch is by
                                  marching tetrahedra: their ridge's crease
                                  is not sharp */
    uint32_t junctions_unfit; /* forks thick enough, with a lateral thick
                                 enough, that no patch fits (Junctions:
                                 axes that bend or still thicken past the
                                 cuts, cuts in
                                 another fork's patch, past a tip or in a
                                 ring under 0.4 cells even on a grid
                                 4 × as fine, a lateral along its
                                 parent or drawn as a twig): meshed as tubes */
} mer_mesh;

/* Meshes the living part of `scene` as the header describes. `options` may be
 * NULL (defaults). `*out` is the caller's, freed with mer_mesh_free(). The
 * result depends only on the scene and options (same input, same bytes).
 * Errors: MER_ERR_RANGE naming the option for a bad option, MER_ERR_LIMIT when a
 * part would pass 2^32 vertices, MER_ERR_NOMEM. Cost: O(internodes × sides)
 * time; memory about 40 bytes per bark vertex, every array sized exactly from
 * the axes before meshing and allocated once. */
mer_result mer_mesh_build(const mer_scene *scene, const mer_mesh_options *options,
                          mer_mesh **out, mer_error *err);

/* Frees `mesh` and its arrays. NULL is fine. */
void mer_mesh_free(mer_mesh *mesh);

#ifdef __cplusplus
}
#endif

#endif
