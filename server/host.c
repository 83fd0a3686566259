/* meristemd — the Host header check (see host.h). */
#include "config.h"

#include <arpa/inet.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "server/host.h"

/* Splits `host` into its name (brackets of an IPv6 literal removed) and port
 * (0 when absent). False when it is not of the form NAME[:PORT]. */
static bool split(const char *host, char *name, size_t size, unsigned long *port)
{
    const char *colon;
    size_t n;
    bool bracketed = host[0] == '[';
    if (bracketed) {
        const char *close = strchr(host, ']');
        if (close == NULL)
            return false;
        n = (size_t)(close - host - 1);
        host++;
        colon = close[1] == ':' ? close + 1 : NULL;
        if (close[1] != '\0' && colon == NULL)
            return false;
    } else {
        colon = strchr(host, ':');
        n = colon != NULL ? (size_t)(colon - host) : strlen(host);
        if (colon != NULL && strchr(colon + 1, ':') != NULL)
            return false;
    }
    // "name." is the same name, fully qualified (RFC 1034 §3.1).
    if (!bracketed && n > 1 && host[n - 1] == '.')
        n--;
    if (n == 0 || n >= size)
        return false;
    memcpy(name, host, n);
    name[n] = '\0';
    *port = 0;
    if (colon != NULL) {
        char *end = NULL;
        if (colon[1] < '0' || colon[1] > '9')
            return false;
        *port = strtoul(colon + 1, &end, 10);
        if (*end != '\0' || *port == 0 || *port > 65535)
            return false;
    }
    return true;
}

static bool ip_literal(const char *name)
{
    unsigned char buf[16];
    return inet_pton(AF_INET, name, buf) == 1 || inet_pton(AF_INET6, name, buf) == 1;
}

bool merd_host_allowed(const char *host, unsigned port, const char *allowed)
{
    if (host == NULL)
        return true;
    char name[256];
    unsigned long got = 0;
    if (!split(host, name, sizeof name, &got))
        return false;
    // Without a port the client means this one; with one, it must be ours.
    if ((ip_literal(name) || strcasecmp(name, "localhost") == 0) && (got == 0 || got == port))
        return true;
    for (const char *a = allowed; a != NULL && *a != '\0'; a += strlen(a) + 1) {
        char want[256];
        unsigned long want_port = 0;
        if (!split(a, want, sizeof want, &want_port) || strcasecmp(want, name) != 0)
            continue;
        if (want_port == 0 || want_port == got)
            return true;
    }
    return false;
}
