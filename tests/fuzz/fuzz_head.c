/* meristem — libFuzzer harness: the front's request-head check
 * (merd_head_check), which reads bytes straight from the network. The first
 * byte picks the budget; the rest is what a client sent. Checks that a verdict
 * is one of the promised ones and that more bytes never take one back: a
 * refused prefix stays refused, a complete head stays complete. */
#include "config.h"

#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "server/head.h"

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

static void check(merd_head_state s, const merd_head_verdict *v, size_t size, size_t budget)
{
    if (s == MERD_HEAD_MORE && size > budget)
        abort();  // past the budget there is always a verdict
    if (s != MERD_HEAD_BAD)
        return;
    if (v->status != 400 && v->status != 413 && v->status != 414 && v->status != 431 &&
        v->status != 505)
        abort();
    if (v->slug == NULL || v->slug[0] == '\0' || strlen(v->detail) < 10)
        abort();
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    size_t budget = 64 + (size_t)data[0] * 16;
    const char *text = (const char *)data + 1;
    size_t n = size - 1;
    merd_head_verdict whole = {0}, part = {0};
    merd_head_state s = merd_head_check(text, n, budget, &whole);
    check(s, &whole, n, budget);
    size_t cut = n / 2;
    merd_head_state p = merd_head_check(text, cut, budget, &part);
    check(p, &part, cut, budget);
    if (p == MERD_HEAD_BAD && s != MERD_HEAD_BAD)
        abort();
    if (p == MERD_HEAD_GOOD && s == MERD_HEAD_MORE)
        abort();
    return 0;
}
