/* test_fill.c — the fill unit's fast paths against the plain ones, and the
 * sample store's deferred work against what it defers: the SIMD row loop
 * against the depth unit sample by sample; whole frames with the fast paths
 * against the plain loops alone (vp->plain_fill), where depths saturate and
 * underflow too; a face shaded when its frame is resolved with the texture
 * it was drawn with; a frame drawn after another as if on a cleared store. */
#include "t.h"
#include "gp_helpers.h"
#include "../tools/scenegen.h"
#include "../vp/simd.h"
#include "../vp/units.h"

#include <stdlib.h>
#include <string.h>

/* The fast loop's preconditions for a row (fill.c): every N > 0 and in the
 * store's range, neither saturating nor underflowing. */
static bool row_in_range(const alb_vp *vp, int64_t z, int64_t dz, uint32_t n, int exp)
{
    const uint32_t dmax = (uint32_t)(((uint64_t)1 << vp->prof.depth_bits) - 1);
    int64_t last = z + (int64_t)(n - 1) * dz, lo = z < last ? z : last, hi = z < last ? last : z;
    return lo > 0 && vp_depth_value(vp, lo, exp) > 0 && vp_depth_value(vp, hi, exp) < dmax;
}

/* The fast loop's bounds on N (units_depth_range, one pair per face)
 * against the depth unit: N lies in [lo, hi] exactly where its stored depth
 * neither underflows to 0 nor saturates — at the bounds and one past them,
 * at random N and at N <= 0, for shifts far both ways and every store
 * width. */
TEST(fill_depth_range_is_the_depth_units)
{
    uint64_t seed = 7;
    unsigned checked = 0, inside = 0, bad = 0;
    for (unsigned bits = 8; bits <= 32; bits++) {
        const int64_t max = ((int64_t)1 << bits) - 1;
        for (int sh = -70; sh <= 70; sh++) {
            int64_t lo, hi;
            units_depth_range(sh, max, &lo, &hi);
            /* one past a bound that is INT64_MIN or INT64_MAX does not exist (skipped
             * below): the bound itself stands in, never an overflowing lo - 1, hi + 1 */
            const int64_t below = lo == INT64_MIN ? lo : lo - 1, above = hi == INT64_MAX ? hi : hi + 1;
            int64_t probe[12] = {below, lo, lo + 1, hi - 1, hi, above, 0, -1, INT64_MAX, 1};
            probe[10] = (int64_t)(t_rand(&seed) >> (t_rand(&seed) % 63));
            probe[11] = (int64_t)(t_rand(&seed) >> 1);
            for (unsigned k = 0; k < 12; k++) {
                const int64_t n = probe[k];
                if ((k == 0 && lo == INT64_MIN) || (k == 5 && hi == INT64_MAX))
                    continue;
                const uint32_t d = units_depth(n, sh, max);
                const bool want = d > 0 && d < (uint32_t)max, got = n >= lo && n <= hi;
                checked++;
                inside += want;
                if (want != got && bad++ < 5)
                    CHECK_MSG(0, "depth_bits %u shift %d N %lld: depth %u, range [%lld, %lld]",
                              bits, sh, (long long)n, d, (long long)lo, (long long)hi);
            }
        }
    }
    CHECK_EQ(bad, 0);
    CHECK_MSG(checked > 30000 && inside > checked / 5, "%u probes, %u in range", checked, inside);
}

/* One sample of the reference: the depth unit and the strict depth test. */
typedef struct {
    uint32_t written, ties, nearest;
    size_t first_tie;
} ref_counts;

static void ref_sample(const alb_vp *vp, uint32_t *depth, uint32_t *tag, size_t i, int64_t z,
                       int exp, uint32_t t, ref_counts *r)
{
    uint32_t dv = vp_depth_value(vp, z, exp);
    if (dv > depth[i]) {   /* strictly nearer wins (docs/vp.md §4) */
        depth[i] = dv;
        tag[i] = t;
        r->written++;
        r->nearest = dv > r->nearest ? dv : r->nearest;
    } else if (dv == depth[i] && r->ties++ == 0) {
        r->first_tie = i;
    }
}

/* Old store values for a sample of depth dv: at, just below or just above
 * it, or anywhere in the store's range (across 2^31 too). */
static uint32_t old_depth(uint64_t *seed, uint32_t dv, unsigned depth_bits)
{
    uint64_t r = t_rand(seed) % 4;
    uint32_t dmax = (uint32_t)(((uint64_t)1 << depth_bits) - 1);
    return r == 0 ? dv : r == 1 ? dv - 1 : r == 2 ? dv + (dv < dmax)
                                         : (uint32_t)(t_rand(seed) % ((uint64_t)dmax + 1));
}

#define STRIDE 40

/* Every form of the fill's fast loop the host runs (AVX2, SSE2, plain C),
 * both shapes — whole rectangles and masked 8 x 8 blocks — against
 * vp_depth_value and the strict depth test on random samples: widths up to
 * 37 (the SIMD bodies and their tails) and heights up to 5, shifts both
 * ways, store depths up to 2^32 - 1 (an unsigned comparison), random masks
 * and level masks; the samples and tags written, the counts written and
 * tied, the first tie in raster order and the largest depth written. */
TEST(fill_fast_forms_equal_the_depth_unit)
{
    vp_depth_forms_t forms[3];
    const char *names[3];
    const unsigned nforms = vp_depth_forms(forms, names);
    CHECK(nforms >= 1);
    static const unsigned depth_bits[] = {8, 16, 24, 31, 32};
    uint64_t seed = 42;
    unsigned shapes = 0, wins = 0, ties = 0, high = 0, straddle = 0, bad = 0, blocks_run = 0;
    for (unsigned b = 0; b < sizeof depth_bits / sizeof *depth_bits && !bad; b++) {
        alb_profile p;
        alb_profile_lookup("t32", &p);
        p.depth_bits = depth_bits[b];
        alb_vp *vp = NULL;
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_vp_create(&vp, &p, &d)) {
            CHECK_MSG(0, "alb_vp_create: %s", d.msg);
            return;
        }
        for (unsigned trial = 0; trial < 6000 && !bad; trial++) {
            /* a rectangle, a masked block, or a rectangle of clean store */
            const unsigned shape = trial % 3;
            const bool block = shape == 1, clean = shape == 2;
            uint32_t w = block ? 8 : 1 + (uint32_t)(t_rand(&seed) % 37);
            uint32_t h = block ? 8 : 1 + (uint32_t)(t_rand(&seed) % 5);
            int exp = (int)(t_rand(&seed) % 48) - 36;
            int sh = exp - (int)vp->p + (int)p.depth_bits;
            /* N of up to 44 bits, steps either way */
            int64_t z = (int64_t)(t_rand(&seed) >> (20 + t_rand(&seed) % 24)) + 1;
            /* steps small or up to 2^30 (past the AVX2 form's 32-bit lanes) */
            const int64_t range = trial % 5 == 4 ? (int64_t)1 << 30 : 2000;
            int64_t dz = (int64_t)(t_rand(&seed) % (uint64_t)(2 * range + 1)) - range;
            int64_t dr = (int64_t)(t_rand(&seed) % (uint64_t)(2 * range + 1)) - range;
            uint64_t mask = t_rand(&seed), mid = t_rand(&seed) & ~mask, fine = t_rand(&seed);
            mask |= mid;   /* some mid samples in the mask */
            mid &= ~fine;
            if (!row_in_range(vp, z, dz, w, exp) || !row_in_range(vp, z + (int64_t)(h - 1) * dr, dz, w, exp))
                continue;
            static uint32_t d0[8 * STRIDE], t0[8 * STRIDE], want_d[8 * STRIDE], want_t[8 * STRIDE];
            ref_counts want = {0, 0, 0, 0};
            const uint32_t tags[3] = {0xABCDE0, 0xABCDE1, 0xABCDE2};
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < STRIDE; x++) {
                    size_t i = y * STRIDE + x;
                    uint32_t dv = vp_depth_value(vp, z + (int64_t)x * dz + (int64_t)y * dr, exp);
                    d0[i] = want_d[i] = x >= w ? 0x5A5A5A5A : clean ? 0 : old_depth(&seed, dv, depth_bits[b]);
                    t0[i] = want_t[i] = (uint32_t)i;
                    high += x < w && dv >= 0x80000000u;
                    straddle += x < w && (dv >= 0x80000000u) != (d0[i] >= 0x80000000u);
                }
            for (uint32_t y = 0; y < h; y++)
                for (uint32_t x = 0; x < w; x++) {
                    unsigned bit = 8 * y + x;
                    if (block && !(mask >> bit & 1))
                        continue;
                    uint32_t t = !block ? tags[0] : fine >> bit & 1 ? tags[2]
                                                  : mid >> bit & 1  ? tags[1] : tags[0];
                    ref_sample(vp, want_d, want_t, y * STRIDE + x,
                               z + (int64_t)x * dz + (int64_t)y * dr, exp, t, &want);
                }
            unsigned sr = sh < 0 ? (unsigned)-sh : 0, sl = sh > 0 ? (unsigned)sh : 0;
            shapes++;
            blocks_run += block;
            wins += want.written;
            ties += want.ties;
            for (unsigned k = 0; k < nforms; k++) {
                static uint32_t depth[8 * STRIDE], tag[8 * STRIDE];
                memcpy(depth, d0, sizeof depth);
                memcpy(tag, t0, sizeof tag);
                vp_rect_result got = {want.written, 0, 0, want.nearest};   /* the store counts none */
                if (block)
                    got = forms[k].block8(depth, tag, STRIDE, z, dz, dr, sr, sl, mask, mid, fine, tags);
                else if (clean)
                    forms[k].store(depth, tag, STRIDE, w, h, z, dz, dr, sr, sl, tags[0]);
                else
                    got = forms[k].rect(depth, tag, STRIDE, w, h, z, dz, dr, sr, sl, tags[0]);
                if (got.written != want.written || got.ties != want.ties ||
                    (want.ties && got.first_tie != want.first_tie) || got.nearest != want.nearest ||
                    (clean && want.written != w * h) ||
                    memcmp(depth, want_d, h * STRIDE * sizeof *depth) ||
                    memcmp(tag, want_t, h * STRIDE * sizeof *tag)) {
                    CHECK_MSG(0, "%s %s, depth_bits %u, %ux%u samples from N = %lld steps %lld, "
                              "%lld, shift %d: %u written, %u tied (first %zu), nearest %u; %u, %u "
                              "(%zu), %u expected, or a sample differs", names[k],
                              block ? "block" : clean ? "clean rectangle" : "rectangle", depth_bits[b], w, h, (long long)z,
                              (long long)dz, (long long)dr, sh, got.written, got.ties,
                              got.first_tie, got.nearest, want.written, want.ties,
                              want.first_tie, want.nearest);
                    bad++;
                    break;
                }
            }
        }
        alb_vp_destroy(vp);
    }
    CHECK_EQ(bad, 0);
    printf("# fast fill forms:");
    for (unsigned k = 0; k < nforms; k++)
        printf(" %s", names[k]);
    printf("\n");
    /* not vacuous: shapes of every kind ran, ties, stores above 2^31 */
    CHECK_MSG(shapes > 4500 && blocks_run > 1500 && wins > shapes && ties > shapes / 2 &&
                  high > 100 && straddle > 100,
              "%u shapes (%u blocks), %u wins, %u ties, %u depths >= 2^31, %u tests across 2^31",
              shapes, blocks_run, wins, ties, high, straddle);
}

#define MAX_FRAMES 8

typedef struct {
    alb_frame f[MAX_FRAMES];
    alb_vp_stats s[MAX_FRAMES];
    unsigned n;
} frames;

static int keep(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    frames *k = ctx;
    if (k->n == MAX_FRAMES)
        return 0;
    k->s[k->n] = *st;
    return alb_frame_copy(&k->f[k->n++], f);
}

static void frames_free(frames *k)
{
    for (unsigned i = 0; i < k->n; i++)
        alb_frame_free(&k->f[i]);
    k->n = 0;
}

/* A stream through a VP of profile p: plain, the fill's plain loops alone. */
static alb_err run_vp(const alb_profile *p, const alb_ws_buf *b, bool plain, unsigned threads,
                      frames *out)
{
    alb_vp *vp = NULL;
    alb_diag d;
    alb_diag_init(&d, NULL);
    memset(out, 0, sizeof *out);
    alb_profile q = *p;
    q.simd = !plain;   /* plain: the fill's plain C forms and the engine's baseline too */
    alb_err e = alb_vp_create(&vp, &q, &d);
    if (!e && threads > 1 && alb_vp_set_threads(vp, threads))
        e = ALB_ERR_NOMEM;
    if (!e) {
        vp->plain_fill = plain;
        e = alb_vp_run_stream(vp, b->w, b->n, "test", keep, out, &d);
    }
    alb_vp_destroy(vp);
    return e;
}

/* The fast paths against the plain loops on a scene: every plane of every
 * frame and every statistic, on one thread and on three. */
static void stream_as_plain(const char *what, const alb_profile *p, const alb_ws_buf *b,
                            alb_vp_stats *sum)
{
    frames plain, fast, fast3;
    if (run_vp(p, b, true, 1, &plain) || run_vp(p, b, false, 1, &fast) ||
        run_vp(p, b, false, 3, &fast3)) {
        CHECK_MSG(0, "%s: a run failed", what);
    } else {
        CHECK(plain.n == fast.n && plain.n == fast3.n && plain.n > 0);
        for (unsigned i = 0; i < plain.n && i < fast.n && i < fast3.n; i++) {
            CHECK_MSG(alb_frame_count_differences(&plain.f[i], &fast.f[i]) == 0 &&
                          alb_frame_count_differences(&plain.f[i], &fast3.f[i]) == 0,
                      "%s frame %u: %zu pixels differ from the plain loops'", what, i,
                      alb_frame_count_differences(&plain.f[i], &fast.f[i]));
            CHECK_MSG(!memcmp(&plain.s[i], &fast.s[i], sizeof plain.s[i]) &&
                          !memcmp(&plain.s[i], &fast3.s[i], sizeof plain.s[i]),
                      "%s frame %u: statistics differ from the plain loops'", what, i);
            sum->samples_written += plain.s[i].samples_written;
            sum->samples_covered += plain.s[i].samples_covered;
            sum->depth_saturated += plain.s[i].depth_saturated;
            sum->depth_underflow += plain.s[i].depth_underflow;
            sum->depth_ties += plain.s[i].depth_ties;
        }
    }
    frames_free(&plain);
    frames_free(&fast);
    frames_free(&fast3);
}

static void same_as_plain(const char *what, const char *text, const char *profile,
                          const char *sets, alb_vp_stats *sum)
{
    alb_profile p;
    alb_profile_lookup(profile, &p);
    profile_set_all(&p, sets);
    alb_ws_buf b;
    if (stream_of(text, &p, &b)) {
        CHECK_MSG(0, "%s: no stream", what);
        return;
    }
    stream_as_plain(what, &p, &b, sum);
    alb_ws_buf_free(&b);
}

/* Random scenes whose nearest faces saturate the depth store (near 6: the
 * faces lie from Z = 2 on) or whose farthest underflow it (near 0.01 with
 * 8 to 10 bits: Z beyond 2.56 to 10.24), the built-in scene, odd profiles:
 * the fast loops decide nothing differently. */
TEST(fast_fill_equals_plain_fill)
{
    alb_vp_stats sum;
    memset(&sum, 0, sizeof sum);
    scenegen_params gp = scenegen_defaults();
    for (uint64_t seed = 1; seed <= 12; seed++) {
        gp.faces = 6 + (unsigned)(seed * 7 % 40);
        gp.flat = seed & 1;
        char *text = scenegen_random(seed, &gp);
        char *near = text ? strstr(text, "near 0.5\n") : NULL;
        CHECK(near != NULL);
        if (!near) {
            free(text);
            return;
        }
        /* "near 0.5" becomes "near 6.0" or "near .01" */
        memcpy(near, seed & 2 ? "near 6.0" : "near .01", 8);
        char what[64];
        snprintf(what, sizeof what, "seed %llu", (unsigned long long)seed);
        static const char *const sets[] = {"depth_bits=8", "depth_bits=9", "aa=1 depth_bits=10",
                                           "width=128 depth_bits=9", "depth_bits=32"};
        same_as_plain(what, text, "a256", sets[seed % 5], &sum);
        free(text);
    }
    /* screens so wide or tall that cells one sample high or wide split
     * with many edges active: their children lie side by side */
    gp.faces = 60;
    gp.flat = true;
    char *wide = scenegen_random(99, &gp);
    same_as_plain("256 x 4", wide, "a256", "height=4", &sum);
    same_as_plain("4 x 256", wide, "a256", "width=4", &sum);
    free(wide);
    char *builtin = builtin_scene_copy();
    same_as_plain("built-in", builtin, "a256", "", &sum);
    same_as_plain("built-in, aa=2", builtin, "a256", "aa=2", &sum);
    free(builtin);
    CHECK_MSG(sum.depth_saturated > 1000 && sum.depth_underflow > 1000 &&
                  sum.samples_written > 100000,
              "not every case met: %llu saturated, %llu underflowed, %llu written",
              (unsigned long long)sum.depth_saturated, (unsigned long long)sum.depth_underflow,
              (unsigned long long)sum.samples_written);
}

/* A fill wholly below the floor of its tile of the store or of its 8 x 8
 * block — the least depth of a face that covered it whole (fill.c) — is
 * skipped without its depth tests.  Against the plain loops, which test every sample: a
 * wall over the whole screen, then a face behind it (skipped), a face at
 * the wall's own depth (parallel to the screen: its greatest depth over a
 * tile is the floor, and every sample ties), a plane crossing the wall
 * (behind on the left, in front on the right: skipped, filled, and raising
 * the floors), and a sloped face after it; in cells, 8 x 8 blocks and whole
 * tiles, with one sample a pixel and four. */
static const char floor_scene[] =
    "albatros-scene 1\nnear 0.5\nscreenspace\nobject s\n"
    "v 0 0 5\nv 256 0 5\nv 256 256 5\nv 0 256 5\n"
    "v 10 10 2\nv 200 30 2\nv 90 220 2\n"
    "v 40 40 5\nv 168 40 5\nv 168 168 5\nv 40 168 5\n"
    "v 0 0 1\nv 256 0 9\nv 256 256 9\nv 0 256 1\n"
    "v 20 100 3\nv 250 120 8\nv 120 250 4\n"
    "f 1 2 3 4 colour 200 0 0\nf 5 6 7 colour 0 200 0\nf 8 9 10 11 colour 0 0 200\n"
    "f 12 13 14 15 colour 200 200 0\nf 16 17 18 colour 0 200 200\nend\n";

TEST(fills_below_a_tiles_floor_are_skipped_as_tested)
{
    static const char *const sets[] = {"", "aa=1"};
    for (unsigned i = 0; i < 2; i++) {
        alb_profile p;
        alb_profile_lookup("a256", &p);
        profile_set_all(&p, sets[i]);
        alb_ws_buf b;
        if (screen_stream_of(floor_scene, &p, &b)) {
            CHECK_MSG(0, "a256 %s: no stream", sets[i]);
            continue;
        }
        alb_vp_stats sum;
        memset(&sum, 0, sizeof sum);
        stream_as_plain(sets[i], &p, &b, &sum);
        /* the wall ties with its copy; the faces behind it cover samples
         * they do not write */
        CHECK_MSG(sum.depth_ties >= 128 * 128 &&
                      sum.samples_covered > sum.samples_written + (uint64_t)p.width * p.height / 2,
                  "a256 %s: %llu ties, %llu covered, %llu written", sets[i],
                  (unsigned long long)sum.depth_ties, (unsigned long long)sum.samples_covered,
                  (unsigned long long)sum.samples_written);
        alb_ws_buf_free(&b);
    }
}

/* The frame a stream of one textured face gives. */
static int face_alone(const alb_profile *p, const alb_ws_texture *tex, const alb_ws_frame *fr,
                      const alb_ws_face *face, alb_frame *out, alb_diag *d)
{
    alb_vp *vp = NULL;
    alb_err e = alb_vp_create(&vp, p, d);
    if (!e)
        e = alb_vp_config(vp, &(alb_ws_config){p->edge_frac_bits, p->coef_bits, 1.0f}, d);
    if (!e)
        e = alb_vp_texture(vp, tex, d);
    if (!e && alb_vp_frame_alloc(vp, out, false))
        e = ALB_ERR_NOMEM;
    if (!e) {
        alb_vp_frame_begin(vp, fr);
        e = alb_vp_face(vp, face, d);
    }
    if (!e)
        alb_vp_frame_end(vp, out);
    alb_vp_destroy(vp);
    return e ? -1 : 0;
}

/* Colour is the output stage's: a face drawn, then its texture replaced
 * before the frame is resolved, is shaded with the texels it was drawn
 * with, as the fill unit would have; a face drawn after the replacement
 * with the new ones.  On one thread and on two (the faces wait in a batch). */
TEST(deferred_shading_keeps_the_texture_a_face_was_drawn_with)
{
    char *text = builtin_scene_copy();
    alb_profile p;
    alb_profile_lookup("a256", &p);
    gp_run_result r;
    memset(&r, 0, sizeof r);
    CHECK(text && gp_run_text(text, "width=256 height=256 edge_frac_bits=13", &r) == 0);
    /* the stream's first textured face and its texture */
    alb_ws_reader rd;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_ws_texture tex = {0};
    uint32_t *texels = NULL, *inverse = NULL;
    const alb_ws_face *face = NULL;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_ws_reader_init(&rd, r.buf.w, r.buf.n, "t");
    while (ev && !rd.ended && alb_ws_next(&rd, ev, &d) == ALB_OK && !texels)
        if (ev->kind == ALB_WS_EV_TEXTURE) {
            size_t n = (size_t)1 << (2 * ev->u.texture.log2size);
            tex = ev->u.texture;
            texels = malloc(n * sizeof *texels);
            inverse = malloc(n * sizeof *inverse);
            for (size_t i = 0; texels && inverse && i < n; i++) {
                texels[i] = ev->u.texture.texels[i];
                inverse[i] = ~texels[i] & 0xFFFFFF;
            }
            tex.texels = texels;
        }
    for (unsigned i = 0; i < r.nfaces && !face; i++)
        if (r.faces[i].flags & ALB_WS_FACE_TEXTURE && r.faces[i].texture == tex.id)
            face = &r.faces[i];
    CHECK_MSG(texels && inverse && face, "the built-in scene's stream has a textured face");
    if (texels && inverse && face) {
        alb_ws_texture other = tex;
        other.texels = inverse;
        alb_ws_frame fr = r.frame;
        fr.fog = false;   /* the texels' colours themselves */
        alb_frame want, want_other;
        memset(&want, 0, sizeof want);
        memset(&want_other, 0, sizeof want_other);
        CHECK(face_alone(&p, &tex, &fr, face, &want, &d) == 0);
        CHECK(face_alone(&p, &other, &fr, face, &want_other, &d) == 0);
        /* the two differ where the face is seen, or the test shows nothing */
        CHECK(want.rgb && want_other.rgb &&
              alb_frame_count_differences(&want, &want_other) > 1000);
        for (unsigned threads = 1; threads <= 2; threads++) {
            alb_vp *vp = NULL;
            alb_frame got;
            memset(&got, 0, sizeof got);
            bool ok = !alb_vp_create(&vp, &p, &d) && !alb_vp_set_threads(vp, threads) &&
                      !alb_vp_config(vp, &(alb_ws_config){p.edge_frac_bits, p.coef_bits, 1.0f}, &d) &&
                      !alb_vp_texture(vp, &tex, &d) && !alb_vp_frame_alloc(vp, &got, false);
            if (ok) {
                alb_vp_frame_begin(vp, &fr);
                ok = !alb_vp_face(vp, face, &d) && !alb_vp_texture(vp, &other, &d);
            }
            if (ok)
                alb_vp_frame_end(vp, &got);
            CHECK_MSG(ok && want.rgb && alb_frame_count_differences(&got, &want) == 0,
                      "%u thread(s): the face drawn before its texture was replaced: %zu pixels "
                      "differ from its render with the old texels", threads,
                      ok && want.rgb ? alb_frame_count_differences(&got, &want) : 0);
            /* the next frame draws with the new texels */
            if (ok) {
                alb_vp_frame_begin(vp, &fr);
                ok = !alb_vp_face(vp, face, &d);
                alb_vp_frame_end(vp, &got);
            }
            CHECK_MSG(ok && want_other.rgb && alb_frame_count_differences(&got, &want_other) == 0,
                      "%u thread(s): the face drawn after the replacement", threads);
            alb_frame_free(&got);
            alb_vp_destroy(vp);
        }
        alb_frame_free(&want);
        alb_frame_free(&want_other);
    }
    free(texels);
    free(inverse);
    free(ev);
    gp_run_free(&r);
    free(text);
}

/* The store is cleared only where a frame's fills reach: a frame after one
 * that covered the whole screen must be what it is on a new VP — the
 * background and no face wherever its own faces do not reach. */
TEST(a_frame_after_another_is_drawn_on_a_clear_store)
{
    alb_profile p;
    alb_profile_lookup("a256", &p);
    static const char big[] =
        "albatros-scene 1\nbackground 10 20 30\nobject wall\n v -9 -9 5\n v 9 -9 5\n v 9 9 5\n"
        " v -9 9 5\n f 1 2 3 4 colour 200 100 50\nend\n";
    /* in front of the wall, and behind it: the first frame's floors
     * (fill.c) are not the second's */
    static const char *const small[] = {
        "albatros-scene 1\nbackground 10 20 30\nobject tile\n v -0.2 -0.3 3\n v 0.4 -0.2 3\n"
        " v 0.1 0.5 3\n f 1 2 3 colour 40 220 90\nend\n",
        "albatros-scene 1\nbackground 10 20 30\nobject tile\n v -0.5 -0.6 8\n v 0.9 -0.4 8\n"
        " v 0.2 1 8\n f 1 2 3 colour 40 220 90\nend\n"};
    alb_ws_buf a, b;
    CHECK(stream_of(big, &p, &a) == 0);
    for (unsigned which = 0; which < 2; which++) {
        CHECK(stream_of(small[which], &p, &b) == 0);
        for (unsigned threads = 1; threads <= 3; threads += 2) {
            frames alone, after;
            memset(&alone, 0, sizeof alone);
            memset(&after, 0, sizeof after);
            CHECK(run_vp(&p, &b, false, threads, &alone) == 0 && alone.n == 1);
            /* one VP: the big frame's stream, then the small one's */
            alb_vp *vp = NULL;
            alb_diag d;
            alb_diag_init(&d, NULL);
            bool ok = !alb_vp_create(&vp, &p, &d) && !alb_vp_set_threads(vp, threads) &&
                      !alb_vp_run_stream(vp, a.w, a.n, "big", keep, &after, &d) &&
                      !alb_vp_run_stream(vp, b.w, b.n, "small", keep, &after, &d);
            CHECK(ok && after.n == 2 && alone.n == 1);
            if (ok && after.n == 2 && alone.n == 1) {
                /* the first covered the screen; the second is the small face alone */
                CHECK(after.f[0].face[0] != ALB_FRAME_NO_FACE);
                CHECK(after.f[1].face[0] == ALB_FRAME_NO_FACE);
                CHECK_MSG(alb_frame_count_differences(&after.f[1], &alone.f[0]) == 0,
                          "%u thread(s): %zu pixels of the second frame differ from it on a new VP",
                          threads, alb_frame_count_differences(&after.f[1], &alone.f[0]));
            }
            alb_vp_destroy(vp);
            frames_free(&alone);
            frames_free(&after);
        }
        alb_ws_buf_free(&b);
    }
    alb_ws_buf_free(&a);
}

/* The frames of a stream through one VP on `threads` threads, each
 * resolved into every plane and into a frame with only the planes `planes`
 * has: those must hold the full frame's values, the others stay NULL. */
static unsigned planes_alone(const alb_profile *p, const alb_ws_buf *b, unsigned planes,
                             unsigned threads)
{
    alb_vp *vp = NULL;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_vp_create(&vp, p, &d))
        return 1;
    if (alb_vp_set_threads(vp, threads)) {
        alb_vp_destroy(vp);
        return 1;
    }
    alb_ws_reader r;
    alb_ws_reader_init(&r, b->w, b->n, "test");
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_frame all, some;
    memset(&all, 0, sizeof all);
    memset(&some, 0, sizeof some);
    unsigned bad = !ev, resolved = 0;
    while (!bad && !r.ended && !alb_ws_next(&r, ev, &d)) {
        if (ev->kind == ALB_WS_EV_CONFIG) {
            alb_frame_free(&all);
            alb_frame_free(&some);
            bad |= alb_vp_config(vp, &ev->u.config, &d) != ALB_OK ||
                   alb_vp_frame_alloc(vp, &all, false) || alb_vp_frame_alloc_planes(vp, &some, planes);
        } else if (ev->kind == ALB_WS_EV_TEXTURE) {
            bad |= alb_vp_texture(vp, &ev->u.texture, &d) != ALB_OK;
        } else if (ev->kind == ALB_WS_EV_FRAME) {
            alb_vp_frame_begin(vp, &ev->u.frame);
        } else if (ev->kind == ALB_WS_EV_FACE) {
            bad |= alb_vp_face(vp, &ev->u.face, &d) != ALB_OK;
        } else if (ev->kind == ALB_WS_EV_FRAME_END) {
            /* the same samples resolved twice: the store is left as it was */
            alb_vp_frame_end(vp, &some);
            alb_vp_frame_end(vp, &all);
            const size_t n = (size_t)all.width * all.height;
            bad |= alb_frame_planes(&some) != planes;
            bad |= some.rgb && memcmp(some.rgb, all.rgb, 3 * n * sizeof *all.rgb);
            bad |= some.depth && memcmp(some.depth, all.depth, n * sizeof *all.depth);
            bad |= some.face && memcmp(some.face, all.face, n * sizeof *all.face);
            bad |= some.level && memcmp(some.level, all.level, n);
            bad |= some.coverage && memcmp(some.coverage, all.coverage, n * sizeof *all.coverage);
            resolved++;
        }
    }
    bad |= !r.ended || resolved == 0;
    free(ev);
    alb_frame_free(&all);
    alb_frame_free(&some);
    alb_vp_destroy(vp);
    return bad;
}

/* Every subset of the planes, on the built-in scene (shaded, textured,
 * fogged) with one sample a pixel and with four. */
TEST(a_frame_resolves_only_the_planes_it_has)
{
    char *text = builtin_scene_copy();
    static const char *const sets[] = {"", "aa=1"};
    for (unsigned k = 0; k < 2; k++) {
        alb_profile p;
        small_profile(&p, sets[k]);
        alb_ws_buf b;
        if (stream_of(text, &p, &b)) {
            CHECK_MSG(0, "no stream");
            break;
        }
        for (unsigned planes = 0; planes <= ALB_FRAME_PLANES; planes++)
            CHECK_MSG(planes_alone(&p, &b, planes, 1) == 0, "%s: planes 0x%02x differ from the full "
                      "frame's", sets[k], planes);
        alb_ws_buf_free(&b);
    }
    free(text);
}

/* A frame of flat faces resolved into its colour plane alone takes each
 * sample's colour from the palette (vp_flat_samples); into every plane,
 * from the runs of one face (sample_row) — two ways to the same bits.
 * Scenes of few large faces (steps of one face: the pattern), of many
 * small ones (rows sample by sample) and both at once, on square and
 * narrow screens, one sample a pixel and four (where the runs alone
 * serve), on one thread and three. */
TEST(flat_colour_plane_alone_is_the_full_frames)
{
    static const struct {
        unsigned faces;
        double size;
    } scenes[] = {{12, 0.5}, {1500, 0.03}, {400, 0.08}};
    static const struct {
        unsigned w, h;
        const char *sets;
    } screens[] = {{256, 256, ""}, {256, 4, ""}, {4, 256, ""}, {128, 128, "aa=1"}};
    for (unsigned k = 0; k < sizeof scenes / sizeof *scenes; k++)
        for (unsigned q = 0; q < sizeof screens / sizeof *screens; q++) {
            alb_profile p;
            alb_profile_lookup("t32", &p);
            profile_set_all(&p, screens[q].sets);
            p.width = screens[q].w;
            p.height = screens[q].h;
            p.edge_frac_bits = 14;
            scenegen_params gp = scenegen_defaults();
            gp.faces = scenes[k].faces;
            gp.size = scenes[k].size;
            gp.flat = true;
            gp.backfacing = 0;
            alb_ws_buf b;
            char *text = random_frames_stream(40 + k, &gp, 1, &p, &b);
            if (!text) {
                CHECK_MSG(0, "no stream");
                continue;
            }
            for (unsigned threads = 1; threads <= 3; threads += 2)
                CHECK_MSG(planes_alone(&p, &b, ALB_FRAME_RGB, threads) == 0,
                          "%u faces of size %g, %u x %u %s, %u thread(s): the colour plane alone "
                          "differs from the full frame's", scenes[k].faces, scenes[k].size,
                          screens[q].w, screens[q].h, screens[q].sets, threads);
            free(text);
            alb_ws_buf_free(&b);
        }
}

/* vp_flat_samples against the rule it keeps — a sample's colour is the
 * palette's entry for its tag's face, the background's after the faces for
 * no face — over runs of faces from one sample long to many steps, at any
 * level: every length from 1 to 70 at every start, both ways of storing a
 * step, and not one value written past the samples; its count of steps of
 * more than one face is checked against a count made here. */
TEST(flat_samples_are_the_palettes_and_nothing_else)
{
    enum { N = 70, NF = 5 };
    /* the palette's words hold a sample's six bytes as the plane does */
    uint16_t col[NF + 1][3];
    uint64_t pal[NF + 1];
    for (unsigned f = 0; f <= NF; f++) {
        for (unsigned ch = 0; ch < 3; ch++)
            col[f][ch] = (uint16_t)(0x1000 * (ch + 1) + f);
        pal[f] = 0;
        memcpy(&pal[f], col[f], sizeof col[f]);
    }
    uint64_t seed = 5;
    uint32_t tag[N + 8];
    uint16_t buf[3 * (N + 8)];
    unsigned bad = 0, bad_count = 0, mixed_seen = 0, one_seen = 0;
    for (unsigned trial = 0; trial < 200; trial++) {
        /* runs of 1 to 20 samples of a face or of none, levels at random */
        for (size_t i = 0; i < N + 8;) {
            const uint64_t r = t_rand(&seed);
            const uint32_t f = (uint32_t)(r % (NF + 1)), len = 1 + (uint32_t)(r >> 8) % (trial % 2 ? 4 : 20);
            for (uint32_t j = 0; j < len && i < N + 8; j++, i++)
                tag[i] = f == NF ? VP_TAG_NONE : f << VP_TAG_LEVEL_BITS | (uint32_t)(t_rand(&seed) % 16);
        }
        for (size_t at = 0; at < 4; at++)
            for (size_t n = 1; n + at <= N; n++)
                for (int by_sample = 0; by_sample < 2; by_sample++) {
                    for (size_t i = 0; i < 3 * (N + 8); i++)
                        buf[i] = (uint16_t)(0x5A00 + i);
                    vp_flat_rows fr = {pal, NF, by_sample, 0, 0};
                    vp_flat_samples(buf + 3 * at, tag + at, n, &fr);
                    for (size_t i = 0; i < N + 8; i++) {
                        const bool in = i >= at && i < at + n;
                        const uint32_t f = tag[i] >> VP_TAG_LEVEL_BITS;
                        const uint16_t *c = col[f < NF ? f : NF];
                        for (unsigned ch = 0; ch < 3; ch++)
                            bad += buf[3 * i + ch] != (in ? c[ch] : (uint16_t)(0x5A00 + 3 * i + ch));
                    }
                    /* the steps: eight samples with at least one more after them */
                    size_t steps = 0, mixed = 0;
                    for (size_t s = 0; s + 8 < n; s += 8, steps++) {
                        unsigned faces = 1;
                        for (unsigned j = 1; j < 8; j++)
                            faces += (tag[at + s + j] | VP_TAG_LEVEL_MASK) != (tag[at + s] | VP_TAG_LEVEL_MASK);
                        mixed += faces > 1;
                        mixed_seen += faces > 1;
                        one_seen += faces == 1;
                    }
#if VP_SSE2
                    bad_count += fr.steps != steps || fr.mixed != mixed;
#else
                    bad_count += fr.steps != 0 || fr.mixed != 0;   /* plain C: no steps */
#endif
                }
    }
    CHECK_EQ(bad, 0);
    CHECK_EQ(bad_count, 0);
    CHECK(mixed_seen > 1000 && one_seen > 1000);
}

/* A run of one colour (the output stage's flat faces): every length from 0
 * to 40 — eight samples a step, the last eight or four overlapping, a few
 * alone — at every start, and not one value past the run. */
TEST(fill_rgb_writes_the_run_and_nothing_else)
{
    const uint16_t rgb[3] = {0x1234, 0xABCD, 0x0F0F};
    uint16_t buf[3 * 48];
    unsigned bad = 0;
    for (size_t at = 0; at < 4; at++)
        for (size_t n = 0; n <= 40; n++) {
            for (size_t i = 0; i < 3 * 48; i++)
                buf[i] = (uint16_t)(0x5A00 + i);
            vp_fill_rgb(buf + 3 * at, n, rgb);
            for (size_t i = 0; i < 3 * 48; i++) {
                const bool in = i >= 3 * at && i < 3 * (at + n);
                bad += buf[i] != (in ? rgb[i % 3] : (uint16_t)(0x5A00 + i));
            }
        }
    CHECK_MSG(bad == 0, "%u values wrong", bad);
}
