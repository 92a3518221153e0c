/* test_fw_core.c — the board side of the bridge (firmware/core.c) against
 * docs/usb-protocol.md, through a fake HAL that records the words forwarded
 * to the VP, the VP restarts and every packet sent to the host.  Packets are
 * built by the test's own encoder with a bit-by-bit CRC-32, and expected
 * counters are counted from what the test injected. */
#include "t.h"
#include "refpacket.h"
#include "../firmware/core.h"

#include <string.h>

/* the independent CRC-32 and packet encoder: refpacket.c */

static size_t enc_u32(uint8_t *out, uint8_t type, uint32_t seq, uint32_t v)
{
    uint8_t b[4];
    le32(b, v);
    return enc(out, type, seq, b, 4);
}

/* WORDS packet of n words from w */
static size_t enc_words(uint8_t *out, uint32_t seq, const uint32_t *w, size_t n)
{
    uint8_t b[4096];
    for (size_t i = 0; i < n; i++)
        le32(b + 4 * i, w[i]);
    return enc(out, PROTO_T_WORDS, seq, b, (uint32_t)(4 * n));
}

/* ---- the fake board ---- */

#define MAX_SENT 4096
#define BIG_PAYLOAD 4096

typedef struct {
    uint8_t data[64];
    uint16_t len;
} sent_pkt;

typedef struct {
    uint32_t words[65536];
    size_t nwords;
    int restarts, full_restarts;
    sent_pkt sent[MAX_SENT];
    int nsent, bad_sent;   /* bad_sent: malformed packets from the core */
    int tiles;
    uint32_t tile_frame;
    uint16_t tile_x, tile_y, tile_w, tile_h;
    uint8_t tile_first[3];
    fw_hal hal;
    fw_core core;
    uint8_t buf[PROTO_HEADER + BIG_PAYLOAD + PROTO_TRAILER];
} fake;

static void fake_words(void *ctx, const uint8_t *d, uint16_t len)
{
    fake *f = ctx;
    for (uint16_t i = 0; i + 4 <= len; i += 4)
        if (f->nwords < sizeof f->words / sizeof f->words[0])
            f->words[f->nwords++] = rd32(d + i);
    if (len % 4)
        f->bad_sent++;
}

static void fake_restart(void *ctx, uint8_t full)
{
    ((fake *)ctx)->restarts++;
    ((fake *)ctx)->full_restarts += full;
}

static void fake_send(void *ctx, const uint8_t *d, uint16_t len)
{
    fake *f = ctx;
    if (len > sizeof f->sent[0].data || f->nsent >= MAX_SENT) {
        f->bad_sent++;
        return;
    }
    memcpy(f->sent[f->nsent].data, d, len);
    f->sent[f->nsent++].len = len;
}

static void fake_tile(void *ctx, uint32_t frame, uint16_t x, uint16_t y, uint16_t w, uint16_t h,
                      const uint8_t *rgb)
{
    fake *f = ctx;
    f->tiles++;
    f->tile_frame = frame;
    f->tile_x = x;
    f->tile_y = y;
    f->tile_w = w;
    f->tile_h = h;
    if (w && h)
        memcpy(f->tile_first, rgb, 3);
}

static fake the_fake;

static fake *fake_new(uint16_t max_payload, int with_tile)
{
    fake *f = &the_fake;
    memset(f, 0, sizeof *f);
    f->hal.ctx = f;
    f->hal.vp_words = fake_words;
    f->hal.vp_restart = fake_restart;
    f->hal.send = fake_send;
    f->hal.tile = with_tile ? fake_tile : NULL;
    fw_init(&f->core, &f->hal, f->buf, max_payload);
    f->core.width = 640;
    f->core.height = 480;
    f->core.fw_version = 0x0102;
    f->core.colour_bits = 8;
    f->core.serial = 0xA1B2C3D4u;
    memcpy(f->core.name, "test board", 10);
    return f;
}

/* A packet the core sent, checked: magic, zero flags/reserved, length, CRC. */
typedef struct {
    uint8_t type;
    uint32_t seq, len;
    const uint8_t *pay;
} rx_pkt;

static rx_pkt sent(const fake *f, int i)
{
    rx_pkt p = {0, 0, 0, NULL};
    CHECK_MSG(i < f->nsent, "packet %d not sent (%d sent)", i, f->nsent);
    if (i >= f->nsent)
        return p;
    const uint8_t *d = f->sent[i].data;
    uint16_t n = f->sent[i].len;
    CHECK(n >= 20);
    CHECK(memcmp(d, "ALB1", 4) == 0);
    CHECK(d[5] == 0 && d[6] == 0 && d[7] == 0);
    p.type = d[4];
    p.seq = rd32(d + 8);
    p.len = rd32(d + 12);
    CHECK_EQ(p.len + 20, n);
    CHECK_EQ(rd32(d + n - 4), ref_crc32(d, (size_t)n - 4));
    p.pay = d + 16;
    return p;
}

/* Checks sent packet i is ERROR code/seq/expected; returns detail. */
static uint32_t check_error(const fake *f, int i, uint32_t code, uint32_t seq, uint32_t expected)
{
    rx_pkt p = sent(f, i);
    if (!p.pay)
        return 0;
    CHECK_EQ(p.type, PROTO_T_ERROR);
    CHECK_EQ(p.len, 16);
    CHECK_EQ(rd32(p.pay), code);
    CHECK_EQ(rd32(p.pay + 4), seq);
    CHECK_EQ(rd32(p.pay + 8), expected);
    return rd32(p.pay + 12);
}

static void feed(fake *f, const uint8_t *d, size_t n)
{
    while (n) {
        uint16_t k = n > 0xFFFF ? 0xFFFF : (uint16_t)n;
        fw_rx(&f->core, d, k);
        d += k;
        n -= k;
    }
}

static void feed_bytes(fake *f, const uint8_t *d, size_t n)
{
    for (size_t i = 0; i < n; i++)
        fw_rx(&f->core, d + i, 1);
}

static void feed_random(fake *f, const uint8_t *d, size_t n, uint64_t seed)
{
    uint64_t s = seed;
    while (n) {
        size_t k = 1 + (size_t)(t_rand(&s) % 700);
        if (k > n)
            k = n;
        fw_rx(&f->core, d, (uint16_t)k);
        d += k;
        n -= k;
    }
}

static uint32_t counter(const fake *f, unsigned off) { return f->core.counters[off / 4]; }

static void fill_words(uint32_t *w, size_t n, uint32_t base)
{
    for (size_t i = 0; i < n; i++)
        w[i] = base + (uint32_t)i * 0x01010101u;
}

/* ---- CRC ---- */

TEST(fw_crc32_check_value)
{
    const uint8_t *s = (const uint8_t *)"123456789";
    CHECK_EQ(proto_crc32(0, s, 9), 0xCBF43926u);
    CHECK_EQ(proto_crc32(0, s, 0), 0);
    CHECK_EQ(proto_crc32(proto_crc32(0, s, 4), s + 4, 5), 0xCBF43926u);
    uint8_t buf[1000];
    uint64_t seed = 7;
    for (size_t i = 0; i < sizeof buf; i++)
        buf[i] = (uint8_t)t_rand(&seed);
    for (uint16_t n = 0; n <= 1000; n += 37) {
        CHECK_EQ(proto_crc32(0, buf, n), ref_crc32(buf, n));
        CHECK_EQ(proto_crc32(proto_crc32(0, buf, n / 3), buf + n / 3, (uint16_t)(n - n / 3)),
                 ref_crc32(buf, n));
    }
}

/* ---- framing ---- */

/* RESET, then WORDS 1..3: 3 + 5 + 0 words */
static size_t three_packets(uint8_t *s, uint32_t *w)
{
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    fill_words(w, 8, 0x11223344u);
    n += enc_words(s + n, 1, w, 3);
    n += enc_words(s + n, 2, w + 3, 5);
    n += enc_words(s + n, 3, w + 8, 0);
    return n;
}

TEST(fw_packets_split_into_single_bytes)
{
    uint8_t s[512];
    uint32_t w[8];
    size_t n = three_packets(s, w);
    fake *f = fake_new(1024, 0);
    feed_bytes(f, s, n);
    CHECK_EQ(f->restarts, 1);
    CHECK_EQ(f->nwords, 8);
    CHECK(memcmp(f->words, w, sizeof w) == 0);
    CHECK_EQ(f->nsent, 0);
    CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 4);
    CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), 0);
    CHECK_EQ(f->core.rx_seq, 4);
    CHECK_EQ(f->core.fill, 0);
}

TEST(fw_several_packets_in_one_feed)
{
    uint8_t s[512];
    uint32_t w[8];
    size_t n = three_packets(s, w);
    fake *f = fake_new(1024, 0);
    feed(f, s, n);
    CHECK_EQ(f->nwords, 8);
    CHECK(memcmp(f->words, w, sizeof w) == 0);
    CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 4);
    CHECK_EQ(f->nsent, 0);
    /* every split point */
    for (size_t cut = 1; cut < n; cut++) {
        f = fake_new(1024, 0);
        feed(f, s, cut);
        feed(f, s + cut, n - cut);
        CHECK_MSG(f->nwords == 8 && memcmp(f->words, w, sizeof w) == 0,
                  "cut at %zu: %zu words", cut, f->nwords);
        CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 4);
    }
}

/* Garbage before, between and after packets; none of it contains 'A' unless
 * listed as a trap, so every injected byte is counted once. */
TEST(fw_garbage_resync)
{
    static uint8_t s[4096];
    uint32_t w[8];
    fill_words(w, 8, 0x0A0B0C0Du);
    size_t n = 0, garbage = 0;
    const char *junk[] = {
        "xyz",          /* plain */
        "AL",           /* magic prefix, then not */
        "ALB",          /* longer prefix */
        "AAALB",        /* overlapping prefixes */
        "ALB1\x02\x00\x01\x00",   /* magic with reserved set (8 bytes + 12 zeros) */
    };
    memcpy(s + n, "\x00\xff\x10", 3);
    n += 3;
    garbage += 3;
    n += enc(s + n, PROTO_T_RESET, 0, NULL, 0);
    for (unsigned j = 0; j < sizeof junk / sizeof junk[0]; j++) {
        size_t k = strlen(junk[j]);
        if (j == 4) {
            memcpy(s + n, junk[j], 8);
            memset(s + n + 8, 0, 12);
            k = 20;
        } else
            memcpy(s + n, junk[j], k);
        n += k;
        garbage += k;
        n += enc_words(s + n, 1 + j, w + j, 1);
    }
    for (int mode = 0; mode < 3; mode++) {
        fake *f = fake_new(1024, 0);
        if (mode == 0)
            feed(f, s, n);
        else if (mode == 1)
            feed_bytes(f, s, n);
        else
            feed_random(f, s, n, 99);
        CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), garbage);
        CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 6);
        CHECK_EQ(f->nwords, 5);
        CHECK(memcmp(f->words, w, 5 * 4) == 0);
        CHECK_EQ(f->nsent, 0);
    }
}

/* A byte corrupted in the header, the payload or the CRC: ERROR BAD_CRC, the
 * whole packet counted as garbage, and the retransmission behind it taken. */
TEST(fw_corrupted_byte)
{
    uint32_t w[16];
    fill_words(w, 16, 0x10203040u);
    /* type, flags, length (64 -> 68: waits for 4 bytes of the next packet),
     * payload, CRC */
    const size_t where[] = {4, 5, 12, 16, 16 + 30, 16 + 63, 16 + 64, 16 + 67};
    for (unsigned j = 0; j < sizeof where / sizeof where[0]; j++) {
        uint8_t s[512];
        size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
        size_t bad = n, badlen = enc_words(s + n, 1, w, 16);
        n += badlen;
        s[bad + where[j]] ^= 0x04;
        n += enc_words(s + n, 1, w, 16);
        n += enc_words(s + n, 2, w, 2);
        for (int bytewise = 0; bytewise < 2; bytewise++) {
            fake *f = fake_new(1024, 0);
            if (bytewise)
                feed_bytes(f, s, n);
            else
                feed(f, s, n);
            CHECK_EQ(f->nsent, 1);
            uint32_t detail = check_error(f, 0, PROTO_E_BAD_CRC, 1, 1);
            /* the CRC the board computed, over the length it was told */
            CHECK_EQ(detail, ref_crc32(s + bad, 16 + (size_t)rd32(s + bad + 12)));
            CHECK_EQ(counter(f, PROTO_STATUS_CRC_ERRORS), 1);
            CHECK_MSG(counter(f, PROTO_STATUS_GARBAGE) == badlen, "byte %zu: garbage %u",
                      where[j], (unsigned)counter(f, PROTO_STATUS_GARBAGE));
            CHECK_EQ(f->nwords, 18);
            CHECK(memcmp(f->words, w, 16 * 4) == 0);
            CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 3);
            CHECK_EQ(f->core.last_error[0], PROTO_E_BAD_CRC);
        }
    }
}

/* A length corrupted upward (still <= max) makes the candidate wait for
 * bytes that are really the next packets; its CRC then fails and the
 * receiver rescans from one byte after its magic, finding them all. */
TEST(fw_corrupted_length_swallows_nothing)
{
    uint32_t w[16];
    fill_words(w, 16, 0x55660000u);
    static uint8_t s[2048];
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    size_t bad = n, badlen = enc_words(s + n, 1, w, 4);
    n += badlen;
    s[bad + 12] = 200;   /* length 16 -> 200 */
    size_t good = n;
    for (uint32_t q = 1; q <= 8; q++)
        n += enc_words(s + n, q, w + q, 4);
    CHECK(n - bad >= 220);   /* enough bytes to complete the bogus candidate */
    for (int mode = 0; mode < 3; mode++) {
        fake *f = fake_new(1024, 0);
        if (mode == 0)
            feed(f, s, n);
        else if (mode == 1)
            feed_bytes(f, s, n);
        else
            feed_random(f, s, n, 5);
        CHECK_EQ(f->nsent, 1);
        check_error(f, 0, PROTO_E_BAD_CRC, 1, 1);
        CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), good - bad);
        CHECK_EQ(f->nwords, 32);
        for (uint32_t q = 1; q <= 8; q++)
            CHECK(memcmp(f->words + 4 * (q - 1), w + q, 16) == 0);
        CHECK_EQ(f->core.rx_seq, 9);
    }
}

TEST(fw_length_above_max_rejected)
{
    uint32_t w[32];
    fill_words(w, 32, 0x77000000u);
    uint8_t s[1024];
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    size_t big = enc_words(s + n, 1, w, 17);   /* 68 bytes > 64 */
    n += big;
    n += enc_words(s + n, 1, w, 16);            /* 64 bytes: the most accepted */
    for (int bytewise = 0; bytewise < 2; bytewise++) {
        fake *f = fake_new(64, 0);
        if (bytewise)
            feed_bytes(f, s, n);
        else
            feed(f, s, n);
        CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), big);
        CHECK_EQ(f->nsent, 0);
        CHECK_EQ(f->nwords, 16);
        CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 2);
    }
    /* a length above 16384 is rejected even with max_payload asked higher */
    fake *f = fake_new(0xFFFF, 0);
    CHECK_EQ(f->core.max_payload, PROTO_MAX_PAYLOAD);
}

/* ---- sequence numbers, error state, RESUME ---- */

TEST(fw_seq_gap_error_state_resume)
{
    static uint8_t s[4096];
    uint32_t a[4] = {0xF0000004u, 1, 2, 3};            /* frame 4 starts */
    uint32_t b[3] = {6, 7, 8};
    uint32_t c6[5] = {9, 0xF0000004u, 0xF0000005u, 10, 11};   /* resumed frame 5 */
    uint32_t d[2] = {12, 13};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc_words(s + n, 1, a, 4);
    feed(f, s, n);
    /* packet 2 is lost on the way */
    n = enc_words(s, 3, b, 3);
    n += enc_words(s + n, 4, b, 3);
    feed(f, s, n);
    CHECK_EQ(f->nsent, 1);
    CHECK_EQ(check_error(f, 0, PROTO_E_SEQ_GAP, 3, 2), 1);
    CHECK_EQ(counter(f, PROTO_STATUS_SEQ_GAPS), 1);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 2);
    CHECK_EQ(f->nwords, 4);
    CHECK(f->core.error_state);
    /* RESUME frame 5 (upper bits beyond the 24-bit frame number ignored) */
    n = enc_u32(s, PROTO_T_RESUME, 5, 0x01000005u);
    n += enc_words(s + n, 6, c6, 5);
    n += enc_words(s + n, 7, d, 2);
    feed(f, s, n);
    CHECK_EQ(f->restarts, 2);
    CHECK_EQ(f->full_restarts, 1);   /* the RESET was a new stream, the RESUME not */
    CHECK(!f->core.error_state);
    CHECK_EQ(f->nsent, 1);
    CHECK_EQ(f->nwords, 4 + 3 + 2);
    uint32_t want[9] = {0xF0000004u, 1, 2, 3, 0xF0000005u, 10, 11, 12, 13};
    CHECK(memcmp(f->words, want, sizeof want) == 0);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 2);
}

TEST(fw_resume_skips_whole_packets_until_frame)
{
    uint8_t s[1024];
    uint32_t x[3] = {1, 2, 3}, y[3] = {0xF0000009u, 4, 5};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 10, NULL, 0);
    n += enc_u32(s + n, PROTO_T_RESUME, 11, 9);
    n += enc_words(s + n, 12, x, 3);
    n += enc_words(s + n, 13, y, 3);
    feed(f, s, n);
    CHECK_EQ(f->nwords, 3);
    CHECK(memcmp(f->words, y, sizeof y) == 0);
    CHECK_EQ(f->nsent, 0);
}

TEST(fw_duplicate)
{
    uint8_t s[512];
    uint32_t w[2] = {0xAB, 0xCD};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc_words(s + n, 1, w, 1);
    n += enc_words(s + n, 1, w, 1);
    n += enc_words(s + n, 2, w + 1, 1);
    feed(f, s, n);
    CHECK_EQ(f->nsent, 1);
    CHECK_EQ(check_error(f, 0, PROTO_E_DUPLICATE, 1, 2), 1);
    CHECK_EQ(counter(f, PROTO_STATUS_DUPLICATES), 1);
    CHECK_EQ(f->nwords, 2);
    CHECK(memcmp(f->words, w, sizeof w) == 0);
    CHECK(!f->core.error_state);
    CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 4);
}

/* Serial arithmetic: numbers wrap from 2^32 - 1 to 0, and "behind" means
 * less than 2^31 behind. */
TEST(fw_seq_wraps)
{
    uint8_t s[512];
    uint32_t w[3] = {7, 8, 9};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0xFFFFFFFEu, NULL, 0);
    n += enc_words(s + n, 0xFFFFFFFFu, w, 1);
    n += enc_words(s + n, 0, w + 1, 1);
    n += enc_words(s + n, 0xFFFFFFFFu, w, 1);        /* 2 behind */
    n += enc_words(s + n, 0x80000002u, w, 1);        /* 2^31 - 1 behind */
    n += enc_words(s + n, 1, w + 2, 1);
    feed(f, s, n);
    CHECK_EQ(f->nwords, 3);
    CHECK(memcmp(f->words, w, sizeof w) == 0);
    CHECK_EQ(f->nsent, 2);
    CHECK_EQ(check_error(f, 0, PROTO_E_DUPLICATE, 0xFFFFFFFFu, 1), 2);
    CHECK_EQ(check_error(f, 1, PROTO_E_DUPLICATE, 0x80000002u, 1), 0x7FFFFFFFu);
    n = enc_words(s, 0x40000000u, w, 1);             /* far ahead: a gap */
    feed(f, s, n);
    CHECK_EQ(check_error(f, 2, PROTO_E_SEQ_GAP, 0x40000000u, 2), 0x3FFFFFFEu);
    CHECK_EQ(f->core.rx_seq, 0x40000001u);
}

TEST(fw_reset)
{
    uint8_t s[512];
    uint32_t w[1] = {42};
    fake *f = fake_new(1024, 0);
    /* before any RESET: dropped with ERROR MODE */
    size_t n = enc_words(s, 0, w, 1);
    n += enc(s + n, PROTO_T_PING, 1, NULL, 0);
    feed(f, s, n);
    CHECK_EQ(f->nsent, 2);
    check_error(f, 0, PROTO_E_MODE, 0, 0);
    check_error(f, 1, PROTO_E_MODE, 1, 0);
    CHECK_EQ(sent(f, 1).seq, 1);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 2);
    CHECK_EQ(f->nwords, 0);
    /* RESET 100: next expected 101, tx numbering restarts at 0 */
    n = enc(s, PROTO_T_RESET, 100, NULL, 0);
    n += enc_words(s + n, 102, w, 1);   /* gap: error state */
    feed(f, s, n);
    CHECK_EQ(f->restarts, 1);
    CHECK_EQ(f->full_restarts, 1);
    CHECK_EQ(f->nsent, 3);
    check_error(f, 2, PROTO_E_SEQ_GAP, 102, 101);
    CHECK_EQ(sent(f, 2).seq, 0);
    CHECK(f->core.error_state);
    /* a second RESET leaves the error state */
    n = enc(s, PROTO_T_RESET, 7, NULL, 0);
    n += enc_words(s + n, 8, w, 1);
    n += enc(s + n, PROTO_T_PING, 9, NULL, 0);
    feed(f, s, n);
    CHECK_EQ(f->restarts, 2);
    CHECK_EQ(f->nwords, 1);
    CHECK_EQ(f->nsent, 4);
    rx_pkt p = sent(f, 3);
    CHECK_EQ(p.type, PROTO_T_STATUS);
    CHECK_EQ(p.seq, 0);
    /* RESET with a payload is refused */
    n = enc_u32(s, PROTO_T_RESET, 50, 0);
    feed(f, s, n);
    CHECK_EQ(check_error(f, 4, PROTO_E_BAD_LENGTH, 50, 10), 4);
    CHECK_EQ(f->core.rx_seq, 10);
    CHECK_EQ(f->restarts, 2);
}

/* ---- results ---- */

static fw_result result_of(uint32_t frame)
{
    fw_result r = {frame, 0xC0DE0000u ^ frame, 1000u * frame, frame >> 2, 3 * frame + 1};
    return r;
}

static void check_result(const fake *f, int i, uint32_t frame)
{
    rx_pkt p = sent(f, i);
    if (!p.pay)
        return;
    fw_result r = result_of(frame);
    CHECK_EQ(p.type, PROTO_T_RESULT);
    CHECK_EQ(p.len, 20);
    CHECK_EQ(rd32(p.pay), r.frame);
    CHECK_EQ(rd32(p.pay + 4), r.crc);
    CHECK_EQ(rd32(p.pay + 8), r.cyc_lo);
    CHECK_EQ(rd32(p.pay + 12), r.cyc_hi);
    CHECK_EQ(rd32(p.pay + 16), r.faces);
}

TEST(fw_query)
{
    uint8_t s[256];
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    feed(f, s, n);
    for (uint32_t fr = 0; fr < 20; fr++) {
        fw_result r = result_of(fr);
        fw_frame_done(&f->core, &r);
    }
    CHECK_EQ(f->nsent, 20);
    for (int i = 0; i < 20; i++) {
        check_result(f, i, (uint32_t)i);
        CHECK_EQ(sent(f, i).seq, (uint32_t)i);
    }
    CHECK_EQ(counter(f, PROTO_STATUS_FRAMES), 20);
    /* kept: the last FW_RESULTS frames, 4..19 */
    n = enc_u32(s, PROTO_T_QUERY, 1, 19);
    n += enc_u32(s + n, PROTO_T_QUERY, 2, 4);
    n += enc_u32(s + n, PROTO_T_QUERY, 3, 3);
    n += enc_u32(s + n, PROTO_T_QUERY, 4, 25);
    feed(f, s, n);
    CHECK_EQ(f->nsent, 24);
    check_result(f, 20, 19);
    check_result(f, 21, 4);
    CHECK_EQ(check_error(f, 22, PROTO_E_OVERFLOW, 3, 3), 19);
    CHECK_EQ(check_error(f, 23, PROTO_E_OVERFLOW, 4, 25), 19);
    CHECK_EQ(sent(f, 23).seq, 23);
    CHECK_EQ(counter(f, PROTO_STATUS_FRAMES), 20);
    /* RESET forgets the results */
    n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc_u32(s + n, PROTO_T_QUERY, 1, 19);
    feed(f, s, n);
    CHECK_EQ(check_error(f, 24, PROTO_E_OVERFLOW, 1, 19), 0xFFFFFFFFu);
}

/* ---- STATUS and the counters, from what was injected ---- */

TEST(fw_ping_status_counts)
{
    static uint8_t s[2048];
    uint32_t w[4] = {1, 2, 3, 4};
    fake *f = fake_new(1024, 0);
    size_t n = 0;
    memcpy(s, "zz", 2);                                   /* garbage 2 */
    n += 2;
    n += enc(s + n, PROTO_T_RESET, 0, NULL, 0);           /* rx 1 */
    n += enc_words(s + n, 1, w, 4);                       /* rx 2 */
    n += enc_words(s + n, 1, w, 4);                       /* rx 3, duplicate, sent 1 */
    size_t bad = n, badlen = enc_words(s + n, 2, w, 4);   /* CRC error, sent 2 */
    n += badlen;
    s[bad + 20] ^= 1;
    n += enc_words(s + n, 4, w, 4);                       /* rx 4, gap, dropped 1, sent 3 */
    n += enc_words(s + n, 5, w, 4);                       /* rx 5, dropped 2 */
    n += enc(s + n, PROTO_T_PING, 6, NULL, 0);            /* rx 6, sent 4 */
    feed_random(f, s, n, 1234);
    CHECK_EQ(f->nsent, 4);
    rx_pkt p = sent(f, 3);
    CHECK_EQ(p.type, PROTO_T_STATUS);
    CHECK_EQ(p.len, PROTO_STATUS_BYTES);
    if (!p.pay)
        return;
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_RX_PACKETS), 6);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_CRC_ERRORS), 1);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_SEQ_GAPS), 1);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_DUPLICATES), 1);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_GARBAGE), 2 + badlen);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_FRAMES), 0);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_TX_PACKETS), 3);   /* before the STATUS itself */
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_LAST_ERROR), PROTO_E_SEQ_GAP);
    CHECK_EQ(rd32(p.pay + PROTO_STATUS_DROPPED), 2);
    CHECK_EQ(f->nwords, 4);
    for (int i = 0; i < 4; i++)
        CHECK_EQ(sent(f, i).seq, (uint32_t)i);
}

TEST(fw_bad_length_and_type)
{
    uint8_t s[512];
    uint8_t six[6] = {1, 2, 3, 4, 5, 6};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc(s + n, PROTO_T_WORDS, 1, six, 6);
    n += enc(s + n, PROTO_T_RESUME, 2, six, 3);
    n += enc(s + n, PROTO_T_QUERY, 3, six, 5);
    n += enc(s + n, PROTO_T_PING, 4, six, 4);
    n += enc(s + n, 0x7E, 5, NULL, 0);
    n += enc(s + n, PROTO_T_RESULT, 6, six, 6);
    feed(f, s, n);
    CHECK_EQ(f->nsent, 6);
    /* expected: the next number, the refused packet kept its place */
    CHECK_EQ(check_error(f, 0, PROTO_E_BAD_LENGTH, 1, 2), 6);
    CHECK_EQ(check_error(f, 1, PROTO_E_BAD_LENGTH, 2, 3), 3);
    CHECK_EQ(check_error(f, 2, PROTO_E_BAD_LENGTH, 3, 4), 5);
    CHECK_EQ(check_error(f, 3, PROTO_E_BAD_LENGTH, 4, 5), 4);
    CHECK_EQ(check_error(f, 4, PROTO_E_BAD_TYPE, 5, 6), 0x7E);
    CHECK_EQ(check_error(f, 5, PROTO_E_BAD_TYPE, 6, 7), PROTO_T_RESULT);
    CHECK_EQ(f->nwords, 0);
    CHECK_EQ(f->restarts, 1);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 6);
    CHECK(!f->core.error_state);   /* refused packets keep their place in the numbering */
    CHECK_EQ(f->core.rx_seq, 7);
}

TEST(fw_tiles_mode)
{
    uint8_t s[512], t[12 + 2 * 3 * 3];
    fake *f = fake_new(1024, 1);
    le32(t, 77);
    t[4] = 5, t[5] = 0, t[6] = 6, t[7] = 0, t[8] = 2, t[9] = 0, t[10] = 3, t[11] = 0;
    for (unsigned i = 12; i < sizeof t; i++)
        t[i] = (uint8_t)(0x90 + i);
    uint32_t w[1] = {1};
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc(s + n, PROTO_T_TILE, 1, t, sizeof t);   /* words mode: refused */
    feed(f, s, n);
    CHECK_EQ(check_error(f, 0, PROTO_E_MODE, 1, 2), PROTO_MODE_WORDS << 8 | PROTO_T_TILE);
    uint8_t rep[64] = {PROTO_HID_MODE, PROTO_MODE_TILES};
    CHECK_EQ(fw_hid_set(&f->core, rep, 2), 0);
    n = enc(s, PROTO_T_TILE, 2, t, sizeof t);
    n += enc(s + n, PROTO_T_TILE, 3, t, sizeof t - 3);   /* one pixel short */
    n += enc_words(s + n, 4, w, 1);                     /* tiles mode: refused */
    feed(f, s, n);
    CHECK_EQ(f->tiles, 1);
    CHECK_EQ(f->tile_frame, 77);
    CHECK_EQ(f->tile_x, 5);
    CHECK_EQ(f->tile_y, 6);
    CHECK_EQ(f->tile_w, 2);
    CHECK_EQ(f->tile_h, 3);
    CHECK_EQ(f->tile_first[0], 0x90 + 12);
    CHECK_EQ(f->nsent, 3);
    CHECK_EQ(check_error(f, 1, PROTO_E_BAD_LENGTH, 3, 4), sizeof t - 3);
    CHECK_EQ(check_error(f, 2, PROTO_E_MODE, 4, 5), PROTO_MODE_TILES << 8 | PROTO_T_WORDS);
    CHECK_EQ(f->nwords, 0);
    /* a board without a tile callback refuses tiles mode */
    f = fake_new(1024, 0);
    CHECK_EQ(fw_hid_set(&f->core, rep, 2), 1);
    CHECK_EQ(f->core.mode, PROTO_MODE_WORDS);
}

/* ---- HID ---- */

TEST(fw_hid_reports)
{
    uint8_t r[64];
    fake *f = fake_new(1000, 0);
    memset(r, 0xEE, sizeof r);
    r[0] = PROTO_HID_INFO;
    CHECK_EQ(fw_hid_get(&f->core, r), 64);
    CHECK(memcmp(r + PROTO_INFO_MAGIC, "ALBI", 4) == 0);
    CHECK_EQ(r[PROTO_INFO_PROTO] | r[PROTO_INFO_PROTO + 1] << 8, PROTO_VERSION);
    CHECK_EQ(r[PROTO_INFO_FW] | r[PROTO_INFO_FW + 1] << 8, 0x0102);
    CHECK_EQ(r[PROTO_INFO_WIDTH] | r[PROTO_INFO_WIDTH + 1] << 8, 640);
    CHECK_EQ(r[PROTO_INFO_HEIGHT] | r[PROTO_INFO_HEIGHT + 1] << 8, 480);
    CHECK_EQ(r[PROTO_INFO_CBITS], 8);
    CHECK_EQ(r[PROTO_INFO_MODE], PROTO_MODE_WORDS);
    CHECK_EQ(rd32(r + PROTO_INFO_SERIAL), 0xA1B2C3D4u);
    CHECK(memcmp(r + PROTO_INFO_NAME, "test board\0\0\0\0\0\0", 16) == 0);
    CHECK_EQ(r[PROTO_INFO_MAXPAY] | r[PROTO_INFO_MAXPAY + 1] << 8, 1000);
    CHECK_EQ(r[63], 0);

    /* MODE */
    uint8_t set[64] = {PROTO_HID_MODE, PROTO_MODE_IDLE};
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 0);
    r[0] = PROTO_HID_MODE;
    CHECK_EQ(fw_hid_get(&f->core, r), 64);
    CHECK_EQ(r[1], PROTO_MODE_IDLE);
    set[1] = 3;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 1);
    CHECK_EQ(fw_hid_set(&f->core, set, 1), 1);
    set[1] = PROTO_MODE_WORDS;
    CHECK_EQ(fw_hid_set(&f->core, set, 64), 0);
    CHECK_EQ(f->core.mode, PROTO_MODE_WORDS);

    /* unknown or SET-only ids */
    r[0] = 9;
    CHECK_EQ(fw_hid_get(&f->core, r), 0);
    r[0] = PROTO_HID_RESET;
    CHECK_EQ(fw_hid_get(&f->core, r), 0);
    set[0] = 9;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 1);

    /* a CRC error and garbage, then COUNTERS and LAST ERROR */
    uint8_t s[256];
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    size_t bad = n, badlen = enc(s + n, PROTO_T_PING, 1, NULL, 0);
    n += badlen;
    s[bad + 16] ^= 0x80;
    feed(f, s, n);
    r[0] = PROTO_HID_COUNTERS;
    CHECK_EQ(fw_hid_get(&f->core, r), 64);
    CHECK_EQ(rd32(r + 1 + PROTO_STATUS_RX_PACKETS), 1);
    CHECK_EQ(rd32(r + 1 + PROTO_STATUS_CRC_ERRORS), 1);
    CHECK_EQ(rd32(r + 1 + PROTO_STATUS_GARBAGE), badlen);
    CHECK_EQ(rd32(r + 1 + PROTO_STATUS_TX_PACKETS), 1);
    CHECK_EQ(rd32(r + 1 + PROTO_STATUS_LAST_ERROR), PROTO_E_BAD_CRC);
    r[0] = PROTO_HID_LASTERR;
    CHECK_EQ(fw_hid_get(&f->core, r), 64);
    CHECK_EQ(rd32(r + 1), PROTO_E_BAD_CRC);
    CHECK_EQ(rd32(r + 5), 1);
    CHECK_EQ(rd32(r + 9), 1);
    CHECK_EQ(rd32(r + 13), ref_crc32(s + bad, badlen - 4));
    CHECK(strcmp((const char *)r + 17, "bad CRC") == 0);

    /* RESET: bad what, counters, link */
    set[0] = PROTO_HID_RESET;
    set[1] = 0;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 1);
    set[1] = 4;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 1);
    set[1] = PROTO_RESET_COUNTERS;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 0);
    r[0] = PROTO_HID_COUNTERS;
    fw_hid_get(&f->core, r);
    for (unsigned i = 0; i < PROTO_STATUS_BYTES; i++)
        CHECK_EQ(r[1 + i], 0);
    r[0] = PROTO_HID_LASTERR;
    fw_hid_get(&f->core, r);
    CHECK_EQ(rd32(r + 1), PROTO_E_NONE);
    CHECK(strcmp((const char *)r + 17, "no error") == 0);
    CHECK_EQ(f->restarts, 1);
    /* link: the next packet expected is number 0, half a packet forgotten */
    n = enc(s, PROTO_T_PING, 5, NULL, 0);
    feed(f, s, 10);
    set[1] = PROTO_RESET_LINK;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 0);
    CHECK_EQ(f->restarts, 2);
    CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), 10);
    n = enc(s, PROTO_T_PING, 0, NULL, 0);
    feed(f, s, n);
    rx_pkt p = sent(f, f->nsent - 1);
    CHECK_EQ(p.type, PROTO_T_STATUS);
    CHECK_EQ(p.seq, 0);
    /* both */
    set[1] = PROTO_RESET_ALL;
    CHECK_EQ(fw_hid_set(&f->core, set, 2), 0);
    CHECK_EQ(f->restarts, 3);
    CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 0);
    CHECK_EQ(f->core.rx_seq, 0);
}

TEST(fw_vp_error_enters_error_state)
{
    uint8_t s[256];
    uint32_t w[2] = {1, 2};
    fake *f = fake_new(1024, 0);
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc_words(s + n, 1, w, 1);
    feed(f, s, n);
    fw_vp_error(&f->core, 1234);
    CHECK_EQ(check_error(f, 0, PROTO_E_STREAM, 1, 2), 1234);
    n = enc_words(s, 2, w + 1, 1);
    feed(f, s, n);
    CHECK_EQ(f->nwords, 1);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 1);
    uint8_t r[64] = {PROTO_HID_LASTERR};
    fw_hid_get(&f->core, r);
    CHECK(strcmp((const char *)r + 17, "malformed word stream") == 0);
}

/* A VP run inside vp_words (the simulated board) finishes frames and finds
 * errors there: RESULT and ERROR go out from within fw_rx, and the parsing
 * around them is undisturbed. */
static fake *vp_fake;

static void vp_inline(void *ctx, const uint8_t *d, uint16_t len)
{
    fake_words(ctx, d, len);
    for (uint16_t i = 0; i + 4 <= len; i += 4) {
        uint32_t w = rd32(d + i);
        if (w >> 24 == 0xFE) {   /* FRAME_END: the frame is done */
            fw_result r = result_of(w & 0xFFFFFF);
            fw_frame_done(&vp_fake->core, &r);
        } else if (w == 0xBADBAD00u)
            fw_vp_error(&vp_fake->core, i / 4);
    }
}

TEST(fw_vp_reports_from_inside_vp_words)
{
    uint8_t s[512];
    uint32_t a[4] = {0xF0000001u, 1, 0xFE000001u, 0xF0000002u};
    uint32_t b[3] = {2, 0xFE000002u, 0xBADBAD00u};
    uint32_t c[1] = {3};
    fake *f = fake_new(1024, 0);
    vp_fake = f;
    f->hal.vp_words = vp_inline;
    size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0);
    n += enc_words(s + n, 1, a, 4);
    n += enc_words(s + n, 2, b, 3);
    n += enc_words(s + n, 3, c, 1);   /* error state: dropped */
    n += enc(s + n, PROTO_T_PING, 4, NULL, 0);
    feed_random(f, s, n, 77);
    CHECK_EQ(f->nwords, 7);
    CHECK_EQ(f->nsent, 4);
    check_result(f, 0, 1);
    check_result(f, 1, 2);
    CHECK_EQ(check_error(f, 2, PROTO_E_STREAM, 2, 3), 2);
    rx_pkt p = sent(f, 3);
    CHECK_EQ(p.type, PROTO_T_STATUS);
    for (int i = 0; i < 4; i++)
        CHECK_EQ(sent(f, i).seq, (uint32_t)i);
    CHECK_EQ(counter(f, PROTO_STATUS_FRAMES), 2);
    CHECK_EQ(counter(f, PROTO_STATUS_DROPPED), 1);
    CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), 5);
}

/* ---- robustness: random splits, random garbage, random bytes ---- */

/* Valid packets of random sizes with garbage free of 'A' between them, fed
 * in random pieces: every word arrives, every garbage byte is counted. */
TEST(fw_random_stream_property)
{
    static uint8_t s[200000];
    static uint32_t w[40000];
    uint64_t seed = 0x5EED;
    for (int round = 0; round < 20; round++) {
        size_t n = enc(s, PROTO_T_RESET, 0, NULL, 0), nw = 0, garbage = 0;
        uint32_t seq = 1;
        while (n < sizeof s - 5000) {
            size_t g = t_rand(&seed) % 8;
            for (size_t i = 0; i < g; i++) {
                uint8_t b = (uint8_t)t_rand(&seed);
                s[n++] = b == 'A' ? 'a' : b;
            }
            garbage += g;
            size_t k = t_rand(&seed) % 257;
            if (nw + k > sizeof w / sizeof w[0])
                break;
            for (size_t i = 0; i < k; i++)
                w[nw + i] = (uint32_t)t_rand(&seed);
            n += enc_words(s + n, seq++, w + nw, k);
            nw += k;
        }
        fake *f = fake_new(1024, 0);
        feed_random(f, s, n, seed);
        CHECK_EQ(f->nsent, 0);
        CHECK_EQ(f->bad_sent, 0);
        CHECK_EQ(counter(f, PROTO_STATUS_GARBAGE), garbage);
        CHECK_EQ(counter(f, PROTO_STATUS_RX_PACKETS), seq);
        CHECK_EQ(f->nwords, nw);
        CHECK(memcmp(f->words, w, nw * 4) == 0);
    }
}

/* Random bytes with real magics and headers sprinkled in: nothing may crash
 * (run under ASan by make asan), every byte is either garbage, part of a
 * packet or still held for an incomplete candidate. */
TEST(fw_random_bytes_survive)
{
    static uint8_t s[65536];
    uint64_t seed = 42;
    for (int round = 0; round < 50; round++) {
        size_t n = sizeof s;
        for (size_t i = 0; i < n; i++)
            s[i] = (uint8_t)t_rand(&seed);
        for (int k = 0; k < 300; k++) {
            size_t at = t_rand(&seed) % (n - 20);
            uint32_t len = (uint32_t)(t_rand(&seed) % 96);
            memcpy(s + at, "ALB1", 4);
            s[at + 6] = s[at + 7] = 0;
            le32(s + at + 12, (k & 1) ? len : (uint32_t)t_rand(&seed));
            if (k % 3 == 0 && at + 20 + len < n) {
                s[at + 4] = (uint8_t)(1 + t_rand(&seed) % 7);
                le32(s + at + 12, len);
                le32(s + at + 16 + len, ref_crc32(s + at, 16 + (size_t)len));
            }
        }
        fake *f = fake_new((uint16_t)(64 + round), round & 1);
        feed_random(f, s, n, seed);
        CHECK(f->core.fill < PROTO_HEADER + f->core.max_payload + PROTO_TRAILER);
        CHECK_EQ(f->bad_sent, 0);
        for (int i = 0; i < f->nsent; i++)
            (void)sent(f, i);
    }
}
