/* peer.c — Mesa's llvmpipe through OSMesa as the bench's peer (see peer.h).
 * The faces come from the exact reference's observer space (tools/ref.c), so
 * both renderers see the same geometry; the vertex data is uploaded once
 * into a buffer object and every timed frame is a clear, one draw and a
 * glFinish (which waits for llvmpipe's rasterizer threads). */
#define _POSIX_C_SOURCE 200809L
#define GL_GLEXT_PROTOTYPES
#include "peer.h"
#include "ref.h"

#include <GL/osmesa.h>
#include <GL/gl.h>
#include <GL/glext.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

void peer_mesh_free(peer_mesh *m)
{
    free(m->xyzw);
    free(m->rgba);
    memset(m, 0, sizeof *m);
}

/* The vertex's intensity (0..1) where the face has one per vertex. */
static double vertex_intensity(const ref_face *f, unsigned k)
{
    const alb_scene_vertex *v = &f->obj->v[f->obj->idx[f->face->first + k]];
    if (f->face->shade == ALB_SHADE_VERTEX && (v->has & ALB_SV_INTENSITY))
        return v->i;
    return f->face->shade == ALB_SHADE_FLAT ? f->face->intensity : 1;
}

int peer_mesh_of(const alb_scene *s, const alb_profile *p, unsigned frame, bool gouraud,
                 peer_mesh *m)
{
    memset(m, 0, sizeof *m);
    ref_frame rf;
    if (ref_prepare(s, p, frame, &rf))
        return -1;
    size_t tris = 0;
    for (unsigned i = 0; i < rf.n; i++)
        tris += rf.faces[i].n - 2;
    /* the near plane at half the scene's `near`: the VP saturates nearer
     * than near, so what is cut off lies where the VP decides nothing
     * either (faces crossing Z = 0 are clipped there, the VP keeps Z > 0) */
    double n = s->near / 2;
    m->xyzw = malloc((tris ? tris : 1) * 3 * 4 * sizeof *m->xyzw);
    m->rgba = malloc((tris ? tris : 1) * 3 * 4);
    if (!m->xyzw || !m->rgba) {
        ref_frame_free(&rf);
        peer_mesh_free(m);
        return -1;
    }
    for (unsigned i = 0; i < rf.n; i++) {
        const ref_face *f = &rf.faces[i];
        uint32_t code = f->id + 1;
        for (unsigned t = 1; t + 1 < f->n; t++) {
            const unsigned corner[3] = {0, t, t + 1};
            for (int j = 0; j < 3; j++) {
                const vec3 *v = &f->v[corner[j]];
                float *x = m->xyzw + 4 * m->nverts;
                uint8_t *c = m->rgba + 4 * m->nverts;
                x[0] = (float)v->x, x[1] = (float)v->y, x[2] = (float)(v->z - 2 * n);
                x[3] = (float)v->z;
                if (gouraud) {
                    double in = vertex_intensity(f, corner[j]);
                    for (int ch = 0; ch < 3; ch++)
                        c[ch] = (uint8_t)lround(f->face->rgb[ch] * fmin(fmax(in, 0), 1));
                } else {
                    c[0] = (uint8_t)code, c[1] = (uint8_t)(code >> 8), c[2] = (uint8_t)(code >> 16);
                }
                c[3] = 255;
                m->nverts++;
            }
        }
    }
    ref_frame_free(&rf);
    return 0;
}

/* ---- in the child ---- */

typedef struct {
    peer_result r;
    char err[200];
} child_report;

static int child(const peer_mesh *m, unsigned w, unsigned h, unsigned frames, bool want_faces,
                 int fd)
{
    child_report rep;
    memset(&rep, 0, sizeof rep);
    uint8_t *buf = malloc((size_t)w * h * 4);
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (!buf || !ctx || !OSMesaMakeCurrent(ctx, buf, GL_UNSIGNED_BYTE, (GLsizei)w, (GLsizei)h)) {
        snprintf(rep.err, sizeof rep.err, "OSMesa: no %ux%u RGBA context with a 24-bit depth "
                 "buffer", w, h);
        rep.r.ms = -1;
    } else {
        const char *renderer = (const char *)glGetString(GL_RENDERER);
        if (!renderer || strncmp(renderer, "llvmpipe", 8)) {
            snprintf(rep.err, sizeof rep.err, "OSMesa renders with '%s', not llvmpipe",
                     renderer ? renderer : "?");
            rep.r.ms = -1;
        }
    }
    if (rep.r.ms == 0) {
        glViewport(0, 0, (GLsizei)w, (GLsizei)h);
        glDisable(GL_DITHER);   /* the face codes must come back exactly */
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);   /* the earlier face keeps a tie, as in the VP */
        glShadeModel(want_faces ? GL_FLAT : GL_SMOOTH);
        glClearColor(0, 0, 0, 0);
        glClearDepth(1);
        GLuint vbo[2];
        glGenBuffers(2, vbo);
        glBindBuffer(GL_ARRAY_BUFFER, vbo[0]);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(m->nverts * 4 * sizeof *m->xyzw), m->xyzw,
                     GL_STATIC_DRAW);
        glVertexPointer(4, GL_FLOAT, 0, NULL);
        glBindBuffer(GL_ARRAY_BUFFER, vbo[1]);
        glBufferData(GL_ARRAY_BUFFER, (GLsizeiptr)(m->nverts * 4), m->rgba, GL_STATIC_DRAW);
        glColorPointer(4, GL_UNSIGNED_BYTE, 0, NULL);
        glEnableClientState(GL_VERTEX_ARRAY);
        glEnableClientState(GL_COLOR_ARRAY);
        double best = INFINITY;
        for (int run = -1; run < 3; run++) {   /* run -1 warms up */
            double t0 = now();
            for (unsigned f = 0; f < frames; f++) {
                glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                glDrawArrays(GL_TRIANGLES, 0, (GLsizei)m->nverts);
                glFinish();
            }
            double ms = 1e3 * (now() - t0) / frames;
            if (run >= 0 && ms < best)
                best = ms;
        }
        rep.r.ms = best;
        rep.r.have_faces = want_faces;
        if (glGetError() != GL_NO_ERROR) {
            snprintf(rep.err, sizeof rep.err, "OpenGL error drawing the mesh");
            rep.r.ms = -1;
        }
    }
    int ok = write(fd, &rep, sizeof rep) == (ssize_t)sizeof rep;
    if (ok && rep.r.ms >= 0 && want_faces) {
        /* row 0 of the window is its bottom; of the frame, its top */
        uint32_t *face = malloc((size_t)w * h * sizeof *face);
        uint8_t *px = malloc((size_t)w * h * 4);
        ok = face && px;
        if (ok) {
            glReadPixels(0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_UNSIGNED_BYTE, px);
            for (unsigned y = 0; y < h; y++)
                for (unsigned x = 0; x < w; x++) {
                    const uint8_t *c = px + 4 * ((size_t)(h - 1 - y) * w + x);
                    uint32_t code = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16;
                    face[(size_t)y * w + x] = code ? code - 1 : 0xFFFFFFFFu;
                }
            size_t want = (size_t)w * h * sizeof *face;
            for (size_t done = 0; ok && done < want;) {
                ssize_t k = write(fd, (const char *)face + done, want - done);
                ok = k > 0;
                done += ok ? (size_t)k : 0;
            }
        }
        free(face);
        free(px);
    }
    if (ctx)
        OSMesaDestroyContext(ctx);
    free(buf);
    return ok ? 0 : 1;
}

static int read_all(int fd, void *p, size_t n)
{
    for (size_t done = 0; done < n;) {
        ssize_t k = read(fd, (char *)p + done, n - done);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -1;
        done += (size_t)k;
    }
    return 0;
}

int peer_measure(const peer_mesh *m, unsigned w, unsigned h, unsigned threads, unsigned frames,
                 peer_result *r, uint32_t *face, char *err, size_t len)
{
    int fd[2];
    if (pipe(fd)) {
        snprintf(err, len, "pipe: %s", strerror(errno));
        return -1;
    }
    fflush(stdout);
    pid_t pid = fork();
    if (pid < 0) {
        snprintf(err, len, "fork: %s", strerror(errno));
        close(fd[0]);
        close(fd[1]);
        return -1;
    }
    if (pid == 0) {
        close(fd[0]);
        char n[16];
        snprintf(n, sizeof n, "%u", threads);
        setenv("LP_NUM_THREADS", n, 1);
        setenv("GALLIUM_DRIVER", "llvmpipe", 1);
        _exit(child(m, w, h, frames, face != NULL, fd[1]));
    }
    close(fd[1]);
    child_report rep;
    int rc = read_all(fd[0], &rep, sizeof rep);
    if (!rc && rep.r.ms < 0) {
        snprintf(err, len, "%s", rep.err);
        rc = -1;
    } else if (rc) {
        snprintf(err, len, "the llvmpipe child died before reporting");
    } else if (face && read_all(fd[0], face, (size_t)w * h * sizeof *face)) {
        snprintf(err, len, "the llvmpipe child's face map was cut short");
        rc = -1;
    }
    close(fd[0]);
    int status;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (!rc)
        *r = rep.r;
    return rc;
}
