/* meristemd — the CPU time a control group allows this process, in cores.
 *
 * A container started with a CPU quota (`--cpus 1`, a Kubernetes CPU
 * limit) still sees every core of its host in its CPU affinity. Lending a
 * snapshot's patches a thread per core there would oversubscribe the
 * quota: the kernel throttles the group for the rest of each period, and
 * the snapshot takes longer than on the cores the quota pays for. So the
 * cores meristemd lends are capped by the quota, rounded up (1.5 cores lends
 * 2 threads).
 *
 * Both cgroup versions: v2's cpu.max ("QUOTA PERIOD", or "max PERIOD" for
 * none) and v1's cpu.cfs_quota_us (-1 for none) and cpu.cfs_period_us. The
 * group is the process's own (/proc/self/cgroup) and the smallest quota of
 * it and the groups above it counts, as the kernel enforces each. */
#ifndef MERISTEMD_CPU_QUOTA_H
#define MERISTEMD_CPU_QUOTA_H

#include <stdint.h>

/* The cores a quota of `quota` µs per `period` µs allows, rounded up; 0
 * when there is no limit (quota or period not positive). */
uint32_t merd_quota_cores(long long quota, long long period);

/* The cores this process's control groups allow (merd_quota_cores of the
 * smallest quota of its group and those above it), read from the cgroup
 * file systems mounted at `root` (normally "/sys/fs/cgroup") for the groups
 * `self_cgroup` names (the text of /proc/self/cgroup); 0 when no quota
 * applies or none can be read. A group path that is not absolute or has a
 * ".." part (outside this cgroup namespace) is passed over. Cost: one or two
 * small file reads per group level. */
uint32_t merd_cgroup_cores(const char *root, const char *self_cgroup);

/* merd_cgroup_cores for this process: /proc/self/cgroup, /sys/fs/cgroup. */
uint32_t merd_cpu_quota_cores(void);

#endif
