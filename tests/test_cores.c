/* test_cores.c — --threads 0 means one thread per core this process may
 * use: the affinity mask taskset or a batch system sets, not every core
 * online. */
#define _GNU_SOURCE
#include "t.h"

#include "../vp/vp_internal.h"

#include <sched.h>

TEST(default_threads_follow_the_affinity_mask)
{
    cpu_set_t old, one;
    if (sched_getaffinity(0, sizeof old, &old) != 0) {
        CHECK_MSG(0, "sched_getaffinity failed");
        return;
    }
    unsigned n = alb_vp_cores();
    CHECK(n >= 1 && n == (unsigned)(CPU_COUNT(&old) < ALB_VP_MAX_THREADS ? CPU_COUNT(&old)
                                                                     : ALB_VP_MAX_THREADS));
    int first = 0;
    while (!CPU_ISSET(first, &old))
        first++;
    CPU_ZERO(&one);
    CPU_SET(first, &one);
    CHECK(sched_setaffinity(0, sizeof one, &one) == 0);
    CHECK_EQ(alb_vp_cores(), 1);
    CHECK(sched_setaffinity(0, sizeof old, &old) == 0);
    CHECK_EQ(alb_vp_cores(), n);
}
