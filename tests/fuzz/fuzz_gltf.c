/* meristem — libFuzzer harness: an uploaded obstacle (a GLB or a .gltf with
 * embedded buffers) through mer_gltf_read_triangles, and its triangles, when
 * it reads, into a scene as a mesh obstacle, as the create request does. */
#include "config.h"

#include <stdlib.h>

#include <meristem.h>

#include "tests/fuzz/fuzz_common.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    float *xyz = NULL;
    size_t triangles = 0;
    mer_error err = {0};
    mer_result rc = mer_gltf_read_triangles(data, size, 20000, &xyz, &triangles, &err);
    if (rc != MER_OK) {
        if (xyz != NULL || (rc != MER_ERR_FORMAT && rc != MER_ERR_LIMIT && rc != MER_ERR_INVALID &&
                            rc != MER_ERR_RANGE))
            abort();
        return 0;
    }
    if (triangles > 20000)
        abort();
    mer_scene *s = NULL;
    if (mer_scene_new(NULL, 1, &s, NULL) != MER_OK)
        abort();
    rc = mer_scene_add_mesh(s, xyz, triangles, &err);
    if (rc == MER_ERR_INTERNAL || rc == MER_ERR_NOMEM)
        abort();
    mer_scene_free(s);
    mer_gltf_free(xyz);
    return 0;
}
