/* frame.c — allocation of frames and the depth-to-distance conversion. */
#include "frame.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int frame_alloc(frame_t *f, unsigned width, unsigned height, bool with_cycles)
{
    size_t n = (size_t)width * height;
    memset(f, 0, sizeof *f);
    f->width = width;
    f->height = height;
    f->rgb = calloc(n * 3, sizeof *f->rgb);
    f->depth = calloc(n, sizeof *f->depth);
    f->face = calloc(n, sizeof *f->face);
    f->level = calloc(n, sizeof *f->level);
    f->coverage = calloc(n, sizeof *f->coverage);
    f->cycles = with_cycles ? calloc(n, sizeof *f->cycles) : NULL;
    if (!f->rgb || !f->depth || !f->face || !f->level || !f->coverage ||
        (with_cycles && !f->cycles)) {
        frame_free(f);
        return -1;
    }
    return 0;
}

void frame_free(frame_t *f)
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

float frame_z(const frame_t *f, uint32_t d)
{
    if (d == 0)
        return INFINITY;
    /* one correctly rounded double division, then one rounding to float */
    return (float)((double)f->near / ldexp((double)d, -(int)f->depth_bits));
}
