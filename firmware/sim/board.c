/* board.c — the simulated board: the firmware core receives the host's
 * packets; its HAL feeds the word stream to this project's VP (the timed
 * model, whose pixels and cycles equal the cycle model's) as it arrives, and
 * reports each frame's CRC and cycle count back through the core at its
 * FRAME_END.  The model keeps its state between packets (alb_sim_feed), so a
 * frame's cycles are those of the whole stream up to it at the cost of the
 * frame alone; a RESUME runs the kept part of the stream again.  The RTL
 * board is the same board with the verilated reference RTL as its VP
 * (rtl_vp.h): its RESULTs are the RTL's frame CRCs and cycle counts, each
 * reported when the RTL's output stage has scanned the frame out. */
#include "board.h"
#include "../core.h"
#include "rtl_load.h"
#include "albatros/words.h"
#include "albatros/link.h"
#include "albatros/sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define SIM_MAX_PAYLOAD PROTO_MAX_PAYLOAD

struct sim_board {
    alb_profile prof;
    fw_core core;
    fw_hal hal;
    uint8_t *rxbuf;
    /* toward the host */
    uint8_t *tx;
    size_t tx_len, tx_cap;
    /* the word stream the VP has accepted */
    uint32_t *w;
    size_t n, cap;
    alb_sim_feed *feed;           /* the VP, fed w[0, n) so far; NULL before a RESET */
    /* the RTL board: the verilated RTL instead of feed (rtl.api not NULL) */
    sim_rtl rtl;
    alb_rtl_vp *rtl_vp;           /* fed w[0, n) so far; NULL before a RESET */
    uint32_t rtl_skip;            /* results of the replayed frames, not reported again */
    bool rtl_hung;
    uint64_t rtl_cycles;          /* clocked by the RTLs closed so far, and the time */
    double rtl_seconds;
    sim_rtl_tally *tally;         /* where they go when the board is destroyed */
    bool replaying;           /* RESUME: the kept stream again, no results */
    bool in_error;
    /* the last frame, for a flipped-bit fault */
    uint32_t flip_frame;
    unsigned flip_x, flip_y, flip_ch, flip_bit;
    bool flip;
    /* result of the VP run */
    uint32_t result_frame, result_crc, result_faces;
    uint64_t result_cycles;
    bool result_ok;
    /* the last frames' stores, for READBACK */
    struct kept_frame {
        uint32_t number;
        uint16_t *rgb;        /* NULL: empty */
        size_t pixels;
    } kept[4];
    unsigned next_kept;
    /* frames mode: the display, RGB888, and the last frame a tile belonged to */
    uint8_t *display;
    uint32_t display_frame;
    uint64_t tiles;
};

static void hal_send(void *ctx, const uint8_t *data, uint16_t len)
{
    sim_board *b = ctx;
    if (b->tx_len + len > b->tx_cap) {
        size_t cap = b->tx_cap ? b->tx_cap * 2 : 65536;
        while (cap < b->tx_len + len)
            cap *= 2;
        uint8_t *nt = realloc(b->tx, cap);
        if (!nt)
            return;   /* the host sees a lost packet: a timeout, then QUERY */
        b->tx = nt;
        b->tx_cap = cap;
    }
    memcpy(b->tx + b->tx_len, data, len);
    b->tx_len += len;
}

static int take_frame(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    sim_board *b = ctx;
    /* the sink sees every frame of the prefix; the last one counts, and is
     * kept (as the board's VP wrote it) for READBACK */
    size_t npix = (size_t)f->width * f->height;
    struct kept_frame *k = &b->kept[b->next_kept];
    uint16_t *rgb = realloc(k->rgb, 3 * npix * sizeof *rgb);
    if (!rgb)
        return -1;
    memcpy(rgb, f->rgb, 3 * npix * sizeof *rgb);
    if (b->flip && f->number == b->flip_frame && b->flip_x < f->width && b->flip_y < f->height)
        /* the faulty VP: one bit of one pixel wrong */
        rgb[3 * ((size_t)b->flip_y * f->width + b->flip_x) + b->flip_ch % 3] ^=
            (uint16_t)(1u << (b->flip_bit % 16));
    *k = (struct kept_frame){f->number, rgb, npix};
    b->result_crc = alb_link_frame_crc(rgb, npix);
    b->result_frame = f->number;
    b->result_cycles = sc->cycles;
    b->result_faces = (uint32_t)vs->faces;
    b->result_ok = true;
    return 0;
}

/* At each FRAME_END: the result to the host, the store kept for READBACK. */
static int board_frame(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
{
    sim_board *b = ctx;
    if (b->replaying)
        return 0;   /* reported before the RESUME */
    b->result_ok = false;
    if (take_frame(ctx, f, vs, sc) || !b->result_ok)
        return -1;
    fw_result r = {b->result_frame, b->result_crc, (uint32_t)b->result_cycles,
                   (uint32_t)(b->result_cycles >> 32), b->result_faces};
    b->next_kept = (b->next_kept + 1) % 4;
    fw_frame_done(&b->core, &r);
    return 0;
}

/* A frame the RTL scanned out: its RESULT to the host (the RTL's CRC, cycles
 * and faces), its store kept for READBACK. */
static void rtl_frame(sim_board *b, const alb_rtl_vp_frame *f)
{
    if (b->rtl_skip) {   /* a frame of the kept stream, reported before the RESUME */
        b->rtl_skip--;
        return;
    }
    size_t npix = (size_t)b->prof.width * b->prof.height;
    struct kept_frame *k = &b->kept[b->next_kept];
    uint16_t *rgb = realloc(k->rgb, 3 * npix * sizeof *rgb);
    if (!rgb)
        return;   /* the host sees no RESULT: a QUERY, then "stopped answering" */
    memcpy(rgb, f->rgb, 3 * npix * sizeof *rgb);
    *k = (struct kept_frame){f->number, rgb, npix};
    uint32_t crc = f->crc;
    if (!f->crc_from_rtl) {
        /* the next retirement cut the scan-out off (rtl/README.md): no CRC
         * left the output stage, so the board's resolve of the store stands in */
        crc = alb_link_frame_crc(rgb, npix);
        fprintf(stderr, "rtl board: frame %u: the next frame retired before its scan-out "
                "ended: its CRC is the board's resolve of the store, not the RTL's output "
                "stage\n", f->number);
    }
    fw_result r = {f->number, crc, (uint32_t)f->cycles, (uint32_t)(f->cycles >> 32), f->faces};
    b->next_kept = (b->next_kept + 1) % 4;
    fw_frame_done(&b->core, &r);
}

/* The words received so far through the RTL, clocked as far as they go;
 * the frames it finished to the host.  An RTL error is the stream's (ERROR
 * STREAM names the word); an RTL that stopped is a board that hangs: it
 * says why on stderr and answers nothing more, as a hung board would. */
static void feed_rtl(sim_board *b)
{
    const alb_rtl_vp_api *api = b->rtl.api;
    char err[400] = "";
    if (b->rtl_hung)
        return;
    int rc = b->rtl_vp ? api->run(b->rtl_vp, b->w, b->n, err, sizeof err) : -1;
    if (b->replaying && b->rtl_vp)
        b->rtl_skip = api->frames_given(b->rtl_vp);
    alb_rtl_vp_frame f;
    while (b->rtl_vp && api->next_frame(b->rtl_vp, &f))
        rtl_frame(b, &f);
    if (!rc)
        return;
    uint32_t word = 0;
    unsigned code = b->rtl_vp ? api->error(b->rtl_vp, &word) : 0;
    if (code) {
        fw_vp_error(&b->core, word);
        b->in_error = true;
    } else {
        fprintf(stderr, "rtl board: %s\n", b->rtl_vp ? err : "the RTL could not be started");
        b->rtl_hung = true;
    }
}

/* The words received so far through the VP; an error stops it until the
 * host restarts the stream (ERROR STREAM names the word). */
static void feed(sim_board *b)
{
    if (b->in_error)
        return;
    if (b->rtl.api) {
        feed_rtl(b);
        return;
    }
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (!b->feed || alb_sim_feed_words(b->feed, b->w, b->n, &d)) {
        fw_vp_error(&b->core, (uint32_t)(b->feed && d.offset >= 0 ? (size_t)d.offset / 4 : b->n));
        b->in_error = true;
    }
}

/* The clocking of the RTL about to be closed, into the board's totals. */
static void add_speed(sim_board *b)
{
    if (!b->rtl_vp)
        return;
    uint64_t cycles;
    double seconds;
    b->rtl.api->speed(b->rtl_vp, &cycles, &seconds);
    b->rtl_cycles += cycles;
    b->rtl_seconds += seconds;
}

/* The RTL board's restart: a new RTL (reset, both stores clear) that runs
 * the kept words again. */
static void restart_rtl(sim_board *b, uint8_t full)
{
    const alb_rtl_vp_api *api = b->rtl.api;
    b->n = full || !b->rtl_vp ? 0 : api->frame_start(b->rtl_vp, b->core.resume_frame);
    add_speed(b);
    api->close(b->rtl_vp);
    alb_rtl_vp_config c = {b->prof.gp_face_cycles, b->prof.gp_edge_cycles,
                           b->prof.gp_frame_cycles};
    char err[400];
    b->rtl_vp = api->open(&c, err, sizeof err);
    if (!b->rtl_vp)
        fprintf(stderr, "rtl board: %s\n", err);
    else if (b->flip)
        api->flip(b->rtl_vp, b->flip_frame, b->flip_x, b->flip_y, b->flip_ch, b->flip_bit);
    b->rtl_skip = 0;
    b->rtl_hung = false;
}

/* RESUME: keep the stream up to its last whole frame (configuration and
 * textures stay loaded: the kept words run through a new VP again); RESET:
 * a new stream from its CONFIG. */
static void hal_restart(void *ctx, uint8_t full)
{
    sim_board *b = ctx;
    if (b->rtl.api) {
        restart_rtl(b, full);
    } else {
        b->n = full || !b->feed ? 0 : alb_sim_feed_frame_start(b->feed);
        alb_sim_feed_close(b->feed);
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_sim_feed_open(&b->feed, &b->prof, "board", board_frame, b, &d))
            b->feed = NULL;
    }
    b->in_error = false;
    b->replaying = true;
    feed(b);
    b->replaying = false;
}

static void hal_words(void *ctx, const uint8_t *data, uint16_t len)
{
    sim_board *b = ctx;
    size_t k = len / 4;
    if (b->n + k > b->cap) {
        size_t cap = b->cap ? b->cap * 2 : 65536;
        while (cap < b->n + k)
            cap *= 2;
        uint32_t *nw = realloc(b->w, cap * sizeof *nw);
        if (!nw)
            return;
        b->w = nw;
        b->cap = cap;
    }
    for (size_t i = 0; i < k; i++)
        b->w[b->n + i] = PROTO_GET32(data + 4 * i);
    b->n += k;
    feed(b);
}

/* READBACK: the kept frame store in PIXELS packets of up to 2048 pixels. */
static uint8_t hal_readback(void *ctx, uint32_t frame)
{
    sim_board *b = ctx;
    const struct kept_frame *k = NULL;
    for (unsigned i = 0; i < 4; i++)
        if (b->kept[i].rgb && b->kept[i].number == frame)
            k = &b->kept[i];
    if (!k)
        return 1;
    uint8_t head[12], body[6 * 2048];
    for (size_t first = 0; first < k->pixels; first += 2048) {
        size_t count = k->pixels - first < 2048 ? k->pixels - first : 2048;
        PROTO_PUT32(head, frame);
        PROTO_PUT32(head + 4, (uint32_t)first);
        PROTO_PUT32(head + 8, (uint32_t)count);
        for (size_t i = 0; i < 3 * count; i++) {
            body[2 * i] = (uint8_t)k->rgb[3 * first + i];
            body[2 * i + 1] = (uint8_t)(k->rgb[3 * first + i] >> 8);
        }
        fw_send_packet(&b->core, PROTO_T_PIXELS, head, 12, body, (uint16_t)(6 * count));
    }
    return 0;
}

/* Frames mode: a tile onto the display, clipped to it. */
static void hal_tile(void *ctx, uint32_t frame, uint16_t x, uint16_t y, uint16_t w, uint16_t h,
                     const uint8_t *rgb)
{
    sim_board *b = ctx;
    b->tiles++;
    b->display_frame = frame;
    for (unsigned r = 0; r < h && y + r < b->prof.height; r++)
        if (x < b->prof.width)
            memcpy(b->display + 3 * ((size_t)(y + r) * b->prof.width + x), rgb + (size_t)3 * w * r,
                   (size_t)3 * (x + w <= b->prof.width ? w : b->prof.width - x));
}

const uint8_t *sim_board_display(const sim_board *b, uint32_t *frame, uint64_t *tiles)
{
    *frame = b->display_frame;
    *tiles = b->tiles;
    return b->display;
}

sim_board *sim_board_create(const alb_profile *p, char *err, size_t errlen)
{
    sim_board *b = calloc(1, sizeof *b);
    if (b) {
        b->rxbuf = malloc(PROTO_HEADER + SIM_MAX_PAYLOAD + PROTO_TRAILER);
        b->display = calloc((size_t)3 * p->width * p->height, 1);
    }
    if (!b || !b->rxbuf || !b->display) {
        snprintf(err, errlen, "out of memory for the simulated board");
        if (b) {
            free(b->rxbuf);
            free(b->display);
        }
        free(b);
        return NULL;
    }
    b->prof = *p;
    b->hal = (fw_hal){b, hal_words, hal_restart, hal_send, hal_tile, hal_readback};
    fw_init(&b->core, &b->hal, b->rxbuf, SIM_MAX_PAYLOAD);
    b->core.width = (uint16_t)p->width;
    b->core.height = (uint16_t)p->height;
    b->core.colour_bits = (uint8_t)p->colour_bits;
    b->core.serial = 1;
    memcpy(b->core.name, "albatros-sim", 13);
    return b;
}

void sim_board_set_max_payload(sim_board *b, uint16_t max_payload)
{
    /* rxbuf holds SIM_MAX_PAYLOAD; the core checks lengths against this */
    b->core.max_payload = max_payload < SIM_MAX_PAYLOAD ? max_payload : SIM_MAX_PAYLOAD;
}

void sim_board_destroy(sim_board *b)
{
    if (!b)
        return;
    free(b->rxbuf);
    free(b->display);
    free(b->tx);
    free(b->w);
    alb_sim_feed_close(b->feed);
    if (b->rtl.api) {
        add_speed(b);
        b->rtl.api->close(b->rtl_vp);
        b->rtl_vp = NULL;
        if (b->tally) {
            b->tally->cycles += b->rtl_cycles;
            b->tally->seconds += b->rtl_seconds;
            snprintf(b->tally->file, sizeof b->tally->file, "%s", b->rtl.file);
        }
    }
    sim_rtl_unload(&b->rtl);
    for (unsigned i = 0; i < 4; i++)
        free(b->kept[i].rgb);
    free(b);
}

void sim_board_rx(sim_board *b, const uint8_t *data, size_t len)
{
    while (len) {
        uint16_t piece = (uint16_t)(len > 0x8000 ? 0x8000 : len);
        fw_rx(&b->core, data, piece);
        data += piece;
        len -= piece;
    }
}

size_t sim_board_tx(sim_board *b, uint8_t *buf, size_t cap)
{
    size_t n = b->tx_len < cap ? b->tx_len : cap;
    if (!n)
        return 0;   /* nothing queued: b->tx may not exist yet */
    memcpy(buf, b->tx, n);
    memmove(b->tx, b->tx + n, b->tx_len - n);
    b->tx_len -= n;
    return n;
}

int sim_board_hid_get(sim_board *b, uint8_t *buf, size_t len)
{
    if (len < PROTO_HID_REPORT)
        return -1;
    return fw_hid_get(&b->core, buf) ? 0 : -1;
}

int sim_board_hid_set(sim_board *b, const uint8_t *buf, size_t len)
{
    return fw_hid_set(&b->core, buf, (uint8_t)(len > 255 ? 255 : len)) ? -1 : 0;
}

void sim_board_flip(sim_board *b, uint32_t frame, unsigned x, unsigned y, unsigned ch, unsigned bit)
{
    b->flip = true;
    b->flip_frame = frame;
    b->flip_x = x, b->flip_y = y, b->flip_ch = ch, b->flip_bit = bit;
    if (b->rtl.api && b->rtl_vp)
        b->rtl.api->flip(b->rtl_vp, frame, x, y, ch, bit);
}

sim_board *sim_board_create_rtl(const alb_profile *p, const char *path, char *warn,
                                size_t warnlen, char *err, size_t errlen)
{
    sim_rtl r;
    if (sim_rtl_load(&r, p, path, warn, warnlen, err, errlen))
        return NULL;
    sim_board *b = sim_board_create(p, err, errlen);
    if (!b) {
        sim_rtl_unload(&r);
        return NULL;
    }
    b->rtl = r;
    memcpy(b->core.name, "albatros-rtl", 13);
    return b;
}

void sim_board_rtl_tally(sim_board *b, sim_rtl_tally *t)
{
    b->tally = t;
}
