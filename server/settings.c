/* meristemd — settings table and command-line parsing. */
#include "config.h"

#include <errno.h>
#include <getopt.h>
#include <limits.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/version.h>

#include "server/settings.h"

#ifndef MER_WEB_ROOT
#define MER_WEB_ROOT "web"
#endif

typedef enum { OPT_STRING, OPT_LONG, OPT_FLAG, OPT_LIST } opt_type;

typedef struct opt_spec {
    const char *name;
    opt_type type;
    long min, max;          /* for OPT_LONG */
    const char *fallback;   /* default, as it would be typed */
    size_t offset;          /* into merd_settings */
    size_t size;            /* of a string field */
    const char *help;
} opt_spec;

#define STR(field) offsetof(merd_settings, field), sizeof(((merd_settings *)0)->field)
#define NUM(field) offsetof(merd_settings, field), 0

static const opt_spec specs[] = {
    {"bind", OPT_STRING, 0, 0, "127.0.0.1", STR(bind),
     "address to listen on; anything but loopback exposes the API"},
    {"port", OPT_LONG, 0, 65535, "8080", NUM(port), "TCP port; 0 picks a free one and logs it"},
    {"web-root", OPT_STRING, 0, 0, MER_WEB_ROOT, STR(web_root), "folder served at /"},
    {"data-dir", OPT_STRING, 0, 0, "meristem-data", STR(data_dir),
     "folder for session journals"},
    {"threads", OPT_LONG, 1, 256, "2", NUM(threads), "HTTP worker threads"},
    {"max-body", OPT_LONG, 1024, 1L << 30, "8388608", NUM(body_limit),
     "largest request body in bytes"},
    {"max-connections", OPT_LONG, 1, 65536, "1024", NUM(connection_limit),
     "open connections at once"},
    {"max-connections-per-ip", OPT_LONG, 1, 65536, "256", NUM(per_ip_limit),
     "open connections from one address"},
    {"connection-memory", OPT_LONG, 4096, 1L << 24, "16384", NUM(memory_limit),
     "buffer bytes per connection; a request head may take half (libmicrohttpd clears it for "
     "every request, so bigger is slower)"},
    {"timeout", OPT_LONG, 1, 86400, "60", NUM(timeout), "seconds an idle connection is kept"},
    {"header-timeout", OPT_LONG, 1, 3600, "5", NUM(header_timeout),
     "seconds a client has to send its request line and headers, however it trickles them"},
    {"max-queue", OPT_LONG, 1, 1000000, "64", NUM(max_queue),
     "requests that may wait for a worker; more get 503 with Retry-After"},
    {"quiet", OPT_FLAG, 0, 0, NULL, NUM(quiet), "no request log on stdout"},
    {"workers", OPT_LONG, 1, 256, "2", NUM(workers), "threads that step and mesh trees"},
    {"patch-threads", OPT_LONG, 0, 64, "0", NUM(patch_threads),
     "threads that build one snapshot's implicit junction patches (the bytes are the same "
     "whatever their number); 0: the machine's cores that the snapshots being built beside "
     "it have not taken, at least 1"},
    {"max-sessions", OPT_LONG, 1, 1000000, "10000", NUM(max_sessions), "live sessions at once"},
    {"max-internodes", OPT_LONG, 1, 50000000, "2000000", NUM(max_internodes),
     "internodes a session's tree may grow to"},
    {"max-markers", OPT_LONG, 1, 20000000, "1000000", NUM(max_markers),
     "markers one request may add"},
    {"max-steps", OPT_LONG, 1, 100000, "1000", NUM(max_steps), "steps one request may ask for"},
    {"max-request-seconds", OPT_LONG, 1, 86400, "300", NUM(max_seconds),
     "seconds an edit batch may run; it then stops at the last whole step"},
    {"checkpoint-every", OPT_LONG, 0, 1000000, "50", NUM(checkpoint_every),
     "write a session's checkpoint every this many revisions (0: never), so that restore "
     "replays only the journal after it"},
    {"compact", OPT_FLAG, 0, 0, NULL, NUM(compact),
     "after each checkpoint, drop the journal records it covers (journals stay short, but "
     "the history before the checkpoint is gone)"},
    {"warm-up", OPT_STRING, 0, 0, "background", STR(warm_up),
     "background: once listening, load the data folder's sessions oldest first at low "
     "priority; off: load each on its first request only"},
    {"fsync", OPT_STRING, 0, 0, "always", STR(fsync),
     "always: flush the journal before every reply; interval: every --fsync-interval ms "
     "(a power cut may lose that long)"},
    {"fsync-interval", OPT_LONG, 1, 60000, "200", NUM(fsync_interval),
     "milliseconds between journal flushes with --fsync=interval"},
    {"token", OPT_STRING, 0, 0, NULL, STR(token),
     "require Authorization: Bearer TOKEN on every /v1 route but health"},
    {"token-file", OPT_STRING, 0, 0, NULL, STR(token_file), "read the token from this file"},
    {"cors-origin", OPT_STRING, 0, 0, NULL, STR(cors_origin),
     "allow this one origin to call the API from a browser (CORS is off without it)"},
    {"allowed-host", OPT_LIST, 0, 0, NULL, STR(allowed_hosts),
     "also accept this name (NAME or NAME:PORT) in the Host header; repeatable. Without it "
     "only IP literals and localhost are, so DNS rebinding cannot reach the daemon"},
};
#define N_SPECS (sizeof specs / sizeof specs[0])

static int set_option(merd_settings *config, const opt_spec *spec, const char *text, FILE *err)
{
    char *base = (char *)config + spec->offset;
    switch (spec->type) {
    case OPT_STRING:
        if (strlen(text) >= spec->size) {
            fprintf(err, "meristemd: --%s is longer than %zu characters\n", spec->name,
                    spec->size - 1);
            return -1;
        }
        memcpy(base, text, strlen(text) + 1);
        return 0;
    case OPT_LIST: {
        size_t used = 0;
        while (base[used] != '\0')
            used += strlen(base + used) + 1;
        if (text[0] == '\0' || used + strlen(text) + 2 > spec->size) {
            fprintf(err, "meristemd: --%s wants a name, and all of them fit in %zu characters\n",
                    spec->name, spec->size - 2);
            return -1;
        }
        memcpy(base + used, text, strlen(text) + 1);
        base[used + strlen(text) + 1] = '\0';
        return 0;
    }
    case OPT_LONG: {
        char *end = NULL;
        errno = 0;
        long value = strtol(text, &end, 10);
        if (errno != 0 || end == text || *end != '\0' || value < spec->min || value > spec->max) {
            fprintf(err, "meristemd: --%s wants an integer from %ld to %ld, got '%s'\n",
                    spec->name, spec->min, spec->max, text);
            return -1;
        }
        memcpy(base, &value, sizeof value);
        return 0;
    }
    case OPT_FLAG: {
        bool on = true;
        memcpy(base, &on, sizeof on);
        return 0;
    }
    }
    return -1;
}

/* The token file's first line, without its newline. */
static int read_token(merd_settings *config, FILE *err)
{
    FILE *f = fopen(config->token_file, "r");
    if (f == NULL) {
        fprintf(err, "meristemd: cannot read --token-file %s: %s\n", config->token_file,
                strerror(errno));
        return -1;
    }
    char line[sizeof config->token];
    if (fgets(line, sizeof line, f) == NULL)
        line[0] = '\0';
    fclose(f);
    line[strcspn(line, "\r\n")] = '\0';
    if (line[0] == '\0') {
        fprintf(err, "meristemd: --token-file %s is empty\n", config->token_file);
        return -1;
    }
    memcpy(config->token, line, strlen(line) + 1);
    return 0;
}

static void print_help(FILE *out)
{
    fprintf(out,
            "Usage: meristemd [OPTION]...\n"
            "Serve live self-organizing tree sessions over HTTP, and the brush client.\n\n");
    for (size_t i = 0; i < N_SPECS; i++) {
        char left[64];
        snprintf(left, sizeof left, "--%s%s", specs[i].name,
                 specs[i].type == OPT_FLAG ? "" : "=VALUE");
        fprintf(out, "  %-30s %s", left, specs[i].help);
        if (specs[i].fallback != NULL)
            fprintf(out, " (default %s)", specs[i].fallback);
        if (specs[i].type == OPT_LONG)
            fprintf(out, " [%ld..%ld]", specs[i].min, specs[i].max);
        fputc('\n', out);
    }
    fprintf(out, "  %-30s %s\n  %-30s %s\n", "--help", "show this help and exit", "--version",
            "show the version and exit");
}

merd_settings_outcome merd_settings_parse(merd_settings *config, int argc, char **argv, FILE *out,
                                    FILE *err)
{
    memset(config, 0, sizeof *config);
    for (size_t i = 0; i < N_SPECS; i++)
        if (specs[i].fallback != NULL && set_option(config, &specs[i], specs[i].fallback, err) != 0)
            return MERD_SETTINGS_ERROR;

    enum { OPT_HELP = 1000, OPT_VERSION };
    struct option longopts[N_SPECS + 3];
    for (size_t i = 0; i < N_SPECS; i++)
        longopts[i] = (struct option){specs[i].name,
                                      specs[i].type == OPT_FLAG ? no_argument : required_argument,
                                      NULL, (int)i};
    longopts[N_SPECS] = (struct option){"help", no_argument, NULL, OPT_HELP};
    longopts[N_SPECS + 1] = (struct option){"version", no_argument, NULL, OPT_VERSION};
    longopts[N_SPECS + 2] = (struct option){0, 0, 0, 0};

    optind = 1;
    opterr = 0;
    int c;
    while ((c = getopt_long(argc, argv, "", longopts, NULL)) != -1) {
        if (c == OPT_HELP) {
            print_help(out);
            return MERD_SETTINGS_EXIT;
        }
        if (c == OPT_VERSION) {
            fprintf(out, "meristemd %s\n", mer_version());
            return MERD_SETTINGS_EXIT;
        }
        if (c < 0 || (size_t)c >= N_SPECS) {
            fprintf(err, "meristemd: unknown or incomplete option '%s'; see --help\n",
                    argv[optind - 1]);
            return MERD_SETTINGS_ERROR;
        }
        if (set_option(config, &specs[c], optarg, err) != 0)
            return MERD_SETTINGS_ERROR;
    }
    if (optind < argc) {
        fprintf(err, "meristemd: unexpected argument '%s'; see --help\n", argv[optind]);
        return MERD_SETTINGS_ERROR;
    }
    if (strcmp(config->warm_up, "background") != 0 && strcmp(config->warm_up, "off") != 0) {
        fprintf(err, "meristemd: --warm-up wants background or off, got '%s'\n", config->warm_up);
        return MERD_SETTINGS_ERROR;
    }
    if (strcmp(config->fsync, "always") != 0 && strcmp(config->fsync, "interval") != 0) {
        fprintf(err, "meristemd: --fsync wants always or interval, got '%s'\n", config->fsync);
        return MERD_SETTINGS_ERROR;
    }
    if (config->token_file[0] != '\0' && read_token(config, err) != 0)
        return MERD_SETTINGS_ERROR;
    return MERD_SETTINGS_RUN;
}
