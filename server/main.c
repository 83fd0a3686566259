/* meristemd — entry point: settings, signals, serve until SIGINT or SIGTERM. */
#include "config.h"

#include <limits.h>
#include <malloc.h>
#include <stdatomic.h>
#include <sys/resource.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdbool.h>
#include <stdlib.h>
#include <time.h>
#include <string.h>

#include <meristem/version.h>

#include "server/app.h"
#include "server/clock.h"
#include "server/export.h"
#include "server/http.h"
#include "server/io_hooks.h"
#include "server/loader.h"
#include "server/settings.h"
#include "server/static_files.h"

/* Set on SIGINT or SIGTERM: running batches stop at their next whole step. */
static atomic_int stopping;
/* The cores lent to the snapshots meshed at once (--patch-threads 0). */
static merd_cores cores;

/* What sessions need of the settings. */
static merd_session_config session_config(const merd_settings *config)
{
    return (merd_session_config){
        .stopping = &stopping,
        .data_dir = config->data_dir,
        .fsync = strcmp(config->fsync, "interval") == 0 ? MERD_FSYNC_INTERVAL : MERD_FSYNC_ALWAYS,
        .limits = {.max_steps = (uint32_t)config->max_steps,
                   .max_markers = (uint32_t)config->max_markers},
        .max_internodes = (uint32_t)config->max_internodes,
        .max_seconds = (double)config->max_seconds,
        .checkpoint_every = (uint32_t)config->checkpoint_every,
        .compact = config->compact,
        .patch_threads = (uint32_t)config->patch_threads,
        .cores = &cores,
    };
}

/* The main thread waits for a stop signal in `stop` and returns it. On every
 * tick (a second, or the --fsync-interval when shorter) it removes the sessions
 * whose time to live has passed and, with --fsync=interval, flushes the journals. */
static int wait_for_stop(const sigset_t *stop, merd_app *app)
{
    bool interval = app->session_config.fsync == MERD_FSYNC_INTERVAL;
    long ms = interval && app->settings->fsync_interval < 1000 ? app->settings->fsync_interval : 1000;
    struct timespec tick = {ms / 1000, (ms % 1000) * 1000000L};
    double synced = merd_now();
    for (;;) {
        int signo = sigtimedwait(stop, NULL, &tick);
        if (signo == SIGINT || signo == SIGTERM)
            return signo;
        merd_registry_expire(app->registry, merd_wall_clock(), stdout);
        if (interval && merd_now() - synced >= 1e-3 * (double)app->settings->fsync_interval) {
            merd_registry_sync(app->registry);
            synced = merd_now();
        }
    }
}

/* In order: no new connections; the background loader ends the session it
 * loads; running batches stop at a whole step and are journaled; every
 * suspended request is answered, and the answers sent; only then
 * libmicrohttpd stops (it aborts on a suspended connection). */
static void shut_down(merd_app *app, merd_server *server, merd_loader *loader)
{
    merd_server_quiesce(server);
    merd_loader_stop(loader);
    atomic_store(&stopping, 1);
    merd_jobs_drain(app->jobs);
    if (!merd_server_settle(server, 5.0))
        printf("meristemd: requests still open after 5 s are dropped\n");
    merd_server_stop(server);
    merd_jobs_stop(app->jobs);
}

int main(int argc, char **argv)
{
    merd_settings config;
    switch (merd_settings_parse(&config, argc, argv, stdout, stderr)) {
    case MERD_SETTINGS_EXIT: return EXIT_SUCCESS;
    case MERD_SETTINGS_ERROR: return 2;
    case MERD_SETTINGS_RUN: break;
    }
    merd_io_faults_from_env();
    // Snapshots allocate tens of megabytes and free them at once. Keeping freed
    // memory in the heap for the next one, instead of returning it to the kernel
    // and faulting it in again, makes a warm snapshot several times faster
    // (tests/bench/bench_mesh: 3.5 ms instead of 15 ms for 10,000 internodes).
    mallopt(M_MMAP_THRESHOLD, 256 << 20);
    mallopt(M_TRIM_THRESHOLD, 512 << 20);

    // One log line per request; line buffering keeps lines whole under pipes.
    setvbuf(stdout, NULL, _IOLBF, 0);

    // Block the stop signals before any thread exists so that every
    // libmicrohttpd worker inherits the mask and only sigwait() sees them.
    sigset_t stop;
    sigemptyset(&stop);
    sigaddset(&stop, SIGINT);
    sigaddset(&stop, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop, NULL);
    signal(SIGPIPE, SIG_IGN);

    if (merd_static_find_root(config.web_root, sizeof config.web_root, stderr) != 0)
        return EXIT_FAILURE;
    char data_dir[PATH_MAX];
    merd_cores_init(&cores, merd_export_cores());
    merd_app app = {.settings = &config, .session_config = session_config(&config)};
    app.metrics = merd_metrics_new();
    app.registry = merd_registry_new(&app.session_config, (uint32_t)config.max_sessions);
    if (app.metrics == NULL || app.registry == NULL)
        return EXIT_FAILURE;
    // Listen first: sessions are only registered here, and loaded on their
    // first request or by the background loader.
    double t0 = merd_now();
    long found = merd_registry_scan(app.registry, stderr);
    if (found < 0)
        return EXIT_FAILURE;
    // The folder exists now: say where it is, whatever the working directory.
    if (realpath(config.data_dir, data_dir) == NULL)
        snprintf(data_dir, sizeof data_dir, "%s", config.data_dir);
    printf("meristemd: data dir %s\n", data_dir);
    if (found > 0)
        printf("meristemd: found %ld sessions in %s in %.3f s; each loads on its first request%s\n",
               found, data_dir, merd_now() - t0,
               strcmp(config.warm_up, "off") != 0 ? " or in the background" : "");
    // Every connection is a descriptor: take all the kernel allows this process.
    struct rlimit files;
    if (getrlimit(RLIMIT_NOFILE, &files) == 0 && files.rlim_cur < files.rlim_max) {
        files.rlim_cur = files.rlim_max;
        setrlimit(RLIMIT_NOFILE, &files);
    }
    app.jobs = merd_jobs_start((size_t)config.workers, (size_t)config.max_queue);
    if (app.jobs == NULL)
        return EXIT_FAILURE;

    merd_server *server = merd_server_start(&config, &app, stderr);
    if (server == NULL)
        return EXIT_FAILURE;
    const char *host = config.bind;
    printf("meristemd %s listening on http://%s%s%s:%u/ (web root %s)\n", mer_version(),
           strchr(host, ':') ? "[" : "", host, strchr(host, ':') ? "]" : "",
           merd_server_port(server), config.web_root[0] ? config.web_root : "none: the API only");

    merd_loader *loader = NULL;
    if (found > 0 && strcmp(config.warm_up, "background") == 0 &&
        (loader = merd_loader_start(app.registry, app.jobs, stdout)) == NULL)
        printf("meristemd: no background loader: sessions load on their first request\n");

    int signo = wait_for_stop(&stop, &app);
    printf("meristemd: %s, shutting down\n", signo == SIGINT ? "SIGINT" : "SIGTERM");
    shut_down(&app, server, loader);
    merd_registry_sync(app.registry);
    merd_registry_free(app.registry);
    merd_metrics_free(app.metrics);
    return EXIT_SUCCESS;
}
