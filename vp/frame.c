/* frame.c — a frame's planes: allocation, copy, and the count of pixels
 * where two frames differ.  Integers only, as everything in vp/: the output
 * stage's floating point (the EXR Z distance, compare's error measures) is
 * in emu/frame_out.c (docs/number-formats.md §0). */
#include "albatros/frame.h"
#include "vp_internal.h"

#include <stdlib.h>
#include <string.h>

int alb_frame_alloc_planes(alb_frame *f, unsigned width, unsigned height, unsigned planes)
{
    size_t n = (size_t)width * height;
    memset(f, 0, sizeof *f);
    f->width = width;
    f->height = height;
    if (planes & ALB_FRAME_RGB)
        f->rgb = vp_plane_alloc(n * 3, sizeof *f->rgb, true);
    if (planes & ALB_FRAME_DEPTH)
        f->depth = vp_plane_alloc(n, sizeof *f->depth, true);
    if (planes & ALB_FRAME_FACE)
        f->face = vp_plane_alloc(n, sizeof *f->face, true);
    if (planes & ALB_FRAME_LEVEL)
        f->level = vp_plane_alloc(n, sizeof *f->level, true);
    if (planes & ALB_FRAME_COVERAGE)
        f->coverage = vp_plane_alloc(n, sizeof *f->coverage, true);
    if (planes & ALB_FRAME_CYCLES)
        f->cycles = vp_plane_alloc(n, sizeof *f->cycles, true);
    if (alb_frame_planes(f) != (planes & (ALB_FRAME_PLANES | ALB_FRAME_CYCLES))) {
        alb_frame_free(f);
        return -1;
    }
    return 0;
}

int alb_frame_alloc(alb_frame *f, unsigned width, unsigned height, bool with_cycles)
{
    return alb_frame_alloc_planes(f, width, height, ALB_FRAME_PLANES | (with_cycles ? ALB_FRAME_CYCLES : 0));
}

unsigned alb_frame_planes(const alb_frame *f)
{
    return (f->rgb ? ALB_FRAME_RGB : 0) | (f->depth ? ALB_FRAME_DEPTH : 0) |
           (f->face ? ALB_FRAME_FACE : 0) | (f->level ? ALB_FRAME_LEVEL : 0) |
           (f->coverage ? ALB_FRAME_COVERAGE : 0) | (f->cycles ? ALB_FRAME_CYCLES : 0);
}

void alb_frame_free(alb_frame *f)
{
    free(f->rgb);
    free(f->depth);
    free(f->face);
    free(f->level);
    free(f->coverage);
    free(f->cycles);
    f->rgb = NULL;
    f->depth = f->face = f->cycles = NULL;
    f->level = NULL;
    f->coverage = NULL;
}

int alb_frame_copy(alb_frame *dst, const alb_frame *src)
{
    if (alb_frame_alloc_planes(dst, src->width, src->height, alb_frame_planes(src)))
        return -1;
    size_t n = (size_t)src->width * src->height;
    if (src->rgb)
        memcpy(dst->rgb, src->rgb, 3 * n * sizeof *dst->rgb);
    if (src->depth)
        memcpy(dst->depth, src->depth, n * sizeof *dst->depth);
    if (src->face)
        memcpy(dst->face, src->face, n * sizeof *dst->face);
    if (src->level)
        memcpy(dst->level, src->level, n * sizeof *dst->level);
    if (src->coverage)
        memcpy(dst->coverage, src->coverage, n * sizeof *dst->coverage);
    if (src->cycles)
        memcpy(dst->cycles, src->cycles, n * sizeof *dst->cycles);
    dst->colour_bits = src->colour_bits;
    dst->depth_bits = src->depth_bits;
    dst->aa_levels = src->aa_levels;
    dst->near = src->near;
    dst->number = src->number;
    return 0;
}

size_t alb_frame_count_differences(const alb_frame *a, const alb_frame *b)
{
    if (a->width != b->width || a->height != b->height || a->colour_bits != b->colour_bits ||
        a->depth_bits != b->depth_bits || a->aa_levels != b->aa_levels)
        return (size_t)-1;
    size_t n = (size_t)a->width * a->height, diff = 0;
    for (size_t i = 0; i < n; i++)
        diff += memcmp(a->rgb + 3 * i, b->rgb + 3 * i, 3 * sizeof *a->rgb) ||
                a->depth[i] != b->depth[i] || a->face[i] != b->face[i] ||
                a->level[i] != b->level[i] || a->coverage[i] != b->coverage[i] ||
                (a->cycles && b->cycles && a->cycles[i] != b->cycles[i]);
    return diff;
}

bool alb_frame_first_diff(const alb_frame *a, const alb_frame *b, size_t *at,
                          const char **channel, uint64_t *va, uint64_t *vb, size_t *count)
{
    size_t n = (size_t)a->width * a->height, found = 0;
    for (size_t i = 0; i < n; i++) {
        const char *ch = NULL;
        uint64_t x = 0, y = 0;
        static const char *const rgb[3] = {"vp.R", "vp.G", "vp.B"};
        if (a->face[i] != b->face[i])
            ch = "face.id", x = a->face[i], y = b->face[i];
        for (int c = 0; c < 3 && !ch; c++)
            if (a->rgb[3 * i + c] != b->rgb[3 * i + c])
                ch = rgb[c], x = a->rgb[3 * i + c], y = b->rgb[3 * i + c];
        if (!ch && a->depth[i] != b->depth[i])
            ch = "vp.depth", x = a->depth[i], y = b->depth[i];
        if (!ch && a->level[i] != b->level[i])
            ch = "vp.level", x = a->level[i], y = b->level[i];
        if (!ch && a->coverage[i] != b->coverage[i])
            ch = "vp.coverage", x = a->coverage[i], y = b->coverage[i];
        if (!ch && a->cycles && b->cycles && a->cycles[i] != b->cycles[i])
            ch = "vp.cycles", x = a->cycles[i], y = b->cycles[i];
        if (!ch)
            continue;
        if (!found++) {
            *at = i;
            *channel = ch;
            *va = x;
            *vb = y;
            if (!count)
                return true;
        }
    }
    if (count)
        *count = found;
    return found > 0;
}
