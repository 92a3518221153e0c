/* test_counters.c — the VP for counters alone (vp_create_counters, the timed
 * model without frames): its fill forms without a tag plane against the
 * depth unit and the strict depth test, and the face a tie keeps — which the
 * tag plane named and a replay of the frame's faces now finds — against runs
 * with frames, on a hand-built scene and on random coplanar ones. */
#include "t.h"
#include "gp_helpers.h"
#include "albatros/sim.h"
#include "../vp/units.h"
#include "../tools/scenegen.h"

#include <stdlib.h>
#include <string.h>

#define STRIDE 24

/* The untagged forms (every one the host runs) on random rectangles, masked
 * 8 x 8 blocks and clean rectangles, with the tag plane NULL: the depths
 * and counts of the depth unit and the strict test, sample by sample. */
TEST(counters_untagged_forms_equal_the_depth_unit)
{
    vp_depth_forms_t forms[3];
    const char *names[3];
    const unsigned nforms = vp_depth_forms_untagged(forms, names);
    alb_profile p;
    alb_profile_lookup("t32", &p);
    alb_vp *vp = NULL;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_vp_create(&vp, &p, &d)) {
        CHECK_MSG(0, "alb_vp_create: %s", d.msg);
        return;
    }
    const uint32_t dmax = (uint32_t)(((uint64_t)1 << p.depth_bits) - 1);
    uint64_t seed = 2024;
    unsigned runs = 0, wins = 0, ties = 0, bad = 0;
    for (unsigned trial = 0; trial < 4000 && !bad; trial++) {
        const unsigned shape = trial % 3;   /* rectangle, block, clean rectangle */
        const uint32_t w = shape == 1 ? 8 : 1 + (uint32_t)(t_rand(&seed) % 19);
        const uint32_t h = shape == 1 ? 8 : 1 + (uint32_t)(t_rand(&seed) % 6);
        /* a shift either way, a first depth mid-store, steps of up to 100
         * depth units that round differently sample to sample */
        const int sh = (int)(t_rand(&seed) % 20) - 16, exp = sh + (int)vp->p - (int)p.depth_bits;
        const unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
        const int64_t one = (int64_t)1 << sr;
        const int64_t z = (((int64_t)(dmax / 4 + t_rand(&seed) % (dmax / 2)) << sr) >> sl) +
                          (int64_t)(t_rand(&seed) % (uint64_t)one);
        const int64_t dc = ((int64_t)(t_rand(&seed) % 201) - 100) * one + (int64_t)(t_rand(&seed) % (uint64_t)one);
        const int64_t dr = ((int64_t)(t_rand(&seed) % 201) - 100) * one + (int64_t)(t_rand(&seed) % (uint64_t)one);
        const uint64_t mask = shape == 1 ? t_rand(&seed) : ~0ull;
        /* the fast forms' precondition: every depth of the shape in range */
        bool in_range = true;
        uint32_t want_d[8 * STRIDE], d0[8 * STRIDE];
        uint32_t written = 0, tied = 0, nearest = 0;
        size_t first_tie = 0;
        for (uint32_t y = 0; y < 8; y++)
            for (uint32_t x = 0; x < STRIDE; x++) {
                const size_t i = y * STRIDE + x;
                const uint32_t dv = vp_depth_value(vp, z + (int64_t)x * dc + (int64_t)y * dr, exp);
                const bool in = x < w && y < h && (mask >> (8 * y + x) & 1);
                if (x < w && y < h && (dv == 0 || dv == dmax || z + (int64_t)x * dc + (int64_t)y * dr <= 0))
                    in_range = false;
                /* old depths at, below, above the new or anywhere */
                const uint64_t r = t_rand(&seed) % 4;
                d0[i] = shape == 2 ? 0 : r == 0 ? dv : r == 1 ? dv - 1 : r == 2 ? dv + 1
                                                                : (uint32_t)(t_rand(&seed) % dmax);
                want_d[i] = d0[i];
                if (!in)
                    continue;
                if (dv > want_d[i]) {
                    want_d[i] = dv;
                    written++;
                    nearest = dv > nearest ? dv : nearest;
                } else if (dv == want_d[i] && tied++ == 0) {
                    first_tie = i;
                }
            }
        if (!in_range)
            continue;
        const uint32_t tags[3] = {1, 2, 3};
        runs++;
        wins += written;
        ties += tied;
        for (unsigned k = 0; k < nforms; k++) {
            uint32_t depth[8 * STRIDE];
            memcpy(depth, d0, sizeof depth);
            vp_rect_result got = {written, 0, 0, nearest};   /* the store counts nothing */
            if (shape == 1)
                got = forms[k].block8(depth, NULL, STRIDE, z, dc, dr, sr, sl, mask, 0, 0, tags);
            else if (shape == 2)
                forms[k].store(depth, NULL, STRIDE, w, h, z, dc, dr, sr, sl, tags[0]);
            else
                got = forms[k].rect(depth, NULL, STRIDE, w, h, z, dc, dr, sr, sl, tags[0]);
            if (got.written != written || got.ties != tied || (tied && got.first_tie != first_tie) ||
                got.nearest != nearest || memcmp(depth, want_d, sizeof depth)) {
                CHECK_MSG(0, "%s, shape %u, %ux%u from N = %lld steps %lld, %lld shift %d: %u "
                          "written, %u tied (first %zu), nearest %u; %u, %u (%zu), %u expected, "
                          "or a depth differs", names[k], shape, w, h, (long long)z, (long long)dc,
                          (long long)dr, sh, got.written, got.ties, got.first_tie, got.nearest,
                          written, tied, first_tie, nearest);
                bad++;
                break;
            }
        }
    }
    alb_vp_destroy(vp);
    CHECK_EQ(bad, 0);
    printf("# untagged fill forms: %u shapes, %u wins, %u ties\n", runs, wins, ties);
    /* not vacuous: shapes ran, won and tied */
    CHECK_MSG(runs > 1000 && wins > runs && ties > runs / 4, "%u shapes, %u wins, %u ties", runs,
              wins, ties);
}

#define MAX_FRAMES 4

typedef struct {
    unsigned n, with_planes;
    alb_vp_stats s[MAX_FRAMES];
    alb_sim_counters c[MAX_FRAMES];
    uint32_t tie_face[MAX_FRAMES];   /* the face plane at the tie's pixel (aa = 0) */
} stats_log;

static int log_stats(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    stats_log *l = ctx;
    l->with_planes += f->rgb || f->depth || f->face;
    if (l->n < MAX_FRAMES) {
        l->s[l->n] = *vs;
        if (sc)
            l->c[l->n] = *sc;
        l->tie_face[l->n] = f->face && vs->depth_ties ? f->face[vs->tie_sample] : ALB_FRAME_NO_FACE;
    }
    l->n++;
    return 0;
}

static alb_err run_stats(const alb_profile *p, const alb_ws_buf *b, alb_fidelity fid, bool counters,
                         stats_log *l)
{
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_sim_options o = {.fid = fid, .counters_only = counters};
    memset(l, 0, sizeof *l);
    return alb_sim_run(p, b->w, b->n, "test", &o, log_stats, l, &d);
}

/* Screen space on t32 (x right, y up, larger depth nearer): A covers the
 * screen at depth 5; B the left half at 7; C the right quarter at 9, nearer
 * than B but not over it; D the left half at 7 again, tying with B.  The
 * lowest tie is the top-left sample: B kept it, not A (first to cover it),
 * nor C (nearest face before D, elsewhere). */
static const char tie_scene[] =
    "albatros-scene 1\n"
    "near 0.5\n"
    "screenspace\n"
    "object s\n"
    "v 0 0 5\nv 32 0 5\nv 32 32 5\nv 0 32 5\n"
    "v 0 0 7\nv 16 0 7\nv 16 32 7\nv 0 32 7\n"
    "v 24 0 9\nv 32 0 9\nv 32 32 9\nv 24 32 9\n"
    "f 1 2 3 4 colour 200 0 0\n"
    "f 5 6 7 8 colour 0 200 0\n"
    "f 9 10 11 12 colour 0 0 200\n"
    "f 5 6 7 8 colour 200 200 0\n"
    "end\n";

TEST(counters_tie_names_the_face_that_kept_it)
{
    alb_profile p;
    alb_profile_lookup("t32", &p);
    alb_ws_buf b;
    if (screen_stream_of(tie_scene, &p, &b)) {
        CHECK_MSG(0, "no stream");
        return;
    }
    stats_log lf, lt, lc;
    CHECK(run_stats(&p, &b, ALB_FIDELITY_FUNCTIONAL, false, &lf) == ALB_OK);
    CHECK(run_stats(&p, &b, ALB_FIDELITY_TIMED, true, &lt) == ALB_OK);
    CHECK(run_stats(&p, &b, ALB_FIDELITY_CYCLE, true, &lc) == ALB_OK);
    CHECK(lf.n == 1 && lt.n == 1 && lc.n == 1 && lt.with_planes == 0);
    /* the GP numbers the faces in the scene's order: A 0, B 1, C 2, D 3 */
    CHECK_EQ(lf.s[0].faces, 4);
    CHECK_EQ(lf.s[0].tie_sample, 0);
    CHECK_EQ(lf.s[0].tie_kept, 1);
    CHECK_EQ(lf.s[0].tie_lost, 3);
    CHECK_EQ(lf.tie_face[0], 1);
    /* D ties with B over the left half, 16 x 32 samples */
    CHECK_EQ(lf.s[0].depth_ties, 16 * 32);
    /* without frames (no tag plane), the same face and every statistic */
    CHECK_EQ(lt.s[0].tie_kept, 1);
    CHECK_MSG(!memcmp(&lt.s[0], &lf.s[0], sizeof lt.s[0]) && !memcmp(&lc.s[0], &lf.s[0], sizeof lc.s[0]),
              "a statistic differs without frames");
    alb_ws_buf_free(&b);
}

/* Random screen-space scenes of rectangles and triangles at four depths, so
 * that coplanar faces overlap and tie everywhere: with and without frames,
 * timed and cycle, simd=0 too, every statistic — the tie's kept face most of
 * all — the same. */
TEST(counters_random_coplanar_ties)
{
    uint64_t seed = 99;
    unsigned scenes = 0, tied = 0, kept_not_first = 0, bad = 0;
    for (unsigned s = 0; s < 60 && !bad; s++) {
        char text[8192];
        size_t at = (size_t)snprintf(text, sizeof text, "albatros-scene 1\nnear 0.5\nscreenspace\n");
        const unsigned nf = 3 + (unsigned)(t_rand(&seed) % 12);
        for (unsigned f = 0; f < nf; f++) {
            const unsigned x0 = (unsigned)(t_rand(&seed) % 28), y0 = (unsigned)(t_rand(&seed) % 28);
            const unsigned x1 = x0 + 2 + (unsigned)(t_rand(&seed) % (32 - x0 - 1));
            const unsigned y1 = y0 + 2 + (unsigned)(t_rand(&seed) % (32 - y0 - 1));
            const unsigned z = 2 + 2 * (unsigned)(t_rand(&seed) % 4);
            if (t_rand(&seed) % 3)
                at += (size_t)snprintf(text + at, sizeof text - at,
                                       "object o%u\nv %u %u %u\nv %u %u %u\nv %u %u %u\nv %u %u %u\n"
                                       "f 1 2 3 4\nend\n", f, x0, y0, z, x1, y0, z, x1, y1, z, x0,
                                       y1, z);
            else
                at += (size_t)snprintf(text + at, sizeof text - at,
                                       "object o%u\nv %u %u %u\nv %u %u %u\nv %u %u %u\nf 1 2 3\nend\n",
                                       f, x0, y0, z, x1, y0, z, x0, y1, z);
        }
        alb_profile p;
        alb_profile_lookup("t32", &p);
        p.simd = s % 4 == 3 ? 0 : 1;
        alb_ws_buf b;
        if (screen_stream_of(text, &p, &b)) {
            CHECK_MSG(0, "scene %u: no stream", s);
            return;
        }
        stats_log lf, lt, lc, ltf;
        if (run_stats(&p, &b, ALB_FIDELITY_FUNCTIONAL, false, &lf) ||
            run_stats(&p, &b, ALB_FIDELITY_TIMED, true, &lt) ||
            run_stats(&p, &b, ALB_FIDELITY_CYCLE, true, &lc) ||
            run_stats(&p, &b, ALB_FIDELITY_TIMED, false, &ltf)) {
            CHECK_MSG(0, "scene %u: a run failed", s);
            bad++;
            break;
        }
        scenes++;
        const alb_vp_stats *w = &lf.s[0];
        tied += w->depth_ties > 0;
        kept_not_first += w->depth_ties > 0 && w->tie_kept != 0;
        if (lt.n != 1 || lc.n != 1 || lt.with_planes ||
            memcmp(&lt.s[0], w, sizeof *w) || memcmp(&lc.s[0], w, sizeof *w) ||
            memcmp(&ltf.s[0], w, sizeof *w) || memcmp(&lt.c[0], &ltf.c[0], sizeof lt.c[0]) ||
            memcmp(&lc.c[0], &ltf.c[0], sizeof lc.c[0])) {
            CHECK_MSG(0, "scene %u (simd=%u): ties %llu at sample %llu, kept %llu / %llu without "
                      "frames, lost %llu, or another statistic or counter differs", s, p.simd,
                      (unsigned long long)w->depth_ties, (unsigned long long)w->tie_sample,
                      (unsigned long long)w->tie_kept, (unsigned long long)lt.s[0].tie_kept,
                      (unsigned long long)w->tie_lost);
            bad++;
        }
        alb_ws_buf_free(&b);
    }
    CHECK_EQ(bad, 0);
    printf("# coplanar scenes: %u, %u with ties, %u kept by a face other than the first\n", scenes,
           tied, kept_not_first);
    /* not vacuous: most scenes tie, and their kept face is often not face 0 */
    CHECK_MSG(scenes == 60 && tied > 30 && kept_not_first > 15, "%u scenes, %u with ties, %u "
              "kept by a face other than the first", scenes, tied, kept_not_first);
}

/* Large sloped triangles that cross one another on a 64 x 64 screen: the
 * first faces cover clean tiles whole, which the store of counters alone
 * leaves to their depth forms (VP_TILE_PLANE) until a later face reaches
 * them and they are written out — every later depth test there reads those
 * depths, so samples_written, the nearest depth and the counters must be
 * those of the run with frames (whose store writes every sample at once). */
TEST(counters_plane_tiles_hold_the_face_depths)
{
    uint64_t seed = 7;
    unsigned bad = 0, scenes = 0;
    uint64_t written = 0;
    for (unsigned s = 0; s < 40 && !bad; s++) {
        char text[4096];
        size_t at = (size_t)snprintf(text, sizeof text, "albatros-scene 1\nnear 0.5\nscreenspace\n");
        const unsigned nf = 2 + (unsigned)(t_rand(&seed) % 6);
        for (unsigned f = 0; f < nf; f++) {
            unsigned v[6];
            for (unsigned k = 0; k < 6; k++)
                v[k] = (unsigned)(t_rand(&seed) % 97) - 16;   /* past the screen too */
            at += (size_t)snprintf(text + at, sizeof text - at,
                                   "object o%u\nv %d %d %u\nv %d %d %u\nv %d %d %u\nf 1 2 3\nend\n", f,
                                   (int)v[0], (int)v[1], 2 + (unsigned)(t_rand(&seed) % 30), (int)v[2],
                                   (int)v[3], 2 + (unsigned)(t_rand(&seed) % 30), (int)v[4], (int)v[5],
                                   2 + (unsigned)(t_rand(&seed) % 30));
        }
        alb_profile p;
        small_profile(&p, "");
        p.simd = s % 3 == 2 ? 0 : 1;
        alb_ws_buf b;
        if (screen_stream_of(text, &p, &b))
            continue;   /* a triangle the GP refuses (degenerate): another scene */
        stats_log lt, ltf;
        if (run_stats(&p, &b, ALB_FIDELITY_TIMED, true, &lt) ||
            run_stats(&p, &b, ALB_FIDELITY_TIMED, false, &ltf)) {
            CHECK_MSG(0, "scene %u: a run failed", s);
            bad++;
        } else if (lt.n != 1 || memcmp(&lt.s[0], &ltf.s[0], sizeof lt.s[0]) ||
                   memcmp(&lt.c[0], &ltf.c[0], sizeof lt.c[0])) {
            CHECK_MSG(0, "scene %u (simd=%u): %llu samples written without frames, %llu with, "
                      "nearest %llu / %llu, or another statistic or counter differs", s, p.simd,
                      (unsigned long long)lt.s[0].samples_written,
                      (unsigned long long)ltf.s[0].samples_written,
                      (unsigned long long)lt.s[0].depth_nearest,
                      (unsigned long long)ltf.s[0].depth_nearest);
            bad++;
        }
        scenes++;
        written += ltf.s[0].samples_written;
        alb_ws_buf_free(&b);
    }
    CHECK_EQ(bad, 0);
    printf("# sloped scenes: %u, %llu samples written\n", scenes, (unsigned long long)written);
    CHECK_MSG(scenes >= 30 && written > 15ull * 64 * 64, "%u scenes, %llu samples written", scenes,
              (unsigned long long)written);
}

/* The timed model's hand-overs below an 8 x 8 cell when every step takes a
 * cycle (vp.c, time_split8_unit) are read off a timeline, and through the
 * fill queue in closed form when nothing can wait: short queues and slow
 * fills make the queue bind right after such blocks, so a cycle wrong in
 * the ring or in the fill unit's free cycle shows — against the cycle
 * model, which steps every clock. */
TEST(counters_unit_steps_through_short_queues)
{
    static const char *const sets[] = {
        "fill_queue=2", "fill_queue=2 fill_rate=2", "fill_queue=3 fill_rate=4",
        "fill_queue=2 fill_rate=1", "fill_rate=2", "fill_queue=2 fill_rate=16",
    };
    scenegen_params gp = scenegen_defaults();
    unsigned bad = 0, runs = 0;
    uint64_t stalls = 0;
    for (uint64_t seed = 1; seed <= 120 && !bad; seed++) {
        alb_profile p;
        small_profile(&p, sets[seed % 6]);
        gp.faces = 3 + (unsigned)(seed % 17);
        alb_ws_buf b;
        char *text = random_frames_stream(seed, &gp, 0, &p, &b);
        if (!text) {
            CHECK_MSG(0, "seed %llu: no stream", (unsigned long long)seed);
            return;
        }
        stats_log lt, lc;
        if (run_stats(&p, &b, ALB_FIDELITY_TIMED, true, &lt) ||
            run_stats(&p, &b, ALB_FIDELITY_CYCLE, true, &lc)) {
            CHECK_MSG(0, "seed %llu: a run failed", (unsigned long long)seed);
            bad++;
        } else {
            runs++;
            for (unsigned i = 0; i < lt.n && i < MAX_FRAMES; i++) {
                stalls += lc.c[i].engine_stall;
                if (lt.n != lc.n || memcmp(&lt.c[i], &lc.c[i], sizeof lt.c[i]) ||
                    memcmp(&lt.s[i], &lc.s[i], sizeof lt.s[i])) {
                    CHECK_MSG(0, "seed %llu (%s) frame %u: timed %llu cycles, %llu stalled; cycle "
                              "%llu, %llu (or another counter differs)", (unsigned long long)seed,
                              sets[seed % 6], i, (unsigned long long)lt.c[i].cycles,
                              (unsigned long long)lt.c[i].engine_stall,
                              (unsigned long long)lc.c[i].cycles,
                              (unsigned long long)lc.c[i].engine_stall);
                    bad++;
                    break;
                }
            }
        }
        alb_ws_buf_free(&b);
        free(text);
    }
    CHECK_EQ(bad, 0);
    printf("# short queues: %u runs, %llu engine stalls\n", runs, (unsigned long long)stalls);
    /* not vacuous: the queue made the engine wait */
    CHECK_MSG(runs == 120 && stalls > 1000, "%u runs, %llu stalls", runs, (unsigned long long)stalls);
}
