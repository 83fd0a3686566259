/* meristemd — the Host header check against DNS rebinding.
 *
 * A page on any site can point a name it controls at 127.0.0.1 and then call
 * the loopback daemon as if it were the same origin; the browser still sends
 * the attacker's name in Host. So a request is served only when its Host names
 * this daemon: an IP literal (a rebinding needs a DNS name, so literals are
 * safe, and they keep --bind 0.0.0.0 usable by address) or localhost, with the
 * bound port or none; or a name given with --allowed-host. */
#ifndef MERISTEMD_HOST_H
#define MERISTEMD_HOST_H

#include <stdbool.h>

/* Whether `host` (the Host header, or NULL when the request had none, as HTTP/1.0
 * may) is acceptable on `port`. `allowed` is the --allowed-host list: names
 * one after another, each NUL-terminated, ending with an empty one; "NAME"
 * allows that name on any port (a proxy in front may use its own), "NAME:PORT"
 * only there. Names compare without regard to case. O(length of the list). */
bool merd_host_allowed(const char *host, unsigned port, const char *allowed);

#endif
