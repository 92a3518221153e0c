/* words.h — the GP -> VP word stream (docs/word-format.md): 32-bit words,
 * packets introduced by an opcode byte.  Packing, a validating decoder that
 * names the offending word and field, and the annotated hex dump. */
#ifndef ALBATROS_WORDS_H
#define ALBATROS_WORDS_H

#include "diag.h"
#include "file.h"

#include <stdbool.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* The library exports what its public headers declare, nothing else. */
#pragma GCC visibility push(default)
#ifdef __cplusplus
extern "C" {
#endif

#define ALB_WS_VERSION          1
#define ALB_WS_MAX_EDGES        64    /* VP edge store per face */
#define ALB_WS_TEX_LOG2_MAX     10    /* textures up to 1024 x 1024 */
#define ALB_WS_MAX_TEXTURES     256

enum alb_ws_opcode {
    ALB_WS_OP_CONFIG = 0xA5,
    ALB_WS_OP_TEXTURE = 0xA7,
    ALB_WS_OP_FRAME = 0xF0,
    ALB_WS_OP_FACE = 0xFA,
    ALB_WS_OP_FRAME_END = 0xFE,
    ALB_WS_OP_END = 0xFF
};

enum alb_ws_face_flag {
    ALB_WS_FACE_SHADE = 1,    /* intensity form present (eq. 7) */
    ALB_WS_FACE_TEXTURE = 2,  /* u and v forms present */
    ALB_WS_FACE_FOG = 4       /* fog applies to this face */
};
#define ALB_WS_FACE_FLAGS_ALL 7u

/* An edge in the VP format (19): U | R | X1 | X2, intercepts unsigned 3.F. */
typedef struct {
    uint8_t u, r;
    uint32_t x1, x2;
} alb_ws_edge;

/* A linear form of screen position in block floating point:
 * value(x, y) = (m[0] x + m[1] y + m[2]) * 2^exp. */
typedef struct {
    int32_t exp;
    int32_t m[3];
} alb_ws_form;

typedef struct {
    unsigned edge_frac_bits, coef_bits;
    float near;               /* the scene's near distance: metadata for
                                 converting near/Z to distances; the VP's
                                 arithmetic does not use it */
} alb_ws_config;

typedef struct {
    uint8_t id, log2size;
    const uint32_t *texels;   /* (1 << log2size)^2 words 0x00RRGGBB, row 0 = v 0 */
} alb_ws_texture;

typedef struct {
    uint32_t number;          /* 24 bits */
    uint32_t background;      /* 0x00RRGGBB */
    bool fog;
    uint32_t fog_rgb;
    uint32_t fog_near, fog_far;  /* Z / near, unsigned 24.8 */
} alb_ws_frame;

typedef struct {
    uint32_t id;
    uint8_t flags, texture, n_edges;
    uint32_t rgb;
    alb_ws_form depth, shade, tex_u, tex_v;
    alb_ws_edge edge[ALB_WS_MAX_EDGES];
} alb_ws_face;

/* A growable word buffer. */
typedef struct {
    uint32_t *w;
    size_t n, cap;
    bool oom;                 /* sticky: an allocation failed */
} alb_ws_buf;

void alb_ws_buf_init(alb_ws_buf *b);
void alb_ws_buf_free(alb_ws_buf *b);
void alb_ws_put(alb_ws_buf *b, uint32_t word);
void alb_ws_put_config(alb_ws_buf *b, const alb_ws_config *c);
void alb_ws_put_texture(alb_ws_buf *b, const alb_ws_texture *t);
void alb_ws_put_frame(alb_ws_buf *b, const alb_ws_frame *f);
void alb_ws_put_face(alb_ws_buf *b, const alb_ws_face *f);
void alb_ws_put_frame_end(alb_ws_buf *b, uint32_t faces);
void alb_ws_put_end(alb_ws_buf *b);
/* Words a face occupies in the stream. */
size_t alb_ws_face_words(const alb_ws_face *f);
/* Words of the packet a header word starts, from the header alone (the
 * FACE's flags and edge count, the TEXTURE's size); 0 for an unknown opcode.
 * The decoder still checks the rest. */
size_t alb_ws_packet_words(uint32_t header);

/* Edge word fields (docs/word-format.md §5). */
static inline uint32_t alb_ws_edge_word0(const alb_ws_edge *e)
{
    return (uint32_t)e->u << 31 | (uint32_t)e->r << 30 | e->x1;
}

typedef enum {
    ALB_WS_EV_CONFIG, ALB_WS_EV_TEXTURE, ALB_WS_EV_FRAME, ALB_WS_EV_FACE, ALB_WS_EV_FRAME_END, ALB_WS_EV_END
} alb_ws_event_kind;

typedef struct {
    alb_ws_event_kind kind;
    size_t first, count;      /* word range of the packet */
    union {
        alb_ws_config config;
        alb_ws_texture texture;
        alb_ws_frame frame;
        alb_ws_face face;
        uint32_t faces;       /* FRAME_END */
    } u;
} alb_ws_event;

/* Pull decoder over a whole stream held in memory. */
typedef struct {
    const uint32_t *w;
    size_t n, pos;
    const char *name;         /* file name for diagnostics */
    alb_ws_config config;
    bool have_config, in_frame, ended;
    uint32_t faces_in_frame;
    uint32_t max_faces;       /* FACE packets a frame may carry (the profile's
                                 frame_faces; 2^24 - 1 after alb_ws_reader_init) */
} alb_ws_reader;

void alb_ws_reader_init(alb_ws_reader *r, const uint32_t *w, size_t n, const char *name);
/* Next packet: ALB_OK with *ev filled, or ALB_ERR_STREAM with d naming the
 * byte offset, the word and what was expected.  After ALB_WS_EV_END, stop. */
alb_err alb_ws_next(alb_ws_reader *r, alb_ws_event *ev, alb_diag *d);

/* Field-level description of word k (0-based) of a decoded packet. */
void alb_ws_describe_word(const alb_ws_event *ev, const alb_ws_config *cfg, size_t k,
                      char *buf, size_t len);
/* Describe word idx of a whole stream by decoding up to its packet (for
 * reports of the first differing word). */
void alb_ws_describe_at(const uint32_t *w, size_t n, size_t idx, char *buf, size_t len);
/* Annotated hex dump: offset, word, field names and values; stops with a
 * message at the first malformed word. */
alb_err alb_ws_dump(FILE *out, const uint32_t *w, size_t n, const char *name, alb_diag *d);
/* The same for a stream in pieces (albatros gp dumps each frame as it is
 * made): words w[0, n) are the next piece, word `base` of the whole stream
 * onward, decoded with r (alb_ws_reader_init before the first piece), whose
 * state carries over. */
alb_err alb_ws_dump_piece(FILE *out, alb_ws_reader *r, const uint32_t *w, size_t n, size_t base,
                          alb_diag *d);

/* Read a stream file: binary (little-endian 32-bit words) or $readmemh
 * text (what alb_ws_write_memh writes; docs/word-format.md), told apart by the
 * first bytes.  Write either; "-" is stdout for memh. */
alb_err alb_ws_read_file(const char *path, uint32_t **w, size_t *n, alb_diag *d);
alb_err alb_ws_write_file(const char *path, const uint32_t *w, size_t n, alb_diag *d);
alb_err alb_ws_write_memh(const char *path, const uint32_t *w, size_t n, alb_diag *d);
/* The same, written as the stream is made (a frame at a time): open, put
 * words, close — nothing is under the name until close succeeds (file.h);
 * abort instead leaves the old file as it was. */
typedef struct {
    alb_out out;
    FILE *f;
    bool memh;
    size_t words;
} alb_ws_writer;
alb_err alb_ws_writer_open(alb_ws_writer *wr, const char *path, bool memh, alb_diag *d);
void alb_ws_writer_put(alb_ws_writer *wr, const uint32_t *w, size_t n);
alb_err alb_ws_writer_close(alb_ws_writer *wr, alb_diag *d);
void alb_ws_writer_abort(alb_ws_writer *wr);

/* Value of a form at screen point (x, y), in double: for tools and tests. */
double alb_ws_form_eval(const alb_ws_form *f, double x, double y);

#ifdef __cplusplus
}
#endif
#pragma GCC visibility pop

#endif
