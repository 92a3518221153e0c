/* test_words.c — the word format: every packet by round trip, every
 * malformation by the message and offset the decoder must give. */
#include "t.h"
#include "../common/fix.h"
#include "albatros/words.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static alb_ws_face random_face(uint64_t *s, unsigned frac, unsigned coef)
{
    alb_ws_face f;
    memset(&f, 0, sizeof f);
    f.id = (uint32_t)t_rand(s);
    f.flags = (uint8_t)(t_rand(s) & ALB_WS_FACE_FLAGS_ALL);
    f.texture = (uint8_t)t_rand(s);
    f.rgb = (uint32_t)t_rand(s) & 0xFFFFFF;
    f.n_edges = (uint8_t)(t_rand(s) % (ALB_WS_MAX_EDGES + 1));
    int32_t lim = (1 << (coef - 1)) - 1;
    alb_ws_form *forms[4] = {&f.depth, &f.shade, &f.tex_u, &f.tex_v};
    for (int i = 0; i < 4; i++) {
        forms[i]->exp = (int32_t)(t_rand(s) % 256) - 128;
        for (int k = 0; k < 3; k++)
            forms[i]->m[k] = (int32_t)(t_rand(s) % (2u * (uint32_t)lim + 1)) - lim;
    }
    for (unsigned i = 0; i < f.n_edges; i++) {
        f.edge[i].u = t_rand(s) & 1;
        f.edge[i].r = t_rand(s) & 1;
        f.edge[i].x1 = (uint32_t)(t_rand(s) % (1u << (3 + frac)));
        f.edge[i].x2 = (uint32_t)(t_rand(s) % (1u << (3 + frac)));
    }
    return f;
}

static bool forms_equal(const alb_ws_form *a, const alb_ws_form *b)
{
    return a->exp == b->exp && !memcmp(a->m, b->m, sizeof a->m);
}

TEST(words_round_trip)
{
    uint64_t s = 99;
    for (int trial = 0; trial < 200; trial++) {
        alb_ws_config cfg = {EDGE_FRAC_MIN + (unsigned)(t_rand(&s) % (EDGE_FRAC_MAX - EDGE_FRAC_MIN + 1)),
                         COEF_BITS_MIN + (unsigned)(t_rand(&s) % (COEF_BITS_MAX - COEF_BITS_MIN + 1)),
                         (float)t_uniform(&s, 0.001, 100)};
        alb_ws_buf b;
        alb_ws_buf_init(&b);
        alb_ws_put_config(&b, &cfg);
        uint32_t tex[16];
        for (int i = 0; i < 16; i++)
            tex[i] = (uint32_t)t_rand(&s) & 0xFFFFFF;
        alb_ws_texture t = {7, 2, tex};
        alb_ws_put_texture(&b, &t);
        alb_ws_frame fr = {(uint32_t)trial, 0x123456, true, 0xABCDEF, 100, 5000};
        alb_ws_put_frame(&b, &fr);
        static alb_ws_face faces[8];
        for (int i = 0; i < 8; i++) {
            faces[i] = random_face(&s, cfg.edge_frac_bits, cfg.coef_bits);
            alb_ws_put_face(&b, &faces[i]);
        }
        alb_ws_put_frame_end(&b, 8);
        alb_ws_put_end(&b);
        alb_ws_reader r;
        alb_ws_reader_init(&r, b.w, b.n, "rt");
        alb_ws_event *ev = malloc(sizeof *ev);
        alb_diag d;
        alb_diag_init(&d, NULL);
        int nface = 0;
        bool ok = true;
        while (ok && !r.ended) {
            if (alb_ws_next(&r, ev, &d)) {
                CHECK_MSG(0, "decode: %s", d.msg);
                ok = false;
                break;
            }
            switch (ev->kind) {
            case ALB_WS_EV_CONFIG:
                CHECK(ev->u.config.edge_frac_bits == cfg.edge_frac_bits &&
                      ev->u.config.coef_bits == cfg.coef_bits && ev->u.config.near == cfg.near);
                break;
            case ALB_WS_EV_TEXTURE:
                CHECK(ev->u.texture.id == 7 && ev->u.texture.log2size == 2 &&
                      !memcmp(ev->u.texture.texels, tex, sizeof tex));
                break;
            case ALB_WS_EV_FRAME:
                CHECK(ev->u.frame.number == fr.number && ev->u.frame.background == fr.background &&
                      ev->u.frame.fog == fr.fog && ev->u.frame.fog_rgb == fr.fog_rgb &&
                      ev->u.frame.fog_near == fr.fog_near && ev->u.frame.fog_far == fr.fog_far);
                break;
            case ALB_WS_EV_FACE: {
                const alb_ws_face *a = &faces[nface++], *g = &ev->u.face;
                bool same = a->id == g->id && a->flags == g->flags && a->texture == g->texture &&
                            a->rgb == g->rgb && a->n_edges == g->n_edges &&
                            forms_equal(&a->depth, &g->depth);
                for (unsigned k = 0; k < a->n_edges && same; k++)
                    same = a->edge[k].u == g->edge[k].u && a->edge[k].r == g->edge[k].r &&
                           a->edge[k].x1 == g->edge[k].x1 && a->edge[k].x2 == g->edge[k].x2;
                if (a->flags & ALB_WS_FACE_SHADE)
                    same &= forms_equal(&a->shade, &g->shade);
                if (a->flags & ALB_WS_FACE_TEXTURE)
                    same &= forms_equal(&a->tex_u, &g->tex_u) && forms_equal(&a->tex_v, &g->tex_v);
                CHECK(same);
                CHECK_EQ(ev->count, alb_ws_face_words(a));
                break;
            }
            case ALB_WS_EV_FRAME_END:
                CHECK_EQ(ev->u.faces, 8);
                break;
            case ALB_WS_EV_END:
                break;
            }
        }
        CHECK_EQ(nface, 8);
        free(ev);
        alb_ws_buf_free(&b);
    }
}

/* A small valid stream: CONFIG, FRAME, one FACE with two edges, FRAME_END, END. */
static size_t valid_stream(uint32_t *w)
{
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_ws_config cfg = {14, 24, 0.5f};
    alb_ws_put_config(&b, &cfg);
    alb_ws_frame fr = {0, 0, false, 0, 0, 0};
    alb_ws_put_frame(&b, &fr);
    alb_ws_face f;
    memset(&f, 0, sizeof f);
    f.n_edges = 2;
    f.flags = ALB_WS_FACE_SHADE;
    f.edge[0] = (alb_ws_edge){1, 0, 3u << 14, 3u << 14};
    f.edge[1] = (alb_ws_edge){0, 1, 3u << 14, 2u << 14};
    alb_ws_put_face(&b, &f);
    alb_ws_put_frame_end(&b, 1);
    alb_ws_put_end(&b);
    memcpy(w, b.w, b.n * 4);
    size_t n = b.n;
    alb_ws_buf_free(&b);
    return n;
}

/* Decode to the first error; return its message and byte offset. */
static alb_err decode_all(const uint32_t *w, size_t n, alb_diag *d)
{
    alb_ws_reader r;
    alb_ws_reader_init(&r, w, n, "bad.stream");
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_err e = ALB_OK;
    while (!r.ended && !(e = alb_ws_next(&r, ev, d)))
        ;
    free(ev);
    return e;
}

TEST(words_malformed_streams_are_named)
{
    uint32_t good[64];
    size_t n = valid_stream(good);
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK_EQ(decode_all(good, n, &d), ALB_OK);
    /* layout: 0-2 CONFIG, 3-7 FRAME, 8 FACE hdr, 9 id, 10 rgb, 11-14 depth,
     * 15-18 shade, 19-22 edges, 23 FRAME_END, 24 END */
    CHECK_EQ(n, 25);
    static const struct {
        size_t word;          /* word to corrupt */
        uint32_t value;
        long long offset;     /* expected error offset in bytes */
        const char *msg;
    } cases[] = {
        {0, 0xA5020002, 0, "CONFIG version 2"},
        {0, 0xA5010001, 0, "CONFIG length 1, expected 2"},
        {0, 0xF0000000, 0, "FRAME before CONFIG"},
        {1, 0x00001803, 4, "CONFIG formats"},
        {2, 0xBF800000, 8, "near = -1"},
        {3, 0x12345678, 12, "not a packet opcode"},
        {4, 0x01000000, 16, "background has bits 31..24"},
        {8, 0xFA02F000, 32, "reserved bits"},
        {8, 0xFA410100, 32, "the VP edge store holds 64"},
        {11, 200, 44, "depth.exp = 200"},
        {12, 1u << 23, 48, "does not fit 24-bit mantissa"},
        {19, 0x80000000u | (8u << 14), 76, "edge[0].X1"},
        {22, 8u << 14, 88, "edge[1].X2"},
        {23, 0xFE000002, 92, "FRAME_END counts 2 faces, the frame had 1"},
        {24, 0xFF000001, 96, "END has reserved bits"},
        {23, 0xF0000001, 92, "FRAME inside a frame"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        uint32_t w[64];
        memcpy(w, good, n * 4);
        w[cases[i].word] = cases[i].value;
        alb_diag_init(&d, NULL);
        alb_err e = decode_all(w, n, &d);
        CHECK_EQ(e, ALB_ERR_STREAM);
        CHECK_EQ(d.offset, cases[i].offset);
        CHECK_STR_CONTAINS(d.msg, cases[i].msg);
    }
    /* truncations: inside a face, before END; extra words after END */
    alb_diag_init(&d, NULL);
    CHECK_EQ(decode_all(good, 21, &d), ALB_ERR_STREAM);
    CHECK_STR_CONTAINS(d.msg, "truncated inside FACE edges");
    alb_diag_init(&d, NULL);
    CHECK_EQ(decode_all(good, 24, &d), ALB_ERR_STREAM);
    CHECK_STR_CONTAINS(d.msg, "without an END");
    uint32_t longer[64];
    memcpy(longer, good, n * 4);
    longer[n] = 0;
    alb_diag_init(&d, NULL);
    CHECK_EQ(decode_all(longer, n + 1, &d), ALB_ERR_STREAM);
    CHECK_STR_CONTAINS(d.msg, "1 words after END");
    alb_diag_init(&d, NULL);
    CHECK_EQ(decode_all(good, 0, &d), ALB_ERR_STREAM);
}

TEST(words_dump_names_fields)
{
    uint32_t good[64];
    size_t n = valid_stream(good);
    char *text = NULL;
    size_t len = 0;
    FILE *f = open_memstream(&text, &len);
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK_EQ(alb_ws_dump(f, good, n, "x", &d), ALB_OK);
    fclose(f);
    CHECK_STR_CONTAINS(text, "0000004c  8000c000  edge[0] U=1 R=0 X1=0xc000 (+0.000000)");
    CHECK_STR_CONTAINS(text, "edge[1] X2=0x8000 (-1.000000)");
    CHECK_STR_CONTAINS(text, "FACE edges=2 flags=S-- texture=0");
    CHECK_STR_CONTAINS(text, "FRAME_END faces=1");
    free(text);
}

TEST(fix_floor_shift_matches_floor_division)
{
    uint64_t s = 1;
    for (int i = 0; i < 100000; i++) {
        int64_t x = (int64_t)(t_rand(&s) >> (t_rand(&s) % 63)) * ((t_rand(&s) & 1) ? 1 : -1);
        unsigned sh = (unsigned)(t_rand(&s) % 40);
        double want = floor((double)x / ldexp(1, (int)sh));
        int64_t got = fix_floor_shr(x, sh);
        if (fabs((double)x) < 9e15 && (double)got != want) {
            CHECK_MSG(0, "floor(%lld / 2^%u) = %lld, expected %.0f", (long long)x, sh,
                      (long long)got, want);
            return;
        }
    }
    CHECK_EQ(fix_floor_shr(-1, 1), -1);
    CHECK_EQ(fix_floor_shr(-2, 1), -1);
    CHECK_EQ(fix_floor_shr(-3, 1), -2);
    CHECK_EQ(fix_floor_shr(INT64_MIN, 63), -1);
    CHECK_EQ(fix_bitlen(0), 0);
    CHECK_EQ(fix_bitlen(1), 1);
    CHECK_EQ(fix_bitlen(0x80000000u), 32);
}
