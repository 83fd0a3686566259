/* Unit tests for the Host header check against DNS rebinding (server/host.c). */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>

#include "server/host.h"

#define PORT 8080u

static bool ok(const char *host) { return merd_host_allowed(host, PORT, ""); }

static void test_loopback_names(void **state)
{
    (void)state;
    assert_true(ok(NULL)); /* HTTP/1.0 may send none */
    assert_true(ok("127.0.0.1"));
    assert_true(ok("127.0.0.1:8080"));
    assert_true(ok("localhost"));
    assert_true(ok("localhost:8080"));
    assert_true(ok("LocalHost:8080"));
    assert_true(ok("LOCALHOST"));
    assert_false(ok("127.0.0.1:8081"));
    assert_false(ok("localhost:80"));
}

static void test_ipv6_literals(void **state)
{
    (void)state;
    assert_true(ok("[::1]"));
    assert_true(ok("[::1]:8080"));
    assert_true(ok("[0:0:0:0:0:0:0:1]:8080"));
    assert_true(ok("[FE80::1]:8080"));
    assert_false(ok("[::1]:8081"));
    assert_false(ok("::1"));          /* unbracketed: the port would be ambiguous */
    assert_false(ok("[::1"));         /* unclosed */
    assert_false(ok("[::1]8080"));    /* junk after the bracket */
    assert_false(ok("[]:8080"));
    assert_false(ok("[evil.example]:8080")); /* brackets hold only literals */
}

static void test_trailing_dot(void **state)
{
    (void)state;
    // "localhost." is the same name, fully qualified; so is an allowed name's.
    assert_true(ok("localhost."));
    assert_true(ok("localhost.:8080"));
    assert_false(ok("localhost.:8081"));
    assert_false(ok("localhost.."));
    const char allowed[] = "tree.example\0";
    assert_true(merd_host_allowed("tree.example.", PORT, allowed));
    assert_true(merd_host_allowed("TREE.example.:8080", PORT, allowed));
    const char dotted[] = "tree.example.\0";
    assert_true(merd_host_allowed("tree.example", PORT, dotted));
}

static void test_malformed(void **state)
{
    (void)state;
    assert_false(ok(""));
    assert_false(ok(":8080"));
    assert_false(ok("localhost:"));
    assert_false(ok("localhost:0"));
    assert_false(ok("localhost:65536"));
    assert_false(ok("localhost:+80"));
    assert_false(ok("localhost:80x"));
    assert_false(ok("localhost:80:80"));
    assert_true(ok("localhost:08080")); /* the same number */
}

static void test_rebinding_names(void **state)
{
    (void)state;
    assert_false(ok("evil.example"));
    assert_false(ok("evil.example:8080"));
    assert_false(ok("localhost.evil.example:8080"));
    assert_false(ok("127.0.0.1.nip.io:8080"));
    assert_false(ok("localhostx"));
}

static void test_allowed_hosts(void **state)
{
    (void)state;
    const char allowed[] = "tree.example\0proxy.example:443\0";
    assert_true(merd_host_allowed("tree.example", PORT, allowed));
    assert_true(merd_host_allowed("tree.example:9999", PORT, allowed)); /* any port */
    assert_true(merd_host_allowed("Tree.Example:8080", PORT, allowed));
    assert_true(merd_host_allowed("proxy.example:443", PORT, allowed));
    assert_false(merd_host_allowed("proxy.example:8080", PORT, allowed)); /* that port only */
    assert_false(merd_host_allowed("proxy.example", PORT, allowed));
    assert_false(merd_host_allowed("other.example", PORT, allowed));
    assert_false(merd_host_allowed("sub.tree.example", PORT, allowed));
    assert_true(merd_host_allowed("localhost:8080", PORT, allowed)); /* still */
    assert_false(merd_host_allowed("tree.example", PORT, NULL));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_loopback_names),  cmocka_unit_test(test_ipv6_literals),
        cmocka_unit_test(test_trailing_dot),    cmocka_unit_test(test_malformed),
        cmocka_unit_test(test_rebinding_names), cmocka_unit_test(test_allowed_hosts),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
