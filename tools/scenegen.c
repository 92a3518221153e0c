/* scenegen.c — seeded random scenes: convex polygons (cyclic, so convex by
 * construction) at random places, sizes and orientations in front of an
 * observer at the origin, overlapping and interpenetrating, some crossing
 * Z = 0 and some seen from the back. */
#include "scenegen.h"
#include "../common/vec3.h"

#include <math.h>
#include <stdbool.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char *s;
    size_t n, cap;
    int oom;
} text_buf;

static void __attribute__((format(printf, 2, 3))) put(text_buf *b, const char *fmt, ...)
{
    va_list ap;
    for (;;) {
        size_t room = b->cap - b->n;
        va_start(ap, fmt);
        int k = b->s ? vsnprintf(b->s + b->n, room, fmt, ap) : -1;
        va_end(ap);
        if (k >= 0 && (size_t)k < room) {
            b->n += (size_t)k;
            return;
        }
        size_t cap = b->cap ? 2 * b->cap : 4096;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->oom = 1;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

static uint64_t next(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1DULL;
}

static double uniform(uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * (double)(next(s) >> 11) * (1.0 / 9007199254740992.0);
}

scenegen_params scenegen_defaults(void)
{
    scenegen_params p = {12, 0.1, 0.1, 6, 0.3, false};
    return p;
}

/* One convex polygon: vertices on a circle at sorted random angles, in a
 * plane with a random normal, counter-clockwise seen from the observer
 * unless `back`. */
static bool polygon(text_buf *b, uint64_t *s, const scenegen_params *p, unsigned id, bool behind,
                    bool back)
{
    unsigned n = 3 + (unsigned)(next(s) % (unsigned)(p->max_vertices - 2));
    double z = uniform(s, 2, 20);
    vec3 c = v3(uniform(s, -0.8, 0.8) * z, uniform(s, -0.8, 0.8) * z, z);
    double r = z * p->size * uniform(s, 0.3, 1.7);
    if (behind) {
        c.z = uniform(s, 0.2, 1.5);
        r = uniform(s, 2.5, 6);
    }
    /* plane basis: a normal tilted at most 70 degrees from the view axis */
    double th = uniform(s, 0, 70) * VEC3_PI / 180, ph = uniform(s, 0, 2 * VEC3_PI);
    vec3 nrm = v3(cr_sin(th) * cr_cos(ph), cr_sin(th) * cr_sin(ph), -cr_cos(th));
    vec3 u = v3_cross(nrm, v3(0, 1, 0));
    u = v3_scale(u, 1 / v3_len(u));
    vec3 w = v3_cross(nrm, u);
    double ang[8];
    for (unsigned k = 0; k < n; k++)
        ang[k] = uniform(s, 0, 2 * VEC3_PI);
    for (unsigned i = 1; i < n; i++)
        for (unsigned j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
            double t = ang[j];
            ang[j] = ang[j - 1];
            ang[j - 1] = t;
        }
    vec3 v[8];
    for (unsigned k = 0; k < n; k++)
        v[k] = v3_add(c, v3_add(v3_scale(u, r * cr_cos(ang[k])), v3_scale(w, r * cr_sin(ang[k]))));
    /* reject near-duplicate angles, which make slivers of zero area */
    for (unsigned k = 0; k < n; k++)
        if (v3_len(v3_sub(v[k], v[(k + 1) % n])) < 1e-2 * r)
            return false;
    /* orientation: counter-clockwise on the screen (front) iff the sum of
     * (R_k x R_k+1) . centroid is positive (docs/gp.md) */
    double side = 0;
    for (unsigned k = 0; k < n; k++)
        side += v3_dot(v3_cross(v[k], v[(k + 1) % n]), c);
    bool flip = (side < 0) != back;
    put(b, "object f%u\n", id);
    /* 9 digits keep the planarity check's tolerance (relative to the face's
     * size) for the usual sizes; small faces far away need every digit */
    int dig = p->size >= 0.05 ? 9 : 17;
    for (unsigned k = 0; k < n; k++) {
        const vec3 *q = &v[flip ? n - 1 - k : k];
        double i = uniform(s, 0.2, 1);   /* drawn either way: flat keeps the geometry */
        if (p->flat)
            put(b, " v %.*g %.*g %.*g\n", dig, q->x, dig, q->y, dig, q->z);
        else
            put(b, " v %.*g %.*g %.*g i %.3f\n", dig, q->x, dig, q->y, dig, q->z, i);
    }
    put(b, " f");
    for (unsigned k = 0; k < n; k++)
        put(b, " %u", k + 1);
    put(b, " colour %u %u %u\nend\n", (unsigned)(next(s) % 256), (unsigned)(next(s) % 256),
        (unsigned)(next(s) % 256));
    return true;
}

char *scenegen_random(uint64_t seed, const scenegen_params *p)
{
    uint64_t s = seed * 0x9E3779B97F4A7C15ULL + 1;
    text_buf b = {0};
    put(&b, "albatros-scene 1\n# random scene, seed %llu\nnear 0.5\nbackground 0 0 0\n"
            "observer fov %.3f\n", (unsigned long long)seed, uniform(&s, 50, 90));
    for (unsigned i = 0; i < p->faces; i++) {
        bool behind = uniform(&s, 0, 1) < p->behind, back = uniform(&s, 0, 1) < p->backfacing;
        while (!polygon(&b, &s, p, i, behind, back))
            ;   /* a draw with near-coincident vertices: draw again */
    }
    if (b.oom) {
        free(b.s);
        return NULL;
    }
    return b.s;
}

char *scenegen_slivers(uint64_t seed, unsigned per_angle)
{
    static const double angles[] = {10, 5, 2, 1, 0.5, 0.2, 0.1, 0.05, 0.02, 0.01};
    uint64_t s = seed * 0x9E3779B97F4A7C15ULL + 1;
    text_buf b = {0};
    unsigned k = 0;
    put(&b, "albatros-scene 1\n# slivers, seed %llu\nobserver fov 90\nbackground 0 0 0\n",
        (unsigned long long)seed);
    for (size_t a = 0; a < sizeof angles / sizeof angles[0]; a++)
        for (unsigned rep = 0; rep < per_angle; rep++, k++) {
            double th = uniform(&s, 0, 2 * VEC3_PI), len = uniform(&s, 0.6, 1.4);
            double cx = uniform(&s, -0.5, 0.5), cy = uniform(&s, -0.5, 0.5);
            double w = len * cr_tan(angles[a] * VEC3_PI / 360), dx = cr_cos(th), dy = cr_sin(th);
            /* base corners, then the tip: counter-clockwise on the screen */
            double p[3][2] = {{cx + dy * w, cy - dx * w}, {cx + dx * len, cy + dy * len},
                              {cx - dy * w, cy + dx * w}};
            double z = 5 + 0.01 * k;
            put(&b, "object s%u\n", k);
            for (int v = 0; v < 3; v++)
                put(&b, " v %.12g %.12g %.12g\n", p[v][0] * z, p[v][1] * z, z);
            put(&b, " f 1 2 3 colour 255 255 255\nend\n");
        }
    if (b.oom) {
        free(b.s);
        return NULL;
    }
    return b.s;
}
