/* Unit tests for the front's request-head check (server/head.c): the verdict
 * libmicrohttpd 0.9.75 would reach, given as a problem before it is reached. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "server/head.h"

#define BUDGET 1024u
#define HOST "Host: 127.0.0.1:8080\r\n"

/* The status of the verdict on `text`: 0 for MORE, 200 for GOOD. */
static unsigned verdict_n(const char *text, size_t n)
{
    merd_head_verdict v = {0};
    switch (merd_head_check(text, n, BUDGET, &v)) {
    case MERD_HEAD_MORE: return 0;
    case MERD_HEAD_GOOD: return 200;
    case MERD_HEAD_BAD:
        assert_non_null(v.slug);
        assert_true(strlen(v.detail) > 10);
        return v.status;
    }
    return 1;
}

static unsigned verdict(const char *text) { return verdict_n(text, strlen(text)); }

static void test_good_heads(void **state)
{
    (void)state;
    assert_int_equal(verdict("GET / HTTP/1.1\r\n" HOST "\r\n"), 200);
    assert_int_equal(verdict("GET / HTTP/1.0\n\n"), 200);              /* bare LF */
    assert_int_equal(verdict("\r\n\r\nGET / HTTP/1.1\r\n\r\n"), 200);  /* empty lines first */
    assert_int_equal(verdict("GET  /a b  HTTP/1.2\r\n\r\n"), 200);     /* spaces, a space in the target */
    assert_int_equal(verdict("GET / HTTP/1.1\r\n: empty name\r\nX : y\r\n\r\n"), 200);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: 18446744073709551615\r\n\r\n"), 200);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: 2\r\nContent-Length: x\r\n\r\n{}"), 200);
    /* A Transfer-Encoding wins: Content-Length is not looked at. */
    assert_int_equal(verdict("POST / HTTP/1.1\r\nTransfer-Encoding: gzip\r\nContent-Length: x\r\n\r\n"), 200);
}

static void test_incomplete_heads(void **state)
{
    (void)state;
    assert_int_equal(verdict(""), 0);
    assert_int_equal(verdict("GET / HTTP/1.1"), 0);
    assert_int_equal(verdict("GET / HTTP/1.1\r\n" HOST), 0);
    assert_int_equal(verdict("GET / HTTP/1.1\r\n" HOST "\r"), 0);
}

static void test_request_line(void **state)
{
    (void)state;
    assert_int_equal(verdict("GARBAGE\r\n\r\n"), 400);
    assert_int_equal(verdict(" GET / HTTP/1.1\r\n\r\n"), 400);   /* empty method */
    assert_int_equal(verdict("GET /\r\n\r\n"), 400);             /* no version */
    assert_int_equal(verdict("GET / \r\n\r\n"), 400);
    assert_int_equal(verdict("GET / HTTP/1.1 \r\n\r\n"), 400);   /* a space after the version */
    assert_int_equal(verdict("GET / http/1.1\r\n\r\n"), 400);
    assert_int_equal(verdict("GET / HTTP/1.10\r\n\r\n"), 400);
    assert_int_equal(verdict("GET / HTTP/1.1\rX: y\r\n\r\n"), 400); /* a bare CR ends no line */
    assert_int_equal(verdict("GET / HTTP/2.0\r\n\r\n"), 505);
    assert_int_equal(verdict("GET / HTTP/0.9\r\n\r\n"), 505);
}

static void test_header_lines(void **state)
{
    (void)state;
    assert_int_equal(verdict("GET / HTTP/1.1\r\nno colon\r\n\r\n"), 400);
    assert_int_equal(verdict("GET / HTTP/1.1\r\nX: a\r\n folded\r\n\r\n"), 400);
    assert_int_equal(verdict("GET / HTTP/1.1\r\n\tX: a\r\n\r\n"), 400);
    /* libmicrohttpd looks for the colon with strchr: a NUL hides it. */
    static const char nul[] = "GET / HTTP/1.1\r\nX\0: a\r\n\r\n";
    assert_int_equal(verdict_n(nul, sizeof nul - 1), 400);
}

static void test_content_length(void **state)
{
    (void)state;
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: ten\r\n\r\n"), 400);
    assert_int_equal(verdict("POST / HTTP/1.1\r\ncontent-length: 2x\r\n\r\n"), 400);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: 2 \r\n\r\n"), 400);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length:\r\n\r\n"), 400);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: -1\r\n\r\n"), 400);
    assert_int_equal(verdict("POST / HTTP/1.1\r\nContent-Length: 18446744073709551616\r\n\r\n"), 413);
}

#define CHUNKED "POST / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n"

static void test_chunks(void **state)
{
    (void)state;
    assert_int_equal(verdict(CHUNKED), 200);
    assert_int_equal(verdict(CHUNKED "2;a=b\r\n{}\r\n0\r\nT: 1\r\n\r\n"), 200);
    assert_int_equal(verdict(CHUNKED "0002\n{}\n0\n\n"), 200);
    assert_int_equal(verdict(CHUNKED "ffffffffffffffff\r\n{}"), 200);  /* 2^64 - 1: waits for it */
    assert_int_equal(verdict(CHUNKED "2\r\n{"), 200);                  /* more to come */
    assert_int_equal(verdict(CHUNKED "2\r\n{}\r"), 200);
    assert_int_equal(verdict(CHUNKED "zz\r\n{}\r\n0\r\n\r\n"), 400);
    assert_int_equal(verdict(CHUNKED "2x"), 400);                      /* seen before the line ends */
    assert_int_equal(verdict(CHUNKED "\r\n"), 400);
    assert_int_equal(verdict(CHUNKED ";x\r\n"), 400);
    assert_int_equal(verdict(CHUNKED "2 \r\n{}\r\n"), 400);
    assert_int_equal(verdict(CHUNKED "2\r\n{}XX0\r\n\r\n"), 400);
    assert_int_equal(verdict(CHUNKED "0\r\nno colon\r\n\r\n"), 400);
    assert_int_equal(verdict(CHUNKED "10000000000000000\r\n"), 413);
    assert_int_equal(verdict(CHUNKED "fffffffffffffffff"), 413);
    /* "chunked " is not chunked: the body is not looked at. */
    assert_int_equal(verdict("POST / HTTP/1.1\r\nTransfer-Encoding: chunked \r\n\r\nzz\r\n"), 200);
}

/* A head of `fields` lines "a:" after a request line. */
static unsigned fields_head(unsigned fields)
{
    char text[4096] = "GET / HTTP/1.1\r\n";
    for (unsigned i = 0; i < fields; i++)
        strcat(text, "a:\r\n");
    strcat(text, "\r\n");
    return verdict(text);
}

static void test_budget(void **state)
{
    (void)state;
    char text[4 * BUDGET];
    /* A request line over the budget, complete or not. */
    memset(text, 'a', sizeof text);
    memcpy(text, "GET /", 5);
    assert_int_equal(verdict_n(text, BUDGET), 0);
    assert_int_equal(verdict_n(text, BUDGET + 1), 414);
    memcpy(text + BUDGET, " HTTP/1.1\r\n\r\n", 13);
    assert_int_equal(verdict_n(text, BUDGET + 13), 414);
    /* Each field costs MERD_HEAD_FIELD_COST more than its bytes. */
    unsigned most = (BUDGET - 18) / (4 + MERD_HEAD_FIELD_COST);
    assert_int_equal(fields_head(most), 200);
    assert_int_equal(fields_head(most + 1), 431);
    /* So do query arguments: the request line alone is then too large. */
    char args[512] = "GET /?";
    for (int i = 0; i < 16; i++)
        strcat(args, "a&");
    strcat(args, " HTTP/1.1\r\n\r\n");
    assert_int_equal(verdict(args), 414);
    /* A header block that never ends. */
    memcpy(text, "GET / HTTP/1.1\r\nX: ", 19);
    memset(text + 19, 'a', sizeof text - 19);
    assert_int_equal(verdict_n(text, BUDGET), 0);
    assert_int_equal(verdict_n(text, sizeof text), 431);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_heads),    cmocka_unit_test(test_incomplete_heads),
        cmocka_unit_test(test_request_line),  cmocka_unit_test(test_header_lines),
        cmocka_unit_test(test_content_length), cmocka_unit_test(test_chunks),
        cmocka_unit_test(test_budget),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
