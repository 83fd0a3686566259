/* meristemd — entry point: settings, signals, serve until SIGINT or SIGTERM. */
#include "config.h"

#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <meristem/version.h>

#include "server/settings.h"
#include "server/http.h"

int main(int argc, char **argv)
{
    mer_settings config;
    switch (mer_settings_parse(&config, argc, argv, stdout, stderr)) {
    case MER_SETTINGS_EXIT: return EXIT_SUCCESS;
    case MER_SETTINGS_ERROR: return 2;
    case MER_SETTINGS_RUN: break;
    }
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

    mer_server *server = mer_server_start(&config, stderr);
    if (server == NULL)
        return EXIT_FAILURE;
    const char *host = config.bind;
    printf("meristemd %s listening on http://%s%s%s:%u/ (web root %s)\n", mer_version(),
           strchr(host, ':') ? "[" : "", host, strchr(host, ':') ? "]" : "",
           mer_server_port(server), config.web_root);

    int signo = 0;
    sigwait(&stop, &signo);
    printf("meristemd: %s, shutting down\n", signo == SIGINT ? "SIGINT" : "SIGTERM");
    mer_server_stop(server);
    return EXIT_SUCCESS;
}
