/* meristemd — its settings: one table feeds the command line, --help and
 * libmicrohttpd's limits, so a limit has exactly one name, default and range. */
#ifndef MERISTEMD_SETTINGS_H
#define MERISTEMD_SETTINGS_H

#include <stdbool.h>
#include <stdio.h>

typedef struct merd_settings {
    char bind[64];          /* --bind: listen address, IPv4 or IPv6 literal */
    long port;              /* --port: TCP port, 0 picks a free one */
    char web_root[4096];    /* --web-root: folder of the brush client */
    char data_dir[4096];    /* --data-dir: session journals */
    long threads;           /* --threads: libmicrohttpd thread-pool size */
    long body_limit;        /* --max-body: request body bytes */
    long connection_limit;  /* --max-connections: open connections in all */
    long per_ip_limit;      /* --max-connections-per-ip */
    long memory_limit;      /* --connection-memory: bytes of buffer per connection */
    long timeout;           /* --timeout: idle connection seconds */
    long header_timeout;    /* --header-timeout: seconds to send the request line and headers */
    long max_queue;         /* --max-queue: requests waiting for a worker before 503 */
    bool quiet;             /* --quiet: no request log */
    long workers;           /* --workers: threads that step and mesh */
    long patch_threads;     /* --patch-threads: threads one mesh's junction patches take, 0: auto */
    long max_sessions;      /* --max-sessions */
    long max_internodes;    /* --max-internodes: per session */
    long max_markers;       /* --max-markers: per request */
    long max_steps;         /* --max-steps: per request */
    long max_seconds;       /* --max-request-seconds: a batch stops at the step past it */
    long checkpoint_every;  /* --checkpoint-every: revisions between checkpoints, 0: none */
    bool compact;           /* --compact: drop the journal records a checkpoint covers */
    char warm_up[16];       /* --warm-up: "background" or "off" */
    char fsync[16];         /* --fsync: "always" or "interval" */
    long fsync_interval;    /* --fsync-interval: milliseconds between flushes */
    char token[256];        /* --token: required as Authorization: Bearer on /v1 but health */
    char token_file[4096];  /* --token-file: read the token from a file */
    char cors_origin[256];  /* --cors-origin: the one origin allowed to call the API */
    /* --allowed-host (repeatable): host names accepted in Host besides IP literals
     * and localhost, one after another, each NUL-terminated, then an empty one */
    char allowed_hosts[1024];
} merd_settings;

typedef enum merd_settings_outcome {
    MERD_SETTINGS_RUN,   /* settings parsed: start the daemon */
    MERD_SETTINGS_EXIT,  /* --help or --version printed: exit 0 */
    MERD_SETTINGS_ERROR  /* a bad option was reported on `err`: exit 2 */
} merd_settings_outcome;

/* Fills `config` with the defaults, then applies argv. Messages go to `out`
 * (help, version) and `err` (mistakes, naming the option and its range). */
merd_settings_outcome merd_settings_parse(merd_settings *config, int argc, char **argv,
                                    FILE *out, FILE *err);

#endif
