/* cmd_render.c — `albatros render`: scene -> GP -> word stream -> VP ->
 * frames (OpenEXR, PNG views); `albatros vp`: the VP alone on a stream file,
 * as an RTL test bench replays it.  Both share the frame sinks below. */
#include "cli.h"
#include "commands.h"
#include "albatros/dump.h"
#include "albatros/exr.h"
#include "albatros/preview.h"
#include "albatros/sim.h"
#include "albatros/vcd.h"
#include "../tools/ref.h"
#include "albatros/vp.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

#define MAX_VIEWS 8

typedef struct {
    const char *output, *png, *stream, *dump;
    struct {
        alb_preview_view view;
        const char *path;
    } views[MAX_VIEWS];
    unsigned nviews;
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

static int render_opt(void *ctx, const char *name, const char *value)
{
    render_args *a = ctx;
    if (strcmp(name, "output") == 0)
        a->output = value;
    else if (strcmp(name, "png") == 0)
        a->png = value;
    else if (strcmp(name, "stream") == 0)
        a->stream = value;
    else if (strcmp(name, "dump") == 0)
        a->dump = value;
    else if (strcmp(name, "view") == 0) {
        const char *colon = strchr(value, ':');
        char vname[32];
        if (!colon || (size_t)(colon - value) >= sizeof vname) {
            fprintf(stderr, "albatros %s: --view %s: expected NAME:FILE.png, e.g. depth:d.png\n",
                    a->cmd, value);
            return -1;
        }
        snprintf(vname, sizeof vname, "%.*s", (int)(colon - value), value);
        if (a->nviews == MAX_VIEWS || alb_preview_view_parse(vname, &a->views[a->nviews].view)) {
            fprintf(stderr, "albatros %s: --view %s: views are colour, depth, face, level, "
                            "cycles, coverage (at most %d)\n", a->cmd, value, MAX_VIEWS);
            return -1;
        }
        a->views[a->nviews++].path = colon + 1;
    } else if (strcmp(name, "fidelity") == 0) {
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
        unsigned long long from, to;
        char tail;
        if (sscanf(value, "%llu:%llu%c", &from, &to, &tail) != 2 || from > to) {
            fprintf(stderr, "albatros %s: --vcd-window %s: expected FROM:TO cycles, FROM <= TO\n",
                    a->cmd, value);
            return -1;
        }
        a->vcd_window = true;
        a->vcd_from = from;
        a->vcd_to = to;
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

static void stats_json(FILE *f, const alb_frame *fr, const alb_vp_stats *st, unsigned levels,
                       const alb_sim_counters *sc, const alb_profile *p)
{
    fprintf(f, "{\"frame\": %u, \"faces\": %llu, \"edges\": %llu, \"cells_per_level\": [",
            fr->number, (unsigned long long)st->faces, (unsigned long long)st->edges);
    for (unsigned l = 0; l <= levels; l++)
        fprintf(f, "%s%llu", l ? ", " : "", (unsigned long long)st->cells[l]);
    fprintf(f, "], \"cells_inside\": %llu, \"cells_outside\": %llu, \"cells_split\": %llu, "
               "\"samples_tested\": %llu, \"samples_covered\": %llu, \"samples_written\": %llu, "
               "\"depth_saturated\": %llu, \"depth_underflow\": %llu, \"depth_ties\": %llu, "
               "\"faces_shaded\": %llu, "
               "\"faces_textured\": %llu, \"faces_fogged\": %llu",
            (unsigned long long)st->cells_inside, (unsigned long long)st->cells_outside,
            (unsigned long long)st->cells_split, (unsigned long long)st->samples_tested,
            (unsigned long long)st->samples_covered, (unsigned long long)st->samples_written,
            (unsigned long long)st->depth_saturated, (unsigned long long)st->depth_underflow,
            (unsigned long long)st->depth_ties, (unsigned long long)st->faces_shaded, (unsigned long long)st->faces_textured,
            (unsigned long long)st->faces_fogged);
    if (sc) {
        fprintf(f, ", \"timing\": ");
        alb_sim_counters_json(f, sc, p);
    }
    fputc('}', f);
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
    char path[1024];
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (st)
        width_warnings(a, f, st);
    if (a->output) {
        cli_frame_path(path, sizeof path, a->output, f->number, a->nframes);
        if (alb_exr_write_frame_threads(path, f, a->threads ? a->threads : alb_vp_cores(), &d)) {
            alb_diag_print(&d, stderr);
            return -1;
        }
    }
    if (a->dump) {
        /* raw by its name, else $writememh text (docs/cosim.md) */
        size_t n = strlen(a->dump);
        bool raw = (n > 4 && !strcmp(a->dump + n - 4, ".raw")) ||
                   (n > 4 && !strcmp(a->dump + n - 4, ".bin"));
        cli_frame_path(path, sizeof path, a->dump, f->number, a->nframes);
        if (alb_dump_write(path, f, raw ? ALB_DUMP_RAW : ALB_DUMP_MEMH, &d)) {
            alb_diag_print(&d, stderr);
            return -1;
        }
    }
    if (a->png) {
        cli_frame_path(path, sizeof path, a->png, f->number, a->nframes);
        if (alb_preview_write(path, f, ALB_PREVIEW_COLOUR, &d)) {
            alb_diag_print(&d, stderr);
            return -1;
        }
    }
    for (unsigned i = 0; i < a->nviews; i++) {
        cli_frame_path(path, sizeof path, a->views[i].path, f->number, a->nframes);
        if (alb_preview_write(path, f, a->views[i].view, &d)) {
            alb_diag_print(&d, stderr);
            return -1;
        }
    }
    if (a->json) {
        printf("%s", a->done ? ",\n  " : "  ");
        if (st)
            stats_json(stdout, f, st, s->levels, sc, &a->prof);
        else
            printf("{\"frame\": %u}", f->number);
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

/* Frames in a stream, by a quick pass of the decoder (0 if malformed: the
 * real pass will report it). */
static unsigned count_frames(const uint32_t *w, size_t n)
{
    alb_ws_reader r;
    alb_ws_event *ev = malloc(sizeof *ev);
    alb_diag d;
    alb_diag_init(&d, NULL);
    unsigned frames = 0;
    alb_ws_reader_init(&r, w, n, "");
    while (ev && !r.ended && alb_ws_next(&r, ev, &d) == ALB_OK)
        frames += ev->kind == ALB_WS_EV_FRAME;
    free(ev);
    return frames;
}

/* --events: each batch of the cycle model's events as text lines. */
static int write_events(void *ctx, const alb_event *ev, size_t n)
{
    FILE *f = ctx;
    char line[160];
    for (size_t i = 0; i < n; i++) {
        int len = alb_sim_event_format(&ev[i], line, sizeof line);
        if (len < 0 || fwrite(line, 1, (size_t)len, f) != (size_t)len)
            return -1;
    }
    return 0;
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
                       .counters_only = !a->output && !a->png && !a->nviews && !a->dump};
    a->prof = *prof;
    if (a->vcd) {
        if (a->fid != ALB_FIDELITY_CYCLE) {
            fprintf(stderr, "albatros %s: --vcd traces the cycle fidelity: add --fidelity cycle\n",
                    a->cmd);
            return 2;
        }
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
                alb_vcd_close(opt.vcd);
                return 2;
            }
    }
    FILE *events = NULL;
    if (a->events) {
        if (a->fid != ALB_FIDELITY_CYCLE) {
            fprintf(stderr, "albatros %s: --events logs the cycle fidelity: add --fidelity cycle\n",
                    a->cmd);
            if (opt.vcd)
                alb_vcd_close(opt.vcd);
            return 2;
        }
        events = strcmp(a->events, "-") ? fopen(a->events, "w") : stdout;
        if (!events) {
            fprintf(stderr, "albatros %s: %s: %s\n", a->cmd, a->events, strerror(errno));
            if (opt.vcd)
                alb_vcd_close(opt.vcd);
            return 1;
        }
        opt.events = a->events_only_given ? a->events_only : ALB_EV_ALL;
        opt.on_events = write_events;
        opt.events_ctx = events;
    }
    a->nframes = count_frames(w, n);
    sink_ctx s = {a, alb_profile_levels(prof)};
    if (a->json)
        printf("{\"profile\": \"%s\", \"fidelity\": \"%s\", \"frames\": [\n", prof->name,
               alb_fidelity_name(a->fid));
    alb_err e = alb_sim_run(prof, w, n, name, &opt, write_outputs, &s, &d);
    if (a->json)
        printf("\n]}\n");
    if (opt.vcd && alb_vcd_close(opt.vcd)) {
        fprintf(stderr, "albatros %s: %s: write error\n", a->cmd, a->vcd);
        e = e ? e : ALB_ERR_IO;
    }
    if (events && (events == stdout ? fflush(events) : fclose(events))) {
        fprintf(stderr, "albatros %s: %s: write error: %s\n", a->cmd, a->events, strerror(errno));
        e = e ? e : ALB_ERR_IO;
    } else if (events && e == ALB_ERR_IO && !d.msg[0]) {
        fprintf(stderr, "albatros %s: %s: write error\n", a->cmd, a->events);
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
    if (!a->output && !a->png && !a->nviews && !a->json && !a->stream && !a->vcd && !a->events &&
        !a->dump) {
        fprintf(stderr, "albatros %s: nothing to write: give -o FRAME.exr, --png FILE, --view "
                        "NAME:FILE or --json\n", a->cmd);
        return 2;
    }
    return 0;
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
    if (cli_parse("render", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos))
        return 2;
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
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    alb_ws_buf buf;
    alb_ws_buf_init(&buf);
    int rc = 0;
    alb_gp_stats gst;
    if (alb_gp_create(&gp, &scene, &o.prof, &d) || alb_gp_run(gp, &buf, &gst, &d)) {
        alb_diag_print(&d, stderr);
        rc = 1;
    } else if (gst.coef_saturated) {
        fprintf(stderr, "albatros: warning: %u linear forms exceeded the exponent range "
                        "(a face nearly edge-on to the observer?)\n", gst.coef_saturated);
    }
    if (!rc && a.stream && alb_ws_write_file(a.stream, buf.w, buf.n, &d)) {
        alb_diag_print(&d, stderr);
        rc = 1;
    }
    if (!rc)
        rc = run_vp(&a, &o.prof, buf.w, buf.n, npos ? pos[0] : "<builtin>");
    alb_ws_buf_free(&buf);
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
    if (cli_parse("vp", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos))
        return 2;
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
    uint32_t *w;
    size_t n;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_ws_read_file(pos[0], &w, &n, &d)) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    /* the stream's near is its CONFIG word, the GP's */
    snprintf(a.near_fix, sizeof a.near_fix, "the GP's --near D, then a new stream");
    int rc = run_vp(&a, &o.prof, w, n, pos[0]);
    free(w);
    return rc;
}

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

int cmd_reference(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "png=", "view=", "dump=", "json", "quiet", "q", "help",
                                       NULL};
    render_args a = {.cmd = "reference", .progress = cli_isatty_stderr()};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    if (cli_parse("reference", argc, argv, spec, render_opt, &a, &o, pos, 1, &npos))
        return 2;
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
    int rc = 0;
    if (a.json)
        printf("{\"profile\": \"%s\", \"frames\": [\n", o.prof.name);
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
    if (a.json)
        printf("\n]}\n");
    alb_scene_free(&scene);
    return rc;
}
