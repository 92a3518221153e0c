/* fuzz_stream.c — the GP -> VP word stream (docs/word-format.md): the
 * validating decoder (common/words.c) with the field description of every
 * word it accepts, then the VP on the same words at each fidelity the CLI's
 * `albatros vp` offers: functional (alb_vp_run_stream), timed and cycle.  The
 * input is the stream file's bytes: little-endian words, a trailing partial
 * word dropped. */
#include "fuzz.h"
#include "albatros/words.h"
#include "albatros/sim.h"
#include "albatros/vp.h"

#include <stdlib.h>
#include <string.h>

/* Packets decoded before the first error (or END). */
static unsigned decode_all(const uint32_t *w, size_t n)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    char desc[160];
    alb_diag_init(&d, NULL);
    unsigned packets = 0;
    if (!ev)
        return 0;
    alb_ws_reader_init(&r, w, n, "fuzz.stream");
    while (!r.ended && alb_ws_next(&r, ev, &d) == ALB_OK) {
        packets++;
        for (size_t k = 0; k < ev->count; k++)
            alb_ws_describe_word(ev, &r.config, k, desc, sizeof desc);
    }
    free(ev);
    return packets;
}

/* Profile t32 (32x32: fast), with the number formats of the stream's CONFIG
 * when it has a valid one, as a user would `--set` them: otherwise every
 * stream written for another profile stops at CONFIG. */
static void stream_profile(const uint32_t *w, size_t n, alb_profile *p)
{
    if (alb_profile_lookup("t32", p))
        abort();
    if (n < 2 || w[0] >> 24 != ALB_WS_OP_CONFIG)
        return;
    alb_profile q = *p;
    char msg[256];
    q.edge_frac_bits = w[1] & 0xFF;
    q.coef_bits = w[1] >> 8 & 0xFF;
    if (alb_profile_check(&q, msg, sizeof msg) == 0)
        *p = q;
}

/* Read every plane of a finished frame, so that the sanitizers see any
 * pixel the VP left outside its buffers. */
static unsigned frame_sum(const alb_frame *f)
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

static int vp_sink(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    *(unsigned *)ctx += frame_sum(f) + (unsigned)st->faces;
    return 0;
}

static int sim_sink_fn(void *ctx, const alb_frame *f, const alb_vp_stats *vs, const alb_sim_counters *sc)
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

    alb_profile prof;
    stream_profile(w, n, &prof);
    alb_diag d;
    alb_diag_init(&d, NULL);
    unsigned sum = 0;
    alb_vp *vp = NULL;
    if (alb_vp_create(&vp, &prof, &d) == ALB_OK)
        alb_vp_run_stream(vp, w, n, "fuzz.stream", vp_sink, &sum, &d);
    alb_vp_destroy(vp);
    /* A stream that fails in or before CONFIG fails there at every fidelity;
     * the clocked models (each with a VP of its own to set up) are for the
     * rest. */
    for (int fid = ALB_FIDELITY_TIMED; packets >= 1 && fid <= ALB_FIDELITY_CYCLE; fid++) {
        alb_sim_options opt = {.fid = (alb_fidelity)fid, .vcd_to = UINT64_MAX, .threads = 1};
        alb_diag_init(&d, NULL);
        alb_sim_run(&prof, w, n, "fuzz.stream", &opt, sim_sink_fn, &sum, &d);
    }
    free(w);
    volatile unsigned keep = sum;   /* keeps the reads of frame_sum */
    (void)keep;
    return 0;
}
