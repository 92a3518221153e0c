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
    m->flat = !gouraud;
    ref_frame_free(&rf);
    return 0;
}

/* ---- in the child ---- */

enum { ORDER_TIME = 1, ORDER_FACES = 2, ORDER_QUIT = 3 };

typedef struct {
    uint32_t order, frames;
} order;

typedef struct {
    double ms;                /* ORDER_TIME's answer; < 0: failed */
    char err[200];
} answer;

static int write_all(int fd, const void *p, size_t n)
{
    for (size_t done = 0; done < n;) {
        ssize_t k = write(fd, (const char *)p + done, n - done);
        if (k < 0 && errno == EINTR)
            continue;
        if (k <= 0)
            return -1;
        done += (size_t)k;
    }
    return 0;
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

/* The child: a context, the mesh in buffer objects, then orders until QUIT
 * or the parent goes.  Its first answer says whether the context is there. */
static int child(const peer_mesh *m, unsigned w, unsigned h, int in, int out)
{
    answer a;
    memset(&a, 0, sizeof a);
    uint8_t *buf = malloc((size_t)w * h * 4);
    OSMesaContext ctx = OSMesaCreateContextExt(OSMESA_RGBA, 24, 0, 0, NULL);
    if (!buf || !ctx || !OSMesaMakeCurrent(ctx, buf, GL_UNSIGNED_BYTE, (GLsizei)w, (GLsizei)h)) {
        snprintf(a.err, sizeof a.err, "OSMesa: no %ux%u RGBA context with a 24-bit depth buffer",
                 w, h);
        a.ms = -1;
    } else {
        const char *renderer = (const char *)glGetString(GL_RENDERER);
        if (!renderer || strncmp(renderer, "llvmpipe", 8)) {
            snprintf(a.err, sizeof a.err, "OSMesa renders with '%s', not llvmpipe",
                     renderer ? renderer : "?");
            a.ms = -1;
        }
    }
    if (a.ms == 0) {
        glViewport(0, 0, (GLsizei)w, (GLsizei)h);
        glDisable(GL_DITHER);   /* the face codes must come back exactly */
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LESS);   /* the earlier face keeps a tie, as in the VP */
        glShadeModel(m->flat ? GL_FLAT : GL_SMOOTH);
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
    }
    int rc = write_all(out, &a, sizeof a) || a.ms < 0;
    order o;
    while (!rc && !read_all(in, &o, sizeof o) && o.order != ORDER_QUIT) {
        if (o.order == ORDER_TIME) {
            double t0 = now();
            for (uint32_t f = 0; f < o.frames; f++) {
                glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
                glDrawArrays(GL_TRIANGLES, 0, (GLsizei)m->nverts);
                glFinish();
            }
            a.ms = 1e3 * (now() - t0) / (o.frames ? o.frames : 1);
            if (glGetError() != GL_NO_ERROR) {
                snprintf(a.err, sizeof a.err, "OpenGL error drawing the mesh");
                a.ms = -1;
            }
            rc = write_all(out, &a, sizeof a);
        } else {
            /* row 0 of the window is its bottom; of the frame, its top */
            uint32_t *face = malloc((size_t)w * h * sizeof *face);
            uint8_t *px = malloc((size_t)w * h * 4);
            if (!face || !px) {
                free(face);
                free(px);
                break;
            }
            glReadPixels(0, 0, (GLsizei)w, (GLsizei)h, GL_RGBA, GL_UNSIGNED_BYTE, px);
            for (unsigned y = 0; y < h; y++)
                for (unsigned x = 0; x < w; x++) {
                    const uint8_t *c = px + 4 * ((size_t)(h - 1 - y) * w + x);
                    uint32_t code = (uint32_t)c[0] | (uint32_t)c[1] << 8 | (uint32_t)c[2] << 16;
                    face[(size_t)y * w + x] = code ? code - 1 : 0xFFFFFFFFu;
                }
            rc = write_all(out, face, (size_t)w * h * sizeof *face);
            free(face);
            free(px);
        }
    }
    if (ctx)
        OSMesaDestroyContext(ctx);
    free(buf);
    return rc ? 1 : 0;
}

struct peer {
    pid_t pid;
    int to, from;             /* orders in, answers out */
    unsigned w, h;
};

peer *peer_start(const peer_mesh *m, unsigned w, unsigned h, unsigned threads, char *err,
                 size_t len)
{
    int down[2], up[2];
    if (pipe(down)) {
        snprintf(err, len, "pipe: %s", strerror(errno));
        return NULL;
    }
    if (pipe(up)) {
        snprintf(err, len, "pipe: %s", strerror(errno));
        close(down[0]);
        close(down[1]);
        return NULL;
    }
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid == 0) {
        close(down[1]);
        close(up[0]);
        char n[16];
        snprintf(n, sizeof n, "%u", threads);
        setenv("LP_NUM_THREADS", n, 1);
        setenv("GALLIUM_DRIVER", "llvmpipe", 1);
        _exit(child(m, w, h, down[0], up[1]));
    }
    close(down[0]);
    close(up[1]);
    peer *p = pid > 0 ? malloc(sizeof *p) : NULL;
    if (!p) {
        snprintf(err, len, pid < 0 ? "fork: %s" : "out of memory", strerror(errno));
        close(down[1]);
        close(up[0]);
        if (pid > 0)
            waitpid(pid, NULL, 0);
        return NULL;
    }
    *p = (peer){pid, down[1], up[0], w, h};
    answer a;
    if (read_all(p->from, &a, sizeof a) || a.ms < 0) {
        snprintf(err, len, "%s", a.ms < 0 ? a.err : "the llvmpipe child died before answering");
        peer_stop(p);
        return NULL;
    }
    return p;
}

double peer_time(peer *p, unsigned frames)
{
    order o = {ORDER_TIME, frames};
    answer a;
    if (write_all(p->to, &o, sizeof o) || read_all(p->from, &a, sizeof a))
        return -1;
    return a.ms;
}

int peer_faces(peer *p, uint32_t *face)
{
    order o = {ORDER_FACES, 0};
    if (write_all(p->to, &o, sizeof o))
        return -1;
    return read_all(p->from, face, (size_t)p->w * p->h * sizeof *face);
}

void peer_stop(peer *p)
{
    if (!p)
        return;
    order o = {ORDER_QUIT, 0};
    write_all(p->to, &o, sizeof o);
    close(p->to);
    close(p->from);
    int status;
    while (waitpid(p->pid, &status, 0) < 0 && errno == EINTR)
        ;
    free(p);
}
