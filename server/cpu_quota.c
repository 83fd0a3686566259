/* meristemd — the CPU time a control group allows this process (cpu_quota.h). */
#include "config.h"

#include "server/cpu_quota.h"

#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>

#define PATH_MAX_LEN 4096

uint32_t merd_quota_cores(long long quota, long long period)
{
    if (quota <= 0 || period <= 0)
        return 0;
    long long cores = quota / period + (quota % period != 0); /* no overflow near LLONG_MAX */
    return cores > UINT32_MAX ? UINT32_MAX : (uint32_t)cores;
}

/* The first line of file `path` into buf (size n); false when unreadable. */
static bool read_line(const char *path, char *buf, size_t n)
{
    FILE *f = fopen(path, "r");
    if (f == NULL)
        return false;
    bool ok = fgets(buf, (int)n, f) != NULL;
    fclose(f);
    return ok;
}

/* The cores one group's files under `dir` allow (v2 when `v2`), or 0. */
static uint32_t group_cores(const char *dir, bool v2)
{
    char path[PATH_MAX_LEN], line[128];
    long long quota = 0, period = 0;
    if (v2) {
        if (snprintf(path, sizeof path, "%s/cpu.max", dir) >= (int)sizeof path || !read_line(path, line, sizeof line))
            return 0;
        if (strncmp(line, "max", 3) == 0 || sscanf(line, "%lld %lld", &quota, &period) != 2)
            return 0;
        return merd_quota_cores(quota, period);
    }
    if (snprintf(path, sizeof path, "%s/cpu.cfs_quota_us", dir) >= (int)sizeof path || !read_line(path, line, sizeof line) ||
        sscanf(line, "%lld", &quota) != 1)
        return 0;
    if (snprintf(path, sizeof path, "%s/cpu.cfs_period_us", dir) >= (int)sizeof path || !read_line(path, line, sizeof line) ||
        sscanf(line, "%lld", &period) != 1)
        return 0;
    return merd_quota_cores(quota, period);
}

/* The smallest of the quotas of group `group` (a path from the hierarchy's
 * root, "/" itself) and its ancestors, mounted at `mount`; 0 for none. */
static uint32_t hierarchy_cores(const char *mount, const char *group, bool v2)
{
    char dir[PATH_MAX_LEN];
    if (snprintf(dir, sizeof dir, "%s%s", mount, group) >= (int)sizeof dir)
        return 0;
    size_t stop = strlen(mount);
    uint32_t least = 0;
    for (;;) {
        size_t len = strlen(dir);
        while (len > stop && dir[len - 1] == '/')
            dir[--len] = '\0';
        uint32_t c = group_cores(dir, v2);
        if (c > 0 && (least == 0 || c < least))
            least = c;
        char *slash = strrchr(dir, '/');
        if (len <= stop || slash == NULL || (size_t)(slash - dir) < stop)
            return least;
        *slash = '\0';
    }
}

/* Whether `path` (NUL-terminated) is a group below the hierarchy's root:
 * absolute and with no ".." part. The kernel shows a group outside the
 * process's cgroup namespace as "/../..", whose files are not under the
 * mount this process sees: read there, they would be another group's. */
static bool inside_root(const char *path)
{
    if (path[0] != '/')
        return false;
    for (const char *p = path; (p = strstr(p, "..")) != NULL; p += 2)
        if (p[-1] == '/' && (p[2] == '/' || p[2] == '\0'))
            return false;
    return true;
}

/* Whether the comma-separated controller list `list` (length n) names "cpu". */
static bool names_cpu(const char *list, size_t n)
{
    for (size_t at = 0; at < n;) {
        size_t end = at;
        while (end < n && list[end] != ',')
            end++;
        if (end - at == 3 && strncmp(list + at, "cpu", 3) == 0)
            return true;
        at = end + 1;
    }
    return false;
}

/* The cores one line of /proc/self/cgroup ("ID:CONTROLLERS:PATH", length
 * len) allows, for the cpu controller's hierarchy (v1) or the unified one
 * (v2: ID 0, no controllers); 0 for others and for none. */
static uint32_t line_cores(const char *root, const char *line, size_t len)
{
    char mount[PATH_MAX_LEN], group[PATH_MAX_LEN];
    const char *c1 = memchr(line, ':', len);
    const char *c2 = c1 != NULL ? memchr(c1 + 1, ':', len - (size_t)(c1 + 1 - line)) : NULL;
    if (c2 == NULL)
        return 0;
    size_t path_len = len - (size_t)(c2 + 1 - line), controllers = (size_t)(c2 - c1 - 1);
    bool v2 = controllers == 0 && c1 - line == 1 && line[0] == '0';
    if (!(v2 || names_cpu(c1 + 1, controllers)) || path_len >= sizeof group)
        return 0;
    memcpy(group, c2 + 1, path_len);
    group[path_len] = '\0';
    if (!inside_root(group))
        return 0;
    if (v2)
        return snprintf(mount, sizeof mount, "%s", root) < (int)sizeof mount ? hierarchy_cores(mount, group, true) : 0;
    /* v1's cpu hierarchy is mounted by its joint name ("cpu,cpuacct"), often
     * with a "cpu" link beside it, or as "cpu" alone */
    int n = snprintf(mount, sizeof mount, "%s/%.*s", root, (int)controllers, c1 + 1);
    uint32_t c = n > 0 && n < (int)sizeof mount ? hierarchy_cores(mount, group, false) : 0;
    if (c == 0 && !(controllers == 3 && strncmp(c1 + 1, "cpu", 3) == 0) &&
        snprintf(mount, sizeof mount, "%s/cpu", root) < (int)sizeof mount)
        c = hierarchy_cores(mount, group, false);
    return c;
}

uint32_t merd_cgroup_cores(const char *root, const char *self_cgroup)
{
    uint32_t least = 0;
    for (const char *line = self_cgroup; line != NULL && *line != '\0';) {
        const char *end = strchr(line, '\n');
        size_t len = end != NULL ? (size_t)(end - line) : strlen(line);
        uint32_t c = line_cores(root, line, len);
        if (c > 0 && (least == 0 || c < least))
            least = c;
        line = end != NULL ? end + 1 : NULL;
    }
    return least;
}

uint32_t merd_cpu_quota_cores(void)
{
    FILE *f = fopen("/proc/self/cgroup", "r");
    if (f == NULL)
        return 0;
    char *text = NULL;
    size_t cap = 0;
    /* the whole file (it holds no NUL), however long: no line cut short */
    ssize_t n = getdelim(&text, &cap, '\0', f);
    fclose(f);
    uint32_t cores = n > 0 ? merd_cgroup_cores("/sys/fs/cgroup", text) : 0;
    free(text);
    return cores;
}
