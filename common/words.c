/* words.c — packing and validating decoding of the GP -> VP word stream.
 * The layouts are those of docs/word-format.md; tests/test_words.c checks
 * every packet by round trip and every malformation by its message. */
#include "albatros/words.h"
#include "memh.h"
#include "albatros/file.h"
#include "fix.h"

#include <ctype.h>
#include <errno.h>
#include <stdarg.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

void alb_ws_buf_init(alb_ws_buf *b) { memset(b, 0, sizeof *b); }

void alb_ws_buf_free(alb_ws_buf *b)
{
    free(b->w);
    memset(b, 0, sizeof *b);
}

void alb_ws_put(alb_ws_buf *b, uint32_t word)
{
    if (b->oom)
        return;
    if (b->n == b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 1024;
        uint32_t *w = realloc(b->w, cap * sizeof *w);
        if (!w) {
            b->oom = true;
            return;
        }
        b->w = w;
        b->cap = cap;
    }
    b->w[b->n++] = word;
}

static uint32_t op_word(unsigned op, uint32_t low24) { return (uint32_t)op << 24 | (low24 & 0xFFFFFF); }

void alb_ws_put_config(alb_ws_buf *b, const alb_ws_config *c)
{
    uint32_t near_bits;
    memcpy(&near_bits, &c->near, sizeof near_bits);
    alb_ws_put(b, op_word(ALB_WS_OP_CONFIG, ALB_WS_VERSION << 16 | 2));
    alb_ws_put(b, (uint32_t)c->coef_bits << 8 | c->edge_frac_bits);
    alb_ws_put(b, near_bits);
}

void alb_ws_put_texture(alb_ws_buf *b, const alb_ws_texture *t)
{
    size_t n = (size_t)1 << (2 * t->log2size);
    alb_ws_put(b, op_word(ALB_WS_OP_TEXTURE, (uint32_t)t->id << 16 | (uint32_t)t->log2size << 8));
    for (size_t i = 0; i < n; i++)
        alb_ws_put(b, t->texels[i] & 0xFFFFFF);
}

void alb_ws_put_frame(alb_ws_buf *b, const alb_ws_frame *f)
{
    alb_ws_put(b, op_word(ALB_WS_OP_FRAME, f->number));
    alb_ws_put(b, f->background & 0xFFFFFF);
    alb_ws_put(b, (f->fog ? 1u << 31 : 0) | (f->fog_rgb & 0xFFFFFF));
    alb_ws_put(b, f->fog_near);
    alb_ws_put(b, f->fog_far);
}

static void put_form(alb_ws_buf *b, const alb_ws_form *f)
{
    alb_ws_put(b, (uint32_t)f->exp);
    for (int i = 0; i < 3; i++)
        alb_ws_put(b, (uint32_t)f->m[i]);
}

void alb_ws_put_face(alb_ws_buf *b, const alb_ws_face *f)
{
    alb_ws_put(b, op_word(ALB_WS_OP_FACE, (uint32_t)f->n_edges << 16 | (uint32_t)f->flags << 8 | f->texture));
    alb_ws_put(b, f->id);
    alb_ws_put(b, f->rgb & 0xFFFFFF);
    put_form(b, &f->depth);
    if (f->flags & ALB_WS_FACE_SHADE)
        put_form(b, &f->shade);
    if (f->flags & ALB_WS_FACE_TEXTURE) {
        put_form(b, &f->tex_u);
        put_form(b, &f->tex_v);
    }
    for (unsigned i = 0; i < f->n_edges; i++) {
        alb_ws_put(b, alb_ws_edge_word0(&f->edge[i]));
        alb_ws_put(b, f->edge[i].x2);
    }
}

size_t alb_ws_face_words(const alb_ws_face *f)
{
    size_t n = 3 + 4;
    if (f->flags & ALB_WS_FACE_SHADE)
        n += 4;
    if (f->flags & ALB_WS_FACE_TEXTURE)
        n += 8;
    return n + 2u * f->n_edges;
}

size_t alb_ws_packet_words(uint32_t header)
{
    unsigned flags = header >> 8 & 0xFF;
    switch (header >> 24) {
    case ALB_WS_OP_CONFIG: return 3;
    case ALB_WS_OP_TEXTURE: {
        unsigned lg = header >> 8 & 0xFF;
        /* a size the decoder refuses: the header alone, refused there */
        return lg > ALB_WS_TEX_LOG2_MAX ? 1 : 1 + ((size_t)1 << (2 * lg));
    }
    case ALB_WS_OP_FRAME: return 5;
    case ALB_WS_OP_FACE:
        return 7 + (flags & ALB_WS_FACE_SHADE ? 4 : 0) + (flags & ALB_WS_FACE_TEXTURE ? 8 : 0) +
               2 * (size_t)(header >> 16 & 0xFF);
    case ALB_WS_OP_FRAME_END:
    case ALB_WS_OP_END: return 1;
    }
    return 0;
}

void alb_ws_put_frame_end(alb_ws_buf *b, uint32_t faces) { alb_ws_put(b, op_word(ALB_WS_OP_FRAME_END, faces)); }
void alb_ws_put_end(alb_ws_buf *b) { alb_ws_put(b, op_word(ALB_WS_OP_END, 0)); }

/* ---- decoding ---- */

void alb_ws_reader_init(alb_ws_reader *r, const uint32_t *w, size_t n, const char *name)
{
    memset(r, 0, sizeof *r);
    r->w = w;
    r->n = n;
    r->name = name ? name : "<stream>";
    r->max_faces = 0xFFFFFF;
}

/* Fail at word `word`: the message names the word index; the diag the byte offset. */
static alb_err __attribute__((format(printf, 4, 5)))
bad(alb_ws_reader *r, alb_diag *d, size_t word, const char *fmt, ...)
{
    char msg[400];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    return alb_diag_off(d, ALB_ERR_STREAM, r->name, (long long)word * 4, "word %zu: %s", word, msg);
}

/* Take `count` words starting at r->pos, or fail naming what was cut short. */
static alb_err need(alb_ws_reader *r, alb_diag *d, size_t count, const char *what)
{
    if (r->n - r->pos < count)
        return bad(r, d, r->n, "stream truncated inside %s (%zu more words expected)", what, count - (r->n - r->pos));
    return ALB_OK;
}

static alb_err read_form(alb_ws_reader *r, alb_diag *d, alb_ws_form *f, const char *name)
{
    alb_err e = need(r, d, 4, name);
    if (e)
        return e;
    int32_t ex = (int32_t)r->w[r->pos];
    if (ex < FORM_EXP_MIN || ex > FORM_EXP_MAX)
        return bad(r, d, r->pos, "%s.exp = %d outside %d..%d", name, ex,
                        FORM_EXP_MIN, FORM_EXP_MAX);
    f->exp = ex;
    int32_t lim = (int32_t)((1u << (r->config.coef_bits - 1)) - 1);
    for (int i = 0; i < 3; i++) {
        size_t at = r->pos + 1 + (size_t)i;
        int32_t m = (int32_t)r->w[at];
        if (m > lim || m < -lim)
            return bad(r, d, at, "%s.%c = %d does not fit %u-bit mantissa (|m| <= %d)", name, "ABC"[i], m, r->config.coef_bits, lim);
        f->m[i] = m;
    }
    r->pos += 4;
    return ALB_OK;
}

static alb_err read_face(alb_ws_reader *r, alb_diag *d, alb_ws_face *f, uint32_t head)
{
    size_t at = r->pos;
    f->n_edges = (uint8_t)(head >> 16);
    f->flags = (uint8_t)(head >> 8);
    f->texture = (uint8_t)head;
    if (f->flags & ~ALB_WS_FACE_FLAGS_ALL)
        return bad(r, d, at, "FACE flags 0x%02x has reserved bits set", f->flags);
    if (f->n_edges > ALB_WS_MAX_EDGES)
        return bad(r, d, at, "FACE has %u edges, the VP edge store holds %d", f->n_edges, ALB_WS_MAX_EDGES);
    r->pos++;
    alb_err e = need(r, d, 2, "FACE header");
    if (e)
        return e;
    f->id = r->w[r->pos];
    if (r->w[r->pos + 1] >> 24)
        return bad(r, d, r->pos + 1, "FACE colour has bits 31..24 set");
    f->rgb = r->w[r->pos + 1];
    r->pos += 2;
    if ((e = read_form(r, d, &f->depth, "depth")))
        return e;
    if ((f->flags & ALB_WS_FACE_SHADE) && (e = read_form(r, d, &f->shade, "shade")))
        return e;
    if (f->flags & ALB_WS_FACE_TEXTURE) {
        if ((e = read_form(r, d, &f->tex_u, "tex_u")) || (e = read_form(r, d, &f->tex_v, "tex_v")))
            return e;
    }
    if ((e = need(r, d, 2u * f->n_edges, "FACE edges")))
        return e;
    uint32_t lim = 1u << (EDGE_INT_BITS + r->config.edge_frac_bits);
    for (unsigned i = 0; i < f->n_edges; i++) {
        uint32_t w0 = r->w[r->pos], w1 = r->w[r->pos + 1];
        alb_ws_edge *ed = &f->edge[i];
        ed->u = (uint8_t)(w0 >> 31);
        ed->r = (uint8_t)(w0 >> 30 & 1);
        ed->x1 = w0 & 0x3FFFFFFF;
        ed->x2 = w1;
        if (ed->x1 >= lim)
            return bad(r, d, r->pos, "edge[%u].X1 = 0x%x exceeds the 3.%u format", i, ed->x1, r->config.edge_frac_bits);
        if (ed->x2 >= lim)
            return bad(r, d, (r->pos + 1), "edge[%u].X2 = 0x%x exceeds the 3.%u format", i, ed->x2, r->config.edge_frac_bits);
        r->pos += 2;
    }
    return ALB_OK;
}

static const char *op_name(unsigned op)
{
    switch (op) {
    case ALB_WS_OP_CONFIG: return "CONFIG";
    case ALB_WS_OP_TEXTURE: return "TEXTURE";
    case ALB_WS_OP_FRAME: return "FRAME";
    case ALB_WS_OP_FACE: return "FACE";
    case ALB_WS_OP_FRAME_END: return "FRAME_END";
    case ALB_WS_OP_END: return "END";
    }
    return NULL;
}

alb_err alb_ws_next(alb_ws_reader *r, alb_ws_event *ev, alb_diag *d)
{
    alb_err e;
    if (r->ended)
        return bad(r, d, r->pos, "read past END");
    if (r->pos >= r->n)
        return bad(r, d, r->n, "stream ends without an END packet%s",
                        r->in_frame ? " (inside a frame)" : "");
    size_t at = r->pos;
    uint32_t head = r->w[at];
    unsigned op = head >> 24;
    ev->first = at;
    if (!op_name(op))
        return bad(r, d, at, "0x%08x is not a packet opcode (expected %s)", head,
                        !r->have_config ? "CONFIG" : r->in_frame ? "FACE or FRAME_END"
                                                                 : "TEXTURE, FRAME or END");
    if (!r->have_config && op != ALB_WS_OP_CONFIG)
        return bad(r, d, at, "%s before CONFIG (a stream starts with CONFIG)", op_name(op));
    if (r->in_frame && op != ALB_WS_OP_FACE && op != ALB_WS_OP_FRAME_END)
        return bad(r, d, at, "%s inside a frame (expected FACE or FRAME_END)", op_name(op));
    if (!r->in_frame && (op == ALB_WS_OP_FACE || op == ALB_WS_OP_FRAME_END))
        return bad(r, d, at, "%s outside a frame (expected FRAME first)", op_name(op));
    switch (op) {
    case ALB_WS_OP_CONFIG: {
        if (r->have_config)
            return bad(r, d, at, "second CONFIG");
        if ((head >> 16 & 0xFF) != ALB_WS_VERSION)
            return bad(r, d, at, "CONFIG version %u, this decoder reads version %d", head >> 16 & 0xFF, ALB_WS_VERSION);
        if ((head & 0xFFFF) != 2)
            return bad(r, d, at, "CONFIG length %u, expected 2", head & 0xFFFF);
        if ((e = need(r, d, 3, "CONFIG")))
            return e;
        uint32_t w1 = r->w[at + 1];
        ev->u.config.edge_frac_bits = w1 & 0xFF;
        ev->u.config.coef_bits = w1 >> 8 & 0xFF;
        if (w1 >> 16 || ev->u.config.edge_frac_bits < EDGE_FRAC_MIN ||
            ev->u.config.edge_frac_bits > EDGE_FRAC_MAX ||
            ev->u.config.coef_bits < COEF_BITS_MIN || ev->u.config.coef_bits > COEF_BITS_MAX)
            return bad(r, d, (at + 1), "CONFIG formats 0x%08x invalid (edge_frac_bits %d..%d, "
                            "coef_bits %d..%d, bits 31..16 zero)", w1, EDGE_FRAC_MIN,
                            EDGE_FRAC_MAX, COEF_BITS_MIN, COEF_BITS_MAX);
        memcpy(&ev->u.config.near, &r->w[at + 2], sizeof ev->u.config.near);
        if (!(ev->u.config.near > 0 && isfinite(ev->u.config.near)))
            return bad(r, d, at + 2, "CONFIG near = %g: must be positive and finite",
                       (double)ev->u.config.near);
        r->config = ev->u.config;
        r->have_config = true;
        r->pos += 3;
        ev->kind = ALB_WS_EV_CONFIG;
        break;
    }
    case ALB_WS_OP_TEXTURE: {
        unsigned lg = head >> 8 & 0xFF;
        if (lg > ALB_WS_TEX_LOG2_MAX)
            return bad(r, d, at, "TEXTURE header 0x%08x: size 2^%u, at most 2^%d", head, lg,
                       ALB_WS_TEX_LOG2_MAX);
        if (head & 0xFF)
            return bad(r, d, at, "TEXTURE header 0x%08x has reserved bits 7..0 set", head);
        size_t count = (size_t)1 << (2 * lg);
        r->pos++;
        if ((e = need(r, d, count, "TEXTURE texels")))
            return e;
        for (size_t i = 0; i < count; i++)
            if (r->w[r->pos + i] >> 24)
                return bad(r, d, r->pos + i, "texel has bits 31..24 set");
        ev->u.texture.id = (uint8_t)(head >> 16);
        ev->u.texture.log2size = (uint8_t)lg;
        ev->u.texture.texels = r->w + r->pos;
        r->pos += count;
        ev->kind = ALB_WS_EV_TEXTURE;
        break;
    }
    case ALB_WS_OP_FRAME: {
        if ((e = need(r, d, 5, "FRAME header")))
            return e;
        const uint32_t *w = r->w + at;
        if (w[1] >> 24)
            return bad(r, d, at + 1, "FRAME background has bits 31..24 set");
        if (w[2] >> 24 & 0x7F)
            return bad(r, d, at + 2, "FRAME fog word has bits 30..24 set");
        alb_ws_frame *f = &ev->u.frame;
        f->number = head & 0xFFFFFF;
        f->background = w[1];
        f->fog = w[2] >> 31;
        f->fog_rgb = w[2] & 0xFFFFFF;
        f->fog_near = w[3];
        f->fog_far = w[4];
        if (f->fog && f->fog_far <= f->fog_near)
            return bad(r, d, at + 4, "FRAME fog far must exceed fog near");
        r->pos += 5;
        r->in_frame = true;
        r->faces_in_frame = 0;
        ev->kind = ALB_WS_EV_FRAME;
        break;
    }
    case ALB_WS_OP_FACE:
        if (r->in_frame && r->faces_in_frame >= r->max_faces)
            return bad(r, d, at, "frame has more than %u faces (frame_faces=%u, docs/limits.md)",
                       r->max_faces, r->max_faces);
        if ((e = read_face(r, d, &ev->u.face, head)))
            return e;
        r->faces_in_frame++;
        ev->kind = ALB_WS_EV_FACE;
        break;
    case ALB_WS_OP_FRAME_END:
        if ((head & 0xFFFFFF) != (r->faces_in_frame & 0xFFFFFF))
            return bad(r, d, at, "FRAME_END counts %u faces, the frame had %u", head & 0xFFFFFF, r->faces_in_frame);
        ev->u.faces = head & 0xFFFFFF;
        r->pos++;
        r->in_frame = false;
        ev->kind = ALB_WS_EV_FRAME_END;
        break;
    case ALB_WS_OP_END:
        if (head & 0xFFFFFF)
            return bad(r, d, at, "END has reserved bits 23..0 set");
        r->pos++;
        if (r->pos != r->n)
            return bad(r, d, r->pos, "%zu words after END", r->n - r->pos);
        r->ended = true;
        ev->kind = ALB_WS_EV_END;
        break;
    }
    ev->count = r->pos - at;
    return ALB_OK;
}

/* ---- description ---- */

static double edge_value(uint32_t x, unsigned frac)
{
    return ldexp((double)x, -(int)frac) - EDGE_ORIGIN;
}

static void describe_face_word(const alb_ws_face *f, const alb_ws_config *cfg, size_t k,
                               char *buf, size_t len)
{
    if (k == 0) {
        snprintf(buf, len, "FACE edges=%u flags=%s%s%s texture=%u", f->n_edges,
                 f->flags & ALB_WS_FACE_SHADE ? "S" : "-", f->flags & ALB_WS_FACE_TEXTURE ? "T" : "-",
                 f->flags & ALB_WS_FACE_FOG ? "F" : "-", f->texture);
        return;
    }
    if (k == 1) {
        snprintf(buf, len, "face.id=%u", f->id);
        return;
    }
    if (k == 2) {
        snprintf(buf, len, "face.rgb=%u,%u,%u", f->rgb >> 16 & 0xFF, f->rgb >> 8 & 0xFF, f->rgb & 0xFF);
        return;
    }
    const alb_ws_form *forms[4];
    const char *names[4];
    unsigned nf = 0;
    forms[nf] = &f->depth, names[nf++] = "depth";
    if (f->flags & ALB_WS_FACE_SHADE)
        forms[nf] = &f->shade, names[nf++] = "shade";
    if (f->flags & ALB_WS_FACE_TEXTURE) {
        forms[nf] = &f->tex_u, names[nf++] = "tex_u";
        forms[nf] = &f->tex_v, names[nf++] = "tex_v";
    }
    size_t j = k - 3;
    if (j < 4u * nf) {
        const alb_ws_form *fm = forms[j / 4];
        if (j % 4 == 0)
            snprintf(buf, len, "%s.exp=%d", names[j / 4], fm->exp);
        else
            snprintf(buf, len, "%s.%c=%d (%.9g)", names[j / 4], "ABC"[j % 4 - 1],
                     fm->m[j % 4 - 1], ldexp(fm->m[j % 4 - 1], fm->exp));
        return;
    }
    j -= 4u * nf;
    const alb_ws_edge *e = &f->edge[j / 2];
    if (j % 2 == 0)
        snprintf(buf, len, "edge[%zu] U=%u R=%u X1=0x%x (%+.6f)", j / 2, e->u, e->r, e->x1,
                 edge_value(e->x1, cfg->edge_frac_bits));
    else
        snprintf(buf, len, "edge[%zu] X2=0x%x (%+.6f)", j / 2, e->x2,
                 edge_value(e->x2, cfg->edge_frac_bits));
}

void alb_ws_describe_word(const alb_ws_event *ev, const alb_ws_config *cfg, size_t k, char *buf, size_t len)
{
    switch (ev->kind) {
    case ALB_WS_EV_CONFIG:
        if (k == 0)
            snprintf(buf, len, "CONFIG version=%d", ALB_WS_VERSION);
        else if (k == 1)
            snprintf(buf, len, "config edge_frac_bits=%u coef_bits=%u",
                     ev->u.config.edge_frac_bits, ev->u.config.coef_bits);
        else
            snprintf(buf, len, "config near=%.9g", (double)ev->u.config.near);
        break;
    case ALB_WS_EV_TEXTURE:
        if (k == 0)
            snprintf(buf, len, "TEXTURE id=%u size=%ux%u", ev->u.texture.id,
                     1u << ev->u.texture.log2size, 1u << ev->u.texture.log2size);
        else {
            unsigned s = 1u << ev->u.texture.log2size;
            uint32_t t = ev->u.texture.texels[k - 1];
            snprintf(buf, len, "texel[%zu,%zu]=%u,%u,%u", (k - 1) % s, (k - 1) / s,
                     t >> 16 & 0xFF, t >> 8 & 0xFF, t & 0xFF);
        }
        break;
    case ALB_WS_EV_FRAME: {
        const alb_ws_frame *f = &ev->u.frame;
        switch (k) {
        case 0: snprintf(buf, len, "FRAME number=%u", f->number); break;
        case 1: snprintf(buf, len, "frame.background=%u,%u,%u", f->background >> 16,
                         f->background >> 8 & 0xFF, f->background & 0xFF); break;
        case 2: snprintf(buf, len, "frame.fog=%s rgb=%u,%u,%u", f->fog ? "on" : "off",
                         f->fog_rgb >> 16, f->fog_rgb >> 8 & 0xFF, f->fog_rgb & 0xFF); break;
        case 3: snprintf(buf, len, "frame.fog_near=%.4f", f->fog_near / 256.0); break;
        default: snprintf(buf, len, "frame.fog_far=%.4f", f->fog_far / 256.0); break;
        }
        break;
    }
    case ALB_WS_EV_FACE:
        describe_face_word(&ev->u.face, cfg, k, buf, len);
        break;
    case ALB_WS_EV_FRAME_END:
        snprintf(buf, len, "FRAME_END faces=%u", ev->u.faces);
        break;
    case ALB_WS_EV_END:
        snprintf(buf, len, "END");
        break;
    }
}

void alb_ws_describe_at(const uint32_t *w, size_t n, size_t idx, char *buf, size_t len)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    snprintf(buf, len, "beyond the end of the stream");
    if (!ev)
        return;
    alb_ws_reader_init(&r, w, n, "");
    while (!r.ended && idx < n) {
        if (alb_ws_next(&r, ev, &d)) {
            snprintf(buf, len, "undecodable: %s", d.msg);
            break;
        }
        if (idx < ev->first + ev->count) {
            alb_ws_describe_word(ev, &r.config, idx - ev->first, buf, len);
            break;
        }
    }
    free(ev);
}

alb_err alb_ws_dump_piece(FILE *out, alb_ws_reader *r, const uint32_t *w, size_t n, size_t base,
                          alb_diag *d)
{
    alb_ws_event *ev = malloc(sizeof *ev);
    char desc[160];
    if (!ev)
        return ALB_ERR_NOMEM;
    r->w = w;
    r->n = n;
    r->pos = 0;
    alb_err e = ALB_OK;
    while (!r->ended && r->pos < n) {
        if ((e = alb_ws_next(r, ev, d)))
            break;
        for (size_t k = 0; k < ev->count; k++) {
            size_t at = ev->first + k;
            alb_ws_describe_word(ev, &r->config, k, desc, sizeof desc);
            fprintf(out, "%08zx  %08x  %s\n", (base + at) * 4, w[at], desc);
        }
    }
    if (e && d->offset >= 0)   /* located in the whole stream */
        d->offset += (long long)base * 4;
    free(ev);
    return e;
}

alb_err alb_ws_dump(FILE *out, const uint32_t *w, size_t n, const char *name, alb_diag *d)
{
    alb_ws_reader r;
    alb_ws_reader_init(&r, w, n, name);
    alb_err e = alb_ws_dump_piece(out, &r, w, n, 0, d);
    if (!e && !r.ended) {   /* the words ran out: the decoder says how */
        alb_ws_event *ev = malloc(sizeof *ev);
        e = ev ? alb_ws_next(&r, ev, d) : ALB_ERR_NOMEM;
        free(ev);
    }
    return e;
}

/* ---- files ---- */

/* The words of a memh stream, into a growing array. */
typedef struct {
    uint32_t *w;
    size_t n, cap;
} memh_words;

static int memh_word(void *ctx, const uint32_t *value, unsigned line, unsigned col)
{
    (void)line, (void)col;
    memh_words *m = ctx;
    if (m->n == m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 4096;
        uint32_t *nw = realloc(m->w, cap * sizeof *nw);
        if (!nw)
            return -1;
        m->w = nw;
        m->cap = cap;
    }
    m->w[m->n++] = value[0];
    return 0;
}

/* The first packet of a binary stream, CONFIG, from its first 12 bytes:
 * a file that does not start with one is refused before the rest is read
 * (/dev/zero or a text file given by mistake would otherwise be read to
 * its end, or to the end of memory). */
static alb_err check_first_packet(const unsigned char *b, const char *path, alb_diag *d)
{
    uint32_t w[3];
    for (int i = 0; i < 3; i++)
        w[i] = (uint32_t)b[4 * i] | (uint32_t)b[4 * i + 1] << 8 | (uint32_t)b[4 * i + 2] << 16 |
               (uint32_t)b[4 * i + 3] << 24;
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    if (!ev)
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
    alb_ws_reader_init(&r, w, 3, path);
    alb_err e = alb_ws_next(&r, ev, d);
    free(ev);
    return e;
}

/* The file's bytes: its first 12 tell memh text from a binary stream, and
 * a binary one whose first packet is wrong is not read further; memh is
 * text, whose reading a NUL ends (memh_scan refuses it). */
static alb_err read_stream_bytes(const char *path, char **text, size_t *len, bool *memh,
                                 alb_diag *d)
{
    const char *why;
    *text = NULL;
    FILE *f = alb_file_open_input(path, false, &why);
    if (!f)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "cannot open: %s", why);
    unsigned char head[12];
    size_t got = fread(head, 1, sizeof head, f);
    *memh = memh_looks_like((const char *)head, got);
    alb_err e = ALB_OK;
    if (ferror(f))
        e = alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(errno));
    else if (!*memh && got == sizeof head)
        e = check_first_packet(head, path, d);
    char *rest = NULL;
    size_t nrest = 0;
    int rc = e ? 0 : *memh ? alb_file_read_text(f, &rest, &nrest) : alb_file_read_all(f, &rest, &nrest);
    int err = errno;
    fclose(f);
    if (e)
        return e;
    if (rc == 0 && !(*text = malloc(got + nrest + 1)))
        rc = -2;
    if (rc == -2) {
        free(rest);
        return alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "too large for memory");
    }
    if (rc)
        return alb_diag_at(d, ALB_ERR_IO, path, 0, 0, "read error: %s", strerror(err));
    memcpy(*text, head, got);
    memcpy(*text + got, rest, nrest);
    *len = got + nrest;
    (*text)[*len] = 0;
    free(rest);
    return ALB_OK;
}

alb_err alb_ws_read_file(const char *path, uint32_t **w, size_t *n, alb_diag *d)
{
    char *text;
    size_t len = 0;
    bool memh = false;
    alb_err le = read_stream_bytes(path, &text, &len, &memh, d);
    if (le)
        return le;
    if (memh) {
        memh_words m = {NULL, 0, 0};
        alb_err e = memh_scan(text, len, path, 32, memh_word, &m, d);
        free(text);
        if (e) {
            free(m.w);
            return e;
        }
        *w = m.w ? m.w : malloc(4);
        *n = m.n;
        return *w ? ALB_OK : alb_diag_at(d, ALB_ERR_NOMEM, path, 0, 0, "out of memory");
    }
    const uint8_t *bytes = (const uint8_t *)text;
    if (len % 4) {
        free(text);
        return alb_diag_off(d, ALB_ERR_STREAM, path, (long long)(len - len % 4),
                        "file length %zu is not a whole number of 32-bit words", len);
    }
    uint32_t *words = malloc(len ? len : 4);
    if (!words) {
        free(text);
        return ALB_ERR_NOMEM;
    }
    for (size_t i = 0; i < len / 4; i++)
        words[i] = (uint32_t)bytes[4 * i] | (uint32_t)bytes[4 * i + 1] << 8 |
                   (uint32_t)bytes[4 * i + 2] << 16 | (uint32_t)bytes[4 * i + 3] << 24;
    free(text);
    *w = words;
    *n = len / 4;
    return ALB_OK;
}

/* Every stream file goes through alb_out (file.h): the old file stays until
 * the new stream is complete, a device or FIFO is written straight through. */
alb_err alb_ws_writer_open(alb_ws_writer *wr, const char *path, bool memh, alb_diag *d)
{
    memset(wr, 0, sizeof *wr);
    wr->memh = memh;
    alb_err e = alb_out_open(&wr->out, path, memh ? ALB_OUT_DASH : 0, d);
    if (e)
        return e;
    if (!(wr->f = alb_out_stdio(&wr->out, d)))
        return ALB_ERR_IO;
    if (memh)
        fprintf(wr->f, "// albatros GP -> VP word stream for $readmemh (docs/word-format.md)\n");
    return ALB_OK;
}

void alb_ws_writer_put(alb_ws_writer *wr, const uint32_t *w, size_t n)
{
    for (size_t i = 0; i < n && !ferror(wr->f); i++) {
        if (wr->memh) {
            fprintf(wr->f, "%08x\n", w[i]);
        } else {
            uint8_t b[4] = {(uint8_t)w[i], (uint8_t)(w[i] >> 8), (uint8_t)(w[i] >> 16),
                            (uint8_t)(w[i] >> 24)};
            fwrite(b, 1, 4, wr->f);
        }
    }
    wr->words += n;
}

alb_err alb_ws_writer_close(alb_ws_writer *wr, alb_diag *d)
{
    if (wr->memh)
        fprintf(wr->f, "// %zu words\n", wr->words);
    return alb_out_commit(&wr->out, d);
}

void alb_ws_writer_abort(alb_ws_writer *wr) { alb_out_abort(&wr->out); }

static alb_err write_words(const char *path, bool memh, const uint32_t *w, size_t n, alb_diag *d)
{
    alb_ws_writer wr;
    alb_err e = alb_ws_writer_open(&wr, path, memh, d);
    if (e)
        return e;
    alb_ws_writer_put(&wr, w, n);
    return alb_ws_writer_close(&wr, d);
}

alb_err alb_ws_write_file(const char *path, const uint32_t *w, size_t n, alb_diag *d)
{
    return write_words(path, false, w, n, d);
}

alb_err alb_ws_write_memh(const char *path, const uint32_t *w, size_t n, alb_diag *d)
{
    return write_words(path, true, w, n, d);
}

double alb_ws_form_eval(const alb_ws_form *f, double x, double y)
{
    return ldexp((double)f->m[0] * x + (double)f->m[1] * y + (double)f->m[2], f->exp);
}
