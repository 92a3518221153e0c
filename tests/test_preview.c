/* test_preview.c — the colour key under the false-colour previews: a level
 * view's key shows each level's colour as the frame shows it, under the
 * frame, and views without a false colour have none (docs/vp.md). */
#include "t.h"

#include "albatros/file.h"
#include "albatros/preview.h"

#include <png.h>
#include <stdlib.h>
#include <string.h>

/* The PNG at path as 8-bit RGB; NULL if unreadable. */
static uint8_t *read_png(const char *path, unsigned *w, unsigned *h)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_file(&img, path))
        return NULL;
    img.format = PNG_FORMAT_RGB;
    uint8_t *px = malloc(PNG_IMAGE_SIZE(img));
    if (!px || !png_image_finish_read(&img, NULL, px, 0, NULL)) {
        free(px);
        png_image_free(&img);
        return NULL;
    }
    *w = img.width;
    *h = img.height;
    return px;
}

TEST(level_view_has_a_key_of_its_colours)
{
    const unsigned W = 64, H = 32, levels = 6;   /* ceil(log2(64)), aa 0 */
    alb_frame f;
    CHECK(alb_frame_alloc(&f, W, H, false) == 0);
    f.colour_bits = 8, f.depth_bits = 24, f.near = 1;
    for (unsigned i = 0; i < W * H; i++) {
        f.face[i] = 1;
        f.level[i] = (uint8_t)(i % W * (levels + 1) / W);   /* columns of each level */
        f.depth[i] = 1000;
    }
    char *level = alb_strprintf("%s/level.png", t_tmpdir()), *face = alb_strprintf("%s/face.png", t_tmpdir());
    alb_diag d;
    alb_diag_init(&d, NULL);
    CHECK(alb_preview_write(level, &f, ALB_PREVIEW_LEVEL, &d) == ALB_OK);
    CHECK(alb_preview_write(face, &f, ALB_PREVIEW_FACE, &d) == ALB_OK);
    unsigned w, h;
    uint8_t *px = read_png(level, &w, &h);
    /* below the frame: 2 rows, a 6-row bar, 1, 5 rows of text, 2 (scale 1) */
    CHECK(px && w == W && h == H + 16);
    for (unsigned l = 0; px && l <= levels; l++) {
        unsigned fx = (2 * l + 1) * W / (2 * (levels + 1));   /* a frame column of level l */
        const uint8_t *in_frame = px + 3 * (size_t)fx, *in_key = px + 3 * ((size_t)(H + 4) * W + fx);
        CHECK_MSG(f.level[fx] == l && !memcmp(in_frame, in_key, 3),
                  "level %u: frame %u,%u,%u, key %u,%u,%u", l, in_frame[0], in_frame[1],
                  in_frame[2], in_key[0], in_key[1], in_key[2]);
    }
    free(px);
    px = read_png(face, &w, &h);
    CHECK(px && w == W && h == H);   /* hashed colours: no key */
    free(px);
    free(level);
    free(face);
    alb_frame_free(&f);
}
