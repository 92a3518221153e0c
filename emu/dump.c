/* dump.c — frame-store dumps of RTL benches (include/albatros/dump.h). */
#include "albatros/dump.h"
#include "albatros/file.h"
#include "../common/memh.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Pixel i of f as the record's four 32-bit limbs, bits 31..0 first. */
static void record(const alb_frame *f, size_t i, uint32_t r[4])
{
    r[3] = f->face[i];
    r[2] = f->depth[i];
    r[1] = (uint32_t)f->rgb[3 * i] << 16 | f->rgb[3 * i + 1];
    r[0] = (uint32_t)f->rgb[3 * i + 2] << 16 | (uint32_t)f->level[i] << 8 |
           (f->coverage[i] > 255 ? 255u : f->coverage[i]);
}

alb_err alb_dump_write(const char *path, const alb_frame *f, alb_dump_format fmt, alb_diag *d)
{
    /* the old file stays until the new one is complete (file.h) */
    alb_out o;
    alb_err e = alb_out_open(&o, path, fmt == ALB_DUMP_MEMH ? ALB_OUT_DASH : 0, d);
    if (e)
        return e;
    FILE *fp = alb_out_stdio(&o, d);
    if (!fp)
        return ALB_ERR_IO;
    size_t n = (size_t)f->width * f->height;
    if (fmt == ALB_DUMP_MEMH)
        fprintf(fp, "// albatros frame %u, %ux%u: face depth R G B level coverage, "
                    "128 bits a pixel (docs/cosim.md)\n", f->number, f->width, f->height);
    for (size_t i = 0; i < n; i++) {
        uint32_t r[4];
        record(f, i, r);
        if (fmt == ALB_DUMP_MEMH) {
            fprintf(fp, "%08x%08x%08x%08x\n", r[3], r[2], r[1], r[0]);
        } else {
            uint8_t b[ALB_DUMP_RECORD_BYTES];
            for (int k = 0; k < 16; k++)
                b[k] = (uint8_t)(r[k / 4] >> (8 * (k % 4)));
            fwrite(b, 1, sizeof b, fp);
        }
    }
    return alb_out_commit(&o, d);
}

bool alb_dump_is_exr(const char *path)
{
    FILE *f = fopen(path, "rb");
    unsigned char m[4] = {0};
    if (f) {
        size_t got = fread(m, 1, 4, f);
        fclose(f);
        return got == 4 && m[0] == 0x76 && m[1] == 0x2f && m[2] == 0x31 && m[3] == 0x01;
    }
    return false;
}

typedef struct {
    alb_frame *f;
    const char *path;
    size_t n, next;
    alb_diag *d;
} reading;

/* One record into pixel `next`: its fields checked against the formats. */
static int put(reading *r, const uint32_t v[4], const char *where)
{
    alb_frame *f = r->f;
    size_t i = r->next;
    if (i >= r->n) {
        alb_diag_at(r->d, ALB_ERR_PARSE, r->path, 0, 0, "%s: more than the %ux%u = %zu pixels",
                    where, f->width, f->height, r->n);
        return -1;
    }
    uint32_t top = (1u << f->colour_bits) - 1, rgb[3] = {v[1] >> 16, v[1] & 0xFFFF, v[0] >> 16};
    static const char *const ch[3] = {"R", "G", "B"};
    for (int c = 0; c < 3; c++)
        if (rgb[c] > top) {
            alb_diag_at(r->d, ALB_ERR_PARSE, r->path, 0, 0,
                        "%s: pixel (%zu, %zu): %s = %u exceeds colour_bits = %u", where,
                        i % f->width, i / f->width, ch[c], rgb[c], f->colour_bits);
            return -1;
        }
    f->face[i] = v[3];
    f->depth[i] = v[2];
    for (int c = 0; c < 3; c++)
        f->rgb[3 * i + c] = (uint16_t)rgb[c];
    f->level[i] = (uint8_t)(v[0] >> 8);
    f->coverage[i] = (uint16_t)(v[0] & 0xFF);
    r->next++;
    return 0;
}

static int put_memh(void *ctx, const uint32_t *value, unsigned line, unsigned col)
{
    reading *r = ctx;
    char where[64];
    snprintf(where, sizeof where, "line %u, column %u", line, col);
    return put(r, value, where);
}

alb_err alb_dump_read(const char *path, const alb_frame *shape, alb_frame *out, alb_diag *d)
{
    memset(out, 0, sizeof *out);
    char *text;
    size_t len;
    alb_err le = alb_file_load(path, &text, &len, d);
    if (le)
        return le;
    if (alb_frame_alloc(out, shape->width, shape->height, false)) {
        free(text);
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
    }
    out->colour_bits = shape->colour_bits;
    out->depth_bits = shape->depth_bits;
    out->aa_levels = shape->aa_levels;
    out->near = shape->near;
    out->number = shape->number;
    reading r = {out, path, (size_t)shape->width * shape->height, 0, d};
    alb_err e = ALB_OK;
    if (memh_looks_like(text, len)) {
        e = memh_scan(text, len, path, 128, put_memh, &r, d);
    } else if (len != r.n * ALB_DUMP_RECORD_BYTES) {
        e = alb_diag_off(d, ALB_ERR_PARSE, path, (long long)(len < r.n * 16 ? len : r.n * 16),
                         "a raw dump of %ux%u pixels is %zu bytes, this one %zu", shape->width,
                         shape->height, r.n * 16, len);
    } else {
        const uint8_t *b = (const uint8_t *)text;
        for (size_t i = 0; i < r.n && !e; i++, b += 16) {
            uint32_t v[4];
            for (int k = 0; k < 4; k++)
                v[k] = (uint32_t)b[4 * k] | (uint32_t)b[4 * k + 1] << 8 |
                       (uint32_t)b[4 * k + 2] << 16 | (uint32_t)b[4 * k + 3] << 24;
            char where[64];
            snprintf(where, sizeof where, "offset %zu", i * 16);
            if (put(&r, v, where))
                e = ALB_ERR_PARSE;
        }
    }
    if (!e && r.next != r.n)
        e = alb_diag_at(d, ALB_ERR_PARSE, path, 0, 0, "%zu pixels, a %ux%u frame has %zu",
                        r.next, shape->width, shape->height, r.n);
    free(text);
    if (e)
        alb_frame_free(out);
    return e;
}
