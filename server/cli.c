/* meristem — the offline command line: grow a tree from a preset, print its
 * summary as JSON, and write the snapshot as GLB (or .gltf for debugging).
 *
 *   meristem grow [--model NAME] [--preset NAME] [--steps N] [--seed S] [--set key=value]...
 *                 [-o FILE.glb|FILE.gltf] [--detail 1..5] [--leaves] [--markers]
 *                 [--color none|order|light|age]
 *   meristem presets
 */
#include "config.h"

#include <errno.h>
#include <getopt.h>
#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <meristem.h>

#include "server/codec.h"
#include "server/export.h"

#define SETS_MAX 256

typedef struct grow_args {
    const char *model; /* NULL: the preset's (P09) */
    const char *preset;
    uint32_t steps;
    uint64_t seed;
    const char *sets[SETS_MAX];
    size_t set_count;
    const char *output;
    mer_mesh_options mesh;
    uint32_t quantized;
    uint32_t compression;
} grow_args;

static void usage(FILE *out)
{
    fprintf(out,
            "Usage: meristem grow [OPTION]...   grow a tree, print its summary as JSON\n"
            "       meristem presets            list the presets\n\n"
            "  --model=NAME       growth model (default p09)\n"
            "  --preset=NAME      parameter set (default \"default\"; see `meristem presets`)\n"
            "  --steps=N          simulation steps (default 20)\n"
            "  --seed=S           random seed, 0..2^64-1 (default 0)\n"
            "  --set=KEY=VALUE    override one parameter, e.g. --set lambda=0.52 (repeatable)\n"
            "  -o, --output=FILE  write the snapshot: FILE.glb binary, FILE.gltf embedded JSON\n"
            "  --detail=1..5      bark level of detail (default %d)\n"
            "  --leaves           add leaf cards\n"
            "  --markers          add the marker points\n"
            "  --color=MODE       vertex colours: none, order, light or age (default none)\n"
            "  --quantize         quantized positions and normals (KHR_mesh_quantization;\n"
            "                     three.js reads it, assimp does not); default float\n"
            "  --unquantized      float positions and normals (the default)\n"
            "  --no-texcoords     leave out the UVs (for viewers that draw no texture)\n"
            "  --compress=MODE    none or meshopt (EXT_meshopt_compression; .glb only;\n"
            "                     three.js reads it, Blender does not)\n"
            "  --twig-lines       twigs in primitives of their own, each with a LINES\n"
            "                     primitive of their lines (a viewer's level of detail)\n"
            "  --junctions=MODE   tubes (default) or implicit: forks of thick branches as\n"
            "                     implicit surfaces with a branch bark ridge (G04 §3)\n"
            "  --help, --version\n",
            MER_MESH_DETAIL_DEFAULT);
}

static int parse_u64(const char *text, uint64_t max, uint64_t *out)
{
    char *end = NULL;
    errno = 0;
    if (text[0] == '-')
        return -1;
    unsigned long long v = strtoull(text, &end, 10);
    if (errno != 0 || end == text || *end != '\0' || v > max)
        return -1;
    *out = v;
    return 0;
}

static int fail(const char *what, const mer_error *err)
{
    fprintf(stderr, "meristem: %s: %s%s%s\n", what, err->field[0] ? err->field : "",
            err->field[0] ? ": " : "", err->message);
    return 1;
}

static int write_file(const char *path, const uint8_t *bytes, size_t size)
{
    FILE *f = fopen(path, "wb");
    if (f == NULL || fwrite(bytes, 1, size, f) != size || fclose(f) != 0) {
        fprintf(stderr, "meristem: cannot write %s: %s\n", path, strerror(errno));
        return 1;
    }
    return 0;
}

static int apply_sets(mer_params *p, const grow_args *a)
{
    for (size_t i = 0; i < a->set_count; i++) {
        char key[128];
        const char *eq = strchr(a->sets[i], '=');
        size_t len = eq != NULL ? (size_t)(eq - a->sets[i]) : 0;
        if (eq == NULL || len == 0 || len >= sizeof key) {
            fprintf(stderr, "meristem: --set wants KEY=VALUE, got '%s'\n", a->sets[i]);
            return 1;
        }
        memcpy(key, a->sets[i], len);
        key[len] = '\0';
        char *end = NULL;
        double value = strtod(eq + 1, &end);
        if (end == eq + 1 || *end != '\0') {
            fprintf(stderr, "meristem: --set %s wants a number, got '%s'\n", key, eq + 1);
            return 1;
        }
        mer_error err;
        if (mer_params_set(p, key, value, &err) != MER_OK)
            return fail("--set", &err);
    }
    return 0;
}

static int grow(const grow_args *a)
{
    mer_error err;
    mer_params params;
    if (mer_preset_params(a->preset, &params, &err) != MER_OK)
        return fail("--preset", &err);
    if (a->model != NULL && mer_model_parse(a->model, &params.model, &err) != MER_OK)
        return fail("--model", &err);
    if (apply_sets(&params, a) != 0)
        return 1;
    mer_scene *scene = NULL;
    if (mer_scene_new(&params, a->seed, &scene, &err) != MER_OK)
        return fail("cannot create the scene", &err);
    int status = 0;
    // An L-system or inverse-model preset starts from its definition.
    const char *source = mer_preset_definition(a->preset);
    if (source != NULL && (params.model == MER_MODEL_LSYSTEM || params.model == MER_MODEL_INVERSE) &&
        mer_scene_set_definition(scene, source, strlen(source), &err) != MER_OK) {
        status = fail("--preset", &err);
        goto done;
    }
    if (mer_scene_step(scene, a->steps, NULL, NULL, NULL, NULL, &err) != MER_OK) {
        status = fail("growth stopped", &err);
        goto done;
    }
    json_t *summary = merd_json_summary(scene);
    json_object_set_new(summary, "preset", json_string(a->preset));
    json_object_set_new(summary, "seed", json_integer((json_int_t)a->seed));

    if (a->output != NULL) {
        size_t n = strlen(a->output);
        mer_gltf_options gopt = {
            .format = n >= 5 && strcmp(a->output + n - 5, ".gltf") == 0 ? MER_GLTF_EMBEDDED
                                                                        : MER_GLTF_BINARY,
            .unquantized = !a->quantized,
            .compression = a->compression};
        merd_origin origin = {.preset = a->preset, .seed = a->seed};
        uint8_t *bytes = NULL;
        size_t size = 0;
        merd_export_counts counts = {0};
        mer_result rc = merd_export_tree(scene, &a->mesh, &gopt, &origin, &bytes, &size,
                                         &counts, &err);
        if (rc != MER_OK) {
            json_decref(summary);
            // Triangles are counted once the tree is meshed (a tree has at least one).
            status = fail(counts.triangles ? "cannot encode glTF" : "cannot mesh the tree", &err);
            goto done;
        }
        json_object_set_new(summary, "triangles", json_integer((json_int_t)counts.triangles));
        if (a->mesh.junctions == MER_JUNCTIONS_IMPLICIT)
            json_object_set_new(summary, "junctions",
                                json_pack("{s:I, s:I, s:I, s:I}", "patches", (json_int_t)counts.junctions,
                                          "smooth", (json_int_t)counts.junctions_smooth, "open",
                                          (json_int_t)counts.junctions_open, "unfit",
                                          (json_int_t)counts.junctions_unfit));
        status = write_file(a->output, bytes, size);
        mer_gltf_free(bytes);
        json_object_set_new(summary, "bytes", json_integer((json_int_t)size));
        json_object_set_new(summary, "output", json_string(a->output));
    }
    json_dumpf(summary, stdout, JSON_INDENT(2) | JSON_PRESERVE_ORDER | JSON_REAL_PRECISION(15));
    fputc('\n', stdout);
    json_decref(summary);
done:
    mer_scene_free(scene);
    return status;
}

static int list_presets(void)
{
    json_t *list = json_array();
    for (size_t i = 0; i < mer_preset_count(); i++)
        json_array_append_new(list, json_pack("{s:s, s:s}", "name", mer_preset_name(i),
                                              "description", mer_preset_description(i)));
    json_dumpf(list, stdout, JSON_INDENT(2) | JSON_PRESERVE_ORDER);
    fputc('\n', stdout);
    json_decref(list);
    return 0;
}

/* grow's long options. */
enum { O_MODEL = 999, O_PRESET = 1000, O_STEPS, O_SEED, O_SET, O_DETAIL, O_LEAVES, O_MARKERS, O_COLOR, O_UNQUANTIZED,
       O_QUANTIZE,
       O_NO_TEXCOORDS, O_COMPRESS, O_TWIG_LINES, O_JUNCTIONS };
static const struct option longopts[] = {
    {"model", required_argument, NULL, O_MODEL},
    {"preset", required_argument, NULL, O_PRESET}, {"steps", required_argument, NULL, O_STEPS},
    {"seed", required_argument, NULL, O_SEED},     {"set", required_argument, NULL, O_SET},
    {"output", required_argument, NULL, 'o'},      {"detail", required_argument, NULL, O_DETAIL},
    {"leaves", no_argument, NULL, O_LEAVES},       {"markers", no_argument, NULL, O_MARKERS},
    {"color", required_argument, NULL, O_COLOR},   {"unquantized", no_argument, NULL, O_UNQUANTIZED},
    {"quantize", no_argument, NULL, O_QUANTIZE},
    {"no-texcoords", no_argument, NULL, O_NO_TEXCOORDS},
    {"twig-lines", no_argument, NULL, O_TWIG_LINES},
    {"compress", required_argument, NULL, O_COMPRESS},
    {"junctions", required_argument, NULL, O_JUNCTIONS},
    {0, 0, 0, 0}};

/* Reads grow's options into *a: 0, or the exit status for a mistake (2). */
static int parse_grow(int argc, char **argv, grow_args *a)
{
    optind = 2;
    int c;
    uint64_t v;
    while ((c = getopt_long(argc, argv, "o:", longopts, NULL)) != -1) {
        switch (c) {
        case O_MODEL: a->model = optarg; break;
        case O_PRESET: a->preset = optarg; break;
        case O_STEPS:
            if (parse_u64(optarg, 100000, &v) != 0) {
                fprintf(stderr, "meristem: --steps wants an integer from 0 to 100000, got '%s'\n", optarg);
                return 2;
            }
            a->steps = (uint32_t)v;
            break;
        case O_SEED:
            if (parse_u64(optarg, UINT64_MAX, &a->seed) != 0) {
                fprintf(stderr, "meristem: --seed wants an integer from 0 to 2^64-1, got '%s'\n", optarg);
                return 2;
            }
            break;
        case O_SET:
            if (a->set_count == SETS_MAX) {
                fprintf(stderr, "meristem: at most %d --set options\n", SETS_MAX);
                return 2;
            }
            a->sets[a->set_count++] = optarg;
            break;
        case 'o': a->output = optarg; break;
        case O_DETAIL:
            if (parse_u64(optarg, MER_MESH_DETAIL_MAX, &v) != 0 || v == 0) {
                fprintf(stderr, "meristem: --detail wants an integer from 1 to %d, got '%s'\n",
                        MER_MESH_DETAIL_MAX, optarg);
                return 2;
            }
            a->mesh.detail = (uint32_t)v;
            break;
        case O_LEAVES: a->mesh.leaves = 1; break;
        case O_MARKERS: a->mesh.markers = 1; break;
        case O_UNQUANTIZED: a->quantized = 0; break;
        case O_QUANTIZE: a->quantized = 1; break;
        case O_NO_TEXCOORDS: a->mesh.no_uvs = 1; break;
        case O_TWIG_LINES: a->mesh.twig_lines = 1; break;
        case O_COMPRESS: {
            int mode = merd_compression_parse(optarg);
            if (mode < 0) {
                fprintf(stderr, "meristem: --compress wants none or meshopt, got '%s'\n", optarg);
                return 2;
            }
            a->compression = (uint32_t)mode;
            break;
        }
        case O_JUNCTIONS: {
            int mode = merd_junctions_parse(optarg);
            if (mode < 0) {
                fprintf(stderr, "meristem: --junctions wants tubes or implicit, got '%s'\n", optarg);
                return 2;
            }
            a->mesh.junctions = (uint32_t)mode;
            break;
        }
        case O_COLOR: {
            int mode = merd_color_mode_parse(optarg);
            if (mode < 0) {
                fprintf(stderr, "meristem: --color wants none, order, light or age, got '%s'\n", optarg);
                return 2;
            }
            a->mesh.color = (uint32_t)mode;
            break;
        }
        default:
            usage(stderr);
            return 2;
        }
    }
    if (optind < argc) {
        fprintf(stderr, "meristem: unexpected argument '%s'\n", argv[optind]);
        return 2;
    }
    return 0;
}

int main(int argc, char **argv)
{
    if (argc >= 2 && (strcmp(argv[1], "--help") == 0 || strcmp(argv[1], "-h") == 0)) {
        usage(stdout);
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "--version") == 0) {
        printf("meristem %s\n", mer_version());
        return 0;
    }
    if (argc >= 2 && strcmp(argv[1], "presets") == 0)
        return list_presets();
    if (argc < 2 || strcmp(argv[1], "grow") != 0) {
        usage(stderr);
        return 2;
    }
    grow_args a = {.preset = "default", .steps = 20};
    int status = parse_grow(argc, argv, &a);
    return status != 0 ? status : grow(&a);
}
