/* meristemd — libmicrohttpd glue. Request lifecycle as in libmicrohttpd's
 * post_example: state on the first call, body chunks appended up to a hard
 * cap, dispatch on the last call, cleanup and the log line when completed. */
#include "config.h"

#include <limits.h>
#include <netdb.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>

#include "server/app.h"
#include "server/clock.h"
#include "server/http.h"
#include "server/request.h"
#include "server/routes.h"

struct merd_server {
    struct MHD_Daemon *daemon;
    merd_app *app;
    merd_settings config;
    char web_root[PATH_MAX];   /* canonical */
    struct sockaddr_storage address;
};

static enum MHD_Result on_request(void *cls, struct MHD_Connection *connection, const char *url,
                                  const char *method, const char *version,
                                  const char *upload_data, size_t *upload_data_size,
                                  void **state)
{
    (void)version;
    merd_server *server = cls;
    merd_request *req = *state;

    if (req == NULL) {
        req = calloc(1, sizeof *req);
        if (req == NULL)
            return MHD_NO;
        req->connection = connection;
        req->app = server->app;
        req->revision = -1;
        req->route = "unknown";
        req->method = method;
        req->url = url;
        req->started = merd_now();
        *state = req;
        // Refuse an announced oversize body before reading any of it.
        const char *length = MHD_lookup_connection_value(connection, MHD_HEADER_KIND,
                                                         MHD_HTTP_HEADER_CONTENT_LENGTH);
        if (length != NULL && strtoull(length, NULL, 10) > (unsigned long long)server->config.body_limit)
            req->body_too_large = true;
        return MHD_YES;
    }

    if (req->async == MERD_ASYNC_READY) {
        // A worker has answered while the connection was suspended.
        req->async = MERD_ASYNC_NONE;
        struct MHD_Response *r = req->pending;
        req->pending = NULL;
        return merd_reply(req, req->pending_status, r, req->pending_size);
    }
    if (req->async == MERD_ASYNC_WAITING)
        return MHD_YES;

    if (*upload_data_size != 0) {
        size_t chunk = *upload_data_size;
        *upload_data_size = 0;
        if (req->body_too_large || req->body_size + chunk > (size_t)server->config.body_limit) {
            req->body_too_large = true;
            return MHD_YES;
        }
        char *grown = realloc(req->body, req->body_size + chunk + 1);
        if (grown == NULL)
            return MHD_NO;
        memcpy(grown + req->body_size, upload_data, chunk);
        req->body = grown;
        req->body_size += chunk;
        req->body[req->body_size] = '\0';
        return MHD_YES;
    }

    if (req->body_too_large) {
        char detail[160];
        snprintf(detail, sizeof detail,
                 "the request body is larger than %ld bytes (meristemd --max-body)",
                 server->config.body_limit);
        return merd_reply_problem(req, 413, "body-too-large", "Content Too Large", detail);
    }
    return merd_route(req, server->web_root);
}

static int hex_value(char c)
{
    if (c >= '0' && c <= '9')
        return c - '0';
    if (c >= 'a' && c <= 'f')
        return c - 'a' + 10;
    if (c >= 'A' && c <= 'F')
        return c - 'A' + 10;
    return -1;
}

/* Percent-decodes the path in place, as libmicrohttpd would, except that "%00"
 * stays encoded: a decoded NUL would silently cut "/%00x" down to "/", and a
 * request for a name with a NUL in it should find nothing. */
static size_t unescape_path(void *cls, struct MHD_Connection *connection, char *s)
{
    (void)cls;
    (void)connection;
    char *out = s;
    for (const char *in = s; *in != '\0'; in++) {
        int hi, lo;
        if (in[0] == '%' && (hi = hex_value(in[1])) >= 0 && (lo = hex_value(in[2])) >= 0 &&
            (hi | lo) != 0) {
            *out++ = (char)(hi * 16 + lo);
            in += 2;
        } else {
            *out++ = *in;
        }
    }
    *out = '\0';
    return (size_t)(out - s);
}

static void on_completed(void *cls, struct MHD_Connection *connection, void **state,
                         enum MHD_RequestTerminationCode code)
{
    (void)connection;
    merd_server *server = cls;
    merd_request *req = *state;
    if (req == NULL)
        return;
    if (server->app != NULL)
        merd_metrics_request(server->app->metrics, req->route, req->status);
    if (req->pending != NULL)
        MHD_destroy_response(req->pending);
    if (!server->config.quiet)
        printf("%s %s %u %llu %.2fms%s\n", req->method, req->url, req->status,
               (unsigned long long)req->bytes_out, (merd_now() - req->started) * 1e3,
               code == MHD_REQUEST_TERMINATED_COMPLETED_OK ? "" : " (aborted)");
    free(req->body);
    free(req);
    *state = NULL;
}

static bool resolve_bind(merd_server *server, FILE *err)
{
    struct addrinfo hints = {.ai_flags = AI_NUMERICHOST | AI_PASSIVE, .ai_socktype = SOCK_STREAM};
    struct addrinfo *found = NULL;
    int rc = getaddrinfo(server->config.bind, NULL, &hints, &found);
    if (rc != 0) {
        fprintf(err, "meristemd: --bind '%s' is not an IPv4 or IPv6 address: %s\n",
                server->config.bind, gai_strerror(rc));
        return false;
    }
    memcpy(&server->address, found->ai_addr, found->ai_addrlen);
    freeaddrinfo(found);
    // Port goes in after resolution; both families keep it at the same offset.
    ((struct sockaddr_in *)&server->address)->sin_port = htons((uint16_t)server->config.port);
    return true;
}

merd_server *merd_server_start(const merd_settings *config, merd_app *app, FILE *err)
{
    merd_server *server = calloc(1, sizeof *server);
    if (server == NULL)
        return NULL;
    server->config = *config;
    server->app = app;
    if (realpath(config->web_root, server->web_root) == NULL) {
        fprintf(err, "meristemd: --web-root '%s' does not exist\n", config->web_root);
        free(server);
        return NULL;
    }
    if (!resolve_bind(server, err)) {
        free(server);
        return NULL;
    }
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_AUTO | MHD_USE_ERROR_LOG |
                     MHD_ALLOW_SUSPEND_RESUME;
    if (server->address.ss_family == AF_INET6)
        flags |= MHD_USE_IPv6;
    server->daemon = MHD_start_daemon(
        flags, (uint16_t)config->port, NULL, NULL, on_request, server,
        MHD_OPTION_SOCK_ADDR, (struct sockaddr *)&server->address,
        MHD_OPTION_THREAD_POOL_SIZE, (unsigned)config->threads,
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)config->connection_limit,
        MHD_OPTION_PER_IP_CONNECTION_LIMIT, (unsigned)config->per_ip_limit,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)config->memory_limit,
        MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)config->timeout,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, server,
        MHD_OPTION_UNESCAPE_CALLBACK, unescape_path, NULL,
        MHD_OPTION_END);
    if (server->daemon == NULL) {
        fprintf(err, "meristemd: cannot listen on %s port %ld (in use, or not permitted)\n",
                config->bind, config->port);
        free(server);
        return NULL;
    }
    return server;
}

unsigned merd_server_port(const merd_server *server)
{
    const union MHD_DaemonInfo *info =
        MHD_get_daemon_info(server->daemon, MHD_DAEMON_INFO_BIND_PORT);
    return info != NULL ? info->port : (unsigned)server->config.port;
}

void merd_server_stop(merd_server *server)
{
    if (server == NULL)
        return;
    MHD_stop_daemon(server->daemon);
    free(server);
}
