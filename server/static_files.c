/* meristemd — static files. */
#include "config.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include "server/static_files.h"

static const struct {
    const char *extension;
    const char *mime;
} mime_types[] = {
    {".html", "text/html; charset=utf-8"},
    {".js", "text/javascript; charset=utf-8"},
    {".mjs", "text/javascript; charset=utf-8"},
    {".css", "text/css; charset=utf-8"},
    {".json", "application/json"},
    {".map", "application/json"},
    {".glb", "model/gltf-binary"},
    {".gltf", "model/gltf+json"},
    {".png", "image/png"},
    {".jpg", "image/jpeg"},
    {".jpeg", "image/jpeg"},
    {".webp", "image/webp"},
    {".svg", "image/svg+xml"},
    {".ico", "image/x-icon"},
    {".wasm", "application/wasm"},
    {".woff2", "font/woff2"},
    {".txt", "text/plain; charset=utf-8"},
    {".md", "text/markdown; charset=utf-8"},
    {".yaml", "application/yaml"},
};

const char *merd_static_mime_type(const char *path)
{
    const char *slash = strrchr(path, '/');
    const char *dot = strrchr(slash != NULL ? slash : path, '.');
    if (dot != NULL)
        for (size_t i = 0; i < sizeof mime_types / sizeof mime_types[0]; i++)
            if (strcasecmp(dot, mime_types[i].extension) == 0)
                return mime_types[i].mime;
    return "application/octet-stream";
}

/* True when every segment of `url` is an ordinary name: no "." or "..", no
 * backslash. Rejecting these outright (rather than normalizing) means no
 * request can even name a place outside the root. */
static bool url_is_plain(const char *url)
{
    if (url[0] != '/')
        return false;
    const char *segment = url + 1;
    for (;;) {
        const char *end = strchr(segment, '/');
        size_t len = end != NULL ? (size_t)(end - segment) : strlen(segment);
        if ((len == 1 && segment[0] == '.') || (len == 2 && segment[0] == '.' && segment[1] == '.'))
            return false;
        if (memchr(segment, '\\', len) != NULL)
            return false;
        if (end == NULL)
            return true;
        segment = end + 1;
    }
}

/* True when the canonical `path` is `root` itself or lies below it. */
static bool inside(const char *path, const char *root)
{
    size_t n = strlen(root);
    return strncmp(path, root, n) == 0 && (path[n] == '\0' || path[n] == '/' || n == 1);
}

static enum MHD_Result not_found(merd_request *req)
{
    char detail[300];
    snprintf(detail, sizeof detail, "there is no file at %.200s", req->url);
    return merd_reply_problem(req, 404, "not-found", "Not Found", detail);
}

static enum MHD_Result send_file(merd_request *req, const char *path, const char *root)
{
    char real[PATH_MAX];
    if (realpath(path, real) == NULL || !inside(real, root))
        return not_found(req);
    int fd = open(real, O_RDONLY | O_CLOEXEC);
    if (fd < 0)
        return not_found(req);
    struct stat st;
    if (fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
        close(fd);
        return not_found(req);
    }
    struct MHD_Response *response = MHD_create_response_from_fd((uint64_t)st.st_size, fd);
    if (response == NULL) {
        close(fd);
        return MHD_NO;
    }
    MHD_add_response_header(response, MHD_HTTP_HEADER_CONTENT_TYPE, merd_static_mime_type(real));
    MHD_add_response_header(response, MHD_HTTP_HEADER_CACHE_CONTROL, "no-cache");
    return merd_reply(req, 200, response, (uint64_t)st.st_size);
}

enum MHD_Result merd_static_serve(merd_request *req, const char *root)
{
    if (root[0] == '\0')
        return merd_reply_problem(req, 404, "not-found", "Not Found",
                                  "this meristemd serves the API only (/v1/...): it found no web "
                                  "root; start it with --web-root=DIR to serve the brush client");
    if (!url_is_plain(req->url))
        return not_found(req);
    char path[PATH_MAX];
    int n = snprintf(path, sizeof path, "%s%s", root, req->url);
    if (n < 0 || (size_t)n >= sizeof path)
        return not_found(req);

    struct stat st;
    if (stat(path, &st) == 0 && S_ISDIR(st.st_mode)) {
        size_t len = strlen(req->url);
        if (req->url[len - 1] != '/') {
            char location[PATH_MAX];
            snprintf(location, sizeof location, "%s/", req->url);
            struct MHD_Response *response =
                MHD_create_response_from_buffer(0, NULL, MHD_RESPMEM_PERSISTENT);
            if (response == NULL)
                return MHD_NO;
            MHD_add_response_header(response, MHD_HTTP_HEADER_LOCATION, location);
            return merd_reply(req, 301, response, 0);
        }
        n = snprintf(path, sizeof path, "%s%sindex.html", root, req->url);
        if (n < 0 || (size_t)n >= sizeof path)
            return not_found(req);
    }
    return send_file(req, path, root);
}

/* The build tree's webroot/ when this executable lies inside that tree (a
 * libtool build keeps it in server/.libs/). */
static bool build_tree_root(char *out, size_t size)
{
#ifdef MER_BUILD_DIR
    char exe[PATH_MAX], built[PATH_MAX];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    if (n <= 0 || realpath(MER_BUILD_DIR, built) == NULL)
        return false;
    exe[n] = '\0';
    size_t len = strlen(built);
    struct stat st;
    int k = snprintf(out, size, "%s/webroot", built);
    return strncmp(exe, built, len) == 0 && exe[len] == '/' && k > 0 && (size_t)k < size &&
           stat(out, &st) == 0 && S_ISDIR(st.st_mode);
#else
    (void)out;
    (void)size;
    return false;
#endif
}

int merd_static_find_root(char *web_root, size_t size, FILE *log)
{
    struct stat st;
    if (stat(web_root, &st) == 0)
        return 0;
    if (strcmp(web_root, MER_WEB_ROOT) != 0) {
        fprintf(log, "meristemd: --web-root '%s' does not exist\n", web_root);
        return -1;
    }
    if (build_tree_root(web_root, size))
        return 0;
    fprintf(log, "meristemd: no web root (%s is not installed; pass --web-root=DIR): serving "
            "the API only\n", MER_WEB_ROOT);
    web_root[0] = '\0';
    return 0;
}
