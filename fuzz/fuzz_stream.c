/* fuzz_stream.c — the GP -> VP word stream (docs/word-format.md): the
 * validating decoder (common/words.c) with the field description of every
 * word it accepts, then the VP on the same words at each fidelity the CLI's
 * `albatros vp` offers: functional (vp_run_stream), timed and cycle.  The
 * input is the stream file's bytes: little-endian words, a trailing partial
 * word dropped. */
#include "fuzz.h"
#include "../common/words.h"
#include "../emu/sim.h"
#include "../vp/vp.h"

#include <stdlib.h>
#include <string.h>

/* Packets decoded before the first error (or END). */
static unsigned decode_all(const uint32_t *w, size_t n)
{
    ws_reader r;
    ws_event *ev = malloc(sizeof *ev);
    diag_t d;
    char desc[160];
    diag_init(&d, NULL);
    unsigned packets = 0;
    if (!ev)
        return 0;
    ws_reader_init(&r, w, n, "fuzz.stream");
    while (!r.ended && ws_next(&r, ev, &d) == ALB_OK) {
        packets++;
        for (size_t k = 0; k < ev->count; k++)
            ws_describe_word(ev, &r.config, k, desc, sizeof desc);
    }
    free(ev);
    return packets;
}

/* Profile t32 (32x32: fast), with the number formats of the stream's CONFIG
 * when it has a valid one, as a user would `--set` them: otherwise every
 * stream written for another profile stops at CONFIG. */
static void stream_profile(const uint32_t *w, size_t n, profile_t *p)
{
    if (profile_lookup("t32", p))
        abort();
    if (n < 2 || w[0] >> 24 != WS_OP_CONFIG)
        return;
    profile_t q = *p;
    char msg[256];
    q.edge_frac_bits = w[1] & 0xFF;
    q.coef_bits = w[1] >> 8 & 0xFF;
    if (profile_check(&q, msg, sizeof msg) == 0)
        *p = q;
}

/* Read every plane of a finished frame, so that the sanitizers see any
 * pixel the VP left outside its buffers. */
static unsigned frame_sum(const frame_t *f)
{
    unsigned sum = 0;
    for (size_t i = 0; i < (size_t)f->width * f->height; i++) {
        sum += f->rgb[3 * i] + f->rgb[3 * i + 1] + f->rgb[3 * i + 2] + f->depth[i] + f->face[i] +
               f->level[i] + f->coverage[i];
        if (f->cycles)
            sum += f->cycles[i];
    }
    return sum;
}

static int vp_sink(void *ctx, const frame_t *f, const vp_stats *st)
{
    *(unsigned *)ctx += frame_sum(f) + (unsigned)st->faces;
    return 0;
}

static int sim_sink_fn(void *ctx, const frame_t *f, const vp_stats *vs, const sim_counters *sc)
{
    *(unsigned *)ctx += frame_sum(f) + (unsigned)vs->faces + (unsigned)(sc ? sc->cycles : 0);
    return 0;
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
    size_t n = size / 4;
    uint32_t *w = malloc(n ? n * sizeof *w : 1);
    if (!w)
        return 0;
    for (size_t i = 0; i < n; i++)
        w[i] = (uint32_t)data[4 * i] | (uint32_t)data[4 * i + 1] << 8 |
               (uint32_t)data[4 * i + 2] << 16 | (uint32_t)data[4 * i + 3] << 24;
    unsigned packets = decode_all(w, n);

    profile_t prof;
    stream_profile(w, n, &prof);
    diag_t d;
    diag_init(&d, NULL);
    unsigned sum = 0;
    vp_t *vp = NULL;
    if (vp_create(&vp, &prof, &d) == ALB_OK)
        vp_run_stream(vp, w, n, "fuzz.stream", vp_sink, &sum, &d);
    vp_destroy(vp);
    /* A stream that fails in or before CONFIG fails there at every fidelity;
     * the clocked models (each with a VP of its own to set up) are for the
     * rest. */
    for (int fid = FIDELITY_TIMED; packets >= 1 && fid <= FIDELITY_CYCLE; fid++) {
        sim_options opt = {.fid = (fidelity)fid, .vcd_to = UINT64_MAX, .threads = 1};
        diag_init(&d, NULL);
        sim_run(&prof, w, n, "fuzz.stream", &opt, sim_sink_fn, &sum, &d);
    }
    free(w);
    volatile unsigned keep = sum;   /* keeps the reads of frame_sum */
    (void)keep;
    return 0;
}
