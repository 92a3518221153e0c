/* test_dump.c — frame-store dumps (docs/cosim.md, "Frame store dumps"):
 * the bit positions read back from the text as the document states them,
 * memh and raw round trips, and the errors, each naming where. */
#include "t.h"
#include "albatros/dump.h"

#include <stdlib.h>
#include <string.h>

/* A frame whose every field is a different function of the pixel. */
static void synthetic(alb_frame *f, unsigned w, unsigned h)
{
    alb_frame_alloc(f, w, h, false);
    f->colour_bits = 10;
    f->depth_bits = 24;
    for (unsigned i = 0; i < w * h; i++) {
        f->face[i] = i % 7 ? 0x01000000u + i * 977 : 0xFFFFFFFFu;
        f->depth[i] = i * 40503u & 0xFFFFFF;
        f->rgb[3 * i] = (uint16_t)(i * 3 & 1023);
        f->rgb[3 * i + 1] = (uint16_t)(1023 - (i & 1023));
        f->rgb[3 * i + 2] = (uint16_t)(i * 11 & 1023);
        f->level[i] = (uint8_t)(i % 9);
        f->coverage[i] = (uint16_t)(i % 5);
    }
}

static char *slurp(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    char *b = f ? malloc(1 << 20) : NULL;
    *n = b ? fread(b, 1, (1 << 20) - 1, f) : 0;
    if (b)
        b[*n] = 0;
    if (f)
        fclose(f);
    return b;
}

TEST(dump_memh_fields_at_their_documented_bits)
{
    alb_frame f;
    synthetic(&f, 8, 4);
    char path[600];
    snprintf(path, sizeof path, "%s/f.memh", t_tmpdir());
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_dump_write(path, &f, ALB_DUMP_MEMH, &d) == ALB_OK);
    size_t n;
    char *text = slurp(path, &n);
    CHECK(text && !strncmp(text, "//", 2));
    /* after the comment line, 32 digits a pixel: face 127..96, depth 95..64,
     * R 63..48, G 47..32, B 31..16, level 15..8, coverage 7..0 */
    char *line = text ? strchr(text, '\n') + 1 : NULL;
    unsigned i = 0;
    for (; line && *line && i < 32; i++) {
        unsigned face, depth, rg, b, lc;
        CHECK(sscanf(line, "%8x%8x%8x%4x%4x", &face, &depth, &rg, &b, &lc) == 5);
        CHECK_EQ(face, f.face[i]);
        CHECK_EQ(depth, f.depth[i]);
        CHECK_EQ(rg >> 16, f.rgb[3 * i]);
        CHECK_EQ(rg & 0xFFFF, f.rgb[3 * i + 1]);
        CHECK_EQ(b, f.rgb[3 * i + 2]);
        CHECK_EQ(lc >> 8, f.level[i]);
        CHECK_EQ(lc & 0xFF, f.coverage[i]);
        CHECK_EQ(strcspn(line, "\n"), 32);
        line = strchr(line, '\n');
        line = line ? line + 1 : NULL;
    }
    CHECK_EQ(i, 32);
    free(text);
    alb_frame_free(&f);
}

TEST(dump_round_trips_memh_and_raw)
{
    alb_frame f, g;
    synthetic(&f, 16, 8);
    for (int fmt = ALB_DUMP_MEMH; fmt <= ALB_DUMP_RAW; fmt++) {
        char path[600];
        snprintf(path, sizeof path, "%s/f.%d", t_tmpdir(), fmt);
        alb_diag d;
        alb_diag_init(&d, NULL);
        CHECK(alb_dump_write(path, &f, (alb_dump_format)fmt, &d) == ALB_OK);
        CHECK(alb_dump_read(path, &f, &g, &d) == ALB_OK);
        size_t at;
        const char *ch;
        uint64_t a, b;
        CHECK_MSG(!alb_frame_first_diff(&f, &g, &at, &ch, &a, &b, NULL), "format %d: %s at %zu",
                  fmt, ch, at);
        alb_frame_free(&g);
        /* raw: 16 bytes a pixel, the record little-endian (coverage first) */
        if (fmt == ALB_DUMP_RAW) {
            size_t n;
            unsigned char *raw = (unsigned char *)slurp(path, &n);
            CHECK_EQ(n, 16 * 16 * 8);
            CHECK(raw && raw[16 * 3] == f.coverage[3] && raw[16 * 3 + 1] == f.level[3] &&
                  raw[16 * 3 + 15] == f.face[3] >> 24);
            free(raw);
        }
    }
    alb_frame_free(&f);
}

/* A dump of a 2x2 frame (text of len bytes; 0: strlen) must be refused so. */
static void expect_error(const char *name, const char *text, size_t len, const char *want)
{
    if (!len)
        len = strlen(text);
    char path[600];
    snprintf(path, sizeof path, "%s/%s", t_tmpdir(), name);
    FILE *fp = fopen(path, "wb");
    CHECK(fp && fwrite(text, 1, len, fp) == len);
    if (fp)
        fclose(fp);
    alb_frame shape, g;
    synthetic(&shape, 2, 2);
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK_EQ(alb_dump_read(path, &shape, &g, &d), ALB_ERR_PARSE);
    char msg[800];
    alb_diag_format(&d, msg, sizeof msg);
    CHECK_STR_CONTAINS(msg, want);
    alb_frame_free(&shape);
}

TEST(dump_errors_name_where)
{
    expect_error("short.memh", "0\n0\n0\n", 0, "3 pixels, a 2x2 frame has 4");
    expect_error("long.memh", "0\n0\n0\n0\n0\n", 0, "line 5, column 1: more than the 2x2 = 4 pixels");
    expect_error("colour.memh", "0\n0\n00000000000000000000040000000000\n0\n", 0,
                 "line 3, column 1: pixel (0, 1): G = 1024 exceeds colour_bits = 10");
    expect_error("x.memh", "0\n0\n0\nx\n", 0, "x.memh:4:1: error: expected a hex value");
    expect_error("wide.memh", "0\n0\n0\n1ffffffffffffffffffffffffffffffff\n", 0,
                 "value wider than 128 bits");
    char raw[63] = {0};
    expect_error("short.raw", raw, sizeof raw, "offset 63: error: a raw dump of 2x2 pixels is 64 bytes, this one 63");
}
