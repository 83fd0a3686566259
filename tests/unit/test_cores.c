/* meristemd's lease of the cores to the snapshots meshed at once (cores.h). */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#include <cmocka.h>
#include <pthread.h>

#include "server/cores.h"

/* Alone, a snapshot is lent every core; beside others, what they left, and
 * at least one; what is given back is lent again. */
static void lends_what_is_free(void **state)
{
    (void)state;
    merd_cores c;
    merd_cores_init(&c, 4);
    assert_int_equal(merd_cores_take(&c), 4);
    assert_int_equal(merd_cores_take(&c), 1); /* none free: one, oversubscribed */
    merd_cores_give(&c, 4);
    assert_int_equal(merd_cores_take(&c), 3); /* the one lent beside it is still out */
    assert_int_equal(merd_cores_take(&c), 1);
    merd_cores_give(&c, 1);
    merd_cores_give(&c, 3);
    merd_cores_give(&c, 1);
    assert_int_equal(atomic_load(&c.in_use), 0);
    assert_int_equal(merd_cores_take(&c), 4);
    merd_cores_give(&c, 4);
    assert_int_equal(atomic_load(&c.leases), 5);
    assert_int_equal(atomic_load(&c.lent), 13);
    merd_cores_init(&c, 1);
    assert_int_equal(merd_cores_take(&c), 1);
    assert_int_equal(merd_cores_take(&c), 1);
}

enum { TAKERS = 8, ROUNDS = 20000 };

static void *take_and_give(void *arg)
{
    merd_cores *c = arg;
    for (int i = 0; i < ROUNDS; i++) {
        uint32_t n = merd_cores_take(c);
        if (n < 1 || n > c->total)
            return (void *)1;
        merd_cores_give(c, n);
    }
    return NULL;
}

/* Threads taking and giving at once leave every core free at the end, and
 * each lease was between one and all of them. */
static void leases_balance_across_threads(void **state)
{
    (void)state;
    merd_cores c;
    merd_cores_init(&c, 2);
    pthread_t t[TAKERS];
    for (int i = 0; i < TAKERS; i++)
        assert_int_equal(pthread_create(&t[i], NULL, take_and_give, &c), 0);
    for (int i = 0; i < TAKERS; i++) {
        void *bad;
        assert_int_equal(pthread_join(t[i], &bad), 0);
        assert_null(bad);
    }
    assert_int_equal(atomic_load(&c.in_use), 0);
    assert_int_equal(atomic_load(&c.leases), (uint64_t)TAKERS * ROUNDS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(lends_what_is_free),
        cmocka_unit_test(leases_balance_across_threads),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
