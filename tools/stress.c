/* stress.c — the stress families of stress.h.  Each builds its geometry in
 * observer space (observer at the origin, fov 90, square), writes every face
 * as its own object, and turns each face to show its front to the observer,
 * so that what a scene claims (the severity) can be read back from its
 * vertices. */
#include "stress.h"
#include "../common/vec3.h"

#include <math.h>
#include <stdarg.h>
#include <stdbool.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    char *s;
    size_t n, cap;
    bool oom;
} st_buf;

static void __attribute__((format(printf, 2, 3))) put(st_buf *b, const char *fmt, ...)
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
        if (b->oom)
            return;
        size_t cap = b->cap ? 2 * b->cap : 4096;
        while (k >= 0 && cap - b->n <= (size_t)k)
            cap *= 2;
        char *s = realloc(b->s, cap);
        if (!s) {
            b->oom = true;
            return;
        }
        b->s = s;
        b->cap = cap;
    }
}

/* xorshift64*, as scenegen.c: seeded, the same scene on every host */
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

static double clampd(double v, double lo, double hi) { return v < lo ? lo : v > hi ? hi : v; }

static void header(st_buf *b, const char *family, double severity, uint64_t seed)
{
    put(b, "albatros-scene 1\n# stress %s severity %.17g seed %llu\n", family, severity,
        (unsigned long long)seed);
    put(b, "observer fov 90 aspect 1\nbackground 0 0 0\n");
}

/* A random colour bright enough to tell faces apart in a view. */
static void colour(uint64_t *s, unsigned rgb[3])
{
    for (int k = 0; k < 3; k++)
        rgb[k] = 64 + (unsigned)(next(s) % 192);
}

/* One object holding one face with the vertices v (object space; the object
 * sits at `at`), wound so that its front faces the observer: the sum of
 * (R_k x R_k+1) . centroid over world points is positive (docs/gp.md).
 * `extra` goes on the face line (colour, texture, ...). */
static void face_object(st_buf *b, unsigned id, const vec3 *v, unsigned n, vec3 at,
                        const char *extra)
{
    vec3 c = {0, 0, 0};
    for (unsigned k = 0; k < n; k++)
        c = v3_add(c, v3_scale(v3_add(v[k], at), 1.0 / n));
    double side = 0;
    for (unsigned k = 0; k < n; k++)
        side += v3_dot(v3_cross(v3_add(v[k], at), v3_add(v[(k + 1) % n], at)), c);
    put(b, "object s%u at %.17g %.17g %.17g\n", id, at.x, at.y, at.z);
    for (unsigned k = 0; k < n; k++) {
        const vec3 *q = &v[side < 0 ? n - 1 - k : k];
        put(b, " v %.17g %.17g %.17g\n", q->x, q->y, q->z);
    }
    put(b, " f");
    for (unsigned k = 0; k < n; k++)
        put(b, " %u", k + 1);
    put(b, " %s\nend\n", extra);
}

static void face_coloured(st_buf *b, unsigned id, const vec3 *v, unsigned n, uint64_t *s)
{
    unsigned rgb[3];
    char extra[64];
    colour(s, rgb);
    snprintf(extra, sizeof extra, "colour %u %u %u", rgb[0], rgb[1], rgb[2]);
    face_object(b, id, v, n, v3(0, 0, 0), extra);
}

/* A rectangle parallel to the screen at depth z: screen x0..x1, y0..y1. */
static void screen_rect(vec3 v[4], double x0, double y0, double x1, double y1, double z)
{
    v[0] = v3(x0 * z, y0 * z, z), v[1] = v3(x1 * z, y0 * z, z);
    v[2] = v3(x1 * z, y1 * z, z), v[3] = v3(x0 * z, y1 * z, z);
}

/* A backdrop filling the view behind everything: what shows through cracks. */
static void backdrop(st_buf *b, unsigned id, double z)
{
    vec3 v[4];
    screen_rect(v, -1.5, -1.5, 1.5, 1.5, z);
    face_object(b, id, v, 4, v3(0, 0, 0), "colour 40 40 40");
}

/* ---- the families ---- */

/* Isosceles triangles whose tip angle is the severity (as scenegen_slivers). */
static void gen_sliver(st_buf *b, double angle, uint64_t *s)
{
    backdrop(b, 0, 10);
    for (unsigned k = 0; k < 8; k++) {
        double th = uniform(s, 0, 2 * VEC3_PI), len = uniform(s, 0.6, 1.2);
        double cx = uniform(s, -0.4, 0.4), cy = uniform(s, -0.4, 0.4), z = 5 + 0.01 * k;
        double w = len * cr_tan(angle * VEC3_PI / 360), dx = cr_cos(th), dy = cr_sin(th);
        vec3 v[3] = {v3((cx + dy * w) * z, (cy - dx * w) * z, z),
                     v3((cx + dx * len) * z, (cy + dy * len) * z, z),
                     v3((cx - dy * w) * z, (cy + dx * w) * z, z)};
        face_coloured(b, k + 1, v, 3, s);
    }
}

/* Floor, two walls and a ceiling running from Z = -f L to (1 - f) L, each
 * wall touching floor and ceiling along its edges (no penetration), and two
 * faces wholly behind the observer (never drawn). */
static void gen_crossing(st_buf *b, double f, uint64_t *s)
{
    const double L = 20, z0 = -f * L, z1 = (1 - f) * L;
    double ya = uniform(s, 1.5, 3), yb = uniform(s, 1.5, 3);   /* ceiling height at z0, z1 */
    unsigned id = 0;
    backdrop(b, id++, 40);
    vec3 floor[4] = {v3(-3, -1, z0), v3(3, -1, z0), v3(3, -1, z1), v3(-3, -1, z1)};
    face_coloured(b, id++, floor, 4, s);
    for (int side = -1; side <= 1; side += 2) {
        double xa = side * uniform(s, 1.5, 2.8), xb = side * uniform(s, 1.5, 2.8);
        vec3 wall[4] = {v3(xa, -1, z0), v3(xb, -1, z1), v3(xb, yb, z1), v3(xa, ya, z0)};
        face_coloured(b, id++, wall, 4, s);
    }
    vec3 ceiling[4] = {v3(-3, ya, z0), v3(-3, yb, z1), v3(3, yb, z1), v3(3, ya, z0)};
    face_coloured(b, id++, ceiling, 4, s);
    for (int k = 0; k < 2; k++) {
        double z = -uniform(s, 1, 5);
        vec3 v[4];
        screen_rect(v, -0.5, -0.5, 0.5, 0.5, z);   /* behind: mirrored through the eye */
        face_coloured(b, id++, v, 4, s);
    }
}

/* A face at distance D in front of a larger one at D + 1, the farther first
 * in the stream: where depth cannot tell them apart, the farther wins. */
static void gen_far(st_buf *b, double D, uint64_t *s)
{
    vec3 v[4];
    double ox = uniform(s, -0.1, 0.1), oy = uniform(s, -0.1, 0.1);
    screen_rect(v, -0.6 + ox, -0.6 + oy, 0.6 + ox, 0.6 + oy, D + 1);
    face_coloured(b, 0, v, 4, s);
    screen_rect(v, -0.8, -0.4 + oy, 0.2 + ox, 0.4, D);
    face_coloured(b, 1, v, 4, s);
}

/* A 4 x 4 period checkered face S periods from its texture origin: object
 * vertices at X = S .. S + 4, the object moved back into view. */
static void gen_texture_far(st_buf *b, double S, uint64_t *s)
{
    put(b, "texture chk checker 6 230 230 230 30 30 30 8\n");
    double y0 = uniform(s, -2.5, -1.5), z = uniform(s, 5, 7);
    vec3 v[4] = {v3(S, y0, 0), v3(S + 4, y0, 0), v3(S + 4, y0 + 4, 0), v3(S, y0 + 4, 0)};
    /* u = X, v = Y: one period per unit */
    face_object(b, 0, v, 4, v3(-S - 2, 0, z), "colour 255 255 255 texture chk axes 1 0 0 0 0 1 0 0");
}

/* Two quads crossing along a line through (0, y0, 6) at the severity's angle;
 * the pair rolled about the view axis. */
static void gen_interpenetrating(st_buf *b, double angle, uint64_t *s)
{
    double th = angle * VEC3_PI / 180, y0 = uniform(s, -0.5, 0.5), roll = uniform(s, 0, 360);
    double cr = cr_cos(roll * VEC3_PI / 180), sr = cr_sin(roll * VEC3_PI / 180);
    vec3 a[4], c[4];
    screen_rect(a, -0.5, -0.5, 0.5, 0.5, 6);
    const double xs[4] = {-2.5, 2.5, 2.5, -2.5}, ss[4] = {-3, -3, 3, 3};
    for (int k = 0; k < 4; k++)
        c[k] = v3(xs[k], y0 + ss[k] * cr_cos(th), 6 + ss[k] * cr_sin(th));
    for (int k = 0; k < 4; k++) {   /* roll both about the z axis */
        a[k] = v3(cr * a[k].x - sr * a[k].y, sr * a[k].x + cr * a[k].y, a[k].z);
        c[k] = v3(cr * c[k].x - sr * c[k].y, sr * c[k].x + cr * c[k].y, c[k].z);
    }
    face_coloured(b, 0, a, 4, s);
    face_coloured(b, 1, c, 4, s);
}

/* Three bars along the sides of a triangle, each nearer than the next where
 * they cross (0 over 1 over 2 over 0).  Built on the screen: bar i is a
 * rectangle of width w along line i, lifted onto the plane whose 1/Z falls
 * linearly from its crossing with bar i + 1 (near) to bar i - 1 (far). */
static void gen_cyclic(st_buf *b, double sigma, uint64_t *s)
{
    const double R = 0.5, Z0 = 10, dz = 1;
    double rot = uniform(s, 0, 2 * VEC3_PI), px[3], py[3];
    for (int i = 0; i < 3; i++) {   /* crossing X(i, i+1) */
        px[i] = R * cr_cos(rot + 2 * VEC3_PI * i / 3), py[i] = R * cr_sin(rot + 2 * VEC3_PI * i / 3);
    }
    double side = R * sqrt(3), w = sigma * side, ext = 0.6 * w + 0.1;
    unsigned first = (unsigned)(next(s) % 3);
    for (unsigned j = 0; j < 3; j++) {
        unsigned i = (first + j) % 3, prev = (i + 2) % 3;
        double ax = px[prev], ay = py[prev], bx = px[i], by = py[i];   /* far end, near end */
        double dx = (bx - ax) / side, dy = (by - ay) / side, nx = -dy, ny = dx;
        double qf = 1 / (Z0 + dz), qn = 1 / (Z0 - dz), k = (qn - qf) / side;
        const double along[4] = {-ext, side + ext, side + ext, -ext};
        const double across[4] = {-w / 2, -w / 2, w / 2, w / 2};
        vec3 v[4];
        for (int c = 0; c < 4; c++) {
            double x = ax + along[c] * dx + across[c] * nx, y = ay + along[c] * dy + across[c] * ny;
            double z = 1 / (qf + k * along[c]);   /* 1/Z linear along the bar */
            v[c] = v3(x * z, y * z, z);
        }
        face_coloured(b, i, v, 4, s);
    }
}

/* Triangles of base 0.8 (screen) whose apex is height = ratio x base off the
 * base, at 20-80% along it. */
static void gen_degenerate(st_buf *b, double ratio, uint64_t *s)
{
    backdrop(b, 0, 10);
    for (unsigned k = 0; k < 10; k++) {
        double th = uniform(s, 0, 2 * VEC3_PI), base = 0.8, t = uniform(s, 0.2, 0.8);
        double cx = uniform(s, -0.3, 0.3), cy = uniform(s, -0.3, 0.3), z = 5 + 0.01 * k;
        double dx = cr_cos(th), dy = cr_sin(th), h = ratio * base;
        double ax = cx - dx * base / 2, ay = cy - dy * base / 2;
        vec3 v[3] = {v3(ax * z, ay * z, z), v3((ax + dx * base) * z, (ay + dy * base) * z, z),
                     v3((ax + dx * base * t - dy * h) * z, (ay + dy * base * t + dx * h) * z, z)};
        face_coloured(b, k + 1, v, 3, s);
    }
}

/* A square of n rows, alternately n and 2n quads wide: the fine rows share
 * edges, and each fine vertex on a coarse row's edge is a T-junction.  One
 * object, tilted; a backdrop shows through any crack. */
static void gen_tjunction(st_buf *b, unsigned n, uint64_t *s)
{
    backdrop(b, 0, 14);
    const double half = 4;
    double yaw = uniform(s, -30, 30), pitch = uniform(s, -30, 30);
    put(b, "object mesh at 0 0 7 yaw %.17g pitch %.17g\n", yaw, pitch);
    /* vertices: n + 1 border lines of 2n + 1 points, left to right */
    for (unsigned j = 0; j <= n; j++)
        for (unsigned i = 0; i <= 2 * n; i++)
            put(b, " v %.17g %.17g 0\n", -half + 2 * half * i / (2 * n),
                half - 2 * half * j / n);
    for (unsigned j = 0; j < n; j++) {
        unsigned step = j % 2 ? 1 : 2;   /* fine rows: every point; coarse: every other */
        for (unsigned i = 0; i < 2 * n; i += step) {
            unsigned tl = j * (2 * n + 1) + i + 1, bl = tl + 2 * n + 1;
            /* counter-clockwise seen from -z (the observer's side) */
            put(b, " f %u %u %u %u colour %s\n", tl, bl, bl + step, tl + step,
                (i / step + j) % 2 ? "220 200 60" : "60 120 220");
        }
    }
    put(b, "end\n");
}

/* k squares stacked in depth, all covering the screen's centre square
 * [-0.25, 0.25]^2, in random stream order. */
static void gen_deep(st_buf *b, unsigned k, uint64_t *s)
{
    unsigned order[64];
    for (unsigned i = 0; i < k; i++)
        order[i] = i;
    for (unsigned i = k; i > 1; i--) {
        unsigned j = (unsigned)(next(s) % i), t = order[i - 1];
        order[i - 1] = order[j], order[j] = t;
    }
    for (unsigned i = 0; i < k; i++) {
        double hw = uniform(s, 0.3, 0.9), hh = uniform(s, 0.3, 0.9);
        double cx = uniform(s, -(hw - 0.25), hw - 0.25), cy = uniform(s, -(hh - 0.25), hh - 0.25);
        vec3 v[4];
        screen_rect(v, cx - hw, cy - hh, cx + hw, cy + hh, 4 + 0.25 * order[i]);
        face_coloured(b, i, v, 4, s);
    }
}

/* 10^e for the coords family, the same bits under any C library (pow's last
 * bit is the library's choice): 10^n of the nearest whole n by strtod of
 * "1en", correctly rounded by glibc and musl alike, times 10^f of the rest
 * (|f| <= 1/2) as e^(f ln 10) by 30 terms of its Taylor series in plain double arithmetic
 * (the build allows no contraction, docs/number-formats.md); within a few
 * ulps of the true value (tests/test_methods.c). */
double stress_pow10(double e)
{
    double n = floor(e + 0.5), x = (e - n) * 2.30258509299404568402, term = 1, frac = 1;
    char text[16];
    snprintf(text, sizeof text, "1e%d", (int)n);
    for (int k = 1; k <= 30; k++) {
        term *= x / k;
        frac += term;
    }
    return strtod(text, NULL) * frac;
}

/* Six tilted pentagons (one layout per seed, overlapping and, as they fall,
 * interpenetrating), every coordinate and `near` times 10^e: the same
 * picture at any scale. */
static void gen_coords(st_buf *b, double e, uint64_t *s)
{
    double scale = stress_pow10(e);
    put(b, "near %.17g\n", 0.1 * scale);
    for (unsigned k = 0; k < 6; k++) {
        double z = uniform(s, 4, 10), cx = uniform(s, -0.4, 0.4) * z, cy = uniform(s, -0.4, 0.4) * z;
        double r = z * uniform(s, 0.15, 0.35), tilt = uniform(s, -0.6, 0.6);
        vec3 v[5];
        for (int j = 0; j < 5; j++) {
            double a = 2 * VEC3_PI * j / 5 + uniform(s, -0.3, 0.3);
            double x = r * cr_cos(a), y = r * cr_sin(a);
            v[j] = v3_scale(v3(cx + x, cy + y, z + tilt * x), scale);
        }
        face_coloured(b, k, v, 5, s);
    }
}

/* ---- the table ---- */

typedef enum { ST_SLIVER, ST_CROSSING, ST_FAR, ST_TEXFAR, ST_INTER, ST_CYCLIC, ST_DEGEN, ST_TJUNC,
               ST_DEEP, ST_COORDS, ST_COUNT } st_family;

static const char *const family_names[ST_COUNT + 1] = {
    "sliver", "crossing-z0", "far", "texture-far", "interpenetrating", "cyclic", "degenerate",
    "tjunction", "deep", "coords", NULL,
};

/* The valid severities of each family (stress.h). */
static const double family_range[ST_COUNT][2] = {
    {1e-4, 60}, {0, 1}, {1, 1e12}, {0, 1125899906842624.0 /* 2^50 */}, {0.001, 80},
    {0.01, 0.4}, {1e-9, 1}, {1, 64}, {1, 64}, {-60, 60},
};

const char *const *stress_families(void) { return family_names; }

static void generate(st_buf *b, st_family f, double sev, uint64_t *s)
{
    switch (f) {
    case ST_SLIVER: gen_sliver(b, sev, s); break;
    case ST_CROSSING: gen_crossing(b, sev, s); break;
    case ST_FAR: gen_far(b, sev, s); break;
    case ST_TEXFAR: gen_texture_far(b, sev, s); break;
    case ST_INTER: gen_interpenetrating(b, sev, s); break;
    case ST_CYCLIC: gen_cyclic(b, sev, s); break;
    case ST_DEGEN: gen_degenerate(b, sev, s); break;
    case ST_TJUNC: gen_tjunction(b, (unsigned)sev, s); break;
    case ST_DEEP: gen_deep(b, (unsigned)sev, s); break;
    case ST_COORDS: gen_coords(b, sev, s); break;
    case ST_COUNT: break;
    }
}

char *stress_scene(const char *family, double severity, uint64_t seed)
{
    unsigned f = 0;
    while (f < ST_COUNT && strcmp(family_names[f], family) != 0)
        f++;
    if (f == ST_COUNT || isnan(severity))
        return NULL;
    double sev = clampd(severity, family_range[f][0], family_range[f][1]);
    if (f == ST_TJUNC || f == ST_DEEP)
        sev = floor(sev + 0.5);   /* counts */
    uint64_t s = seed * 0x9E3779B97F4A7C15ULL + 1;
    st_buf b = {0};
    header(&b, family_names[f], sev, seed);
    generate(&b, (st_family)f, sev, &s);
    if (b.oom) {
        free(b.s);
        return NULL;
    }
    return b.s;
}
