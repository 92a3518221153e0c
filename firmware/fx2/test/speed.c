/* speed.c — the FX2 image's parsing speed on what the bridge sends
 * (speed.h).
 *
 * What s51 counts: oscillator clocks of the core it simulates.  For -t C52
 * that is the classic 8051, 12 clocks a machine cycle and 1 to 4 machine
 * cycles an instruction.  The FX2's core takes 4 clocks a cycle and mostly
 * one cycle per instruction byte (i8051.h), so neither "clocks / 12 × 4"
 * nor "clocks / 3" is its time.  The FX2 figure here is counted instruction
 * by instruction instead: s51's per-address code-fetch counts over the
 * measured window, at each instruction start the listings give, times the
 * FX2's cycles for that opcode.  The same counts times the classic cycles
 * must give back s51's own clock count exactly: that checks the counting.
 * With -t DS320 (Dallas's 4-clock core, which the FX2's follows) s51's
 * clocks / 4 are a second, independent figure. */
#include "speed.h"
#include "fx2sim.h"
#include "i8051.h"
#include "../../proto.h"
#include "../../sim/board.h"
#include "albatros/profile.h"
#include "albatros/stream.h"
#include "albatros/transport.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FX2_MHZ        48.0
#define FX2_CLOCKS     4.0      /* per FX2 instruction cycle */
#define CLASSIC_CLOCKS 12.0     /* per classic machine cycle */
#define STRETCH_RESET  1u       /* CKCON.MD2..0 after reset: MOVX takes 3 cycles */
#define BOARD_PAYLOAD  (PROTO_BULK_MAXPKT - PROTO_HEADER - PROTO_TRAILER)

/* ---- the bridge's traffic, recorded ---- */

typedef enum { EV_BULK, EV_HID_GET, EV_HID_SET } ev_kind;

typedef struct {
    ev_kind kind;
    uint8_t *data;
    size_t len;
} cap_event;

typedef struct {
    alb_transport *inner;
    cap_event *ev;
    size_t n, cap;
    uint8_t *cur;             /* the transfer being filled */
    size_t cur_len, cur_cap;
    bool oom;
} capture;

static int cap_push(capture *c, ev_kind kind, const uint8_t *d, size_t len)
{
    if (c->n == c->cap) {
        size_t cap = c->cap ? c->cap * 2 : 256;
        cap_event *p = realloc(c->ev, cap * sizeof *p);
        if (!p)
            return -1;
        c->ev = p;
        c->cap = cap;
    }
    uint8_t *copy = malloc(len ? len : 1);
    if (!copy)
        return -1;
    memcpy(copy, d, len);
    c->ev[c->n++] = (cap_event){kind, copy, len};
    return 0;
}

static capture *cap_of(alb_transport *t) { return t->impl; }

static alb_tr_status pass_error(alb_transport *t, alb_tr_status st)
{
    if (st != ALB_TR_OK)
        snprintf(t->error, sizeof t->error, "%s", cap_of(t)->inner->error);
    return st;
}

static alb_tr_status rec_write(alb_transport *t, const uint8_t *data, size_t len)
{
    capture *c = cap_of(t);
    if (c->cur_len + len > c->cur_cap) {
        size_t cap = c->cur_cap ? c->cur_cap * 2 : 65536;
        while (cap < c->cur_len + len)
            cap *= 2;
        uint8_t *p = realloc(c->cur, cap);
        if (!p) {
            c->oom = true;
            return ALB_TR_ERROR;
        }
        c->cur = p;
        c->cur_cap = cap;
    }
    memcpy(c->cur + c->cur_len, data, len);
    c->cur_len += len;
    return pass_error(t, c->inner->ops->write(c->inner, data, len));
}

/* The USB transport ends a transfer here (transport.h). */
static alb_tr_status rec_flush(alb_transport *t)
{
    capture *c = cap_of(t);
    if (c->cur_len) {
        if (cap_push(c, EV_BULK, c->cur, c->cur_len))
            c->oom = true;
        c->cur_len = 0;
    }
    return pass_error(t, c->inner->ops->flush(c->inner));
}

static alb_tr_status rec_read(alb_transport *t, uint8_t *buf, size_t cap, size_t *got, unsigned ms)
{
    capture *c = cap_of(t);
    return pass_error(t, c->inner->ops->read(c->inner, buf, cap, got, ms));
}

static alb_tr_status rec_hid_get(alb_transport *t, uint8_t *buf, size_t len)
{
    capture *c = cap_of(t);
    if (cap_push(c, EV_HID_GET, buf, 1))
        c->oom = true;
    return pass_error(t, c->inner->ops->hid_get(c->inner, buf, len));
}

static alb_tr_status rec_hid_set(alb_transport *t, const uint8_t *buf, size_t len)
{
    capture *c = cap_of(t);
    if (cap_push(c, EV_HID_SET, buf, len))
        c->oom = true;
    return pass_error(t, c->inner->ops->hid_set(c->inner, buf, len));
}

static void rec_close(alb_transport *t) { (void)t; }   /* the caller closes the inner one */

static const alb_transport_ops rec_ops = {"recording", rec_write, rec_flush, rec_read,
                                      rec_hid_get, rec_hid_set, rec_close};

static void cap_free(capture *c)
{
    for (size_t i = 0; i < c->n; i++)
        free(c->ev[i].data);
    free(c->ev);
    free(c->cur);
}

static uint32_t *read_stream(const char *path, size_t *n)
{
    FILE *f = fopen(path, "rb");
    if (!f) {
        fprintf(stderr, "fx2_s51: %s: %s\n", path, strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 16, len = 0;
    uint8_t *b = malloc(cap);
    size_t k;
    while (b && (k = fread(b + len, 1, cap - len, f)) > 0) {
        len += k;
        if (len == cap) {
            uint8_t *p = realloc(b, cap * 2);
            if (!p) {
                free(b);
                b = NULL;
                break;
            }
            b = p;
            cap *= 2;
        }
    }
    bool bad = ferror(f) != 0;
    fclose(f);
    if (!b || bad || len % 4 || !len) {
        fprintf(stderr, "fx2_s51: %s: %s\n", path, !b ? "out of memory" : bad ? "read error" :
                !len ? "empty" : "not a whole number of 32-bit words");
        free(b);
        return NULL;
    }
    uint32_t *w = malloc(len);
    if (!w) {
        free(b);
        fprintf(stderr, "fx2_s51: out of memory\n");
        return NULL;
    }
    for (size_t i = 0; i < len / 4; i++)
        w[i] = (uint32_t)b[4 * i] | (uint32_t)b[4 * i + 1] << 8 | (uint32_t)b[4 * i + 2] << 16 |
               (uint32_t)b[4 * i + 3] << 24;
    free(b);
    *n = len / 4;
    return w;
}

/* The bridge sending the stream to the simulated board with the FX2's
 * payload, every transfer recorded. */
static int record_bridge(const uint32_t *w, size_t n, alb_stream_frame *frames, unsigned nf,
                         capture *c)
{
    alb_profile prof;
    char err[512];
    if (alb_profile_lookup("a512", &prof)) {
        fprintf(stderr, "fx2_s51: no profile a512\n");
        return -1;
    }
    alb_transport *inner = sim_board_transport(&prof, BOARD_PAYLOAD, err, sizeof err);
    if (!inner) {
        fprintf(stderr, "fx2_s51: the simulated board: %s\n", err);
        return -1;
    }
    c->inner = inner;
    alb_transport rec = {&rec_ops, c, "", inner->max_payload};
    alb_stream_opts so;
    alb_stream_opts_default(&so);
    so.readback = false;   /* the frames carry no emulator results: no CRC to match */
    alb_stream_report r;
    /* 1 (frames differ) is expected: these frames carry no emulator CRC */
    int rc = alb_stream_run(&rec, w, n, frames, nf, &so, &r);
    inner->ops->close(inner);
    if (c->oom || rc < 0) {
        fprintf(stderr, "fx2_s51: the bridge's stream failed: %s\n",
                c->oom ? "out of memory" : r.first_problem);
        return -1;
    }
    return 0;
}

/* ---- the replay through the image ---- */

/* Turns of the main loop by what they carried. */
enum { T_FULL, T_SHORT, T_ZLP, T_RESULT, T_FRAME, T_KINDS };
static const char *const turn_name[T_KINDS] = {
    "a full USB packet (512 bytes: one 492-byte WORDS packet)",
    "a short USB packet (a frame's last WORDS, the RESET)",
    "a zero-length packet (after each full one)",
    "a RESULT record from the FPGA",
    "a new USB frame count (HID COUNTERS report when due)",
};

typedef struct {
    uint64_t clocks[T_KINDS], turns[T_KINDS];
    uint64_t bytes, packets, transfers, words_bytes;
    uint64_t in_packets, in_errors;
    size_t fpga_bytes;
    /* by part of the stream: [0] the preamble (RESET, the words before the
     * first FRAME), [k + 1] frame k with its RESULT */
    uint64_t *part_bytes, *part_clocks, *part_words;
    unsigned parts;
} tally;

static void take(fx2_t *f, tally *t, int kind, unsigned part)
{
    t->clocks[kind] += f->turn_clocks;
    t->turns[kind]++;
    t->part_clocks[part] += f->turn_clocks;
    for (size_t i = 0; i < f->in.n; i++) {
        t->in_packets++;
        if (f->in.pkt[i].len > 4 && f->in.pkt[i].data[4] == PROTO_T_ERROR)
            t->in_errors++;
    }
    t->fpga_bytes += f->nfpga;
    fx2_clear(f);
}

static int control(fx2_t *f, uint8_t rt, uint8_t req, uint16_t value, uint16_t index,
                   const uint8_t *out, uint16_t len)
{
    uint8_t s[8] = {rt, req, (uint8_t)value, (uint8_t)(value >> 8), (uint8_t)index,
                    (uint8_t)(index >> 8), (uint8_t)len, (uint8_t)(len >> 8)};
    return fx2_control(f, s, out, out ? len : 0);
}

static void put32(uint8_t *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint32_t get32(const uint8_t *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* The recorded traffic through the image; the FPGA answers each frame's
 * last word with its RESULT record, and the USB frame counter moves on by
 * one stream frame's time (1000 / fps ms). */
static int replay(fx2_t *f, const capture *c, const alb_stream_frame *fr, unsigned nf, unsigned fps,
                  tally *t)
{
    size_t words = 0;
    unsigned next = 0, part = 0;
    uint16_t usb_frame = 0;
    for (size_t e = 0; e < c->n; e++) {
        const cap_event *ev = &c->ev[e];
        while (part < nf && words >= fr[part].first_word)
            part++;   /* the frame this transfer's words belong to */
        if (ev->kind == EV_HID_GET) {
            if (control(f, 0xA1, 0x01, (uint16_t)(0x0300 | ev->data[0]), PROTO_IF_HID, NULL,
                        PROTO_HID_REPORT))
                return -1;
            fx2_clear(f);
            continue;
        }
        if (ev->kind == EV_HID_SET) {
            if (control(f, 0x21, 0x09, (uint16_t)(0x0300 | ev->data[0]), PROTO_IF_HID, ev->data,
                        (uint16_t)ev->len))
                return -1;
            fx2_clear(f);
            continue;
        }
        t->transfers++;
        t->bytes += ev->len;
        t->part_bytes[part] += ev->len;
        for (size_t off = 0; off < ev->len || (off == ev->len && ev->len % 512 == 0);) {
            uint16_t k = ev->len - off > 512 ? 512 : (uint16_t)(ev->len - off);
            if (fx2_bulk_out(f, ev->data + off, k))
                return -1;
            t->packets++;
            take(f, t, k == 512 ? T_FULL : k ? T_SHORT : T_ZLP, part);
            off += k;
            if (!k)
                break;
        }
        /* one protocol packet per transfer (the bridge flushes each) */
        if (ev->len >= PROTO_HEADER && ev->data[PROTO_OFF_TYPE] == PROTO_T_WORDS) {
            uint32_t len = get32(ev->data + PROTO_OFF_LEN);
            words += len / 4;
            t->words_bytes += len;
            t->part_words[part] += len;
        }
        while (next < nf && words >= fr[next].end_word) {
            uint8_t rec[PROTO_RESULT_BYTES] = {0};
            put32(rec + PROTO_RESULT_FRAME, fr[next].number);
            if (fx2_record(f, rec, sizeof rec))
                return -1;
            take(f, t, T_RESULT, next + 1);
            usb_frame = (uint16_t)(usb_frame + 1000u / fps);
            if (fx2_frame(f, usb_frame))
                return -1;
            take(f, t, T_FRAME, next + 1);
            next++;
        }
    }
    return 0;
}

/* ---- the counts ---- */

typedef struct {
    uint64_t insns, classic, fx2, fx2_nostretch;
} counts;

typedef struct {
    const char *name;
    uint64_t fx2;
} fn_cost;

static int by_cost(const void *a, const void *b)
{
    const fn_cost *x = a, *y = b;
    return x->fx2 < y->fx2 ? 1 : x->fx2 > y->fx2 ? -1 : strcmp(x->name, y->name);
}

static void count_window(const listing_t *l, const uint64_t *before, const uint64_t *after,
                         counts *k, bool profile)
{
    fn_cost *fn = profile ? calloc(l->nlabels + 1, sizeof *fn) : NULL;
    size_t nfn = 0;
    memset(k, 0, sizeof *k);
    for (unsigned a = 0; a < l->code_end; a++) {
        if (!l->insn[a])
            continue;
        uint64_t runs = after[a] - before[a];
        if (!runs)
            continue;
        i8051_op o = i8051_opcode(l->rom[a]);
        unsigned cyc = i8051_fx2_cycles(l->rom[a], STRETCH_RESET);
        k->insns += runs;
        k->classic += runs * o.classic;
        k->fx2 += runs * cyc;
        k->fx2_nostretch += runs * i8051_fx2_cycles(l->rom[a], 0);
        if (fn) {
            const listing_label *lab = listing_function(l, a);
            const char *name = lab ? lab->name : "?";
            size_t i = 0;
            while (i < nfn && strcmp(fn[i].name, name))
                i++;
            if (i == nfn)
                fn[nfn++].name = name;
            fn[i].fx2 += runs * cyc;
        }
    }
    if (!fn)
        return;
    qsort(fn, nfn, sizeof *fn, by_cost);
    printf("\nwhere the FX2's cycles go (by function, from the listings' labels):\n");
    for (size_t i = 0; i < nfn && i < 14; i++)
        printf("  %5.1f%%  %12llu  %s\n", 100.0 * (double)fn[i].fx2 / (double)k->fx2,
               (unsigned long long)fn[i].fx2, fn[i].name);
    free(fn);
}

static double fx2_seconds(uint64_t cycles) { return (double)cycles * FX2_CLOCKS / (FX2_MHZ * 1e6); }

/* One replay of the recorded traffic through the image on `cpu`; with
 * `stats`, s51's code-fetch counts over it into before/after. */
static int measure(const char *ihx, const listing_t *l, const char *cpu, const char *preload,
                   const capture *c, const alb_stream_frame *fr, unsigned nf, unsigned fps,
                   uint64_t *before, uint64_t *after, tally *t, uint64_t *clocks)
{
    static fx2_t f;
    int rc = -1;
    uint64_t *pb = t->part_bytes, *pc = t->part_clocks, *pw = t->part_words;
    memset(t, 0, sizeof *t);
    memset(pb, 0, (nf + 1) * sizeof *pb);
    memset(pc, 0, (nf + 1) * sizeof *pc);
    memset(pw, 0, (nf + 1) * sizeof *pw);
    t->part_bytes = pb;
    t->part_clocks = pc;
    t->part_words = pw;
    t->parts = nf + 1;
    if (fx2_open(&f, cpu, ihx, l, preload) || control(&f, 0x00, 0x09, 1, 0, NULL, 0))
        goto out;
    fx2_clear(&f);
    uint64_t c0 = f.clocks;
    if ((before && s51_rom_reads(&f.s, 0, l->code_end - 1, before)) ||
        replay(&f, c, fr, nf, fps, t) ||
        (after && s51_rom_reads(&f.s, 0, l->code_end - 1, after)))
        goto out;
    *clocks = f.clocks - c0;
    rc = 0;
out:
    if (rc)
        fprintf(stderr, "fx2_s51: s51 -t %s: %s%s\n", cpu, f.error, f.error[0] ? "" : f.s.error);
    fx2_close(&f);
    return rc;
}

static void report(const tally *t, const tally *td, const counts *k, uint64_t clocks,
                   uint64_t dallas, unsigned nf, unsigned fps)
{
    printf("bridge traffic: %llu bytes in %llu transfers, %llu USB packets (%llu of them "
           "zero-length); %llu bytes of words\n", (unsigned long long)t->bytes,
           (unsigned long long)t->transfers, (unsigned long long)t->packets,
           (unsigned long long)t->turns[T_ZLP], (unsigned long long)t->words_bytes);
    printf("the image answered with %llu packets (%llu ERRORs) and passed %zu bytes to the FPGA\n",
           (unsigned long long)t->in_packets, (unsigned long long)t->in_errors, t->fpga_bytes);
    printf("\nthe cycles, from the first bulk packet to the last:\n");
    printf("  s51 -t C52 (the classic 8051, 12 clocks a machine cycle): %llu clocks, %llu "
           "machine cycles\n", (unsigned long long)clocks, (unsigned long long)clocks / 12);
    printf("    %llu instructions ran (s51's code-fetch counts at the listings' instruction "
           "starts);\n    their classic cycles add up to %llu: %s\n", (unsigned long long)k->insns,
           (unsigned long long)k->classic,
           k->classic * 12 == clocks ? "s51's count, exactly" : "NOT s51's count");
    printf("  the same instructions at the FX2's timing (EZ-USB TRM; MOVX stretch 1, the reset "
           "value):\n    %llu cycles of 4 clocks (with stretch 0: %llu)\n",
           (unsigned long long)k->fx2, (unsigned long long)k->fx2_nostretch);
    printf("  s51 -t DS320 (Dallas's 4-clock core): %llu clocks, %.0f cycles (%+.3f%% of the "
           "above)\n", (unsigned long long)dallas, (double)dallas / FX2_CLOCKS,
           100.0 * ((double)dallas / FX2_CLOCKS - (double)k->fx2) / (double)k->fx2);
    double sec = fx2_seconds(k->fx2), naive = fx2_seconds(k->classic);
    double raw = (double)clocks / (FX2_MHZ * 1e6);
    double rate = (double)t->bytes / sec;
    printf("\nat 48 MHz: %.4f s for the stream\n", sec);
    printf("  (not s51's clocks as FX2 clocks: %.4f s; nor its machine cycles as FX2 cycles: "
           "%.4f s)\n", raw, naive);
    printf("parse rate: %.0f bytes/s of bridge traffic (%.0f bytes/s of words)\n", rate,
           (double)t->words_bytes / sec);
    /* frames after the preamble: the steady stream */
    uint64_t fbytes = 0, fclocks = 0, worst = 0;
    printf("\n  part of the stream  words bytes  bridge bytes  FX2 ms (-t DS320)\n");
    for (unsigned i = 0; i < t->parts; i++) {
        char name[32];
        if (i == 0)
            snprintf(name, sizeof name, "preamble");
        else
            snprintf(name, sizeof name, "frame %u", i - 1);
        printf("  %-18s %11llu %13llu %10.2f\n", name, (unsigned long long)t->part_words[i],
               (unsigned long long)t->part_bytes[i],
               (double)td->part_clocks[i] / (FX2_MHZ * 1e6) * 1000.0);
        if (i) {
            fbytes += t->part_bytes[i];
            fclocks += td->part_clocks[i];
            if (td->part_clocks[i] > worst)
                worst = td->part_clocks[i];
        }
    }
    double per_frame = (double)fbytes / nf, frame_ms = (double)fclocks / nf / (FX2_MHZ * 1e3);
    double need = per_frame * fps, frate = (double)fbytes / ((double)fclocks / (FX2_MHZ * 1e6));
    printf("\na %u Hz stream of these frames: %.0f bytes/s (%.0f bytes a frame); the firmware parses "
           "%.0f bytes/s of it:\n  it %s, %.2fx %s\n", fps, need, per_frame, frate,
           frate >= need ? "keeps up" : "does NOT keep up", frate >= need ? frate / need :
           need / frate, frate >= need ? "to spare" : "too slow");
    printf("  a frame takes %.2f ms (the slowest %.2f ms) of the %.2f ms it has: %.1f frames/s\n",
           frame_ms, (double)worst / (FX2_MHZ * 1e3), 1000.0 / fps, 1000.0 / frame_ms);
    printf("\none turn of the main loop, on average (cycles: classic from -t C52, FX2 from -t "
           "DS320):\n");
    for (int i = 0; i < T_KINDS; i++)
        if (t->turns[i])
            printf("  %8.0f %8.0f  x %-4llu %s\n",
                   (double)t->clocks[i] / (double)t->turns[i] / CLASSIC_CLOCKS,
                   (double)td->clocks[i] / (double)td->turns[i] / FX2_CLOCKS,
                   (unsigned long long)t->turns[i], turn_name[i]);
    printf("summary: bytes %llu frames %u fx2_cycles %llu dallas_cycles %.0f seconds %.4f "
           "rate %.0f frame_bytes %.0f frame_ms %.2f need %.0f ratio %.2f\n",
           (unsigned long long)t->bytes, nf, (unsigned long long)k->fx2,
           (double)dallas / FX2_CLOCKS, sec, rate, per_frame, frame_ms, need, need / frate);
}

/* s51's statistics under -t DS320 count every code byte twice, so the
 * per-instruction figures come from the -t C52 run, and the DS320 run
 * gives only its clock count. */
int speed_run(const char *ihx, const listing_t *l, const char *stream_path, const char *preload,
              const speed_opts *o)
{
    size_t n = 0;
    uint32_t *w = read_stream(stream_path, &n);
    if (!w)
        return 1;
    alb_stream_frame *fr = NULL;
    unsigned nf = 0;
    if (alb_stream_frames(w, n, &fr, &nf) || !nf) {
        fprintf(stderr, "fx2_s51: %s: %s\n", stream_path,
                nf ? "a malformed word stream" : "no frames in the stream");
        free(w);
        free(fr);
        return 1;
    }
    capture c = {0};
    uint64_t *before = calloc(l->code_end, sizeof *before), *after = calloc(l->code_end, sizeof *after);
    int rc = 1;
    static tally t, td;
    uint64_t clocks = 0, dallas = 0;
    t.part_bytes = calloc(nf + 1, sizeof(uint64_t));
    t.part_clocks = calloc(nf + 1, sizeof(uint64_t));
    t.part_words = calloc(nf + 1, sizeof(uint64_t));
    td.part_bytes = calloc(nf + 1, sizeof(uint64_t));
    td.part_clocks = calloc(nf + 1, sizeof(uint64_t));
    td.part_words = calloc(nf + 1, sizeof(uint64_t));
    if (!before || !after || !t.part_bytes || !t.part_clocks || !t.part_words || !td.part_bytes ||
        !td.part_clocks || !td.part_words) {
        fprintf(stderr, "fx2_s51: out of memory\n");
        goto out;
    }
    if (record_bridge(w, n, fr, nf, &c))
        goto out;
    printf("fx2 speed: %s; %s: %zu words, %u frames, sent as the bridge sends them, at %u Hz\n",
           ihx, stream_path, n, nf, o->fps);
    if (measure(ihx, l, "C52", preload, &c, fr, nf, o->fps, before, after, &t, &clocks) ||
        measure(ihx, l, "DS320", preload, &c, fr, nf, o->fps, NULL, NULL, &td, &dallas))
        goto out;
    counts k;
    count_window(l, before, after, &k, false);
    report(&t, &td, &k, clocks, dallas, nf, o->fps);
    if (o->profile)
        count_window(l, before, after, &k, true);
    rc = t.in_errors || td.in_errors || k.classic * 12 != clocks ? 1 : 0;
    if (t.in_errors || td.in_errors)
        fprintf(stderr, "fx2_s51: the image sent ERROR packets: the replay is not clean\n");
out:
    free(t.part_bytes);
    free(t.part_clocks);
    free(t.part_words);
    free(td.part_bytes);
    free(td.part_clocks);
    free(td.part_words);
    cap_free(&c);
    free(before);
    free(after);
    free(fr);
    free(w);
    return rc;
}
