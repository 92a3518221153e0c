/* stream.c — the streaming engine behind `albatros stream`: RESET, the
 * stream's preamble, then frames in WORDS packets no more than `window`
 * frames ahead of the last RESULT; RESULTs compared with the emulator; on a
 * board ERROR the first unconfirmed frame is RESUMEd and resent; a missing
 * RESULT is asked for once with QUERY, behind zero bytes that complete any
 * packet the board holds half-received, then the board has stopped answering.
 * Payloads are as long as the board's INFO report allows.  Every loss is
 * counted, the first problem described, and the first loss on the link named
 * by the packet and what it carried (the streamer remembers what it sent). */
#include "albatros/stream.h"
#include "../../firmware/proto.h"
#include "albatros/link.h"
#include "albatros/words.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* What a packet sent carried, kept so a loss the board reports by sequence
 * number can be named: WORDS a = first word, b = end; TILE a = frame, b = y
 * << 16 | x; RESUME, QUERY, READBACK a = frame. */
typedef struct {
    uint32_t seq;
    uint8_t type;
    bool used;
    uint32_t a, b;
} sent_packet;

#define SENT_RING 4096   /* packets remembered: the window's 16 frames at any payload */

typedef struct {
    alb_transport *t;
    const uint32_t *w;
    size_t n;
    alb_stream_frame *f;
    unsigned nf;
    const alb_stream_opts *o;
    alb_stream_report *r;
    alb_link_rx rx;
    uint32_t seq;
    uint8_t *pkt;             /* encode buffer: zero padding, then a packet */
    size_t max;               /* payload in use (board_payload) */
    size_t board_max;         /* the board's largest payload (its INFO report) */
    sent_packet *sent;        /* SENT_RING, indexed by seq */
    bool need_resume, failed;
    bool gone;                /* the device disconnected; o->reattach will be tried */
    bool can_reattach;        /* alb_stream_run, with o->reattach */
    unsigned next;            /* next frame to send */
    /* a READBACK in progress */
    int rb_frame;
    size_t rb_got, rb_first_bad;
    char rb_what[160];
    /* the last STATUS (frames mode confirms each frame with a PING) */
    bool have_status;
    uint32_t status[PROTO_STATUS_BYTES / 4];
} streamer;

void alb_stream_opts_default(alb_stream_opts *o)
{
    memset(o, 0, sizeof *o);
    o->timeout_ms = 2000;
    o->retries = 3;
    o->window = 16;
    o->readback = true;
    o->reattach_max = 3;
}

static void __attribute__((format(printf, 2, 3))) problem(streamer *s, const char *fmt, ...)
{
    if (s->r->first_problem[0])
        return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(s->r->first_problem, sizeof s->r->first_problem, fmt, ap);
    va_end(ap);
}

static void __attribute__((format(printf, 2, 3))) note(streamer *s, const char *fmt, ...)
{
    if (!s->o->log)
        return;
    va_list ap;
    va_start(ap, fmt);
    if (s->o->progress)
        fputc('\n', s->o->log);
    vfprintf(s->o->log, fmt, ap);
    va_end(ap);
    fputc('\n', s->o->log);
}

/* Ctrl-C (o->stop): every loop ends through s->failed; the report is marked
 * partial rather than given a problem. */
static bool stopped(streamer *s)
{
    if (!s->r->interrupted && s->o->stop && *s->o->stop) {
        s->r->interrupted = true;
        s->failed = true;
    }
    return s->r->interrupted;
}

static sent_packet *sent_at(streamer *s, uint32_t seq) { return &s->sent[seq % SENT_RING]; }

/* The packet sent as `seq`, for a report: "packet 5 (WORDS: words 512..575,
 * frame 1)". */
static void describe(streamer *s, uint32_t seq, char *out, size_t cap)
{
    const sent_packet *p = sent_at(s, seq);
    if (!p->used || p->seq != seq) {
        snprintf(out, cap, "packet %u", seq);
        return;
    }
    switch (p->type) {
    case PROTO_T_WORDS: {
        const char *where = "the stream's end";
        char frame[32] = "";
        if (!s->nf || p->a < s->f[0].first_word)
            where = "the stream's preamble";
        for (unsigned i = 0; i < s->nf; i++)
            if (p->a >= s->f[i].first_word && p->a < s->f[i].end_word) {
                snprintf(frame, sizeof frame, "frame %u", s->f[i].number);
                where = frame;
            }
        snprintf(out, cap, "packet %u (WORDS: words %u..%u, %s)", seq, p->a, p->b - 1, where);
        break;
    }
    case PROTO_T_TILE:
        snprintf(out, cap, "packet %u (TILE: frame %u, tile at (%u, %u))", seq, p->a, p->b & 0xFFFF,
                 p->b >> 16);
        break;
    case PROTO_T_RESUME: snprintf(out, cap, "packet %u (RESUME of frame %u)", seq, p->a); break;
    case PROTO_T_QUERY: snprintf(out, cap, "packet %u (QUERY of frame %u)", seq, p->a); break;
    case PROTO_T_READBACK: snprintf(out, cap, "packet %u (READBACK of frame %u)", seq, p->a); break;
    case PROTO_T_RESET: snprintf(out, cap, "packet %u (RESET)", seq); break;
    case PROTO_T_PING: snprintf(out, cap, "packet %u (PING)", seq); break;
    default: snprintf(out, cap, "packet %u (type %u)", seq, p->type); break;
    }
}

/* A disconnect the stream may survive: marked, named as the first loss on
 * the link, and left to the main loop (reattach). */
static bool may_reattach(streamer *s, const char *doing, uint32_t seq)
{
    if (!s->can_reattach || s->r->reattaches >= s->o->reattach_max)
        return false;
    s->gone = true;
    if (!s->r->first_link_error[0])
        snprintf(s->r->first_link_error, sizeof s->r->first_link_error,
                 "the device disconnected while %s (packet %u): %.200s", doing, (unsigned)seq,
                 s->t->error);
    return true;
}

/* One packet, after `pad` zero bytes (at most PAD_MAX) in the same write:
 * the largest packet rounded up to whole USB packets. */
#define PAD_MAX ((PROTO_MAX_PAYLOAD + PROTO_HEADER + PROTO_TRAILER + PROTO_BULK_MAXPKT - 1) / \
                 PROTO_BULK_MAXPKT * PROTO_BULK_MAXPKT)

static int send_padded(streamer *s, size_t pad, uint8_t type, const uint8_t *payload, uint32_t len)
{
    if (s->gone)
        return -1;
    if (stopped(s))
        return -1;
    *sent_at(s, s->seq) = (sent_packet){s->seq, type, true, len >= 4 ? PROTO_GET32(payload) : 0, 0};
    memset(s->pkt, 0, pad);
    size_t n = pad + alb_link_encode(s->pkt + pad, type, s->seq++, payload, len);
    /* one packet a transfer: a packet then starts a USB packet, where the
     * FX2 firmware parses it in place (firmware/fx2/main.c); a padding is a
     * whole number of USB packets, so the packet behind it starts one too */
    alb_tr_status st = s->t->ops->write(s->t, s->pkt, n);
    if (st == ALB_TR_OK)
        st = s->t->ops->flush(s->t);
    if (stopped(s))
        return -1;
    if (st != ALB_TR_OK) {
        if (st == ALB_TR_GONE && may_reattach(s, "sending", s->seq - 1))
            return -1;
        problem(s, "link failed while sending packet %u (%s): %s", (unsigned)(s->seq - 1),
                st == ALB_TR_GONE ? "device disconnected" : "I/O error", s->t->error);
        s->failed = true;
        return -1;
    }
    s->r->bytes += n;
    s->r->packets++;
    return 0;
}

static int send_packet(streamer *s, uint8_t type, const uint8_t *payload, uint32_t len)
{
    return send_padded(s, 0, type, payload, len);
}

static int send_u32(streamer *s, uint8_t type, uint32_t v)
{
    uint8_t p[4];
    PROTO_PUT32(p, v);
    return send_packet(s, type, p, 4);
}

/* QUERY for a RESULT that did not come.  The board may be waiting for the
 * rest of a packet cut short (the last before the silence): with nothing
 * behind it, the QUERY's own bytes would only fill that packet, fail its CRC
 * and be lost with it.  So the QUERY goes behind zero bytes enough to
 * complete any packet the board can hold (its largest payload, header and
 * CRC): a packet held is completed, fails its CRC (ERROR BAD_CRC) and the
 * board resynchronises; the zeros are garbage to it (no magic), and the
 * QUERY is read as usual — its sequence number then shows the lost packet
 * as a gap, and the frame is resumed (docs/usb-protocol.md, "Errors"). */
static size_t flush_bytes(const streamer *s)
{
    size_t pad = s->board_max + PROTO_HEADER + PROTO_TRAILER;
    pad = (pad + PROTO_BULK_MAXPKT - 1) / PROTO_BULK_MAXPKT * PROTO_BULK_MAXPKT;
    return pad < PAD_MAX ? pad : PAD_MAX;
}

static int send_query(streamer *s, uint32_t frame)
{
    uint8_t p[4];
    PROTO_PUT32(p, frame);
    return send_padded(s, flush_bytes(s), PROTO_T_QUERY, p, 4);
}

/* The payload every board takes: one high-speed bulk packet less header and
 * CRC, the FX2 firmware's (firmware/fx2/main.c, FX2_MAX_PAYLOAD). */
#define SAFE_PAYLOAD (PROTO_BULK_MAXPKT - PROTO_HEADER - PROTO_TRAILER)

/* The payload to use: the board's (its INFO report), the transport's, and
 * for WORDS o->chunk_bytes, whichever is least; at least `least` bytes, else
 * the stream cannot go (a board that takes less is not one we can drive).
 * A board whose INFO cannot be read (its HID side broken, the bulk side
 * working) gets SAFE_PAYLOAD, and the log says so. */
static int board_payload(streamer *s, size_t least, bool words)
{
    uint8_t rep[PROTO_HID_REPORT + 1] = {PROTO_HID_INFO};
    alb_link_info info;
    if (s->t->ops->hid_get(s->t, rep, PROTO_HID_REPORT)) {
        note(s, "the board's INFO report (HID report 1) could not be read (%s): payloads of %u "
                "bytes, which every board takes", s->t->error, SAFE_PAYLOAD);
        memset(&info, 0, sizeof info);
        info.max_payload = SAFE_PAYLOAD;
    } else if (alb_link_info_decode(rep, &info)) {
        problem(s, "the device's INFO report lacks the ALBI magic: not an albatros board?");
        s->failed = true;
        return -1;
    }
    size_t max = info.max_payload;
    s->board_max = max > PROTO_MAX_PAYLOAD ? PROTO_MAX_PAYLOAD : max;
    if (max > s->t->max_payload)
        max = s->t->max_payload;
    if (max > PROTO_MAX_PAYLOAD)
        max = PROTO_MAX_PAYLOAD;
    if (words && s->o->chunk_bytes && s->o->chunk_bytes < max)
        max = s->o->chunk_bytes;
    if (max < least) {
        problem(s, "the board takes payloads of %zu bytes (INFO): too small for a %s", max,
                words ? "word" : "tile");
        s->failed = true;
        return -1;
    }
    s->max = max;
    s->r->max_payload = max;
    return 0;
}

static int send_words(streamer *s, size_t from, size_t to)
{
    size_t per = s->max / 4;
    uint8_t *buf = malloc(per * 4);
    if (!buf)
        return -1;
    for (size_t i = from; i < to && !s->failed && !s->gone; i += per) {
        size_t k = to - i < per ? to - i : per;
        for (size_t j = 0; j < k; j++)
            PROTO_PUT32(buf + 4 * j, s->w[i + j]);
        if (!send_packet(s, PROTO_T_WORDS, buf, (uint32_t)(4 * k)))
            *sent_at(s, s->seq - 1) = (sent_packet){s->seq - 1, PROTO_T_WORDS, true, (uint32_t)i,
                                                    (uint32_t)(i + k)};
    }
    free(buf);
    return s->failed || s->gone ? -1 : 0;
}

static int frame_index(const streamer *s, uint32_t number)
{
    for (unsigned i = 0; i < s->nf; i++)
        if (s->f[i].number == number)
            return (int)i;
    return -1;
}

static unsigned first_unconfirmed(const streamer *s)
{
    unsigned i = 0;
    while (i < s->nf && s->f[i].have)
        i++;
    return i;
}

static void on_result(streamer *s, const alb_link_packet *p)
{
    if (p->len < PROTO_RESULT_BYTES)
        return;
    uint32_t number = PROTO_GET32(p->payload + PROTO_RESULT_FRAME);
    int i = frame_index(s, number);
    if (i < 0) {
        problem(s, "the board reported frame %u, which the stream does not have", number);
        return;
    }
    alb_stream_frame *f = &s->f[i];
    uint32_t crc = PROTO_GET32(p->payload + PROTO_RESULT_CRC);
    uint64_t cyc = PROTO_GET32(p->payload + PROTO_RESULT_CYC_LO) |
                   (uint64_t)PROTO_GET32(p->payload + PROTO_RESULT_CYC_HI) << 32;
    if (f->have)
        return;   /* a resent frame's result again */
    f->have = true;
    f->board_crc = crc;
    f->board_cycles = cyc;
    s->r->frames++;
    bool ok = true;
    if (crc != f->crc) {
        s->r->crc_mismatch++;
        ok = false;
        note(s, "frame %u: frame CRC %08x, the emulator's %08x", number, crc, f->crc);
    }
    if (cyc != f->cycles) {
        s->r->cycle_mismatch++;
        ok = ok && s->o->cycles_unchecked;
        note(s, "frame %u: %llu cycles, the emulator's %llu", number, (unsigned long long)cyc,
             (unsigned long long)f->cycles);
    }
    if (ok)
        s->r->matched++;
    else if (crc != f->crc)
        problem(s, "frame %u: the board's frame CRC %08x differs from the emulator's %08x", number,
                crc, f->crc);   /* readback() adds where, for this frame only */
    else
        problem(s, "frame %u: the board took %llu cycles, the emulator %llu", number,
                (unsigned long long)cyc, (unsigned long long)f->cycles);
}

static void on_error(streamer *s, const alb_link_packet *p)
{
    if (p->len < 16)
        return;
    uint32_t code = PROTO_GET32(p->payload), seq = PROTO_GET32(p->payload + 4);
    uint32_t expected = PROTO_GET32(p->payload + 8), detail = PROTO_GET32(p->payload + 12);
    s->r->board_errors[code < ALB_STREAM_ERROR_CODES ? code : 0]++;
    /* name the packet concerned: for a gap the first one missing (ERROR
     * fields: firmware/core.c), else the one the board refused */
    char what[200], text[300];
    if (code == PROTO_E_SEQ_GAP) {
        describe(s, expected, what, sizeof what);
        snprintf(text, sizeof text, "board: sequence gap: %s never arrived%s (packet %u came next)",
                 what, detail > 1 ? ", nor the ones after it" : "", seq);
    } else {
        describe(s, seq, what, sizeof what);
        snprintf(text, sizeof text, "board: %s at %s (expected %u, detail %u)",
                 alb_link_error_name(code), what, expected, detail);
    }
    note(s, "%s", text);
    if (!s->r->first_link_error[0])
        snprintf(s->r->first_link_error, sizeof s->r->first_link_error, "%s", text);
    if (code != PROTO_E_DUPLICATE)
        s->need_resume = true;
}

static void on_pixels(streamer *s, const alb_link_packet *p)
{
    if (p->len < 12 || s->rb_frame < 0)
        return;
    const alb_stream_frame *f = &s->f[s->rb_frame];
    uint32_t first = PROTO_GET32(p->payload + 4), count = PROTO_GET32(p->payload + 8);
    size_t npix = (size_t)f->width * f->height;
    if ((uint64_t)count * 6 + 12 != p->len || first + (uint64_t)count > npix)
        return;
    for (uint32_t k = 0; k < count && s->rb_first_bad == (size_t)-1; k++)
        for (int ch = 0; ch < 3; ch++) {
            uint16_t b = (uint16_t)(p->payload[12 + 6 * k + 2 * ch] |
                                    p->payload[13 + 6 * k + 2 * ch] << 8);
            uint16_t e = f->rgb[3 * (first + k) + ch];
            if (b != e && s->rb_first_bad == (size_t)-1) {
                s->rb_first_bad = first + k;
                snprintf(s->rb_what, sizeof s->rb_what, "pixel (%zu, %zu) channel %c: board %u, "
                         "emulator %u", (size_t)(first + k) % f->width,
                         (size_t)(first + k) / f->width, "RGB"[ch], b, e);
            }
        }
    s->rb_got += count;
}

static void on_status(streamer *s, const alb_link_packet *p)
{
    if (p->len < PROTO_STATUS_BYTES)
        return;
    for (unsigned i = 0; i < PROTO_STATUS_BYTES / 4; i++)
        s->status[i] = PROTO_GET32(p->payload + 4 * i);
    s->have_status = true;
}

static void dispatch(streamer *s, const alb_link_packet *p)
{
    switch (p->type) {
    case PROTO_T_RESULT: on_result(s, p); break;
    case PROTO_T_ERROR: on_error(s, p); break;
    case PROTO_T_PIXELS: on_pixels(s, p); break;
    case PROTO_T_STATUS: on_status(s, p); break;
    default: break;   /* anything newer */
    }
}

/* Read what the board has (waiting up to timeout_ms for the first bytes);
 * returns true if any packet arrived. */
static bool pump(streamer *s, unsigned timeout_ms)
{
    uint8_t buf[65536];
    bool any = false;
    if (s->gone)
        return false;
    for (;;) {
        size_t got = 0;
        alb_tr_status st = s->t->ops->read(s->t, buf, sizeof buf, &got, any ? 0 : timeout_ms);
        if (stopped(s))
            return any;
        if (st == ALB_TR_GONE && may_reattach(s, "reading", s->seq - 1))
            return any;
        if (st == ALB_TR_GONE || st == ALB_TR_ERROR) {
            problem(s, "link failed while reading from the board: %s", s->t->error);
            s->failed = true;
            return any;
        }
        if (!got)
            break;
        if (alb_link_rx_feed(&s->rx, buf, got))
            break;
        alb_link_packet p;
        while (alb_link_rx_next(&s->rx, &p) == 1) {
            any = true;
            dispatch(s, &p);
        }
        timeout_ms = 0;
    }
    return any;
}

/* Ask a board for a bad frame's store and name its first wrong pixel. */
static void readback(streamer *s, unsigned i)
{
    alb_stream_frame *f = &s->f[i];
    if (!f->rgb)
        return;
    s->rb_frame = (int)i;
    s->rb_got = 0;
    s->rb_first_bad = (size_t)-1;
    s->rb_what[0] = 0;
    if (send_u32(s, PROTO_T_READBACK, f->number))
        return;
    size_t npix = (size_t)f->width * f->height;
    while (s->rb_got < npix && !stopped(s) && pump(s, s->o->timeout_ms))
        ;
    if (s->rb_first_bad != (size_t)-1)
        note(s, "frame %u: first difference at %s", f->number, s->rb_what);
    else if (s->rb_got < npix)
        note(s, "frame %u: the board did not send its frame store back", f->number);
    /* the first problem names this frame's first wrong pixel if it is this
     * frame's CRC (on_result's text), never another frame's */
    char mine[64];
    snprintf(mine, sizeof mine, "frame %u: the board's frame CRC ", f->number);
    if (s->rb_first_bad != (size_t)-1 && !strncmp(s->r->first_problem, mine, strlen(mine)) &&
        !strstr(s->r->first_problem, ": first at ")) {
        size_t len = strlen(s->r->first_problem);
        snprintf(s->r->first_problem + len, sizeof s->r->first_problem - len, ": first at %s",
                 s->rb_what);
    }
    s->rb_frame = -1;
}

static void resume(streamer *s)
{
    s->need_resume = false;
    unsigned i = first_unconfirmed(s);
    if (i >= s->nf)
        return;   /* every frame confirmed: the loss was in the stream's tail */
    if (s->f[i].resends++ >= s->o->retries) {
        problem(s, "frame %u still failing after %u resends", s->f[i].number, s->o->retries);
        s->failed = true;
        return;
    }
    s->r->resumes++;
    if (i == 0) {
        /* nothing confirmed yet: the loss may be in the preamble (CONFIG,
         * textures), which RESUME would not resend — start the stream over */
        note(s, "restarting the stream (no frame confirmed yet)");
        s->rx.have_seq = false;   /* the board numbers from 0 again after RESET */
        if (!send_packet(s, PROTO_T_RESET, NULL, 0))
            send_words(s, 0, s->nf ? s->f[0].first_word : s->n);
        s->next = 0;
        return;
    }
    note(s, "resuming from frame %u", s->f[i].number);
    if (!send_u32(s, PROTO_T_RESUME, s->f[i].number))
        s->next = i;
}

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* The end of a run: the progress line closed, the host decoder's counts
 * into the report, the time, the buffers freed. */
static void finish(streamer *s, double t0)
{
    if (s->o->progress && s->o->log)
        fputc('\n', s->o->log);
    s->r->rx_crc_errors = s->rx.crc_errors;
    s->r->rx_garbage = s->rx.garbage;
    s->r->rx_gaps = s->rx.seq_gaps;
    s->r->rx_duplicates = s->rx.duplicates;
    if (!s->r->first_link_error[0] && (s->rx.crc_errors || s->rx.garbage || s->rx.seq_gaps))
        snprintf(s->r->first_link_error, sizeof s->r->first_link_error, "host: %llu bad CRCs, "
                 "%llu garbage bytes, %llu sequence gaps in the board's packets",
                 (unsigned long long)s->rx.crc_errors, (unsigned long long)s->rx.garbage,
                 (unsigned long long)s->rx.seq_gaps);
    s->r->seconds = now() - t0;
    alb_link_rx_free(&s->rx);
    free(s->pkt);
    free(s->sent);
}

/* A streamer for t, its buffers allocated (s->failed if not). */
static void start(streamer *s, alb_transport *t, const alb_stream_opts *o, alb_stream_report *r)
{
    memset(s, 0, sizeof *s);
    memset(r, 0, sizeof *r);
    s->t = t;
    s->o = o;
    s->r = r;
    r->cycles_unchecked = o->cycles_unchecked;
    s->rb_frame = -1;
    alb_link_rx_init(&s->rx);
    s->pkt = malloc(PAD_MAX + PROTO_HEADER + PROTO_MAX_PAYLOAD + PROTO_TRAILER);
    s->sent = calloc(SENT_RING, sizeof *s->sent);
    if (!s->pkt || !s->sent) {
        problem(s, "out of memory");
        s->failed = true;
    }
}

/* The device went away: the link opened again (o->reattach) and the
 * stream started over from RESET and its preamble — a board that was
 * unplugged or reconfigured has lost its words, results and textures. */
static void reattach(streamer *s, size_t preamble)
{
    s->gone = false;
    note(s, "the board disconnected: waiting for it to come back (%u of at most %u)",
         s->r->reattaches + 1, s->o->reattach_max);
    char err[600] = "";
    s->t = s->o->reattach(s->o->reattach_ctx, s->t, err, sizeof err);
    if (!s->t) {
        problem(s, "the board disconnected and did not come back: %s", err);
        s->failed = true;
        return;
    }
    s->r->reattaches++;   /* counted once it is back: the report says "came back" */
    /* what the old link left half-read is not the new board's */
    s->rx.start = s->rx.len = 0;
    s->rx.have_seq = false;
    note(s, "the board is back: starting the stream over (%u of %u frames already confirmed)",
         first_unconfirmed(s), s->nf);
    if (board_payload(s, 4, true) || send_packet(s, PROTO_T_RESET, NULL, 0))
        return;
    send_words(s, 0, preamble);
    s->next = 0;
}

uint64_t alb_stream_board_errors(const alb_stream_report *r)
{
    uint64_t n = 0;
    for (unsigned c = 0; c < ALB_STREAM_ERROR_CODES; c++)
        n += r->board_errors[c];
    return n;
}

int alb_stream_run(alb_transport *t, const uint32_t *w, size_t n, alb_stream_frame *frames, unsigned nframes,
               const alb_stream_opts *o, alb_stream_report *r)
{
    streamer s;
    double t0 = now();
    start(&s, t, o, r);
    s.w = w;
    s.n = n;
    s.f = frames;
    s.nf = nframes;
    s.can_reattach = o->reattach != NULL;
    size_t preamble = nframes ? frames[0].first_word : n;
    bool end_sent = false, queried = false;
    double wait_from = 0;     /* when the host began to wait for the missing RESULT */
    if (!s.failed && !board_payload(&s, 4, true) && send_packet(&s, PROTO_T_RESET, NULL, 0) == 0)
        send_words(&s, 0, preamble);
    while (!s.failed && !stopped(&s)) {
        if (s.gone) {
            reattach(&s, preamble);
            s.need_resume = false;
            end_sent = queried = false;
            continue;
        }
        if (s.need_resume) {
            resume(&s);
            end_sent = false;
            continue;
        }
        /* the window slides as RESULTs come in while frames go out: a window
         * fixed at its start stalls a stream of more than `window` frames
         * once the board has answered everything sent (it then waits for
         * words, the host for a RESULT) */
        while (!s.failed && !s.gone && !s.need_resume && s.next < nframes &&
               s.next < first_unconfirmed(&s) + o->window) {
            send_words(&s, frames[s.next].first_word, frames[s.next].end_word);
            s.next++;
            pump(&s, 0);
        }
        if (s.failed || s.gone || s.need_resume)
            continue;
        if (s.next == nframes && !end_sent) {
            send_words(&s, nframes ? frames[nframes - 1].end_word : preamble, n);
            end_sent = true;
        }
        if (first_unconfirmed(&s) == nframes) {
            /* a PING after the last packet: a loss of the stream's tail (no
             * frame in it) still shows as a sequence gap, reported.  A tail
             * cut short would swallow the PING as it swallows a QUERY, so
             * without a STATUS the PING goes again behind the padding */
            s.have_status = false;
            if (!send_packet(&s, PROTO_T_PING, NULL, 0))
                pump(&s, o->timeout_ms);
            if (!s.have_status && !s.failed && !s.gone && !stopped(&s) &&
                !send_padded(&s, flush_bytes(&s), PROTO_T_PING, NULL, 0))
                pump(&s, o->timeout_ms);
            if (!s.have_status && !s.failed && !s.gone && !stopped(&s))
                note(&s, "the board did not answer the closing PING (every frame was confirmed)");
            break;
        }
        if (o->progress && o->log)
            fprintf(o->log, "\r%u/%u frames confirmed, %.1f MB sent", s.r->frames, nframes,
                    (double)s.r->bytes / 1e6);
        double waiting = now();
        if (pump(&s, o->timeout_ms)) {
            queried = false;
            continue;
        }
        if (s.failed)
            break;
        if (s.gone)
            continue;
        unsigned i = first_unconfirmed(&s);
        if (queried) {
            /* the time the host really waited: a board read returns early
             * when the transport knows nothing can come (the simulated
             * board answers at once or not at all) */
            problem(&s, "the board stopped answering: no RESULT for frame %u in %.2f s after "
                        "sending up to frame %u and a QUERY (each read waits up to %u ms)",
                    frames[i].number, now() - wait_from, s.next ? frames[s.next - 1].number : 0,
                    o->timeout_ms);
            s.failed = true;
            break;
        }
        s.r->queries++;
        queried = true;
        wait_from = waiting;
        send_query(&s, frames[i].number);
    }
    if (!s.failed && o->readback)
        for (unsigned i = 0; i < nframes && !s.failed; i++)
            if (frames[i].have && frames[i].board_crc != frames[i].crc)
                readback(&s, i);
    r->link = s.t;
    finish(&s, t0);
    if (r->interrupted)
        return -2;
    if (s.failed)
        return -1;
    return r->matched == nframes ? 0 : 1;
}

int alb_stream_frames(const uint32_t *w, size_t n, alb_stream_frame **frames, unsigned *nframes)
{
    alb_ws_reader rd;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_stream_frame *f = NULL;
    unsigned nf = 0;
    int rc = ev ? 0 : -1;
    alb_ws_reader_init(&rd, w, n, "stream");
    while (!rc && !rd.ended) {
        if (alb_ws_next(&rd, ev, &d)) {
            rc = -1;
            break;
        }
        if (ev->kind == ALB_WS_EV_FRAME) {
            alb_stream_frame *nfp = realloc(f, (nf + 1) * sizeof *nfp);
            if (!nfp) {
                rc = -1;
                break;
            }
            f = nfp;
            memset(&f[nf], 0, sizeof f[nf]);
            f[nf].number = ev->u.frame.number;
            f[nf].first_word = ev->first;
            nf++;
        }
        if (ev->kind == ALB_WS_EV_FRAME_END)
            f[nf - 1].end_word = ev->first + ev->count;
    }
    free(ev);
    if (rc) {
        free(f);
        return -1;
    }
    *frames = f;
    *nframes = nf;
    return 0;
}

/* ---- frames mode: finished frames as TILE packets for a display ---- */

/* One frame's tiles: strips as tall as a payload holds (narrower than the
 * frame only if one row does not fit). */
static void send_tiles(streamer *s, const alb_stream_tiles_frame *f, uint8_t *buf, size_t max)
{
    size_t per_row = (max - 12) / 3;
    unsigned tw = f->width < per_row ? f->width : (unsigned)per_row;
    unsigned th = (unsigned)((max - 12) / (3 * (size_t)tw));
    th = th < 1 ? 1 : th > f->height ? f->height : th;
    for (unsigned y = 0; y < f->height && !s->failed; y += th)
        for (unsigned x = 0; x < f->width && !s->failed; x += tw) {
            unsigned w = f->width - x < tw ? f->width - x : tw;
            unsigned h = f->height - y < th ? f->height - y : th;
            PROTO_PUT32(buf, f->number);
            buf[4] = (uint8_t)x, buf[5] = (uint8_t)(x >> 8);
            buf[6] = (uint8_t)y, buf[7] = (uint8_t)(y >> 8);
            buf[8] = (uint8_t)w, buf[9] = (uint8_t)(w >> 8);
            buf[10] = (uint8_t)h, buf[11] = (uint8_t)(h >> 8);
            for (unsigned r = 0; r < h; r++)
                memcpy(buf + 12 + (size_t)3 * w * r,
                       f->rgb + 3 * ((size_t)(y + r) * f->width + x), (size_t)3 * w);
            if (!send_packet(s, PROTO_T_TILE, buf, (uint32_t)(12 + (size_t)3 * w * h)))
                sent_at(s, s->seq - 1)->b = (uint32_t)y << 16 | x;
        }
}

int alb_stream_tiles(alb_transport *t, const alb_stream_tiles_frame *frames, unsigned nframes,
                 const alb_stream_opts *o, alb_stream_report *r)
{
    streamer s;
    double t0 = now();
    start(&s, t, o, r);
    uint8_t *buf = malloc(PROTO_MAX_PAYLOAD);
    uint8_t mode[PROTO_HID_REPORT + 1] = {PROTO_HID_MODE, PROTO_MODE_TILES};
    if (!buf && !s.failed) {
        problem(&s, "out of memory");
        s.failed = true;
    }
    if (s.failed || board_payload(&s, 12 + 3, false)) {
        /* reported */
    } else if (t->ops->hid_set(t, mode, PROTO_HID_REPORT)) {
        problem(&s, "the board refused frames mode (HID MODE 2: no display?): %s", t->error);
        s.failed = true;
    } else {
        send_packet(&s, PROTO_T_RESET, NULL, 0);
    }
    /* each frame's tiles, then a PING: its STATUS confirms the frame unless
     * an ERROR came first, in which case the frame's tiles go again */
    for (unsigned i = 0; i < nframes && !s.failed; i++) {
        unsigned tries = 0;
        for (;;) {
            s.need_resume = false;
            s.have_status = false;
            uint64_t errors = r->board_errors[PROTO_E_BAD_CRC] + r->board_errors[PROTO_E_SEQ_GAP];
            send_tiles(&s, &frames[i], buf, s.max);
            if (s.failed || send_packet(&s, PROTO_T_PING, NULL, 0))
                break;
            while (!s.have_status && !s.failed && pump(&s, o->timeout_ms))
                ;
            if (s.failed)
                break;
            /* no STATUS: the PING or its answer was lost, or the board is gone */
            bool lost = !s.have_status || s.need_resume ||
                        r->board_errors[PROTO_E_BAD_CRC] + r->board_errors[PROTO_E_SEQ_GAP] != errors;
            if (!lost) {
                r->frames++;
                r->matched++;
                break;
            }
            if (tries++ >= o->retries) {
                if (s.have_status)
                    problem(&s, "frame %u still losing tiles after %u resends", frames[i].number,
                            o->retries);
                else
                    problem(&s, "the board stopped answering: no STATUS within %u ms after frame "
                                "%u, %u times", o->timeout_ms, frames[i].number, tries);
                s.failed = true;
                break;
            }
            r->resumes++;
            note(&s, "frame %u: %s, sending it again", frames[i].number,
                 s.have_status ? "tiles lost on the link" : "no STATUS came back");
        }
        if (o->progress && o->log)
            fprintf(o->log, "\r%u/%u frames shown, %.1f MB sent", r->frames, nframes,
                    (double)r->bytes / 1e6);
    }
    finish(&s, t0);
    free(buf);
    return r->interrupted ? -2 : s.failed ? -1 : 0;
}
