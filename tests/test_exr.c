/* test_exr.c — OpenEXR frames: the bytes of a file do not depend on how many
 * threads compress its chunks, and every exact plane reads back unchanged. */
#include "t.h"

#include "albatros/exr.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static uint64_t seed = 88172645463325252ull;

static uint32_t rnd(void)
{
    seed ^= seed << 13;
    seed ^= seed >> 7;
    seed ^= seed << 17;
    return (uint32_t)(seed >> 16);
}

/* A frame of random planes within their formats' ranges. */
static int random_frame(alb_frame *f, unsigned w, unsigned h, unsigned aa, bool cycles)
{
    if (alb_frame_alloc(f, w, h, cycles))
        return -1;
    f->colour_bits = 1 + rnd() % 16;
    f->depth_bits = 24;
    f->aa_levels = aa;
    f->near = 0.5f;
    f->number = rnd();
    size_t n = (size_t)w * h;
    for (size_t i = 0; i < n; i++) {
        for (int c = 0; c < 3; c++)
            f->rgb[3 * i + (size_t)c] = (uint16_t)(rnd() & ((1u << f->colour_bits) - 1));
        bool none = rnd() % 5 == 0;
        f->depth[i] = none ? 0 : 1 + rnd() % ((1u << 24) - 1);
        f->face[i] = none ? ALB_FRAME_NO_FACE : rnd();
        f->level[i] = none ? ALB_FRAME_NO_LEVEL : (uint8_t)(rnd() % 12);
        f->coverage[i] = (uint16_t)(rnd() % ((1u << (2 * aa)) + 1));
        if (cycles)
            f->cycles[i] = rnd();
    }
    return 0;
}

static unsigned char *slurp(const char *path, size_t *len)
{
    FILE *fp = fopen(path, "rb");
    if (!fp)
        return NULL;
    fseek(fp, 0, SEEK_END);
    long n = ftell(fp);
    fseek(fp, 0, SEEK_SET);
    unsigned char *b = malloc(n > 0 ? (size_t)n : 1);
    *len = b ? fread(b, 1, (size_t)n, fp) : 0;
    fclose(fp);
    return b;
}

TEST(exr_bytes_do_not_depend_on_threads)
{
    static const struct {
        unsigned w, h, aa;
        bool cycles;
    } shapes[] = {
        {256, 256, 0, false}, {64, 100, 1, true}, {1, 37, 0, false},
        {300, 15, 2, true},   {32, 1, 0, true},   {1024, 48, 0, false},
    };
    static const unsigned threads[] = {2, 3, 8, 64};
    char p1[512], pn[512];
    snprintf(p1, sizeof p1, "%s/one.exr", t_tmpdir());
    snprintf(pn, sizeof pn, "%s/many.exr", t_tmpdir());
    for (size_t s = 0; s < sizeof shapes / sizeof shapes[0]; s++) {
        alb_frame f;
        if (random_frame(&f, shapes[s].w, shapes[s].h, shapes[s].aa, shapes[s].cycles)) {
            CHECK_MSG(0, "no memory");
            return;
        }
        alb_diag d;
        alb_diag_init(&d, NULL);
        CHECK_MSG(alb_exr_write_frame(p1, &f, &d) == ALB_OK, "%s", d.msg);
        size_t n1 = 0;
        unsigned char *b1 = slurp(p1, &n1);
        CHECK(b1 && n1 > 0);
        for (size_t k = 0; b1 && k < sizeof threads / sizeof threads[0]; k++) {
            CHECK_MSG(alb_exr_write_frame_threads(pn, &f, threads[k], &d) == ALB_OK, "%s", d.msg);
            size_t nn = 0;
            unsigned char *bn = slurp(pn, &nn);
            CHECK_MSG(bn && nn == n1 && memcmp(b1, bn, n1) == 0,
                      "%ux%u on %u threads: %zu bytes against %zu, or different", shapes[s].w,
                      shapes[s].h, threads[k], nn, n1);
            free(bn);
        }
        free(b1);
        /* and what was written is what was rendered */
        alb_frame back;
        CHECK_MSG(alb_exr_read_frame(pn, &back, &d) == ALB_OK, "%s", d.msg);
        CHECK_EQ(alb_frame_count_differences(&f, &back), 0);
        CHECK_EQ(back.number, f.number);
        alb_frame_free(&back);
        alb_frame_free(&f);
    }
}
