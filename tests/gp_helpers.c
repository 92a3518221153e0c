/* gp_helpers.c — see gp_helpers.h. */
#include "gp_helpers.h"
#include "../tools/scenegen.h"

#include <dirent.h>
#include <stdlib.h>
#include <string.h>

int gp_run_text(const char *text, const char *sets, gp_run_result *r)
{
    memset(r, 0, sizeof *r);
    alb_profile p;
    alb_profile_lookup("a512", &p);
    if (sets) {
        char buf[512];
        snprintf(buf, sizeof buf, "%s", sets);
        for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
            if (alb_profile_set(&p, tok, r->err, sizeof r->err))
                return -1;
    }
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_parse(text, strlen(text), "test.scene", &s, &d)) {
        snprintf(r->err, sizeof r->err, "%u:%u: %s", d.line, d.col, d.msg);
        return -1;
    }
    alb_gp *gp = NULL;
    alb_ws_buf_init(&r->buf);
    alb_err e = alb_gp_create(&gp, &s, &p, &d);
    if (!e)
        e = alb_gp_run(gp, &r->buf, &r->st, &d);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
    if (e) {
        snprintf(r->err, sizeof r->err, "%s", d.msg);
        return -1;
    }
    alb_ws_reader rd;
    alb_ws_reader_init(&rd, r->buf.w, r->buf.n, "test");
    alb_ws_event *ev = malloc(sizeof *ev);
    unsigned frames = 0;
    while (ev && !rd.ended && !(e = alb_ws_next(&rd, ev, &d))) {
        if (ev->kind == ALB_WS_EV_CONFIG)
            r->cfg = ev->u.config;
        if (ev->kind == ALB_WS_EV_FRAME && frames++ == 0)
            r->frame = ev->u.frame;
        if (ev->kind == ALB_WS_EV_FACE && frames == 1) {
            alb_ws_face *nf = realloc(r->faces, (r->nfaces + 1) * sizeof *nf);
            if (!nf)
                break;
            r->faces = nf;
            r->faces[r->nfaces++] = ev->u.face;
        }
    }
    free(ev);
    if (e) {
        snprintf(r->err, sizeof r->err, "decoding: %s", d.msg);
        return -1;
    }
    return 0;
}

void gp_run_free(gp_run_result *r)
{
    alb_ws_buf_free(&r->buf);
    free(r->faces);
    r->faces = NULL;
}

typedef struct {
    alb_frame *out;
    alb_vp_stats *st;
    bool got;
} first_frame;

static int keep_first(void *ctx, const alb_frame *f, const alb_vp_stats *st)
{
    first_frame *ff = ctx;
    if (ff->got)
        return 0;
    if (alb_frame_alloc(ff->out, f->width, f->height, false))
        return -1;
    alb_frame *o = ff->out;
    size_t n = (size_t)f->width * f->height;
    memcpy(o->rgb, f->rgb, 3 * n * sizeof *o->rgb);
    memcpy(o->depth, f->depth, n * sizeof *o->depth);
    memcpy(o->face, f->face, n * sizeof *o->face);
    memcpy(o->level, f->level, n * sizeof *o->level);
    memcpy(o->coverage, f->coverage, n * sizeof *o->coverage);
    o->colour_bits = f->colour_bits;
    o->depth_bits = f->depth_bits;
    o->aa_levels = f->aa_levels;
    o->near = f->near;
    o->number = f->number;
    if (ff->st)
        *ff->st = *st;
    ff->got = true;
    return 0;
}

int render_text(const char *text, const char *profile_name, const char *sets, alb_frame *out,
                alb_vp_stats *st, alb_profile *prof_out, char *err, size_t errlen)
{
    alb_profile p;
    if (alb_profile_lookup(profile_name ? profile_name : "a512", &p)) {
        snprintf(err, errlen, "no profile %s", profile_name);
        return -1;
    }
    if (sets) {
        char buf[512];
        snprintf(buf, sizeof buf, "%s", sets);
        for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
            if (alb_profile_set(&p, tok, err, errlen))
                return -1;
    }
    if (prof_out)
        *prof_out = p;
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    if (alb_scene_parse(text, strlen(text), "test.scene", &s, &d) ||
        alb_scene_resolve_screenspace(&s, p.width, p.height, &d)) {
        snprintf(err, errlen, "%u:%u: %s", d.line, d.col, d.msg);
        return -1;
    }
    alb_gp *gp = NULL;
    alb_vp *vp = NULL;
    alb_ws_buf b;
    alb_ws_buf_init(&b);
    first_frame ff = {out, st, false};
    alb_err e = alb_gp_create(&gp, &s, &p, &d);
    if (!e)
        e = alb_gp_run(gp, &b, NULL, &d);
    if (!e)
        e = alb_vp_create(&vp, &p, &d);
    if (!e)
        e = alb_vp_run_stream(vp, b.w, b.n, "test", keep_first, &ff, &d);
    if (e)
        snprintf(err, errlen, "%s", d.msg);
    alb_vp_destroy(vp);
    alb_gp_destroy(gp);
    alb_ws_buf_free(&b);
    alb_scene_free(&s);
    return e || !ff.got ? -1 : 0;
}

char *builtin_scene_copy(void)
{
    size_t len;
    const char *text = alb_scene_builtin_text(&len);
    char *copy = malloc(len + 1);
    if (copy) {
        memcpy(copy, text, len);
        copy[len] = 0;
    }
    return copy;
}

void profile_set_all(alb_profile *p, const char *sets)
{
    char buf[256], err[256];
    snprintf(buf, sizeof buf, "%s", sets);
    for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
        alb_profile_set(p, tok, err, sizeof err);
}

void small_profile(alb_profile *p, const char *sets)
{
    alb_profile_lookup("t32", p);
    p->width = p->height = 64;
    p->edge_frac_bits = 11;
    profile_set_all(p, sets);
}

static int stream_of_scene(const char *text, const alb_profile *p, alb_ws_buf *b, bool screen)
{
    alb_scene s;
    alb_diag d;
    alb_diag_init(&d, NULL);
    alb_ws_buf_init(b);
    if (alb_scene_parse(text, strlen(text), "t", &s, &d))
        return -1;
    alb_gp *gp = NULL;
    alb_err e = screen ? alb_scene_resolve_screenspace(&s, p->width, p->height, &d) : ALB_OK;
    if (!e)
        e = alb_gp_create(&gp, &s, p, &d);
    if (!e)
        e = alb_gp_run(gp, b, NULL, &d);
    alb_gp_destroy(gp);
    alb_scene_free(&s);
    return e ? -1 : 0;
}

int stream_of(const char *text, const alb_profile *p, alb_ws_buf *b)
{
    return stream_of_scene(text, p, b, false);
}

int screen_stream_of(const char *text, const alb_profile *p, alb_ws_buf *b)
{
    return stream_of_scene(text, p, b, true);
}

void vector_profile(const char *name, alb_profile *p)
{
    char path[600], opts[1024] = "";
    snprintf(path, sizeof path, "test-vectors/%s/options", name);
    FILE *f = fopen(path, "r");
    if (f) {
        size_t k = fread(opts, 1, sizeof opts - 1, f);
        opts[k] = 0;
        fclose(f);
    }
    alb_profile_lookup("a512", p);
    char err[256];
    for (char *tok = strtok(opts, " \n"); tok; tok = strtok(NULL, " \n")) {
        if (!strcmp(tok, "--profile") && (tok = strtok(NULL, " \n")))
            alb_profile_lookup(tok, p);
        else if (!strcmp(tok, "--set") && (tok = strtok(NULL, " \n")))
            alb_profile_set(p, tok, err, sizeof err);
    }
}

unsigned for_each_vector(vector_fn fn, void *ctx)
{
    DIR *dir = opendir("test-vectors");
    if (!dir)
        return 0;
    unsigned n = 0;
    struct dirent *de;
    while ((de = readdir(dir))) {
        if (de->d_name[0] == '.')
            continue;
        char path[600];
        snprintf(path, sizeof path, "test-vectors/%s/expected.stream", de->d_name);
        alb_ws_buf b;
        alb_ws_buf_init(&b);
        alb_diag d;
        alb_diag_init(&d, NULL);
        if (alb_ws_read_file(path, &b.w, &b.n, &d))
            continue;   /* not a vector */
        alb_profile p;
        vector_profile(de->d_name, &p);
        fn(de->d_name, &p, &b, ctx);
        alb_ws_buf_free(&b);
        n++;
    }
    closedir(dir);
    return n;
}

char *random_frames_stream(uint64_t seed, const scenegen_params *gp, unsigned extra,
                           const alb_profile *p, alb_ws_buf *b)
{
    char *text = scenegen_random(seed, gp), *more = NULL;
    if (text && (more = realloc(text, strlen(text) + 7 * extra + 1)) != NULL) {
        text = more;
        for (unsigned i = 0; i < extra; i++)
            strcat(text, "\nframe\n");
    }
    if (!more || stream_of(text, p, b)) {
        free(more ? more : text);
        return NULL;
    }
    return text;
}

