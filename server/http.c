/* meristemd — libmicrohttpd glue. Request lifecycle as in libmicrohttpd's
 * post_example: state on the first call, body chunks appended up to a hard
 * cap, dispatch on the last call, cleanup and the log line when completed.
 * libmicrohttpd does not listen: the front (front.h) accepts, answers the
 * requests libmicrohttpd would refuse in HTML with problem+json, and relays
 * the others; it counts connections per address, and learns here when a
 * request is completed. */
#include "config.h"

#include <limits.h>
#include <netdb.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include "server/app.h"
#include "server/clock.h"
#include "server/front.h"
#include "server/guard.h"
#include "server/head.h"
#include "server/host.h"
#include "server/http.h"
#include "server/request.h"
#include "server/routes.h"

/* Connections past --max-connections that libmicrohttpd still accepts while the
 * guard closes the oldest idle ones. */
#define GUARD_MARGIN 64

struct merd_server {
    struct MHD_Daemon *daemon;
    merd_guard *guard;
    merd_front *front;
    atomic_int requests;       /* begun and not completed */
    unsigned port;             /* bound */
    merd_app *app;
    merd_settings config;
    char web_root[PATH_MAX];   /* canonical */
    struct sockaddr_storage address;
};

static enum MHD_Result refuse_too_large(merd_server *server, merd_request *req)
{
    char detail[160];
    snprintf(detail, sizeof detail, "the request body is larger than %ld bytes (meristemd --max-body)",
             server->config.body_limit);
    return merd_reply_problem(req, 413, "body-too-large", "Content Too Large", detail);
}

/* What can be refused from the head alone is refused before any body is read:
 * libmicrohttpd then closes the connection instead of reading the upload. */
static enum MHD_Result first_call(merd_server *server, merd_request *req, const char *version)
{
    const char *host = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                   MHD_HTTP_HEADER_HOST);
    if (host == NULL && strcmp(version, MHD_HTTP_VERSION_1_0) != 0)
        return merd_reply_problem(req, 400, "missing-host", "Bad Request",
                                  "an HTTP/1.1 request must say Host (RFC 9112 §3.2)");
    if (!merd_host_allowed(host, server->port, server->config.allowed_hosts)) {
        char detail[400];
        snprintf(detail, sizeof detail, "this meristemd does not answer to the host '%.200s'; "
                 "use its address, localhost, or start it with --allowed-host NAME", host);
        return merd_reply_problem(req, 421, "host-not-allowed", "Misdirected Request", detail);
    }
    const char *length = MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND,
                                                     MHD_HTTP_HEADER_CONTENT_LENGTH);
    unsigned long long announced = length != NULL ? strtoull(length, NULL, 10) : 0;
    unsigned long long limit = (unsigned long long)server->config.body_limit;
    if (announced <= limit)
        return MHD_YES;
    // A client waiting for 100-continue, or announcing more than twice the limit,
    // is answered now and its connection closed unread. A smaller overshoot is
    // read and discarded first (at most --max-body more): most clients send the
    // whole body before reading, and would otherwise see a reset, not the 413.
    if (MHD_lookup_connection_value(req->connection, MHD_HEADER_KIND, MHD_HTTP_HEADER_EXPECT) != NULL ||
        announced > 2 * limit)
        return refuse_too_large(server, req);
    req->body_too_large = true;
    return MHD_YES;
}

static enum MHD_Result on_request(void *cls, struct MHD_Connection *connection, const char *url,
                                  const char *method, const char *version,
                                  const char *upload_data, size_t *upload_data_size,
                                  void **state)
{
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
        atomic_fetch_add(&server->requests, 1);
        merd_guard_request_began(server->guard, connection);
        return first_call(server, req, version);
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
    if (req->status != 0) {  // answered from the head: the body is not wanted
        *upload_data_size = 0;
        return MHD_YES;
    }

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

    if (req->body_too_large)
        return refuse_too_large(server, req);
    return merd_route(req, server->web_root);
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
        if (in[0] == '%' && (hi = merd_head_hex_digit(in[1])) >= 0 &&
            (lo = merd_head_hex_digit(in[2])) >= 0 && (hi | lo) != 0) {
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
    merd_server *server = cls;
    merd_request *req = *state;
    const union MHD_ConnectionInfo *fd =
        MHD_get_connection_info(connection, MHD_CONNECTION_INFO_CONNECTION_FD);
    if (fd != NULL)
        merd_front_answered(server->front, fd->connect_fd,
                            code == MHD_REQUEST_TERMINATED_COMPLETED_OK);
    if (req == NULL)
        return;
    merd_guard_request_ended(server->guard, connection);
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
    atomic_fetch_sub(&server->requests, 1);
}

static void log_mhd(void *cls, const char *fmt, va_list ap)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 0)))
#endif
    ;

/* libmicrohttpd's messages, but its complaints that TCP options cannot be set:
 * its sockets are the front's socketpairs, where they mean nothing, and it
 * says so for every answer. */
static void log_mhd(void *cls, const char *fmt, va_list ap)
{
    (void)cls;
    if (strncmp(fmt, "Setting %s option", 17) == 0 || strncmp(fmt, "Failed to push the data", 23) == 0)
        return;
    vfprintf(stderr, fmt, ap);
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
    atomic_init(&server->requests, 0);
    if (config->web_root[0] != '\0' && realpath(config->web_root, server->web_root) == NULL) {
        fprintf(err, "meristemd: --web-root '%s' does not exist\n", config->web_root);
        free(server);
        return NULL;
    }
    server->guard = merd_guard_start((unsigned)config->connection_limit,
                                     (double)config->header_timeout, (double)config->timeout);
    if (server->guard == NULL || !resolve_bind(server, err)) {
        merd_guard_stop(server->guard);
        free(server);
        return NULL;
    }
    unsigned flags = MHD_USE_INTERNAL_POLLING_THREAD | MHD_USE_AUTO | MHD_USE_ERROR_LOG |
                     MHD_ALLOW_SUSPEND_RESUME | MHD_USE_NO_LISTEN_SOCKET;
    server->daemon = MHD_start_daemon(
        flags, 0, NULL, NULL, on_request, server,
        MHD_OPTION_THREAD_POOL_SIZE, (unsigned)config->threads,
        // The guard keeps the count at --max-connections by closing the oldest
        // connection not in a request; the margin absorbs arrivals meanwhile.
        MHD_OPTION_CONNECTION_LIMIT, (unsigned)config->connection_limit + GUARD_MARGIN,
        MHD_OPTION_NOTIFY_CONNECTION, merd_guard_notify, server->guard,
        MHD_OPTION_CONNECTION_MEMORY_LIMIT, (size_t)config->memory_limit,
        MHD_OPTION_CONNECTION_TIMEOUT, (unsigned)config->timeout,
        MHD_OPTION_NOTIFY_COMPLETED, on_completed, server,
        MHD_OPTION_UNESCAPE_CALLBACK, unescape_path, NULL,
        MHD_OPTION_EXTERNAL_LOGGER, log_mhd, NULL,
        MHD_OPTION_END);
    merd_front_config front = {
        .head_seconds = (double)config->header_timeout,
        .idle_seconds = (double)config->timeout,
        .per_ip_limit = (unsigned)config->per_ip_limit,
        .soft_limit = (unsigned)config->connection_limit,
        .budget = (size_t)config->memory_limit / 2,
    };
    if (server->daemon == NULL ||
        !merd_front_start(&server->address, &front, server->daemon, server->guard, &server->front)) {
        fprintf(err, "meristemd: cannot listen on %s port %ld (in use, or not permitted)\n",
                config->bind, config->port);
        if (server->daemon != NULL)
            MHD_stop_daemon(server->daemon);
        merd_guard_stop(server->guard);
        free(server);
        return NULL;
    }
    server->port = merd_front_port(server->front);
    return server;
}

unsigned merd_server_port(const merd_server *server)
{
    return server->port;
}

void merd_server_quiesce(merd_server *server)
{
    merd_front_quiesce(server->front);
}

bool merd_server_settle(merd_server *server, double seconds)
{
    double until = merd_now() + seconds;
    while (atomic_load(&server->requests) > 0) {
        if (merd_now() > until)
            return false;
        struct timespec tick = {0, 10 * 1000000L};
        nanosleep(&tick, NULL);
    }
    return true;
}

void merd_server_stop(merd_server *server)
{
    if (server == NULL)
        return;
    merd_front_stop(server->front);
    // Completions of the requests it aborts still reach the front's slots.
    MHD_stop_daemon(server->daemon);
    merd_front_free(server->front);
    merd_guard_stop(server->guard);
    free(server);
}
