/* cmd_gp.c — `albatros gp`: run the GP on a scene and write the word stream
 * (binary and annotated hex); `albatros dump`: check and print a stream;
 * `albatros profiles`. */
#include "cli.h"
#include "commands.h"

#include <stdlib.h>
#include <string.h>

void gp_stats_json(FILE *f, const alb_gp_stats *s)
{
    fprintf(f, "{\"faces_in\": %u, \"faces_out\": %u, \"faces_behind\": %u, "
               "\"faces_backfacing\": %u, \"faces_edge_on\": %u, \"faces_offscreen\": %u, "
               "\"edges_out\": %u, \"edges_behind\": %u, \"edges_degenerate\": %u, "
               "\"edges_offscreen\": %u, \"bound_added\": %u, \"bound_culled\": %u, "
               "\"bound_excess\": %u, \"coef_saturated\": %u, \"words\": %llu}",
            s->faces_in, s->faces_out, s->faces_behind, s->faces_backfacing, s->faces_edge_on,
            s->faces_offscreen, s->edges_out, s->edges_behind, s->edges_degenerate,
            s->edges_offscreen, s->bound_added, s->bound_culled, s->bound_excess,
            s->coef_saturated, s->words);
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
    if (s->coef_saturated)
        fprintf(f, "  warning: %u coefficient forms saturated their exponent\n", s->coef_saturated);
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

static int write_hex(const char *path, const alb_ws_buf *b, const char *name)
{
    FILE *f = strcmp(path, "-") == 0 ? stdout : fopen(path, "w");
    if (!f) {
        perror(path);
        return 1;
    }
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_err e = alb_ws_dump(f, b->w, b->n, name, &d);
    int bad = ferror(f);
    if (f != stdout)
        bad |= fclose(f);
    if (e) {
        alb_diag_print(&d, stderr);
        return 1;
    }
    if (bad) {
        fprintf(stderr, "albatros gp: %s: write error\n", path);
        return 1;
    }
    return 0;
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
    if (cli_parse("gp", argc, argv, spec, gp_opt, &a, &o, pos, 1, &npos))
        return 2;
    if (a.help) {
        printf("%s%s", gp_help, run_opts_help);
        return 0;
    }
    if (!a.output && !a.hex && !a.memh && !a.json) {
        fprintf(stderr, "albatros gp: nothing to write: give -o STREAM, --hex FILE, --memh FILE "
                        "or --json\n");
        return 2;
    }
    if (cli_check_profile(&o.prof))
        return 2;
    alb_scene scene;
    if (cli_load_scene(npos ? pos[0] : NULL, &o, &scene))
        return 1;
    alb_diag d;
    alb_diag_init(&d, stderr);
    alb_gp *gp = NULL;
    alb_err e = alb_gp_create(&gp, &scene, &o.prof, &d);
    alb_ws_buf buf;
    alb_ws_buf_init(&buf);
    alb_gp_stats st;
    if (!e)
        e = alb_gp_run(gp, &buf, &st, &d);
    int rc = 0;
    if (e) {
        alb_diag_print(&d, stderr);
        rc = 1;
    } else {
        if (a.output) {
            alb_diag wd;
            alb_diag_init(&wd, NULL);
            if (alb_ws_write_file(a.output, buf.w, buf.n, &wd)) {
                alb_diag_print(&wd, stderr);
                rc = 1;
            }
        }
        if (!rc && a.hex)
            rc = write_hex(a.hex, &buf, a.output ? a.output : "<gp>");
        if (!rc && a.memh) {
            alb_diag wd;
            alb_diag_init(&wd, NULL);
            if (alb_ws_write_memh(a.memh, buf.w, buf.n, &wd)) {
                alb_diag_print(&wd, stderr);
                rc = 1;
            }
        }
        if (a.json) {
            printf("{\"scene\": \"%s\", \"profile\": \"%s\", \"frames\": %u, \"totals\": ",
                   npos ? pos[0] : "builtin", o.prof.name, scene.nframes);
            gp_stats_json(stdout, &st);
            printf("}\n");
        } else if (!a.quiet && !(a.hex && strcmp(a.hex, "-") == 0) &&
                   !(a.memh && strcmp(a.memh, "-") == 0)) {
            fprintf(stderr, "gp: %s, profile %s, %u frame%s\n", npos ? pos[0] : "built-in scene",
                    o.prof.name, scene.nframes, scene.nframes == 1 ? "" : "s");
            gp_stats_text(stderr, &st);
        }
    }
    alb_ws_buf_free(&buf);
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
    if (cli_parse("dump", argc, argv, spec, gp_opt, &a, NULL, pos, 1, &npos))
        return 2;
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
    (void)argv;
    if (argc > 0) {
        printf("usage: albatros profiles\n\nList the built-in profiles (docs/profiles.md).\n");
        return strcmp(argv[0], "--help") == 0 ? 0 : 2;
    }
    for (const char *const *n = alb_profile_names(); *n; n++) {
        alb_profile p;
        char buf[1024];
        alb_profile_lookup(*n, &p);
        alb_profile_describe(&p, buf, sizeof buf);
        printf("%s\n", buf);
    }
    return 0;
}
