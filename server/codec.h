/* meristem — JSON views of library values, shared by meristemd and the CLI.
 * lib never sees JSON; this is where its structs become documents. */
#ifndef MERISTEM_CODEC_H
#define MERISTEM_CODEC_H

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>

#include <jansson.h>

#include <meristem/gltf.h>
#include <meristem/mesh.h>
#include <meristem/scene.h>

/* The scene summary as an object (new reference; NULL when out of memory):
 * step, plants, internodes, buds, flowers, markers, height, crown_width,
 * crown_base, crown_depth, bounds {min, max}, hash (hex digest of the scene). */
json_t *merd_json_summary(const mer_scene *scene);

/* A float as the shortest decimal that reads back as the same float, so 0.55f
 * prints as 0.55, not 0.550000011920929 (new reference). */
json_t *merd_json_float(float x);

/* A parameter value: integral values as integers (exact, e.g. marker_count),
 * others as merd_json_float (parameters are floats). */
json_t *merd_json_param(double v);

/* Every named parameter that bears on a scene of `p` (mer_params_field_used: its
 * model's and every model's, noise's while it is on), but those of the schedule,
 * by name (new reference). */
json_t *merd_json_params(const mer_params *p);

/* The apical-control schedule: apical_off by order (null: never),
 * eta_order_scale, lambda_keys and eta_keys as [step, value] (new reference). */
json_t *merd_json_schedule(const mer_schedule *s);

/* True for the named fields that belong to the schedule (apical_off.N, ...). */
bool merd_param_in_schedule(const char *name);

/* json_dumps flags for replies: compact, reals with 15 significant digits
 * (enough for every double that came from a float via merd_json_float). */
#define MERD_JSON_DUMP_FLAGS (JSON_COMPACT | JSON_REAL_PRECISION(15))

/* `j` as a reply body (caller frees): MERD_JSON_DUMP_FLAGS and a closing
 * newline, so a body printed by curl ends its line. NULL when out of memory. */
char *merd_json_body(const json_t *j);

/* Decodes standard base64 (RFC 4648 §4, padding optional, no whitespace)
 * into *out (caller frees). 0, or -1 for a character outside the alphabet or a
 * bad length. */
int merd_base64_decode(const char *in, uint8_t **out, size_t *size);

/* Parses a colour mode name ("none", "order", "light", "age"). -1 if unknown. */
int merd_color_mode_parse(const char *name);
/* "tubes" or "implicit" → mer_junction_mode; -1 for anything else. */
int merd_junctions_parse(const char *name);

/* Parses a snapshot compression name ("none", "meshopt") into a
 * mer_gltf_compression. -1 if unknown. */
int merd_compression_parse(const char *name);

#endif
