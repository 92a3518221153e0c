/* test_threads.c — the functional renderer on its worker threads
 * (vp/parallel.c): frames of several batches of faces, with ties in every
 * sample two faces share, drawn by one VP whose thread count changes from
 * one run to the next, each the same as on one thread — every plane and
 * every statistic, the first tie and the faces that kept and lost it. */
#include "t.h"

#include "gp_helpers.h"
#include "../vp/vp_internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct {
    alb_frame f;
    alb_vp_stats st;
    unsigned n;
} first_frame;

static int keep(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    first_frame *k = ctx;
    if (k->n++ == 0) {
        if (alb_frame_copy(&k->f, f))
            return -1;
        k->st = *st;
    }
    return 0;
}

/* Every face of the scene text twice, the copy in another colour: the
 * copy ties with the first in every sample they share and loses each. */
static char *twice(const char *text)
{
    size_t n = strlen(text);
    char *out = malloc(2 * n + 1), *o = out;
    if (!out)
        return NULL;
    for (const char *line = text; *line;) {
        const char *end = strchr(line, '\n');
        size_t len = end ? (size_t)(end - line) + 1 : strlen(line);
        memcpy(o, line, len);
        o += len;
        const char *colour = strstr(line, " colour ");
        if (line[0] == ' ' && line[1] == 'f' && line[2] == ' ' && colour && colour < line + len) {
            size_t head = (size_t)(colour - line);
            memcpy(o, line, head);
            o += head;
            o += sprintf(o, " colour 7 7 7\n");
        }
        line += len;
    }
    *o = '\0';
    return out;
}

static int run_on(alb_vp *vp, const alb_ws_buf *b, first_frame *k)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    memset(k, 0, sizeof *k);
    return alb_vp_run_stream(vp, b->w, b->n, "test", keep, k, &d) != ALB_OK || k->n != 1;
}

TEST(threads_batches_and_ties_as_on_one_thread)
{
    scenegen_params gp = scenegen_defaults();
    gp.faces = 1600;   /* 3200 faces drawn: four batches of the threaded renderer */
    gp.behind = 0;
    gp.backfacing = 0;
    gp.size = 0.25;
    gp.flat = false;
    char *text = scenegen_random(3, &gp), *both = text ? twice(text) : NULL;
    alb_profile p;
    alb_ws_buf b;
    CHECK(both && alb_profile_lookup("a256", &p) == 0);
    if (!both || stream_of(both, &p, &b)) {
        CHECK_MSG(0, "no stream of the scene");
        free(text);
        free(both);
        return;
    }
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_vp *one = NULL, *many = NULL;
    first_frame ref, got;
    CHECK(alb_vp_create(&one, &p, &d) == ALB_OK && alb_vp_create(&many, &p, &d) == ALB_OK);
    if (one && many && !run_on(one, &b, &ref)) {
        CHECK_MSG(ref.st.faces > 2 * VP_BATCH, "%llu faces", (unsigned long long)ref.st.faces);
        CHECK_MSG(ref.st.depth_ties > 1000, "%llu ties", (unsigned long long)ref.st.depth_ties);
        /* the thread count changed on the same VP between the runs: the
         * workers stopped and started again */
        static const unsigned counts[] = {2, 3, 1, 5, 2, 8};
        for (unsigned i = 0; i < sizeof counts / sizeof counts[0]; i++) {
            CHECK(alb_vp_set_threads(many, counts[i]) == 0);
            CHECK_EQ(alb_vp_threads(many), counts[i]);
            if (run_on(many, &b, &got)) {
                CHECK_MSG(0, "the run on %u threads failed", counts[i]);
                continue;
            }
            CHECK_MSG(alb_frame_count_differences(&got.f, &ref.f) == 0,
                      "%zu pixels differ on %u threads", alb_frame_count_differences(&got.f, &ref.f),
                      counts[i]);
            CHECK_MSG(!memcmp(&got.st, &ref.st, sizeof got.st),
                      "statistics differ on %u threads (ties %llu / %llu, kept %llu / %llu)", counts[i],
                      (unsigned long long)got.st.depth_ties, (unsigned long long)ref.st.depth_ties,
                      (unsigned long long)got.st.tie_kept, (unsigned long long)ref.st.tie_kept);
            alb_frame_free(&got.f);
        }
        alb_frame_free(&ref.f);
    } else {
        CHECK_MSG(0, "the run on one thread failed");
    }
    alb_vp_destroy(one);
    alb_vp_destroy(many);
    alb_ws_buf_free(&b);
    free(text);
    free(both);
}
