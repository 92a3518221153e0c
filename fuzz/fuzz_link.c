/* fuzz_link.c — the host's side of the bridge reading what a board sends
 * (emu/bridge/): the packet decoder with its resynchronisation, then the
 * whole `albatros stream` engine (alb_stream_run) talking to a "board" whose
 * every reply is the fuzzer's bytes — RESULTs for frames that do not exist,
 * ERRORs that force RESUMEs, PIXELS of any length during READBACK.
 *
 * The input's first byte seeds the cuts of the rest into reads.  Oracles
 * beyond the sanitizers: a decoded packet re-encodes to a packet that
 * decodes to itself, and the engine ends (it must not wait for ever on a
 * board that talks nonsense) with a report whose counts add up. */
#include "fuzz.h"
#include "../firmware/proto.h"
#include "albatros/link.h"
#include "albatros/stream.h"

#include <stdlib.h>
#include <string.h>

static void check(int ok)
{
    if (!ok)
        abort();
}

static uint32_t next(uint32_t *s)
{
    *s ^= *s << 13;
    *s ^= *s >> 17;
    *s ^= *s << 5;
    return *s;
}

/* Decode the bytes in pieces; every packet must survive a round trip. */
static void decode(const uint8_t *data, size_t size, uint32_t seed)
{
    alb_link_rx rx, again;
    alb_link_rx_init(&rx);
    static uint8_t out[PROTO_HEADER + PROTO_MAX_PAYLOAD + PROTO_TRAILER];
    while (size) {
        size_t piece = 1 + next(&seed) % 700;
        piece = piece < size ? piece : size;
        check(alb_link_rx_feed(&rx, data, piece) == 0);
        data += piece, size -= piece;
        alb_link_packet p;
        while (alb_link_rx_next(&rx, &p) == 1) {
            check(p.len <= PROTO_MAX_PAYLOAD);
            size_t n = alb_link_encode(out, p.type, p.seq, p.payload, p.len);
            alb_link_rx_init(&again);
            alb_link_packet q;
            check(alb_link_rx_feed(&again, out, n) == 0 && alb_link_rx_next(&again, &q) == 1);
            check(q.type == p.type && q.seq == p.seq && q.len == p.len &&
                  memcmp(q.payload, p.payload, p.len) == 0 && again.garbage == 0);
            alb_link_rx_free(&again);
        }
    }
    alb_link_rx_free(&rx);
}

/* ---- a transport whose board says whatever the input says ---- */

typedef struct {
    const uint8_t *data;
    size_t size;
    uint32_t seed;
    unsigned reads;
} replies;

static alb_tr_status fz_write(alb_transport *t, const uint8_t *data, size_t len)
{
    (void)t, (void)data, (void)len;
    return ALB_TR_OK;
}

static alb_tr_status fz_flush(alb_transport *t)
{
    (void)t;
    return ALB_TR_OK;
}

static alb_tr_status fz_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned ms)
{
    (void)ms;
    replies *r = t->impl;
    *got = 0;
    r->reads++;
    if (!r->size) {
        snprintf(t->error, sizeof t->error, "the fuzzer's bytes are used up");
        return ALB_TR_GONE;
    }
    uint32_t k = next(&r->seed);
    if (k % 8 == 0)
        return ALB_TR_TIMEOUT;   /* a quiet moment */
    size_t n = 1 + k % 1500;
    n = n < r->size ? n : r->size;
    n = n < cap ? n : cap;
    memcpy(buf, r->data, n);
    r->data += n, r->size -= n;
    *got = n;
    return ALB_TR_OK;
}

static alb_tr_status fz_hid(alb_transport *t, uint8_t *buf, size_t len)
{
    (void)t, (void)buf, (void)len;
    return ALB_TR_ERROR;
}

static alb_tr_status fz_hid_set(alb_transport *t, const uint8_t *buf, size_t len)
{
    (void)t, (void)buf, (void)len;
    return ALB_TR_ERROR;
}

static void fz_close(alb_transport *t) { (void)t; }

static const alb_transport_ops fz_ops = {"fuzz", fz_write, fz_flush, fz_read, fz_hid, fz_hid_set,
                                     fz_close};

/* Three frames of a 4 x 4 screen, each with a frame store for READBACK. */
static void run_engine(const uint8_t *data, size_t size, uint32_t seed)
{
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    alb_ws_config cfg = {14, 24, 0.5f};
    alb_ws_put_config(&b, &cfg);
    for (uint32_t k = 0; k < 3; k++) {
        alb_ws_frame f = {k, 0x102030, false, 0, 0, 0};
        alb_ws_put_frame(&b, &f);
        alb_ws_put_frame_end(&b, 0);
    }
    alb_ws_put_end(&b);
    alb_stream_frame *frames = NULL;
    unsigned nf = 0;
    check(!b.oom && alb_stream_frames(b.w, b.n, &frames, &nf) == 0 && nf == 3);
    static uint16_t rgb[3][4 * 4 * 3];
    for (unsigned k = 0; k < nf; k++) {
        frames[k].crc = 0x11111111u * (k + 1);
        frames[k].cycles = 100 * k;
        frames[k].rgb = rgb[k];
        frames[k].width = frames[k].height = 4;
    }
    replies r = {data, size, seed, 0};
    alb_transport t = {&fz_ops, &r, "", 4096};
    alb_stream_opts o;
    alb_stream_opts_default(&o);
    o.timeout_ms = 0;
    o.readback = true;
    alb_stream_report rep;
    int rc = alb_stream_run(&t, b.w, b.n, frames, nf, &o, &rep);
    check(rc >= -1 && rc <= 1);
    check(rep.matched + rep.crc_mismatch <= rep.frames + rep.cycle_mismatch &&
          rep.frames <= nf && rep.matched <= nf);
    check(rc != 0 || rep.matched == nf);
    free(frames);
    alb_ws_buf_free(&b);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    if (size < 1)
        return 0;
    uint32_t seed = 0x9E3779B9u ^ data[0];
    decode(data + 1, size - 1, seed);
    run_engine(data + 1, size - 1, seed);
    return 0;
}
