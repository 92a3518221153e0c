/* png.c — PNG previews of a frame's planes and diff images of two frames.
 * Each view maps a plane to 8-bit RGB pixels; libpng's simplified writer
 * stores them (it writes no tIME chunk, so equal frames give equal files). */
#include "albatros/preview.h"
#include "albatros/file.h"

#include <errno.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include <png.h>

static const char *const view_names[] = {"colour", "depth", "face", "level", "cycles", "coverage"};

int alb_preview_view_parse(const char *name, alb_preview_view *view)
{
    for (size_t i = 0; i < sizeof view_names / sizeof view_names[0]; i++) {
        if (strcmp(name, view_names[i]) == 0) {
            *view = (alb_preview_view)i;
            return 0;
        }
    }
    return -1;
}

const char *alb_preview_view_name(alb_preview_view view)
{
    if ((unsigned)view < sizeof view_names / sizeof view_names[0])
        return view_names[view];
    return "?";
}

/* ---- colour helpers ------------------------------------------------------ */

static void put(uint8_t *px, unsigned r, unsigned g, unsigned b)
{
    px[0] = (uint8_t)r;
    px[1] = (uint8_t)g;
    px[2] = (uint8_t)b;
}

static unsigned round_unit(double t, unsigned scale)
{
    if (!(t > 0))
        return 0;
    return t >= 1 ? scale : (unsigned)floor(t * scale + 0.5);
}

/* Frame store value v of 0..2^cb-1 as 0..255, rounded to nearest. */
static unsigned to8(uint32_t v, unsigned cb)
{
    uint64_t max = (UINT64_C(1) << cb) - 1;
    return (unsigned)((2 * (uint64_t)v * 255 + max) / (2 * max));
}

/* Piecewise-linear colour ramp through n stops, t in [0, 1]. */
static void ramp(const uint8_t (*stops)[3], unsigned n, double t, uint8_t *px)
{
    double pos = (t < 0 ? 0 : t > 1 ? 1 : t) * (n - 1);
    unsigned i = (unsigned)pos;
    if (i >= n - 1)
        i = n - 2;
    double frac = pos - i;
    for (int c = 0; c < 3; c++)
        px[c] = (uint8_t)floor(stops[i][c] + (stops[i + 1][c] - stops[i][c]) * frac + 0.5);
}

/* A fully saturated colour of hue 0..1535 (six sectors of 256) and value v. */
static void hue(unsigned h, unsigned v, uint8_t *px)
{
    unsigned f = h % 256, up = v * f / 255, down = v * (255 - f) / 255;
    switch (h / 256) {
    case 0: put(px, v, up, 0); break;
    case 1: put(px, down, v, 0); break;
    case 2: put(px, 0, v, up); break;
    case 3: put(px, 0, down, v); break;
    case 4: put(px, up, 0, v); break;
    default: put(px, v, 0, down); break;
    }
}

/* Knuth's multiplicative hash spreads consecutive ids over the hue circle,
 * the extra mixing decorrelates hue from brightness. */
static void face_colour(uint32_t id, uint8_t *px)
{
    uint32_t h = id * UINT32_C(0x9E3779B1);
    h ^= h >> 16;
    h *= UINT32_C(0x85EBCA6B);
    h ^= h >> 13;
    /* values 160..255 stay clear of the black background */
    hue(h % 1536, 160 + (h >> 24) % 96, px);
}

/* ---- views ------------------------------------------------------------- */

static void view_colour(const alb_frame *f, size_t i, uint8_t *px)
{
    const uint16_t *c = &f->rgb[3 * i];
    put(px, to8(c[0], f->colour_bits), to8(c[1], f->colour_bits), to8(c[2], f->colour_bits));
}

typedef struct {
    double lo, span;     /* log2 of the farthest covered depth, log2 range */
    uint32_t max;        /* largest value in the frame (cycles) */
    unsigned levels;     /* last subdivision level */
} view_scale;

static unsigned last_level(const alb_frame *f)
{
    unsigned side = f->width > f->height ? f->width : f->height, n = 0;
    while ((1u << n) < side && n < 31)   /* ceil(log2) for any size */
        n++;
    return n + f->aa_levels;
}

static view_scale scale_of(const alb_frame *f)
{
    view_scale s = {0, 0, 0, last_level(f)};
    uint32_t dmin = UINT32_MAX, dmax = 0;
    for (size_t i = 0; i < (size_t)f->width * f->height; i++) {
        uint32_t dv = f->depth[i];
        if (dv != 0 && dv < dmin)
            dmin = dv;
        if (dv > dmax)
            dmax = dv;
        if (f->cycles && f->cycles[i] > s.max)
            s.max = f->cycles[i];
    }
    if (dmax != 0) {
        s.lo = log2(dmin);
        s.span = log2(dmax) - s.lo;
    }
    return s;
}

static void view_depth(const alb_frame *f, const view_scale *s, size_t i, uint8_t *px)
{
    uint32_t dv = f->depth[i];
    if (dv == 0) {
        put(px, 0, 0, 0);
        return;
    }
    /* the depth store is near/Z: larger is nearer, so the maximum is white */
    unsigned g = s->span > 0 ? 40 + round_unit((log2(dv) - s->lo) / s->span, 215) : 255;
    put(px, g, g, g);
}

static void view_level(const alb_frame *f, const view_scale *s, size_t i, uint8_t *px)
{
    static const uint8_t stops[][3] = {
        {0, 0, 255}, {0, 255, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
    if (f->level[i] == ALB_FRAME_NO_LEVEL || f->face[i] == ALB_FRAME_NO_FACE) {
        put(px, 0, 0, 0);
        return;
    }
    double t = s->levels > 0 ? (double)f->level[i] / s->levels : 1.0;
    ramp(stops, sizeof stops / sizeof stops[0], t, px);
}

static void view_cycles(const alb_frame *f, const view_scale *s, size_t i, uint8_t *px)
{
    static const uint8_t stops[][3] = {{0, 0, 0}, {255, 0, 0}, {255, 255, 0}, {255, 255, 255}};
    double t = s->max > 0 ? (double)f->cycles[i] / s->max : 0.0;
    ramp(stops, sizeof stops / sizeof stops[0], t, px);
}

static void view_pixel(const alb_frame *f, alb_preview_view view, const view_scale *s, size_t i,
                       uint8_t *px)
{
    unsigned g;
    switch (view) {
    case ALB_PREVIEW_COLOUR: view_colour(f, i, px); break;
    case ALB_PREVIEW_DEPTH: view_depth(f, s, i, px); break;
    case ALB_PREVIEW_LEVEL: view_level(f, s, i, px); break;
    case ALB_PREVIEW_CYCLES: view_cycles(f, s, i, px); break;
    case ALB_PREVIEW_FACE:
        if (f->face[i] == ALB_FRAME_NO_FACE)
            put(px, 0, 0, 0);
        else
            face_colour(f->face[i], px);
        break;
    case ALB_PREVIEW_COVERAGE:
        g = round_unit(ldexp((double)f->coverage[i], -2 * (int)f->aa_levels), 255);
        put(px, g, g, g);
        break;
    }
}

/* ---- the colour key of a false-colour view ---------------------------------
 * Below the frame, on black: a bar of the view's colours (one swatch per
 * level; a ramp for cycles and depth) and, under it, what they stand for
 * in a 3x5 pixel font scaled with the image (docs/vp.md, "Previews"). */

/* 3x5 glyphs, rows top first, 3 bits a row (bit 2 the left column). */
static const struct {
    char c;
    uint8_t rows[5];
} glyphs[] = {
    {'0', {7, 5, 5, 5, 7}}, {'1', {2, 6, 2, 2, 7}}, {'2', {7, 1, 7, 4, 7}},
    {'3', {7, 1, 7, 1, 7}}, {'4', {5, 5, 7, 1, 1}}, {'5', {7, 4, 7, 1, 7}},
    {'6', {7, 4, 7, 5, 7}}, {'7', {7, 1, 1, 1, 1}}, {'8', {7, 5, 7, 5, 7}},
    {'9', {7, 5, 7, 1, 7}}, {'.', {0, 0, 0, 0, 2}}, {'-', {0, 0, 7, 0, 0}},
    {'+', {0, 2, 7, 2, 0}}, {'e', {0, 7, 7, 4, 7}}, {'z', {0, 7, 1, 4, 7}},
    {'=', {0, 7, 0, 7, 0}}, {' ', {0, 0, 0, 0, 0}},
};

typedef struct {
    uint8_t *px;             /* the whole image */
    unsigned w, y0, scale;   /* width; the key's first row; glyph scale */
} key_canvas;

static unsigned key_scale(unsigned w) { return w >= 1024 ? 3 : w >= 256 ? 2 : 1; }

/* Rows the key adds below a w-pixel-wide frame: bar, gap, text, margin. */
static unsigned key_rows(unsigned w)
{
    unsigned s = key_scale(w);
    return 2 * s + 6 * s + s + 5 * s + 2 * s;
}

static unsigned text_width(const char *t, unsigned s) { return (unsigned)strlen(t) * 4 * s; }

/* White text with its left end at x (clipped at the image's edges). */
static void key_text(const key_canvas *k, unsigned x, const char *t)
{
    unsigned s = k->scale, ty = k->y0 + 2 * s + 6 * s + s;
    for (; *t; t++, x += 4 * s)
        for (size_t g = 0; g < sizeof glyphs / sizeof glyphs[0]; g++) {
            if (glyphs[g].c != *t)
                continue;
            for (unsigned r = 0; r < 5 * s; r++)
                for (unsigned c = 0; c < 3 * s; c++)
                    if (glyphs[g].rows[r / s] >> (2 - c / s) & 1 && x + c < k->w)
                        put(k->px + 3 * ((size_t)(ty + r) * k->w + x + c), 255, 255, 255);
            break;
        }
}

static void key_bar(const key_canvas *k, unsigned x0, unsigned x1, const uint8_t *rgb)
{
    unsigned s = k->scale;
    for (unsigned y = k->y0 + 2 * s; y < k->y0 + 8 * s; y++)
        for (unsigned x = x0; x < x1 && x < k->w; x++)
            put(k->px + 3 * ((size_t)y * k->w + x), rgb[0], rgb[1], rgb[2]);
}

/* The levels: a swatch each, its number centred under it when it fits
 * (every other one, or fewer, on a narrow image). */
static void key_levels(const key_canvas *k, const alb_frame *f, const view_scale *vs)
{
    static const uint8_t stops[][3] = {
        {0, 0, 255}, {0, 255, 255}, {0, 255, 0}, {255, 255, 0}, {255, 0, 0}};
    unsigned n = vs->levels + 1, every = 1;
    char t[16];
    snprintf(t, sizeof t, "%u", vs->levels);
    while (every < n && text_width(t, k->scale) + k->scale > every * k->w / n)
        every++;
    (void)f;
    for (unsigned l = 0; l < n; l++) {
        uint8_t c[3];
        ramp(stops, sizeof stops / sizeof stops[0], vs->levels ? (double)l / vs->levels : 1, c);
        unsigned x0 = l * k->w / n, x1 = (l + 1) * k->w / n;
        key_bar(k, x0, x1, c);
        snprintf(t, sizeof t, "%u", l);
        unsigned tw = text_width(t, k->scale) - k->scale;
        if (l % every == 0 && x1 - x0 >= tw)
            key_text(k, x0 + (x1 - x0 - tw) / 2, t);
    }
}

/* A ramp from the view's value at 0 to its value at 1, with labels at both
 * ends. */
static void key_ramp(const key_canvas *k, const alb_frame *f, alb_preview_view view,
                     const view_scale *vs, const char *lo, const char *hi)
{
    for (unsigned x = 0; x < k->w; x++) {
        uint8_t c[3];
        double t = k->w > 1 ? (double)x / (k->w - 1) : 0;
        if (view == ALB_PREVIEW_CYCLES) {
            static const uint8_t stops[][3] = {{0, 0, 0}, {255, 0, 0}, {255, 255, 0},
                                               {255, 255, 255}};
            ramp(stops, sizeof stops / sizeof stops[0], t, c);
        } else {   /* depth: grey 40 (farthest) .. 255 (nearest), as view_depth */
            unsigned g = vs->span > 0 ? 40 + round_unit(t, 215) : 255;
            put(c, g, g, g);
        }
        key_bar(k, x, x + 1, c);
    }
    (void)f;
    unsigned hw = text_width(hi, k->scale) - k->scale;
    key_text(k, 0, lo);
    if (text_width(lo, k->scale) + 2 * k->scale + hw <= k->w)
        key_text(k, k->w - hw, hi);
}

static bool has_key(alb_preview_view v)
{
    return v == ALB_PREVIEW_LEVEL || v == ALB_PREVIEW_CYCLES || v == ALB_PREVIEW_DEPTH;
}

static void draw_key(uint8_t *px, const alb_frame *f, alb_preview_view view, const view_scale *vs)
{
    key_canvas k = {px, f->width, f->height, key_scale(f->width)};
    memset(px + 3 * (size_t)f->width * f->height, 0, 3 * (size_t)f->width * key_rows(f->width));
    char lo[48], hi[48];
    switch (view) {
    case ALB_PREVIEW_LEVEL:
        key_levels(&k, f, vs);
        break;
    case ALB_PREVIEW_CYCLES:
        snprintf(hi, sizeof hi, "%u", vs->max);
        key_ramp(&k, f, view, vs, "0", hi);
        break;
    default: {
        /* the depth store is near/Z: its ends as Z, the far end first */
        double dmin = exp2(vs->lo), dmax = exp2(vs->lo + vs->span);
        snprintf(lo, sizeof lo, "z=%.3g", vs->span > 0 || dmax > 0 ? alb_frame_z(f, (uint32_t)dmin) : 0.0);
        snprintf(hi, sizeof hi, "z=%.3g", dmax > 0 ? alb_frame_z(f, (uint32_t)dmax) : 0.0);
        key_ramp(&k, f, view, vs, lo, hi);
        break;
    }
    }
}

/* ---- writing ------------------------------------------------------------- */

static alb_err check_frame(const char *path, const alb_frame *f, alb_diag *d)
{
    if (f->width < 1 || f->height < 1 || f->width > 65535 || f->height > 65535)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0,
                       "cannot draw a %ux%u frame: sides must be 1..65535", f->width, f->height);
    if (f->colour_bits < 1 || f->colour_bits > 16 || f->aa_levels > 7)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0,
                       "cannot draw a frame with colour_bits=%u aa=%u (need 1..16, 0..7)",
                       f->colour_bits, f->aa_levels);
    if (!f->rgb || !f->depth || !f->face || !f->level || !f->coverage)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0, "cannot draw a frame without planes");
    return ALB_OK;
}

static uint8_t *alloc_rgb(unsigned w, unsigned h, const char *path, alb_diag *d)
{
    uint8_t *px = malloc((size_t)w * h * 3);
    if (!px)
        alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory for a %ux%u image", w, h);
    return px;
}

/* Store w x h RGB pixels, top row first, as an 8-bit RGB PNG. */
static alb_err write_rgb(const char *path, unsigned w, unsigned h, const uint8_t *px,
                         alb_diag *d)
{
    /* the old file stays until the new one is complete; a device or FIFO
     * is written straight through and never removed (file.h) */
    alb_out out;
    alb_err e = alb_out_open(&out, path, 0, d);
    if (e != ALB_OK)
        return e;
    FILE *fp = alb_out_stdio(&out, d);
    if (!fp)
        return ALB_ERR_IO;
    png_image img;
    memset(&img, 0, sizeof img);
    img.version = PNG_IMAGE_VERSION;
    img.width = w;
    img.height = h;
    img.format = PNG_FORMAT_RGB;
    errno = 0;
    if (!png_image_write_to_stdio(&img, fp, 0, px, 0, NULL))
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot write PNG: %s (libpng)%s%s",
                        img.message, errno ? ": " : "", errno ? strerror(errno) : "");
    png_image_free(&img);
    if (e == ALB_OK)
        e = alb_out_commit(&out, d);
    else
        alb_out_abort(&out);
    return e;
}

alb_err alb_preview_write(const char *path, const alb_frame *f, alb_preview_view view, alb_diag *d)
{
    alb_err e = check_frame(path, f, d);
    if (e != ALB_OK)
        return e;
    if ((unsigned)view > ALB_PREVIEW_COVERAGE)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0, "unknown PNG view %d", (int)view);
    if (view == ALB_PREVIEW_CYCLES && !f->cycles)
        return alb_diag_at(d, ALB_ERR_CONFIG, path, 0, 0,
                       "this frame has no cycle counts (render with --fidelity cycle or timed)");
    unsigned rows = f->height + (has_key(view) ? key_rows(f->width) : 0);
    uint8_t *px = alloc_rgb(f->width, rows, path, d);
    if (!px)
        return ALB_ERR_NOMEM;
    view_scale s = scale_of(f);
    for (size_t i = 0; i < (size_t)f->width * f->height; i++)
        view_pixel(f, view, &s, i, px + 3 * i);
    if (has_key(view))
        draw_key(px, f, view, &s);
    e = write_rgb(path, f->width, rows, px, d);
    free(px);
    return e;
}

/* Pixel i has the same colour in a and b, each channel compared as a
 * fraction of its frame's full scale (exact: cross-multiplied). */
static int same_colour(const alb_frame *a, const alb_frame *b, size_t i)
{
    uint64_t amax = (UINT64_C(1) << a->colour_bits) - 1;
    uint64_t bmax = (UINT64_C(1) << b->colour_bits) - 1;
    for (int c = 0; c < 3; c++)
        if ((uint64_t)a->rgb[3 * i + (size_t)c] * bmax != (uint64_t)b->rgb[3 * i + (size_t)c] * amax)
            return 0;
    return 1;
}

/* Colour of one diff pixel; counts what it found. */
static void diff_pixel(const alb_frame *a, const alb_frame *b, size_t i, uint8_t *px,
                       unsigned *faces, unsigned *colours)
{
    int face_same = a->face[i] == b->face[i];
    int colour_same = same_colour(a, b, i);
    *faces += !face_same;
    *colours += !colour_same;
    if (!face_same) {
        put(px, 255, 0, 0);
    } else if (!colour_same) {
        put(px, 255, 255, 0);
    } else {
        uint8_t c[3];
        view_colour(a, i, c);
        /* Rec. 601 luma, then a quarter of it, rounded */
        unsigned y = (299u * c[0] + 587u * c[1] + 114u * c[2] + 500u) / 1000u;
        unsigned g = (y + 2) / 4;
        put(px, g, g, g);
    }
}

alb_err alb_preview_write_diff(const char *path, const alb_frame *a, const alb_frame *b,
                       unsigned *face_diff, unsigned *colour_diff, alb_diag *d)
{
    alb_err e = check_frame(path, a, d);
    if (e == ALB_OK)
        e = check_frame(path, b, d);
    if (e != ALB_OK)
        return e;
    if (a->width != b->width || a->height != b->height)
        return alb_diag_at(d, ALB_ERR_MISMATCH, path, 0, 0,
                       "cannot diff a %ux%u frame with a %ux%u one", a->width, a->height,
                       b->width, b->height);
    uint8_t *px = alloc_rgb(a->width, a->height, path, d);
    if (!px)
        return ALB_ERR_NOMEM;
    unsigned faces = 0, colours = 0;
    for (size_t i = 0; i < (size_t)a->width * a->height; i++)
        diff_pixel(a, b, i, px + 3 * i, &faces, &colours);
    e = write_rgb(path, a->width, a->height, px, d);
    free(px);
    if (face_diff)
        *face_diff = faces;
    if (colour_diff)
        *colour_diff = colours;
    return e;
}
