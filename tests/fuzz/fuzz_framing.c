/* meristem — libFuzzer harness: the front's body check (merd_framing_feed),
 * which reads bytes straight from the network, after a request head
 * (merd_head_check). The first byte picks the budget, the second the size of
 * the pieces the body arrives in; the rest is what a client sent. Checks that
 * a verdict is one of the promised ones, that a piece is never overrun, and
 * that the verdict and the byte it falls on do not depend on the pieces. */
#include "config.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "server/framing.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

/* Feeds text[0..n) in pieces of `piece`; the state and *at, where it ended. */
static merd_head_state feed(const merd_head_verdict *head, size_t budget, const char *text,
                            size_t n, size_t piece, size_t *at, merd_head_verdict *v)
{
    merd_framing f;
    merd_framing_start(&f, head, budget);
    size_t done = 0;
    merd_head_state s = head->body == MERD_BODY_NONE ? MERD_HEAD_GOOD : MERD_HEAD_MORE;
    while (done < n) {
        size_t size = n - done < piece ? n - done : piece, used = 0;
        s = merd_framing_feed(&f, text + done, size, &used, v);
        if (used > size)
            abort();
        done += used;
        if (s != MERD_HEAD_MORE)
            break;
        if (used != size)
            abort();
    }
    *at = done;
    return s;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 2)
        return 0;
    size_t budget = 64 + (size_t)data[0] * 16;
    size_t piece = 1 + data[1] % 16;
    const char *text = (const char *)data + 2;
    size_t n = size - 2;
    merd_head_verdict head = {0};
    if (merd_head_check(text, n, budget, &head) != MERD_HEAD_GOOD)
        return 0;
    if (head.head_size > n)
        abort();
    const char *body = text + head.head_size;
    size_t left = n - head.head_size, whole_at = 0, piece_at = 0;
    merd_head_verdict whole = {0}, pieces = {0};
    merd_head_state s = feed(&head, budget, body, left, left + 1, &whole_at, &whole);
    merd_head_state p = feed(&head, budget, body, left, piece, &piece_at, &pieces);
    if (s != p || whole_at != piece_at)
        abort();
    if (s == MERD_HEAD_BAD) {
        if (whole.status != 400 && whole.status != 413 && whole.status != 431)
            abort();
        if (whole.status != pieces.status || strcmp(whole.slug, pieces.slug) != 0 ||
            strlen(whole.detail) < 10)
            abort();
    }
    return 0;
}
