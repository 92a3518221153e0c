/* cmd_gp.c — `albatros gp`: run the GP on a scene and write the word stream
 * (binary and annotated hex); `albatros dump`: check and print a stream;
 * `albatros profiles`. */
#include "cli.h"
#include "commands.h"
#include "albatros/file.h"
#include "albatros/json.h"

#include <stdlib.h>
#include <string.h>

void gp_stats_json(alb_json *j, const alb_gp_stats *s)
{
    alb_json_begin_object(j);
    alb_json_kv_uint(j, "faces_in", s->faces_in);
    alb_json_kv_uint(j, "faces_out", s->faces_out);
    alb_json_kv_uint(j, "faces_behind", s->faces_behind);
    alb_json_kv_uint(j, "faces_backfacing", s->faces_backfacing);
    alb_json_kv_uint(j, "faces_edge_on", s->faces_edge_on);
    alb_json_kv_uint(j, "faces_offscreen", s->faces_offscreen);
    alb_json_kv_uint(j, "edges_out", s->edges_out);
    alb_json_kv_uint(j, "edges_behind", s->edges_behind);
    alb_json_kv_uint(j, "edges_degenerate", s->edges_degenerate);
    alb_json_kv_uint(j, "edges_offscreen", s->edges_offscreen);
    alb_json_kv_uint(j, "bound_added", s->bound_added);
    alb_json_kv_uint(j, "bound_culled", s->bound_culled);
    alb_json_kv_uint(j, "bound_excess", s->bound_excess);
    alb_json_kv_uint(j, "coef_saturated", s->coef_saturated);
    alb_json_kv_uint(j, "words", s->words);
    alb_json_end_object(j);
}

void gp_stats_text(FILE *f, const alb_gp_stats *s)
{
    fprintf(f, "  faces: %u in, %u out; dropped %u behind, %u back-facing, %u edge-on, "
               "%u off-screen\n", s->faces_in, s->faces_out, s->faces_behind,
            s->faces_backfacing, s->faces_edge_on, s->faces_offscreen);
    fprintf(f, "  edges: %u out (%u bounding); dropped %u behind, %u degenerate, %u off-screen, "
               "%u bounding off-screen\n", s->edges_out, s->bound_added, s->edges_behind,
            s->edges_degenerate, s->edges_offscreen, s->bound_culled);
    if (s->bound_excess)
        fprintf(f, "  note: %u vert%s of faces not strictly convex on the screen called for a "
                   "third bounding edge or more, left out (at most two per face; docs/gp.md)\n",
                s->bound_excess, s->bound_excess == 1 ? "ex" : "ices");
    fprintf(f, "  words: %llu\n", s->words);
}

static const char gp_help[] =
    "usage: albatros gp [SCENE] [-o STREAM] [--hex FILE] [--memh FILE] [--json] [options]\n\n"
    "Run the geometry processor on SCENE (a .scene text file, or a .obj file with\n"
    "the camera options below; the built-in scene if omitted) and write the VP\n"
    "word stream (docs/word-format.md).\n\n"
    "  -o, --output FILE  binary stream: little-endian 32-bit words\n"
    "  --hex FILE         annotated hex dump, one word per line ('-' = stdout)\n"
    "  --memh FILE        the words as $readmemh text for an RTL bench, one per line\n"
    "                     ('-' = stdout); dump and vp read it back\n"
    "  --json             print statistics as JSON on stdout\n"
    "  -q, --quiet        no summary\n\n";

typedef struct {
    const char *output, *hex, *memh;
    bool json, quiet, help;
} gp_args;

static int gp_opt(void *ctx, const char *name, const char *value)
{
    gp_args *a = ctx;
    if (strcmp(name, "output") == 0)
        a->output = value;
    else if (strcmp(name, "hex") == 0)
        a->hex = value;
    else if (strcmp(name, "memh") == 0)
        a->memh = value;
    else if (strcmp(name, "json") == 0)
        a->json = true;
    else if (strcmp(name, "quiet") == 0 || strcmp(name, "q") == 0)
        a->quiet = true;
    else if (strcmp(name, "help") == 0)
        a->help = true;
    return 0;
}

/* The outputs of gp, written a frame at a time as the GP makes them, so that
 * memory does not grow with the frames (docs/limits.md). */
typedef struct {
    alb_ws_writer bin, memh;
    alb_out hex;
    FILE *hexf;
    alb_ws_reader hex_reader;
    bool has_bin, has_memh, has_hex;
    size_t words;
} gp_outputs;

static alb_err outputs_open(gp_outputs *g, const gp_args *a, const char *name, alb_diag *d)
{
    memset(g, 0, sizeof *g);
    alb_err e = ALB_OK;
    if (a->output && !(e = alb_ws_writer_open(&g->bin, a->output, false, d)))
        g->has_bin = true;
    if (!e && a->memh && !(e = alb_ws_writer_open(&g->memh, a->memh, true, d)))
        g->has_memh = true;
    if (!e && a->hex && !(e = alb_out_open(&g->hex, a->hex, ALB_OUT_DASH, d))) {
        if ((g->hexf = alb_out_stdio(&g->hex, d)))
            g->has_hex = true;
        else
            e = ALB_ERR_IO;
    }
    alb_ws_reader_init(&g->hex_reader, NULL, 0, name);
    return e;
}

static alb_err outputs_put(gp_outputs *g, const alb_ws_buf *b, alb_diag *d)
{
    if (b->oom)
        return alb_diag_at(d, ALB_ERR_NOMEM, "", 0, 0, "out of memory for the word stream");
    if (g->has_bin)
        alb_ws_writer_put(&g->bin, b->w, b->n);
    if (g->has_memh)
        alb_ws_writer_put(&g->memh, b->w, b->n);
    alb_err e = g->has_hex ? alb_ws_dump_piece(g->hexf, &g->hex_reader, b->w, b->n, g->words, d)
                           : ALB_OK;
    g->words += b->n;
    return e;
}

/* Every output under its name, or (on failure) none: the old files stay. */
static alb_err outputs_close(gp_outputs *g, alb_err e, alb_diag *d)
{
    if (g->has_bin)
        e = e ? (alb_ws_writer_abort(&g->bin), e) : alb_ws_writer_close(&g->bin, d);
    if (g->has_memh)
        e = e ? (alb_ws_writer_abort(&g->memh), e) : alb_ws_writer_close(&g->memh, d);
    if (g->has_hex)
        e = e ? (alb_out_abort(&g->hex), e) : alb_out_commit(&g->hex, d);
    return e;
}

/* The whole stream, a piece at a time: header, each frame, END. */
static alb_err gp_stream(alb_gp *gp, unsigned nframes, gp_outputs *g, alb_gp_stats *sum,
                         alb_diag *d)
{
    alb_ws_buf buf;
    alb_ws_buf_init(&buf);
    alb_gp_stats st;
    memset(sum, 0, sizeof *sum);
    alb_gp_stream_header(gp, &buf);
    alb_err e = outputs_put(g, &buf, d);
    for (unsigned f = 0; f < nframes && !e; f++) {
        buf.n = 0;
        if (!(e = alb_gp_frame(gp, f, &buf, &st, d))) {
            alb_gp_stats_add(sum, &st);
            e = outputs_put(g, &buf, d);
        }
    }
    if (!e) {
        buf.n = 0;
        alb_ws_put_end(&buf);
        e = outputs_put(g, &buf, d);
    }
    sum->words = g->words;
    alb_ws_buf_free(&buf);
    return e;
}

/* At most one output on stdout: --json, --hex - or --memh - (they would
 * interleave). */
static int one_stdout(const gp_args *a)
{
    int n = a->json + (a->hex && !strcmp(a->hex, "-")) + (a->memh && !strcmp(a->memh, "-"));
    if (n <= 1)
        return 0;
    fprintf(stderr, "albatros gp: --json, --hex - and --memh - all write to stdout: give one of "
                    "them stdout, the others files\n");
    return -1;
}

int cmd_gp(int argc, char **argv)
{
    static const char *const spec[] = {"output=", "hex=", "memh=", "json", "quiet", "q", "help",
                                       NULL};
    gp_args a = {0};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int parsed = cli_parse("gp", argc, argv, spec, gp_opt, &a, &o, pos, 1, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help) {
        printf("%s%s", gp_help, run_opts_help);
        return 0;
    }
    if (!a.output && !a.hex && !a.memh && !a.json) {
        fprintf(stderr, "albatros gp: nothing to write: give -o STREAM, --hex FILE, --memh FILE "
                        "or --json\n");
        return 2;
    }
    if (one_stdout(&a) || cli_check_profile(&o.prof))
        return 2;
    alb_scene scene;
    if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
        return 1;
    int claimed = a.output ? cli_output("gp", "-o", a.output) : 0;
    if (!claimed && a.hex)
        claimed = cli_output("gp", "--hex", a.hex);
    if (!claimed && a.memh)
        claimed = cli_output("gp", "--memh", a.memh);
    if (claimed) {
        alb_scene_free(&scene);
        return claimed;
    }
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    alb_err e = alb_gp_create(&gp, &scene, &o.prof, &d);
    alb_gp_stats st;
    memset(&st, 0, sizeof st);
    if (!e) {
        gp_outputs g;
        alb_diag wd;
        alb_diag_init(&wd, NULL);
        e = outputs_open(&g, &a, a.output ? a.output : "<gp>", &wd);
        if (!e)
            e = gp_stream(gp, scene.nframes, &g, &st, &d);
        e = outputs_close(&g, e, &wd);
        if (wd.msg[0] && e)
            d = wd;
    }
    int rc = 0;
    if (e) {
        alb_diag_print(&d, stderr);
        rc = 1;
    } else {
        cli_warn_saturated(scene.file, &st);
        if (a.json) {
            alb_json j;
            alb_json_init(&j, stdout);
            alb_json_begin_object(&j);
            alb_json_kv_string(&j, "scene", npos ? pos[0] : "builtin");
            alb_json_kv_string(&j, "profile", o.prof.name);
            alb_json_kv_uint(&j, "frames", scene.nframes);
            alb_json_key(&j, "totals");
            gp_stats_json(&j, &st);
            alb_json_end_object(&j);
            alb_json_end_line(&j);
        } else if (!a.quiet && !(a.hex && strcmp(a.hex, "-") == 0) &&
                   !(a.memh && strcmp(a.memh, "-") == 0)) {
            fprintf(stderr, "gp: %s, profile %s, %u frame%s\n", npos ? pos[0] : "built-in scene",
                    o.prof.name, scene.nframes, scene.nframes == 1 ? "" : "s");
            gp_stats_text(stderr, &st);
        }
    }
    alb_gp_destroy(gp);
    alb_scene_free(&scene);
    return rc;
}

int cmd_dump(int argc, char **argv)
{
    static const char *const spec[] = {"help", NULL};
    gp_args a = {0};
    const char *pos[1];
    int npos;
    int parsed = cli_parse("dump", argc, argv, spec, gp_opt, &a, NULL, pos, 1, &npos);
    if (parsed)
        return CLI_PARSE_EXIT(parsed);
    if (a.help || npos != 1) {
        printf("usage: albatros dump STREAM\n\nCheck a binary word stream and print each word "
               "with its field names.\nExit status 1 at the first malformed word, named by "
               "offset and field.\n");
        return a.help ? 0 : 2;
    }
    uint32_t *w;
    size_t n;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_ws_read_file(pos[0], &w, &n, &d)) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    alb_err e = alb_ws_dump(stdout, w, n, pos[0], &d);
    free(w);
    if (e) {
        fflush(stdout);
        alb_diag_print(&d, stderr);
        return 1;
    }
    return 0;
}

int cmd_profiles(int argc, char **argv)
{
    static const char *const spec[] = {"help", NULL};
    gp_args a = {0};
    run_opts o;
    run_opts_init(&o);
    const char *pos[1];
    int npos;
    int parsed = cli_parse("profiles", argc, argv, spec, gp_opt, &a, &o, pos, 1, &npos);
    if (parsed || a.help) {
        if (a.help)
            printf("usage: albatros profiles [NAME] [--set KEY=VALUE ...] [--size WxH]\n\n"
                   "List the built-in profiles (docs/profiles.md), one key=value line a field;\n"
                   "with NAME (or --profile NAME) that profile alone, with the overrides\n"
                   "applied and checked, as the other subcommands would run it (what an RTL\n"
                   "build takes its parameters from: rtl/profile-params.sh).\n");
        return parsed ? CLI_PARSE_EXIT(parsed) : 0;
    }
    char buf[1024];
    if (npos || o.noverrides || strcmp(o.prof.name, "a512")) {
        char err[300];
        /* a NAME re-applies every --set and --size after it, as --profile does */
        if (npos && run_opts_apply(&o, "profile", pos[0], err, sizeof err) < 0) {
            fprintf(stderr, "albatros profiles: %s\n", err);
            return 2;
        }
        if (cli_check_profile(&o.prof))
            return 2;
        alb_profile_describe(&o.prof, buf, sizeof buf);
        printf("%s\n", buf);
        return 0;
    }
    for (const char *const *n = alb_profile_names(); *n; n++) {
        alb_profile p;
        alb_profile_lookup(*n, &p);
        alb_profile_describe(&p, buf, sizeof buf);
        printf("%s\n", buf);
    }
    return 0;
}
