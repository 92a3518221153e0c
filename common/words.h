/* words.h — the GP -> VP word stream (docs/word-format.md): 32-bit words,
 * packets introduced by an opcode byte.  Packing, a validating decoder that
 * names the offending word and field, and the annotated hex dump. */
#ifndef ALBATROS_WORDS_H
#define ALBATROS_WORDS_H

#include "diag.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#define WS_VERSION          1
#define WS_MAX_EDGES        64    /* VP edge store per face */
#define WS_TEX_LOG2_MAX     10    /* textures up to 1024 x 1024 */
#define WS_MAX_TEXTURES     256

enum ws_opcode {
    WS_OP_CONFIG = 0xA5,
    WS_OP_TEXTURE = 0xA7,
    WS_OP_FRAME = 0xF0,
    WS_OP_FACE = 0xFA,
    WS_OP_FRAME_END = 0xFE,
    WS_OP_END = 0xFF
};

enum ws_face_flag {
    WS_FACE_SHADE = 1,    /* intensity form present (eq. 7) */
    WS_FACE_TEXTURE = 2,  /* u and v forms present */
    WS_FACE_FOG = 4       /* fog applies to this face */
};
#define WS_FACE_FLAGS_ALL 7u

/* An edge in the VP format (19): U | R | X1 | X2, intercepts unsigned 3.F. */
typedef struct {
    uint8_t u, r;
    uint32_t x1, x2;
} ws_edge;

/* A linear form of screen position in block floating point:
 * value(x, y) = (m[0] x + m[1] y + m[2]) * 2^exp. */
typedef struct {
    int32_t exp;
    int32_t m[3];
} ws_form;

typedef struct {
    unsigned edge_frac_bits, coef_bits;
    float near;               /* the scene's near distance: metadata for
                                 converting near/Z to distances; the VP's
                                 arithmetic does not use it */
} ws_config;

typedef struct {
    uint8_t id, log2size;
    const uint32_t *texels;   /* (1 << log2size)^2 words 0x00RRGGBB, row 0 = v 0 */
} ws_texture;

typedef struct {
    uint32_t number;          /* 24 bits */
    uint32_t background;      /* 0x00RRGGBB */
    bool fog;
    uint32_t fog_rgb;
    uint32_t fog_near, fog_far;  /* Z / near, unsigned 24.8 */
} ws_frame;

typedef struct {
    uint32_t id;
    uint8_t flags, texture, n_edges;
    uint32_t rgb;
    ws_form depth, shade, tex_u, tex_v;
    ws_edge edge[WS_MAX_EDGES];
} ws_face;

/* A growable word buffer. */
typedef struct {
    uint32_t *w;
    size_t n, cap;
    bool oom;                 /* sticky: an allocation failed */
} ws_buf;

void ws_buf_init(ws_buf *b);
void ws_buf_free(ws_buf *b);
void ws_put(ws_buf *b, uint32_t word);
void ws_put_config(ws_buf *b, const ws_config *c);
void ws_put_texture(ws_buf *b, const ws_texture *t);
void ws_put_frame(ws_buf *b, const ws_frame *f);
void ws_put_face(ws_buf *b, const ws_face *f);
void ws_put_frame_end(ws_buf *b, uint32_t faces);
void ws_put_end(ws_buf *b);
/* Words a face occupies in the stream. */
size_t ws_face_words(const ws_face *f);
/* Words of the packet a header word starts, from the header alone (the
 * FACE's flags and edge count, the TEXTURE's size); 0 for an unknown opcode.
 * The decoder still checks the rest. */
size_t ws_packet_words(uint32_t header);

/* Edge word fields (docs/word-format.md §5). */
static inline uint32_t ws_edge_word0(const ws_edge *e)
{
    return (uint32_t)e->u << 31 | (uint32_t)e->r << 30 | e->x1;
}

typedef enum {
    WS_EV_CONFIG, WS_EV_TEXTURE, WS_EV_FRAME, WS_EV_FACE, WS_EV_FRAME_END, WS_EV_END
} ws_event_kind;

typedef struct {
    ws_event_kind kind;
    size_t first, count;      /* word range of the packet */
    union {
        ws_config config;
        ws_texture texture;
        ws_frame frame;
        ws_face face;
        uint32_t faces;       /* FRAME_END */
    } u;
} ws_event;

/* Pull decoder over a whole stream held in memory. */
typedef struct {
    const uint32_t *w;
    size_t n, pos;
    const char *name;         /* file name for diagnostics */
    ws_config config;
    bool have_config, in_frame, ended;
    uint32_t faces_in_frame;
    uint32_t max_faces;       /* FACE packets a frame may carry (the profile's
                                 frame_faces; 2^24 - 1 after ws_reader_init) */
} ws_reader;

void ws_reader_init(ws_reader *r, const uint32_t *w, size_t n, const char *name);
/* Next packet: ALB_OK with *ev filled, or ALB_ERR_STREAM with d naming the
 * byte offset, the word and what was expected.  After WS_EV_END, stop. */
alb_err ws_next(ws_reader *r, ws_event *ev, diag_t *d);

/* Field-level description of word k (0-based) of a decoded packet. */
void ws_describe_word(const ws_event *ev, const ws_config *cfg, size_t k,
                      char *buf, size_t len);
/* Describe word idx of a whole stream by decoding up to its packet (for
 * reports of the first differing word). */
void ws_describe_at(const uint32_t *w, size_t n, size_t idx, char *buf, size_t len);
/* Annotated hex dump: offset, word, field names and values; stops with a
 * message at the first malformed word. */
alb_err ws_dump(FILE *out, const uint32_t *w, size_t n, const char *name, diag_t *d);

/* Read a stream file: binary (little-endian 32-bit words) or $readmemh
 * text (what ws_write_memh writes; docs/word-format.md), told apart by the
 * first bytes.  Write either; "-" is stdout for memh. */
alb_err ws_read_file(const char *path, uint32_t **w, size_t *n, diag_t *d);
alb_err ws_write_file(const char *path, const uint32_t *w, size_t n, diag_t *d);
alb_err ws_write_memh(const char *path, const uint32_t *w, size_t n, diag_t *d);

/* Value of a form at screen point (x, y), in double: for tools and tests. */
double ws_form_eval(const ws_form *f, double x, double y);

#endif
