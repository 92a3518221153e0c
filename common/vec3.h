/* vec3.h — double-precision 3-vectors and 3x3 matrices for the GP and the
 * reference renderer (never used by the VP, which has no floating point). */
#ifndef ALBATROS_VEC3_H
#define ALBATROS_VEC3_H

#include "albatros/vec3.h"
#include "crmath.h"

#include <math.h>

#define VEC3_PI 3.14159265358979323846

/* The scene database's vector (public, albatros/vec3.h), by its short name
 * inside the project. */
typedef alb_vec3 vec3;

typedef struct {
    double m[3][3];   /* row-major: (M v)_i = sum_j m[i][j] v_j */
} mat3;

static inline vec3 v3(double x, double y, double z) { return (vec3){x, y, z}; }
static inline vec3 v3_add(vec3 a, vec3 b) { return v3(a.x + b.x, a.y + b.y, a.z + b.z); }
static inline vec3 v3_sub(vec3 a, vec3 b) { return v3(a.x - b.x, a.y - b.y, a.z - b.z); }
static inline vec3 v3_scale(vec3 a, double s) { return v3(a.x * s, a.y * s, a.z * s); }
static inline double v3_dot(vec3 a, vec3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
static inline double v3_len(vec3 a) { return sqrt(v3_dot(a, a)); }

/* eq. (16): the cross product, written out in the paper's order. */
static inline vec3 v3_cross(vec3 a, vec3 b)
{
    return v3(a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x);
}

static inline vec3 m3_apply(const mat3 *m, vec3 v)
{
    return v3(m->m[0][0] * v.x + m->m[0][1] * v.y + m->m[0][2] * v.z,
              m->m[1][0] * v.x + m->m[1][1] * v.y + m->m[1][2] * v.z,
              m->m[2][0] * v.x + m->m[2][1] * v.y + m->m[2][2] * v.z);
}

static inline mat3 m3_mul(const mat3 *a, const mat3 *b)
{
    mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[i][0] * b->m[0][j] + a->m[i][1] * b->m[1][j] + a->m[i][2] * b->m[2][j];
    return r;
}

static inline mat3 m3_transpose(const mat3 *a)
{
    mat3 r;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r.m[i][j] = a->m[j][i];
    return r;
}

/* (M^-1)^T = cofactor(M) / det(M): the T_k of eq. (3).  Returns 0 if singular. */
static inline int m3_inverse_transpose(const mat3 *a, mat3 *r)
{
    const double (*m)[3] = a->m;
    mat3 c;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++) {
            int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
            c.m[i][j] = m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1];
        }
    double det = m[0][0] * c.m[0][0] + m[0][1] * c.m[0][1] + m[0][2] * c.m[0][2];
    if (det == 0 || !isfinite(det))
        return 0;
    for (int i = 0; i < 3; i++)
        for (int j = 0; j < 3; j++)
            r->m[i][j] = c.m[i][j] / det;
    return 1;
}

/* Orientation from yaw (about y, toward +x), pitch (about x, toward +y) and
 * roll (about z, up toward +x), degrees; maps body axes to parent axes
 * (docs/scene-format.md, "Orientation").  Each angle is reduced modulo 360
 * exactly, then sin and cos are the correctly rounded ones of crmath.h, so
 * the matrix does not depend on the C library (docs/number-formats.md §0). */
static inline mat3 m3_orientation(double yaw_deg, double pitch_deg, double roll_deg)
{
    const double k = VEC3_PI / 180;
    double y = cr_deg_reduce(yaw_deg) * k, p = cr_deg_reduce(pitch_deg) * k,
           r = cr_deg_reduce(roll_deg) * k;
    double cy = cr_cos(y), sy = cr_sin(y), cp = cr_cos(p), sp = cr_sin(p);
    double cr = cr_cos(r), sr = cr_sin(r);
    mat3 ry = {{{cy, 0, sy}, {0, 1, 0}, {-sy, 0, cy}}};
    mat3 rx = {{{1, 0, 0}, {0, cp, sp}, {0, -sp, cp}}};
    mat3 rz = {{{cr, sr, 0}, {-sr, cr, 0}, {0, 0, 1}}};
    mat3 t = m3_mul(&ry, &rx);
    return m3_mul(&t, &rz);
}

/* The orientation of an eye at `eye` looking toward `at` with `up` up (its
 * body axes in the parent frame, as m3_orientation's columns): z the unit
 * view direction, x = up x z normalised (right, in this left-handed frame),
 * y = z x x.  Square roots only: no angle, no C library function but the
 * correctly rounded sqrt. */
/* v / |v|; where |v| over- or underflows (a component near 1e308, a
 * denormal) v is first divided by its largest component, so a direction
 * the command line accepts (alb_scene_camera_check) has a unit vector.
 * Every other v gets v * (1 / |v|), bit for bit as before. */
static inline vec3 v3_unit_robust(vec3 v)
{
    double l = v3_len(v);
    if (l > 0 && isfinite(l) && isfinite(1 / l))
        return v3_scale(v, 1 / l);
    double m = fmax(fabs(v.x), fmax(fabs(v.y), fabs(v.z)));
    if (!(m > 0) || !isfinite(m))
        return v3_scale(v, 1 / l);
    vec3 s = {v.x / m, v.y / m, v.z / m};
    return v3_scale(s, 1 / v3_len(s));
}

static inline mat3 m3_look_at(vec3 eye, vec3 at, vec3 up)
{
    vec3 z = v3_unit_robust(v3_sub(at, eye));
    vec3 x = v3_unit_robust(v3_cross(up, z));
    vec3 y = v3_cross(z, x);
    mat3 m = {{{x.x, y.x, z.x}, {x.y, y.y, z.y}, {x.z, y.z, z.z}}};
    return m;
}

#endif
