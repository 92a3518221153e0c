/* cmd_render.c — `albatros render`: scene -> GP -> word stream -> VP ->
 * frames (OpenEXR, PNG views); `albatros vp`: the VP alone on a stream file,
 * as an RTL test bench replays it; `albatros reference`.  They share the
 * frame sinks below.  The functional fidelity takes the GP's frames one at
 * a time, so its memory does not grow with the frames; the timed and cycle
 * models take the whole stream (docs/limits.md, "Memory"). */
#include "cli.h"
#include "commands.h"
#include "albatros/exr.h"
#include "albatros/file.h"
#include "albatros/json.h"
#include "albatros/preview.h"
#include "albatros/sim.h"
#include "albatros/vcd.h"
#include "../tools/ref.h"
#include "albatros/vp.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

typedef struct {
    cli_frames out;           /* -o, --png, --view */
    const char *stream;
    bool json, quiet, help;
    alb_fidelity fid;
    unsigned threads;         /* 0: one per core */
    const char *vcd;
    bool vcd_window;          /* --vcd-window given */
    uint64_t vcd_from, vcd_to;
    bool vcd_units_given;     /* --vcd-units given */
    unsigned vcd_units;       /* mask of alb_sim_trace_units_parse */
    const char *events;       /* --events FILE: the cycle model's event log */
    bool events_only_given;
    uint32_t events_only;     /* --events-only KINDS */
    alb_profile prof;
    /* how the input's near is changed, for the depth warnings: "'near' in
     * SCENE or --near", "--near" (OBJ), ... (docs/vp.md §4) */
    char near_fix[300];
    /* run state */
    unsigned nframes, done;
    const char *cmd;
    bool progress;
    alb_json j;               /* --json on stdout */
    char software[32];        /* "albatros X.Y.Z", for the EXR header */
} render_args;

/* --vcd-units LIST; an unknown name is reported with the valid ones. */
static int parse_vcd_units(render_args *a, const char *value)
{
    const char *bad;
    size_t badlen;
    if (!alb_sim_trace_units_parse(value, &a->vcd_units, &bad, &badlen)) {
        a->vcd_units_given = true;
        return 0;
    }
    if (badlen)
        fprintf(stderr, "albatros %s: --vcd-units %s: unknown unit '%.*s'; units are all", a->cmd,
                value, (int)badlen, bad);
    else
        fprintf(stderr, "albatros %s: --vcd-units %s: empty unit name; units are all", a->cmd,
                value);
    for (unsigned i = 0; alb_sim_trace_unit_name(i); i++)
        fprintf(stderr, ", %s", alb_sim_trace_unit_name(i));
    fputc('\n', stderr);
    return -1;
}

/* A cycle number of --vcd-window: decimal digits, at most 2^64 - 1 (a
 * longer number is refused, not wrapped or saturated).  The end of it in *end. */
static bool parse_cycle(const char *s, const char **end, uint64_t *v)
{
    const char *p = s;
    *v = 0;
    for (; *p >= '0' && *p <= '9'; p++) {
        unsigned dgt = (unsigned)(*p - '0');
        if (*v > (UINT64_MAX - dgt) / 10)
            return false;
        *v = *v * 10 + dgt;
    }
    *end = p;
    return p != s;
}

static int parse_vcd_window(render_args *a, const char *value)
{
    const char *p;
    uint64_t from, to;
    if (!parse_cycle(value, &p, &from) || *p != ':' || !parse_cycle(p + 1, &p, &to) || *p ||
        from > to) {
        fprintf(stderr, "albatros %s: --vcd-window %s: expected FROM:TO cycles, decimal, "
                        "FROM <= TO <= %llu\n", a->cmd, value, (unsigned long long)UINT64_MAX);
        return -1;
    }
    a->vcd_window = true;
    a->vcd_from = from;
    a->vcd_to = to;
    return 0;
}

static int render_opt(void *ctx, const char *name, const char *value)
{
    render_args *a = ctx;
    int took = cli_frames_option(&a->out, a->cmd, name, value);
    if (took)
        return took < 0 ? -1 : 0;
    if (strcmp(name, "stream") == 0)
        a->stream = value;
    else if (strcmp(name, "fidelity") == 0) {
        if (alb_fidelity_parse(value, &a->fid)) {
            fprintf(stderr, "albatros %s: --fidelity %s: expected functional, timed or cycle\n",
                    a->cmd, value);
            return -1;
        }
    } else if (strcmp(name, "threads") == 0) {
        char *end;
        unsigned long v = strtoul(value, &end, 10);
        if (end == value || *end || value[0] == '-' || v > ALB_VP_MAX_THREADS) {
            fprintf(stderr, "albatros %s: --threads %s: expected 0 (one per core) to %d\n",
                    a->cmd, value, ALB_VP_MAX_THREADS);
            return -1;
        }
        a->threads = (unsigned)v;
    } else if (strcmp(name, "vcd") == 0) {
        a->vcd = value;
    } else if (strcmp(name, "vcd-window") == 0) {
        if (parse_vcd_window(a, value))
            return -1;
    } else if (strcmp(name, "vcd-units") == 0) {
        if (parse_vcd_units(a, value))
            return -1;
    } else if (strcmp(name, "events") == 0) {
        a->events = value;
    } else if (strcmp(name, "events-only") == 0) {
        const char *bad;
        size_t badlen;
        if (alb_sim_events_parse(value, &a->events_only, &bad, &badlen)) {
            fprintf(stderr, "albatros %s: --events-only %s: unknown kind '%.*s'; kinds are all",
                    a->cmd, value, (int)badlen, bad);
            for (unsigned i = 0; i < 32; i++)
                if (alb_sim_event_name(1u << i))
                    fprintf(stderr, ", %s", alb_sim_event_name(1u << i));
            fputc('\n', stderr);
            return -1;
        }
        a->events_only_given = true;
    } else if (strcmp(name, "json") == 0)
        a->json = true;
    else if (strcmp(name, "quiet") == 0 || strcmp(name, "q") == 0)
        a->quiet = true;
    else if (strcmp(name, "help") == 0)
        a->help = true;
    return 0;
}

static void stats_json(alb_json *j, const alb_frame *fr, const alb_vp_stats *st, unsigned levels,
                       const alb_sim_counters *sc, const alb_profile *p)
{
    alb_json_begin_object(j);
    alb_json_kv_uint(j, "frame", fr->number);
    alb_json_kv_uint(j, "faces", st->faces);
    alb_json_kv_uint(j, "edges", st->edges);
    alb_json_key(j, "cells_per_level");
    alb_json_begin_array(j);
    for (unsigned l = 0; l <= levels; l++)
        alb_json_uint(j, st->cells[l]);
    alb_json_end_array(j);
    alb_json_kv_uint(j, "cells_inside", st->cells_inside);
    alb_json_kv_uint(j, "cells_outside", st->cells_outside);
    alb_json_kv_uint(j, "cells_split", st->cells_split);
    alb_json_kv_uint(j, "samples_tested", st->samples_tested);
    alb_json_kv_uint(j, "samples_covered", st->samples_covered);
    alb_json_kv_uint(j, "samples_written", st->samples_written);
    alb_json_kv_uint(j, "depth_saturated", st->depth_saturated);
    alb_json_kv_uint(j, "depth_underflow", st->depth_underflow);
    alb_json_kv_uint(j, "depth_ties", st->depth_ties);
    alb_json_kv_uint(j, "faces_shaded", st->faces_shaded);
    alb_json_kv_uint(j, "faces_textured", st->faces_textured);
    alb_json_kv_uint(j, "faces_fogged", st->faces_fogged);
    if (sc) {
        alb_json_key(j, "timing");
        alb_sim_counters_json(j, sc, p);
    }
    alb_json_end_object(j);
}

static uint64_t total_cells(const alb_vp_stats *st)
{
    uint64_t n = 0;
    for (unsigned l = 0; l < ALB_VP_MAX_LEVELS; l++)
        n += st->cells[l];
    return n;
}

/* "1 4 16 52": cells visited at levels 0 .. levels (as cells_per_level). */
static void cells_per_level_text(FILE *f, const alb_vp_stats *st, unsigned levels)
{
    for (unsigned l = 0; l <= levels && l < ALB_VP_MAX_LEVELS; l++)
        fprintf(f, "%s%llu", l ? " " : "", (unsigned long long)st->cells[l]);
}

typedef struct {
    render_args *a;
    unsigned levels;
} sink_ctx;

/* A distance for a message: 3 significant digits. */
static void distance_text(char *out, size_t len, double z) { snprintf(out, len, "%.3g", z); }

/* The largest "round" near (one significant digit, rounded down) that keeps
 * the frame's nearest surface, at distance z, below the saturation of the
 * depth store. */
static double round_down(double z)
{
    double p = 1;
    while (p * 10 <= z)
        p *= 10;
    while (p > z)
        p /= 10;
    return floor(z / p) * p;
}

/* Depth precision the frame needed beyond the profile's (docs/vp.md §4),
 * with the fix that fits the input (a->near_fix).  A depth tie between
 * faces is warned about when there are more tied samples than one screen
 * side of samples: faces that cross each other tie along their crossing, a
 * strip about one sample wide; more than that many is faces overlapping in
 * one depth step over an area, where the face drawn first wins, nearer or
 * not. */
static void width_warnings(const render_args *a, const alb_frame *f, const alb_vp_stats *st)
{
    unsigned aa = f->aa_levels, sw = f->width << aa, sh = f->height << aa;
    double full = ldexp(1, (int)f->depth_bits), near = f->near;
    /* the nearest surface: the largest depth in the frame (a run that draws
     * no frame has no planes, but this statistic) */
    uint64_t dmax = st->depth_nearest;
    char znear[32];
    distance_text(znear, sizeof znear, dmax ? near * full / dmax : 0);
    if (st->depth_saturated)
        fprintf(stderr, "albatros: warning: frame %u: %llu samples are nearer than near=%g: the "
                        "depth store saturates and they tie (first face wins); lower near "
                        "(%s)\n", f->number, (unsigned long long)st->depth_saturated, near,
                a->near_fix);
    if (st->depth_underflow)
        fprintf(stderr, "albatros: warning: frame %u: %llu samples are farther than near x "
                        "2^depth_bits = %g and are not drawn; raise depth_bits (--set "
                        "depth_bits=%u) or near (%s)%s%s%s\n",
                f->number, (unsigned long long)st->depth_underflow, near * full,
                f->depth_bits < 32 ? 32 : f->depth_bits, a->near_fix,
                dmax ? ": the nearest surface of the frame is at Z = " : "", dmax ? znear : "",
                dmax && dmax < full - 1 ? ", as far as near may go" : "");
    if (st->depth_ties > (sw > sh ? sw : sh)) {
        uint64_t c = st->tie_sample % sw, r = st->tie_sample / sw;
        double z = near * full / (double)st->tie_depth, step = z / (double)st->tie_depth;
        char zt[32], dz[32], dz32[32];
        distance_text(zt, sizeof zt, z);
        distance_text(dz, sizeof dz, step);
        distance_text(dz32, sizeof dz32, step * ldexp(1, (int)f->depth_bits - 32));
        fprintf(stderr, "albatros: warning: frame %u: %llu samples where two faces fell into one "
                        "depth step, so the face drawn first kept them, nearer or not: e.g. "
                        "faces %llu (kept) and %llu at pixel (%llu, %llu), depth %llu of 2^%u, "
                        "Z = %s, "
                        "where one step is %s in Z; raise depth_bits (--set depth_bits=32: "
                        "a step of %s there) or near (%s)",
                f->number, (unsigned long long)st->depth_ties, (unsigned long long)st->tie_kept,
                (unsigned long long)st->tie_lost, (unsigned long long)(c >> aa),
                (unsigned long long)(r >> aa), (unsigned long long)st->tie_depth, f->depth_bits,
                zt, dz, dz32, a->near_fix);
        if (dmax && dmax < full - 1) {
            char zn[32];
            distance_text(zn, sizeof zn, round_down(0.9 * near * full / dmax));
            fprintf(stderr, ": the nearest surface is at Z = %s, so near up to %s keeps it", znear,
                    zn);
        }
        fputc('\n', stderr);
    }
}

static int write_outputs(void *ctx, const alb_frame *f, const alb_vp_stats *st, const alb_sim_counters *sc)
{
    sink_ctx *s = ctx;
    render_args *a = s->a;
    if (st)
        width_warnings(a, f, st);
    if (cli_frames_write(&a->out, f, a->nframes))
        return -1;
    if (a->json) {
        if (st)
            stats_json(&a->j, f, st, s->levels, sc, &a->prof);
        else {
            alb_json_begin_object(&a->j);
            alb_json_kv_uint(&a->j, "frame", f->number);
            alb_json_end_object(&a->j);
        }
    } else if (!a->quiet && !st) {
        fprintf(stderr, "%sreference frame %u\n", a->progress ? "\r" : "", f->number);
    } else if (!a->quiet) {
        /* the units the frame ran: the fill loops skip the others (docs/vp.md §8) */
        fprintf(stderr, "%sframe %u: %llu faces (%llu shaded, %llu textured, %llu fogged), "
                        "%llu cells visited (by level: ",
                a->progress ? "\r" : "", f->number, (unsigned long long)st->faces,
                (unsigned long long)st->faces_shaded, (unsigned long long)st->faces_textured,
                (unsigned long long)st->faces_fogged, (unsigned long long)total_cells(st));
        cells_per_level_text(stderr, st, s->levels);
        fprintf(stderr, "), %llu samples written\n", (unsigned long long)st->samples_written);
        if (sc)
            alb_sim_counters_text(stderr, sc, &a->prof);
    }
    a->done++;
    return 0;
}

static int vp_sink(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    return write_outputs(ctx, f, st, NULL);
}

/* The frame numbers of a stream, by a quick pass of the decoder (none if
 * malformed: the real pass will report it); NULL if out of memory. */
static uint32_t *frame_numbers(const uint32_t *w, size_t n, unsigned *count)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    unsigned frames = 0, cap = 16;
    uint32_t *num = malloc(cap * sizeof *num);
    alb_ws_reader_init(&r, w, n, "");
    while (ev && num && !r.ended && alb_ws_next(&r, ev, &d) == ALB_OK) {
        if (ev->kind != ALB_WS_EV_FRAME)
            continue;
        if (frames == cap) {
            uint32_t *nn = cap < UINT_MAX / 2 ? realloc(num, 2 * cap * sizeof *nn) : NULL;
            if (!nn) {
                free(num);
                num = NULL;
                break;
            }
            num = nn;
            cap *= 2;
        }
        num[frames++] = ev->u.frame.number;
    }
    free(ev);
    *count = frames;
    return num;
}

/* --events: each batch of the cycle model's events as text lines; the
 * first failed write's errno kept for the message. */
typedef struct {
    FILE *f;
    int err;
} events_ctx;

static int write_events(void *ctx, const alb_event *ev, size_t n)
{
    events_ctx *c = ctx;
    char line[160];
    for (size_t i = 0; i < n; i++) {
        int len = alb_sim_event_format(&ev[i], line, sizeof line);
        errno = 0;
        if (len < 0 || fwrite(line, 1, (size_t)len, c->f) != (size_t)len) {
            c->err = errno ? errno : EIO;
            return -1;
        }
    }
    return 0;
}

static void json_head(render_args *a, const alb_profile *prof, bool fidelity)
{
    if (!a->json)
        return;
    alb_json_init(&a->j, stdout);
    alb_json_begin_object(&a->j);
    alb_json_kv_string(&a->j, "profile", prof->name);
    if (fidelity)
        alb_json_kv_string(&a->j, "fidelity", alb_fidelity_name(a->fid));
    alb_json_key(&a->j, "frames");
    alb_json_begin_lines(&a->j);
}

static void json_tail(render_args *a)
{
    if (!a->json)
        return;
    alb_json_end_array(&a->j);
    alb_json_end_object(&a->j);
    alb_json_end_line(&a->j);
}

/* The EXR's provenance: program, profile, fidelity, source (its file name,
 * without the folder: the same input gives the same bytes wherever it is). */
static void set_provenance(render_args *a, const char *profile, const char *fidelity,
                           const char *source)
{
    snprintf(a->software, sizeof a->software, "albatros %s", ALBATROS_VERSION);
    const char *slash = source ? strrchr(source, '/') : NULL;
    a->out.exr_opt = (alb_exr_options){a->threads ? a->threads : alb_vp_cores(), a->software,
                                       profile, fidelity, slash ? slash + 1 : source};
}

/* The VP on a whole stream at the chosen fidelity, frames to the sinks. */
static int run_vp(render_args *a, const alb_profile *prof, const uint32_t *w, size_t n,
                  const char *name)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_sim_options opt = {.fid = a->fid, .vcd_from = a->vcd_from,
                       .vcd_to = a->vcd_window ? a->vcd_to : UINT64_MAX,
                       .threads = a->threads ? a->threads : alb_vp_cores(),
                       /* nothing to draw: the clocked models time without
                        * pixels (the statistics and counters are the same) */
                       .counters_only = !cli_frames_any(&a->out)};
    a->prof = *prof;
    unsigned nnum;
    uint32_t *numbers = frame_numbers(w, n, &nnum);
    if (!numbers) {
        fprintf(stderr, "albatros %s: out of memory\n", a->cmd);
        return 1;
    }
    a->nframes = nnum;
    int claimed = cli_frames_claim(&a->out, a->cmd, numbers, nnum);
    free(numbers);
    if (claimed)
        return claimed;
    if (a->vcd) {
        if (!(opt.vcd = alb_vcd_open(a->vcd, &d))) {
            alb_diag_print(&d, stderr);
            return 1;
        }
        /* --vcd-units: the writer keeps those units' scopes, the model
         * records only what the writer keeps */
        for (unsigned i = 0; a->vcd_units_given && a->vcd_units != ALB_SIM_TRACE_ALL &&
                             alb_sim_trace_unit_name(i); i++)
            if (a->vcd_units >> i & 1 && alb_vcd_keep_scope(opt.vcd, alb_sim_trace_unit_name(i))) {
                fprintf(stderr, "albatros %s: --vcd-units: too many units\n", a->cmd);
                alb_vcd_abort(opt.vcd);
                return 2;
            }
    }
    alb_out events_out;
    FILE *events = NULL;
    events_ctx ec = {NULL, 0};
    if (a->events) {
        alb_diag ed;
        alb_diag_init(&ed, NULL);
        if (alb_out_open(&events_out, a->events, ALB_OUT_DASH, &ed) ||
            !(events = alb_out_stdio(&events_out, &ed))) {
            alb_diag_print(&ed, stderr);
            if (opt.vcd)
                alb_vcd_abort(opt.vcd);
            return 1;
        }
        opt.events = a->events_only_given ? a->events_only : ALB_EV_ALL;
        opt.on_events = write_events;
        ec.f = events;
        opt.events_ctx = &ec;
    }
    sink_ctx s = {a, alb_profile_levels(prof)};
    json_head(a, prof, true);
    alb_err e = alb_sim_run(prof, w, n, name, &opt, write_outputs, &s, &d);
    json_tail(a);
    int vcd_err = opt.vcd ? alb_vcd_close(opt.vcd) : 0;
    if (vcd_err) {
        fprintf(stderr, "albatros %s: %s: write error: %s (the trace was not written)\n", a->cmd,
                a->vcd, strerror(vcd_err));
        e = e ? e : ALB_ERR_IO;
    }
    if (events) {
        alb_diag ed;
        alb_diag_init(&ed, NULL);
        /* a failed write (write_events) or flush: the old file, if any, stays */
        if (ec.err) {
            alb_out_abort(&events_out);
            fprintf(stderr, "albatros %s: %s: write error: %s\n", a->cmd,
                    strcmp(a->events, "-") ? a->events : "stdout", strerror(ec.err));
            e = e ? e : ALB_ERR_IO;
        } else if (alb_out_commit(&events_out, &ed)) {
            alb_diag_print(&ed, stderr);
            e = e ? e : ALB_ERR_IO;
        }
    }
    if (e && (e != ALB_ERR_IO || d.msg[0]))
        alb_diag_print(&d, stderr);
    struct rusage ru;
    if (!e && !a->quiet && !getrusage(RUSAGE_SELF, &ru))
        /* not in --json: it differs between runs, the JSON must not */
        fprintf(stderr, "%u frames, peak memory %.1f MB resident\n", a->done,
                (double)ru.ru_maxrss / 1024);
    return e == ALB_ERR_INTERRUPTED ? 130 : e ? 1 : 0;
}

static const char render_help[] =
    "usage: albatros render [SCENE] [-o FRAME.exr] [--png FRAME.png] [--view NAME:FILE.png]\n"
    "                       [--stream FILE] [--json] [options]\n\n"
    "Render SCENE (the built-in scene if omitted): GP -> word stream -> VP -> frames.\n"
    "With several frames, outputs are numbered: frame.exr -> frame.0000.exr, ...\n\n"
    "  -o, --output FILE   OpenEXR frame: R G B, Z, face.id, vp.level, vp.depth, ...\n"
    "                      (docs/vp.md, \"Frames\")\n"
    "  --png FILE          PNG preview of the colour\n"
    "  --view NAME:FILE    PNG of one view: colour, depth, face, level, coverage,\n"
    "                      cycles (timed or cycle fidelity)\n"
    "  --stream FILE       also write the GP's word stream\n"
    "  --dump FILE         each frame as a frame-store dump, 128 bits a pixel, the\n"
    "                      form an RTL bench writes ($writememh text; raw if FILE\n"
    "                      ends in .raw or .bin; docs/cosim.md): albatros compare\n"
    "                      reads it\n"
    "  --fidelity F        functional (default: pixels only), timed or cycle (cycle\n"
    "                      counts, unit counters, vp.cycles; docs/microarchitecture.md)\n"
    "  --threads N         threads of the functional renderer and of the EXR\n"
    "                      compression (default 0: one per core); frames and files\n"
    "                      are bit-identical for every N\n"
    "  --vcd FILE          VCD waveform of the cycle model (with --fidelity cycle)\n"
    "  --vcd-window A:B    trace only cycles A to B (with --vcd)\n"
    "  --vcd-units LIST    trace only these units (with --vcd), comma-separated:\n"
    "                      gp, fifo, parser, engine, fill, pipe, or all (default);\n"
    "                      clk and frame_open are always traced\n"
    "  --events FILE       the cycle model's events, one line each (with --fidelity\n"
    "                      cycle; - for stdout): pushes, pops, faces, cells, writes,\n"
    "                      frames with their CRC (docs/cosim.md)\n"
    "  --events-only KINDS only these kinds (with --events), comma-separated: push,\n"
    "                      pop, load, start, cell, end, fill, write, frame, or all\n"
    "  --json              per-frame VP statistics (and counters) as JSON on stdout\n"
    "                      (docs/microarchitecture.md, \"JSON output\")\n"
    "  -q, --quiet         no summary\n\n";

static const char vp_help[] =
    "usage: albatros vp STREAM [-o FRAME.exr] [--png FRAME.png] [--view NAME:FILE.png]\n"
    "                   [--json] [--profile NAME] [--set KEY=VALUE]\n\n"
    "Run the VP alone on a word stream (as written by albatros gp), as an RTL test\n"
    "bench replays it.  The profile must match the stream's CONFIG formats.\n"
    "Options as for render: -o, --png, --view, --dump, --json, --fidelity, --threads, --vcd,\n"
    "--vcd-window, --vcd-units, --events, --events-only.\n\n";

static const char reference_help[] =
    "usage: albatros reference [SCENE] [-o FRAME.exr] [--png FRAME.png] [--view NAME:FILE]\n"
    "                          [--json] [-q] [options]\n\n"
    "Render SCENE with the exact double-precision reference (docs/reference.md): the\n"
    "ground truth the VP is measured against (albatros compare).  Same outputs as\n"
    "render; vp.level is 255 (the reference does not subdivide).\n\n"
    "  -o, --output FILE   OpenEXR frame, with render's channels\n"
    "  --png FILE          PNG preview of the colour\n"
    "  --view NAME:FILE    PNG of one view: colour, depth, face, level, coverage\n"
    "  --json              the frames rendered, as JSON on stdout\n"
    "  -q, --quiet         no line per frame\n\n";

static int check_outputs(render_args *a)
{
    /* a window of no trace would be silently ignored */
    if (a->vcd_window && !a->vcd) {
        fprintf(stderr, "albatros %s: --vcd-window limits a trace: add --vcd FILE (and "
                        "--fidelity cycle)\n", a->cmd);
        return 2;
    }
    if (a->vcd_units_given && !a->vcd) {
        fprintf(stderr, "albatros %s: --vcd-units limits a trace: add --vcd FILE (and "
                        "--fidelity cycle)\n", a->cmd);
        return 2;
    }
    if (a->events_only_given && !a->events) {
        fprintf(stderr, "albatros %s: --events-only limits the event log: add --events FILE "
                        "(and --fidelity cycle)\n", a->cmd);
        return 2;
    }
    if (a->vcd && a->fid != ALB_FIDELITY_CYCLE) {
        fprintf(stderr, "albatros %s: --vcd traces the cycle fidelity: add --fidelity cycle\n",
                a->cmd);
        return 2;
    }
    if (a->events && a->fid != ALB_FIDELITY_CYCLE) {
        fprintf(stderr, "albatros %s: --events logs the cycle fidelity: add --fidelity cycle\n",
                a->cmd);
        return 2;
    }
    if (!cli_frames_any(&a->out) && !a->json && !a->stream && !a->vcd && !a->events) {
        fprintf(stderr, "albatros %s: nothing to write: give -o FRAME.exr, --png FILE, --view "
                        "NAME:FILE or --json\n", a->cmd);
        return 2;
    }
    return 0;
}

/* The outputs that are one file whatever the frames: claimed before any
 * work (cli_output), so that one overwriting an input or another is
 * refused at once. */
static int claim_outputs(render_args *a)
{
    int rc = a->stream ? cli_output(a->cmd, "--stream", a->stream) : 0;
    if (!rc && a->vcd)
        rc = cli_output(a->cmd, "--vcd", a->vcd);
    if (!rc && a->events)
        rc = cli_output(a->cmd, "--events", a->events);
    return rc;
}

/* What a run may hold in memory: the machine's, or less under ulimit -v/-d. */
static double memory_budget(void)
{
    long pages = sysconf(_SC_PHYS_PAGES), size = sysconf(_SC_PAGESIZE);
    double b = pages > 0 && size > 0 ? (double)pages * (double)size : 1e300;
    struct rlimit rl;
    if (!getrlimit(RLIMIT_AS, &rl) && rl.rlim_cur != RLIM_INFINITY && (double)rl.rlim_cur < b)
        b = (double)rl.rlim_cur;
    if (!getrlimit(RLIMIT_DATA, &rl) && rl.rlim_cur != RLIM_INFINITY && (double)rl.rlim_cur < b)
        b = (double)rl.rlim_cur;
    return b;
}

/* The timed and cycle models take the whole stream: its words, the model's
 * copy and the buffer's growth, about three times its size.  Refused as
 * soon as the frames made so far say that it cannot fit, before the memory
 * runs out (docs/limits.md, "Memory"). */
static int stream_fits(const render_args *a, size_t words, unsigned done, unsigned nframes,
                       double budget)
{
    double need = 3.0 * 4.0 * (double)words / done * nframes;
    if (need <= budget)
        return 0;
    fprintf(stderr, "albatros %s: the word stream of these %u frames needs about %.0f MB in "
                    "memory (%.1f KB a frame so far) with --fidelity %s, more than the %.0f MB "
                    "available; render fewer frames, or with --fidelity functional, which takes "
                    "the frames one at a time (docs/limits.md)\n", a->cmd, nframes, need / 1e6,
            4.0 * (double)words / done / 1e3, alb_fidelity_name(a->fid), budget / 1e6);
    return -1;
}

/* timed, cycle: the whole stream, then the model on it */
static int render_whole(render_args *a, alb_gp *gp, const alb_scene *scene, const alb_profile *prof,
                        const char *name, alb_gp_stats *total)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_ws_buf buf;
    alb_ws_buf_init(&buf);
    double budget = memory_budget();
    alb_gp_stats st;
    memset(total, 0, sizeof *total);
    alb_gp_stream_header(gp, &buf);
    int rc = 0;
    for (unsigned f = 0; f < scene->nframes && !rc; f++) {
        if (alb_gp_frame(gp, f, &buf, &st, &d)) {
            alb_diag_print(&d, stderr);
            rc = 1;
        } else if (stream_fits(a, buf.n, f + 1, scene->nframes, budget)) {
            rc = 1;
        }
        alb_gp_stats_add(total, &st);
    }
    if (!rc) {
        alb_ws_put_end(&buf);
        if (buf.oom) {
            fprintf(stderr, "albatros %s: out of memory for the word stream\n", a->cmd);
            rc = 1;
        }
    }
    if (!rc && a->stream && alb_ws_write_file(a->stream, buf.w, buf.n, &d)) {
        alb_diag_print(&d, stderr);
        rc = 1;
    }
    if (!rc)
        rc = run_vp(a, prof, buf.w, buf.n, name);
    alb_ws_buf_free(&buf);
    return rc;
}

/* functional: each frame from the GP straight into the VP, so that memory
 * stays one frame's stream however many frames there are; --stream is
 * written as it is made */
static int render_frames(render_args *a, alb_gp *gp, const alb_scene *scene, const alb_profile *prof,
                         const char *name, alb_gp_stats *total)
{
    alb_diag d;
    alb_diag_init(&d, stderr);
    a->prof = *prof;
    a->nframes = scene->nframes;
    uint32_t *numbers = malloc((scene->nframes ? scene->nframes : 1) * sizeof *numbers);
    if (!numbers) {
        fprintf(stderr, "albatros %s: out of memory\n", a->cmd);
        return 1;
    }
    for (unsigned f = 0; f < scene->nframes; f++)
        numbers[f] = f & 0xFFFFFF;   /* the FRAME packet's 24-bit number */
    int claimed = cli_frames_claim(&a->out, a->cmd, numbers, scene->nframes);
    free(numbers);
    if (claimed)
        return claimed;
    alb_vp *vp = NULL;
    alb_vp_feed *feed = NULL;
    alb_ws_writer wr;
    bool writing = false;
    sink_ctx s = {a, alb_profile_levels(prof)};
    unsigned threads = a->threads ? a->threads : alb_vp_cores();
    alb_err e = alb_vp_create(&vp, prof, &d);
    if (!e && threads > 1 && alb_vp_set_threads(vp, threads))
        e = alb_diag_at(&d, ALB_ERR_NOMEM, name, 0, 0, "out of memory for %u threads", threads);
    if (!e)
        e = alb_vp_feed_open(&feed, vp, name, vp_sink, &s, &d);
    if (!e && a->stream && !(e = alb_ws_writer_open(&wr, a->stream, false, &d)))
        writing = true;
    alb_ws_buf buf;
    alb_ws_buf_init(&buf);
    alb_gp_stats st;
    memset(total, 0, sizeof *total);
    json_head(a, prof, true);
    for (unsigned f = 0; !e && f <= scene->nframes + 1; f++) {
        buf.n = 0;   /* the header, each frame, then END: one piece at a time */
        if (f == 0)
            alb_gp_stream_header(gp, &buf);
        else if (f <= scene->nframes && !(e = alb_gp_frame(gp, f - 1, &buf, &st, &d)))
            alb_gp_stats_add(total, &st);
        else if (f > scene->nframes)
            alb_ws_put_end(&buf);
        if (!e && buf.oom)
            e = alb_diag_at(&d, ALB_ERR_NOMEM, name, 0, 0, "out of memory for the word stream");
        if (!e && writing)
            alb_ws_writer_put(&wr, buf.w, buf.n);
        if (!e)
            e = alb_vp_feed_words(feed, buf.w, buf.n, &d);
    }
    json_tail(a);
    if (writing && !e)
        e = alb_ws_writer_close(&wr, &d);
    else if (writing)
        alb_ws_writer_abort(&wr);
    if (e && (e != ALB_ERR_IO || d.msg[0]))
        alb_diag_print(&d, stderr);
    alb_ws_buf_free(&buf);
    alb_vp_feed_close(feed);
    alb_vp_destroy(vp);
    struct rusage ru;
    if (!e && !a->quiet && !getrusage(RUSAGE_SELF, &ru))
        fprintf(stderr, "%u frames, peak memory %.1f MB resident\n", a->done,
                (double)ru.ru_maxrss / 1024);
    return e ? 1 : 0;
}

int cmd_render(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "png=", "view=", "stream=", "dump=", "json", "quiet",
                                       "q", "help", "fidelity=", "threads=", "vcd=", "vcd-window=",
                                       "vcd-units=", "events=", "events-only=", NULL};
    render_args a = {.cmd = "render", .progress = cli_isatty_stderr()};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int pr = cli_parse("render", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos);
    if (pr)
        return pr < 0 ? 2 : 0;
    if (a.help) {
        printf("%s%s", render_help, run_opts_help);
        return 0;
    }
    if (check_outputs(&a) || cli_check_profile(&o.prof))
        return 2;
    alb_scene scene;
    if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
        return 1;
    if (cli_is_obj(npos ? pos[0] : NULL))
        snprintf(a.near_fix, sizeof a.near_fix, "--near D; now %g", scene.near);
    else
        snprintf(a.near_fix, sizeof a.near_fix, "'near' in %s or --near D; now %g",
                 npos ? pos[0] : "the scene", scene.near);
    int claimed = claim_outputs(&a);
    if (claimed) {
        alb_scene_free(&scene);
        return claimed;
    }
    const char *name = npos ? pos[0] : "<builtin>";
    set_provenance(&a, o.prof.name, alb_fidelity_name(a.fid), npos ? pos[0] : "builtin");
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    int rc = 0;
    alb_gp_stats gst;
    memset(&gst, 0, sizeof gst);
    if (alb_gp_create(&gp, &scene, &o.prof, &d)) {
        alb_diag_print(&d, stderr);
        rc = 1;
    } else if (a.fid == ALB_FIDELITY_FUNCTIONAL) {
        rc = render_frames(&a, gp, &scene, &o.prof, name, &gst);
    } else {
        rc = render_whole(&a, gp, &scene, &o.prof, name, &gst);
    }
    cli_warn_saturated(scene.file, &gst);
    alb_gp_destroy(gp);
    alb_scene_free(&scene);
    return rc;
}

int cmd_vp(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "png=", "view=", "dump=", "json", "quiet", "q", "help",
                                       "fidelity=", "threads=", "vcd=", "vcd-window=",
                                       "vcd-units=", "events=", "events-only=", NULL};
    render_args a = {.cmd = "vp", .progress = cli_isatty_stderr()};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int pr = cli_parse("vp", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos);
    if (pr)
        return pr < 0 ? 2 : 0;
    if (a.help) {
        printf("%s", vp_help);
        return 0;
    }
    if (npos != 1) {
        fprintf(stderr, "albatros vp: give the STREAM file (see --help)\n");
        return 2;
    }
    if (check_outputs(&a) || cli_check_profile(&o.prof))
        return 2;
    cli_input(pos[0]);
    int claimed = claim_outputs(&a);
    if (claimed)
        return claimed;
    uint32_t *w;
    size_t n;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_ws_read_file(pos[0], &w, &n, &d)) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    set_provenance(&a, o.prof.name, alb_fidelity_name(a.fid), pos[0]);
    /* the stream's near is its CONFIG word, the GP's */
    snprintf(a.near_fix, sizeof a.near_fix, "the GP's --near D, then a new stream");
    int rc = run_vp(&a, &o.prof, w, n, pos[0]);
    free(w);
    return rc;
}

int cmd_reference(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "png=", "view=", "dump=", "json", "quiet", "q", "help",
                                       NULL};
    render_args a = {.cmd = "reference", .progress = cli_isatty_stderr()};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int pr = cli_parse("reference", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos);
    if (pr)
        return pr < 0 ? 2 : 0;
    if (a.help) {
        printf("%s%s", reference_help, run_opts_help);
        return 0;
    }
    if (check_outputs(&a) || cli_check_profile(&o.prof))
        return 2;
    alb_scene scene;
    if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
        return 1;
    sink_ctx s = {&a, alb_profile_levels(&o.prof)};
    a.nframes = scene.nframes;
    set_provenance(&a, o.prof.name, "reference", npos ? pos[0] : "builtin");
    uint32_t *numbers = malloc((scene.nframes ? scene.nframes : 1) * sizeof *numbers);
    int rc = numbers ? 0 : 1;
    for (unsigned f = 0; f < scene.nframes && numbers; f++)
        numbers[f] = f;
    if (numbers)
        rc = cli_frames_claim(&a.out, a.cmd, numbers, scene.nframes);
    free(numbers);
    if (rc) {
        alb_scene_free(&scene);
        return rc;
    }
    json_head(&a, &o.prof, false);
    for (unsigned f = 0; f < scene.nframes && !rc; f++) {
        alb_frame fr;
        if (ref_render(&scene, &o.prof, f, &fr)) {
            fprintf(stderr, "albatros reference: out of memory\n");
            rc = 1;
            break;
        }
        rc = write_outputs(&s, &fr, NULL, NULL) ? 1 : 0;
        alb_frame_free(&fr);
    }
    json_tail(&a);
    alb_scene_free(&scene);
    return rc;
}
