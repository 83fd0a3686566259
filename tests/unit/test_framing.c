/* Unit tests for the front's body check (server/framing.c): a chunked body
 * taken in pieces, as it arrives, gives the verdict libmicrohttpd 0.9.75
 * would reach, at the byte where it is reached. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

#include <cmocka.h>

#include "server/framing.h"

#define BUDGET 256u

/* Feeds `text` in pieces of `piece` bytes to a body of `kind`. Returns 0 while
 * the body goes on, 200 when it ended, else the refusal's status; *at is the
 * byte where the body ended or went wrong (the bytes fed when it goes on). */
static unsigned feed(merd_body_kind kind, unsigned long long length, const char *text,
                     size_t piece, size_t *at)
{
    merd_head_verdict head = {.body = kind, .length = length}, v = {0};
    merd_framing f;
    merd_framing_start(&f, &head, BUDGET);
    size_t n = strlen(text), done = 0;
    while (done < n) {
        size_t size = n - done < piece ? n - done : piece, used = 0;
        merd_head_state s = merd_framing_feed(&f, text + done, size, &used, &v);
        assert_true(used <= size);
        done += used;
        if (s == MERD_HEAD_GOOD) {
            *at = done;
            return 200;
        }
        if (s == MERD_HEAD_BAD) {
            assert_non_null(v.slug);
            assert_true(strlen(v.detail) > 10);
            *at = done;
            return v.status;
        }
        assert_int_equal(used, size);
    }
    *at = done;
    return kind == MERD_BODY_NONE ? 200 : 0;
}

/* The verdict on `text` whatever the pieces it arrives in: every size from one
 * byte to the whole gives the same verdict at the same byte. */
static unsigned verdict_at(merd_body_kind kind, const char *text, size_t *at)
{
    size_t first_at = 0;
    unsigned first = feed(kind, 0, text, strlen(text) + 1, &first_at);
    for (size_t piece = 1; piece <= strlen(text); piece++) {
        size_t where = 0;
        assert_int_equal(feed(kind, 0, text, piece, &where), first);
        assert_int_equal(where, first_at);
    }
    *at = first_at;
    return first;
}

static unsigned chunked(const char *text)
{
    size_t at;
    return verdict_at(MERD_BODY_CHUNKED, text, &at);
}

static void test_good_chunks(void **state)
{
    (void)state;
    size_t at;
    const char *body = "2\r\n{}\r\n0\r\n\r\nGET / HTTP/1.1\r\n\r\n";
    assert_int_equal(verdict_at(MERD_BODY_CHUNKED, body, &at), 200);
    assert_int_equal(at, strlen("2\r\n{}\r\n0\r\n\r\n"));      /* the next request is not the body's */
    assert_int_equal(chunked("2;ext=1\r\n{}\r\n0\r\n\r\n"), 200);   /* an extension */
    assert_int_equal(chunked("2\n{}\n0\n\n"), 200);                 /* bare LF */
    assert_int_equal(chunked("A\r\n0123456789\r\n0\r\n\r\n"), 200); /* hexadecimal */
    assert_int_equal(chunked("1\r\nx\r\n0\r\nX-T: 1\r\n folded\r\n\r\n"), 200);
    assert_int_equal(chunked("ffffffffffffffff\r\n"), 0);           /* 64 bits fit */
    assert_int_equal(chunked("2\r\n{"), 0);
    assert_int_equal(chunked("0\r\nX-T: 1\r\n"), 0);
}

static void test_bad_chunks(void **state)
{
    (void)state;
    size_t at;
    assert_int_equal(verdict_at(MERD_BODY_CHUNKED, "2\r\n{}\r\nzz\r\n", &at), 400);
    assert_int_equal(at, strlen("2\r\n{}\r\n"));                    /* at the bad byte */
    assert_int_equal(verdict_at(MERD_BODY_CHUNKED, "2\r\n{}XX0\r\n\r\n", &at), 400);
    assert_int_equal(at, strlen("2\r\n{}"));
    assert_int_equal(chunked("\r\n"), 400);                         /* no digits */
    assert_int_equal(chunked(";x\r\n"), 400);
    assert_int_equal(chunked("1 \r\nx\r\n"), 400);                  /* a space */
    assert_int_equal(chunked("1\rx\n"), 400);                       /* a CR not before LF */
    assert_int_equal(chunked("1\r\nx\rX"), 400);
    assert_int_equal(chunked("0\r\nno colon\r\n\r\n"), 400);        /* a trailer */
    assert_int_equal(chunked("0\r\n folded first\r\n\r\n"), 400);
    assert_int_equal(chunked("10000000000000000\r\n"), 413);        /* over 64 bits */
}

static void test_long_lines(void **state)
{
    (void)state;
    char text[2 * BUDGET];
    memset(text, 0, sizeof text);
    text[0] = '1';
    text[1] = ';';
    memset(text + 2, 'e', BUDGET);
    assert_int_equal(chunked(text), 431);                           /* an extension */
    memcpy(text, "0\r\nX:", 5);
    memset(text + 5, 'v', BUDGET);
    assert_int_equal(chunked(text), 431);                           /* the trailers */
}

static void test_other_bodies(void **state)
{
    (void)state;
    size_t at = 0;
    assert_int_equal(feed(MERD_BODY_LENGTH, 5, "abcdeGET", 3, &at), 200);
    assert_int_equal(at, 5);
    assert_int_equal(feed(MERD_BODY_LENGTH, 50, "abcde", 2, &at), 0);
    assert_int_equal(feed(MERD_BODY_NONE, 0, "GET", 2, &at), 200);
    assert_int_equal(at, 0);
    assert_int_equal(feed(MERD_BODY_UNTIL_CLOSE, 0, "anything\r\nat all", 4, &at), 0);
    assert_int_equal(at, 16);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_chunks),
        cmocka_unit_test(test_bad_chunks),
        cmocka_unit_test(test_long_lines),
        cmocka_unit_test(test_other_bodies),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
