/* gp_helpers.c — see gp_helpers.h. */
#include "gp_helpers.h"

#include <stdlib.h>
#include <string.h>

int gp_run_text(const char *text, const char *sets, gp_run_result *r)
{
    memset(r, 0, sizeof *r);
    profile_t p;
    profile_lookup("a512", &p);
    if (sets) {
        char buf[512];
        snprintf(buf, sizeof buf, "%s", sets);
        for (char *tok = strtok(buf, " "); tok; tok = strtok(NULL, " "))
            if (profile_set(&p, tok, r->err, sizeof r->err))
                return -1;
    }
    scene_t s;
    diag_t d;
    diag_init(&d, NULL);
    if (scene_parse(text, strlen(text), "test.scene", &s, &d)) {
        snprintf(r->err, sizeof r->err, "%u:%u: %s", d.line, d.col, d.msg);
        return -1;
    }
    gp_t *gp = NULL;
    ws_buf_init(&r->buf);
    alb_err e = gp_create(&gp, &s, &p, &d);
    if (!e)
        e = gp_run(gp, &r->buf, &r->st, &d);
    gp_destroy(gp);
    scene_free(&s);
    if (e) {
        snprintf(r->err, sizeof r->err, "%s", d.msg);
        return -1;
    }
    ws_reader rd;
    ws_reader_init(&rd, r->buf.w, r->buf.n, "test");
    ws_event *ev = malloc(sizeof *ev);
    unsigned frames = 0;
    while (ev && !rd.ended && !(e = ws_next(&rd, ev, &d))) {
        if (ev->kind == WS_EV_CONFIG)
            r->cfg = ev->u.config;
        if (ev->kind == WS_EV_FRAME && frames++ == 0)
            r->frame = ev->u.frame;
        if (ev->kind == WS_EV_FACE && frames == 1) {
            ws_face *nf = realloc(r->faces, (r->nfaces + 1) * sizeof *nf);
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
    ws_buf_free(&r->buf);
    free(r->faces);
    r->faces = NULL;
}
