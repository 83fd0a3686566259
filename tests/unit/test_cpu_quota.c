/* The cores a control group's CPU quota allows (server/cpu_quota.h), read
 * from cgroup file systems laid out in a temporary directory. */
#include "config.h"

#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <limits.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cmocka.h>

#include "server/cpu_quota.h"

static char root[256];

/* Writes `text` to root/rel, making its directories. */
static void put(const char *rel, const char *text)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s", root, rel);
    for (char *p = path + strlen(root) + 1; *p != '\0'; p++)
        if (*p == '/') {
            *p = '\0';
            mkdir(path, 0700);
            *p = '/';
        }
    FILE *f = fopen(path, "w");
    assert_non_null(f);
    fputs(text, f);
    fclose(f);
}

static int make_root(void **state)
{
    (void)state;
    snprintf(root, sizeof root, "%s/mer-cgroup-XXXXXX", getenv("TMPDIR") ? getenv("TMPDIR") : "/tmp");
    return mkdtemp(root) == NULL ? -1 : 0;
}

static int remove_root(void **state)
{
    (void)state;
    char cmd[300];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", root);
    return system(cmd) == 0 ? 0 : -1;
}

/* Rounded up; no limit is 0. */
static void quota_arithmetic(void **state)
{
    (void)state;
    assert_int_equal(merd_quota_cores(100000, 100000), 1);
    assert_int_equal(merd_quota_cores(150000, 100000), 2);
    assert_int_equal(merd_quota_cores(50000, 100000), 1);
    assert_int_equal(merd_quota_cores(400000, 100000), 4);
    assert_int_equal(merd_quota_cores(-1, 100000), 0);
    assert_int_equal(merd_quota_cores(100000, 0), 0);
    assert_int_equal(merd_quota_cores(LLONG_MAX, 2), UINT32_MAX); /* no overflow on the way */
    assert_int_equal(merd_quota_cores(LLONG_MAX, LLONG_MAX), 1);
}

/* cgroup v2: the group's cpu.max and its ancestors', the smallest; a group
 * outside the namespace ("/../..") or a path that is not absolute is not
 * read (its files would be another group's). */
static void v2_smallest_up_the_tree(void **state)
{
    (void)state;
    char v2[300];
    snprintf(v2, sizeof v2, "%s/v2", root);
    put("v2/cpu.max", "junk that the root does not have\n");
    put("v2/a/cpu.max", "max 100000\n");
    put("v2/a/b/cpu.max", "150000 100000\n");
    assert_int_equal(merd_cgroup_cores(v2, "0::/a/b\n"), 2);
    assert_int_equal(merd_cgroup_cores(v2, "0::/a\n"), 0); /* "max": none */
    put("v2/a/cpu.max", "100000 100000\n");
    assert_int_equal(merd_cgroup_cores(v2, "0::/a/b\n"), 1);
    assert_int_equal(merd_cgroup_cores(v2, "0::/a/b/\n"), 1);
    assert_int_equal(merd_cgroup_cores(v2, "0::/nowhere\n"), 0);
    put("cpu.max", "200000 100000\n"); /* the directory above the mount */
    assert_int_equal(merd_cgroup_cores(v2, "0::/..\n"), 0);
    assert_int_equal(merd_cgroup_cores(v2, "0::/a/../..\n"), 0);
    assert_int_equal(merd_cgroup_cores(v2, "0::a/b\n"), 0);
    assert_int_equal(merd_cgroup_cores(v2, "0::/a/b..c\n"), 1); /* a name, not "..": /a above it counts */
}

/* cgroup v1: the cpu hierarchy by its joint name, or "cpu"; -1 is none;
 * other hierarchies' lines are passed over. */
static void v1_cpu_hierarchy(void **state)
{
    (void)state;
    char v1[300];
    snprintf(v1, sizeof v1, "%s/v1", root);
    put("v1/cpu,cpuacct/docker/x/cpu.cfs_quota_us", "250000\n");
    put("v1/cpu,cpuacct/docker/x/cpu.cfs_period_us", "100000\n");
    put("v1/cpu,cpuacct/cpu.cfs_quota_us", "-1\n");
    put("v1/cpu,cpuacct/cpu.cfs_period_us", "100000\n");
    assert_int_equal(merd_cgroup_cores(v1, "12:memory:/docker/x\n4:cpu,cpuacct:/docker/x\n0::/\n"), 3);
    put("v1/cpu/k/cpu.cfs_quota_us", "-1\n");
    put("v1/cpu/k/cpu.cfs_period_us", "100000\n");
    assert_int_equal(merd_cgroup_cores(v1, "1:cpu:/k\n"), 0);
    put("v1/cpu/k/cpu.cfs_quota_us", "50000\n");
    assert_int_equal(merd_cgroup_cores(v1, "1:cpu:/k\n2:cpuacct:/k"), 1);
    assert_int_equal(merd_cgroup_cores(v1, "4:cpu,cpuacct:/k\n"), 1); /* no joint mount: "cpu" */
    assert_int_equal(merd_cgroup_cores(v1, "3:cpuset:/k\n"), 0); /* not the cpu controller */
}

/* Nothing readable, or text that is no cgroup list: no quota. */
static void nothing_to_read(void **state)
{
    (void)state;
    assert_int_equal(merd_cgroup_cores(root, ""), 0);
    assert_int_equal(merd_cgroup_cores(root, "no colons here\n::\n0:\n"), 0);
    assert_int_equal(merd_cgroup_cores("/nonexistent-root", "0::/\n1:cpu:/\n"), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(quota_arithmetic),
        cmocka_unit_test(v2_smallest_up_the_tree),
        cmocka_unit_test(v1_cpu_hierarchy),
        cmocka_unit_test(nothing_to_read),
    };
    return cmocka_run_group_tests(tests, make_root, remove_root);
}
