/* texture.c — texture images for the GP's database: the built-in procedural
 * checker and PNG files through libpng.  The VP sees only texels, loaded
 * through TEXTURE packets of the word stream. */
#include "albatros/scene.h"
#include "albatros/file.h"

#include <errno.h>
#ifndef ALB_NO_EXTERNAL
#include <png.h>
#endif
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

alb_err alb_scene_texture_checker(alb_scene_texture *t, unsigned log2size, const uint8_t a[3],
                              const uint8_t b[3], unsigned squares)
{
    unsigned size = 1u << log2size;
    t->log2size = log2size;
    t->texels = malloc((size_t)size * size * sizeof *t->texels);
    if (!t->texels)
        return ALB_ERR_NOMEM;
    uint32_t ca = (uint32_t)a[0] << 16 | (uint32_t)a[1] << 8 | a[2];
    uint32_t cb = (uint32_t)b[0] << 16 | (uint32_t)b[1] << 8 | b[2];
    for (unsigned y = 0; y < size; y++)
        for (unsigned x = 0; x < size; x++) {
            unsigned sx = x * squares / size, sy = y * squares / size;
            t->texels[(size_t)y * size + x] = (sx + sy) % 2 ? cb : ca;
        }
    return ALB_OK;
}

#ifdef ALB_NO_EXTERNAL
/* The build without external libraries (make crosscheck's musl build,
 * docs/golden-vectors.md): no libpng, so no PNG textures. */
alb_err alb_scene_texture_png(alb_scene_texture *t, const char *path, alb_diag *d)
{
    (void)t;
    return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read the PNG texture '%s': this albatros "
                   "was built with ALB_NO_EXTERNAL, without libpng", path);
}
#else
/* libpng reports every short read as "Read Error": a read that failed at
 * the end of the file means the file was cut short. */
static alb_err png_failed(alb_diag *d, const char *path, FILE *f, const char *doing,
                          const char *libpng_msg)
{
    if (feof(f))
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "'%s' is truncated: the file ends after %ld "
                       "bytes, before the PNG image is complete", path, ftell(f));
    return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot %s PNG: %s", doing, libpng_msg);
}

/* libpng allocates a chunk's claimed length before it reads the chunk, so a
 * 45-byte file claiming a 1.7 GB text chunk took 1.7 GB and seconds (found
 * by fuzz_png).  Walk the chunk headers first: every chunk must fit in what
 * is left of the file.  f is just past the signature; left there. */
static alb_err png_check_chunks(const char *path, FILE *f, alb_diag *d)
{
    if (fseek(f, 0, SEEK_END))
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
    long size = ftell(f);
    long at = 8;
    while (size >= 0 && at + 8 <= size) {
        unsigned char h[8];
        if (fseek(f, at, SEEK_SET) || fread(h, 1, sizeof h, f) != sizeof h)
            return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read '%s': %s", path,
                           strerror(errno));
        uint32_t len = (uint32_t)h[0] << 24 | (uint32_t)h[1] << 16 | (uint32_t)h[2] << 8 | h[3];
        char type[5];
        for (int i = 0; i < 4; i++)   /* as written, but printable */
            type[i] = h[4 + i] >= 0x20 && h[4 + i] < 0x7f ? (char)h[4 + i] : '?';
        type[4] = 0;
        /* length, type, data, CRC */
        if (len > 0x7fffffffu || (uint64_t)len + 12 > (uint64_t)(size - at))
            return alb_diag_at(d, ALB_ERR_IO, path, 0, 0,
                           "'%s' is truncated: the file ends after %ld bytes, inside PNG chunk "
                           "'%s' at byte %ld (which claims %lu bytes of data)",
                           path, size, type, at, (unsigned long)len);
        if (!memcmp(h + 4, "IEND", 4))
            break;
        at += 12 + (long)len;
    }
    if (fseek(f, 0, SEEK_SET))
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
    return ALB_OK;
}

static alb_err png_read(alb_scene_texture *t, const char *path, FILE *f, alb_diag *d)
{
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    if (!png_image_begin_read_from_stdio(&img, f))
        return png_failed(d, path, f, "read", img.message);
    if (img.width != img.height || img.width < 2 || img.width > 1024 ||
        (img.width & (img.width - 1))) {
        unsigned w = img.width, h = img.height;
        png_image_free(&img);
        return alb_diag_at(d, ALB_ERR_PARSE, path, 0, 0,
                       "texture is %ux%u; the VP takes square powers of two, 2..1024", w, h);
    }
    img.format = PNG_FORMAT_RGB;
    size_t n = (size_t)img.width * img.height;
    uint8_t *rgb = malloc(n * 3);
    t->texels = malloc(n * sizeof *t->texels);
    if (!rgb || !t->texels) {
        free(rgb);
        free(t->texels);
        t->texels = NULL;
        png_image_free(&img);
        return ALB_ERR_NOMEM;
    }
    /* Negative stride: PNG row 0 is the image top; texel row 0 is v = 0, the
     * bottom, as in OBJ and the paper's y-up screen.  An image with alpha is
     * composited onto black: without a background libpng composites onto
     * whatever the buffer holds, which made such texels vary from run to run
     * (found by valgrind on the fuzz seeds). */
    static const png_color black = {0, 0, 0};
    if (!png_image_finish_read(&img, &black, rgb,
                               -(png_int_32)(img.width * 3), NULL)) {
        free(rgb);
        free(t->texels);
        t->texels = NULL;
        return png_failed(d, path, f, "decode", img.message);
    }
    for (size_t i = 0; i < n; i++)
        t->texels[i] = (uint32_t)rgb[3 * i] << 16 | (uint32_t)rgb[3 * i + 1] << 8 | rgb[3 * i + 2];
    free(rgb);
    unsigned lg = 0;
    while ((1u << lg) < img.width)
        lg++;
    t->log2size = lg;
    return ALB_OK;
}

alb_err alb_scene_texture_png(alb_scene_texture *t, const char *path, alb_diag *d)
{
    /* Opened here rather than by libpng, so that the messages can name the
     * path and the system's reason, and tell an empty file from a bad one. */
    const char *why;
    /* a regular file only: a FIFO would block, a device might never end */
    FILE *f = alb_file_open_input(path, true, &why);
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open '%s': %s", path, why);
    png_byte sig[8];
    size_t got = fread(sig, 1, sizeof sig, f);
    alb_err e;
    if (ferror(f))   /* a directory, for one */
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
    else if (got == 0)
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "'%s' is empty (0 bytes); expected a PNG image",
                    path);
    else if (got < sizeof sig && png_sig_cmp(sig, 0, got) == 0)
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "'%s' is truncated: the file ends after %zu "
                    "bytes, inside the PNG signature", path, got);
    else if (png_sig_cmp(sig, 0, sizeof sig) == 0 && (e = png_check_chunks(path, f, d)))
        ;
    else if (fseek(f, 0, SEEK_SET))
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot read '%s': %s", path, strerror(errno));
    else
        e = png_read(t, path, f, d);
    fclose(f);
    return e;
}
#endif
