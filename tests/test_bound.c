/* test_bound.c — Fig. 2's sectors and the 64-entry bounding-edge table,
 * checked against geometry computed here from edge directions, not from the
 * table or the sector numbering. */
#include "t.h"
#include "../common/vec3.h"
#include "../gp/gp_internal.h"

#include <math.h>
#include <string.h>

#define DEG (VEC3_PI / 180)

/* The screen line of an edge traversed in direction theta (degrees) with the
 * face on its left: inside is A x + B y + C >= 0, so (A, B) is the left normal. */
static gp_line line_of_direction(double theta)
{
    return (gp_line){-sin(theta * DEG), cos(theta * DEG), 0};
}

/* Fig. 2 read geometrically: sector n holds the directions from 180 + 45(n-1)
 * to 180 + 45 n degrees (counter-clockwise from +x). */
static unsigned sector_by_angle(double theta)
{
    double a = fmod(theta - 180 + 720, 360);
    return (unsigned)(a / 45) + 1;
}

TEST(sectors_of_fig2)
{
    for (double theta = 0.05; theta < 360; theta += 0.1) {
        if (fabs(fmod(theta, 45)) < 0.01)
            continue;
        gp_line l = line_of_direction(theta);
        unsigned s = gp_sector(gp_sgn(l.a), gp_sgn(l.b), gp_line_u(l));
        CHECK_MSG(s == sector_by_angle(theta), "direction %.2f: sector %u, expected %u", theta, s,
                  sector_by_angle(theta));
    }
    /* the paper's table row by row: + - 0 -> 1, ..., - - 0 -> 8 */
    static const unsigned rows[8][4] = {{0, 1, 0, 1}, {0, 1, 1, 2}, {0, 0, 1, 3}, {0, 0, 0, 4},
                                        {1, 0, 0, 5}, {1, 0, 1, 6}, {1, 1, 1, 7}, {1, 1, 0, 8}};
    for (int i = 0; i < 8; i++)
        CHECK_EQ(gp_sector(rows[i][0], rows[i][1], rows[i][2]), rows[i][3]);
}

/* Signed turn from direction a to direction b in degrees, in (-180, 180]. */
static double turn(double a, double b)
{
    double t = fmod(b - a + 720, 360);
    return t > 180 ? t - 360 : t;
}

/* Every direction whose (SgnA, SgnB, U) is the 3-bit code, sampled finely. */
static unsigned directions_with_code(unsigned code3, double *out, unsigned max)
{
    unsigned n = 0;
    for (double theta = 0.013; theta < 360 && n < max; theta += 0.25)
        if (gp_edge_code3(line_of_direction(theta)) == code3)
            out[n++] = theta;
    return n;
}

TEST(bounding_table_all_64_codes_against_angles)
{
    static double d1s[400], d2s[400];
    for (unsigned code = 0; code < 64; code++) {
        unsigned n1 = directions_with_code(code >> 3, d1s, 400);
        unsigned n2 = directions_with_code(code & 7, d2s, 400);
        CHECK(n1 > 100 && n2 > 100);
        unsigned rom = gp_bound_rom[code];
        bool sharp_possible = false, all_ok = true;
        for (unsigned i = 0; i < n1; i += 3) {
            for (unsigned j = 0; j < n2; j += 3) {
                double t = turn(d1s[i], d2s[j]);
                if (!(t > 0 && t < 180))
                    continue;   /* not a convex counter-clockwise vertex */
                double interior = 180 - t;
                if (interior < 45)
                    sharp_possible = true;
                if (!(rom & BOUND_ROM_GEN))
                    continue;
                /* The bounding edge: axis-parallel line through the vertex,
                 * inside A x + B y >= 0 per U and R; it is traversed in
                 * direction (B, -A). */
                unsigned u = (rom & BOUND_ROM_U) != 0, r = rom & BOUND_ROM_R;
                double a = u ? (r ? -1 : 1) : 0, b = u ? 0 : (r ? -1 : 1);
                double beta = atan2(-a, b) / DEG;
                double t1 = turn(d1s[i], beta), t2 = turn(beta, d2s[j]);
                /* a supporting line (both turns >= 0: the face is inside) and
                 * both new angles 180 - turn at least 45 degrees */
                if (!(t1 >= -1e-9 && t2 >= -1e-9 && t1 <= 135 + 1e-9 && t2 <= 135 + 1e-9 &&
                      fabs(t1 + t2 - t) < 1e-6)) {
                    if (all_ok)
                        t_fail(__FILE__, __LINE__, "code %u: directions %.2f %.2f: turns %.2f %.2f",
                               code, d1s[i], d2s[j], t1, t2);
                    all_ok = false;
                }
            }
        }
        CHECK_MSG(((rom & BOUND_ROM_GEN) != 0) == sharp_possible,
                  "code %u: table says %s, geometry says an angle under 45 degrees is %s", code,
                  rom & BOUND_ROM_GEN ? "generate" : "none",
                  sharp_possible ? "possible" : "impossible");
        CHECK(all_ok);
        /* the paper's formula on the sector numbers agrees too */
        unsigned s1 = gp_sector(code >> 5 & 1, code >> 4 & 1, code >> 3 & 1);
        unsigned s2 = gp_sector(code >> 2 & 1, code >> 1 & 1, code & 1);
        CHECK_EQ(((s1 + 4 - s2) % 8 < 2), (rom & BOUND_ROM_GEN) != 0);
        /* both vertical -> horizontal bounding edge; both horizontal -> vertical */
        if ((rom & BOUND_ROM_GEN) && ((code >> 3 & 1) == (code & 1)))
            CHECK_EQ((rom & BOUND_ROM_U) != 0, !(code & 1));
    }
}

/* A convex polygon with vertices on a circle at random angles. */
static unsigned random_convex(uint64_t *seed, vec3 *p)
{
    unsigned n = 3 + (unsigned)(t_rand(seed) % 8);
    double ang[16];
    for (unsigned k = 0; k < n; k++)
        ang[k] = t_uniform(seed, 0, 360);
    for (unsigned i = 1; i < n; i++)
        for (unsigned j = i; j > 0 && ang[j - 1] > ang[j]; j--) {
            double t = ang[j];
            ang[j] = ang[j - 1];
            ang[j - 1] = t;
        }
    for (unsigned k = 0; k < n; k++)
        p[k] = v3(cos(ang[k] * DEG) * 0.5, sin(ang[k] * DEG) * 0.3, 1);
    return n;
}

TEST(at_most_two_bounding_edges_per_convex_polygon)
{
    uint64_t seed = 7;
    unsigned worst = 0;
    for (int trial = 0; trial < 20000; trial++) {
        vec3 p[16];
        unsigned n = random_convex(&seed, p), gen = 0;
        for (unsigned k = 0; k < n; k++) {
            vec3 e1 = v3_cross(p[(k + n - 1) % n], p[k]), e2 = v3_cross(p[k], p[(k + 1) % n]);
            gp_line l1 = {e1.x, e1.y, e1.z}, l2 = {e2.x, e2.y, e2.z};
            if ((l1.a == 0 && l1.b == 0) || (l2.a == 0 && l2.b == 0))
                continue;
            gen += (gp_bound_rom[gp_edge_code3(l1) << 3 | gp_edge_code3(l2)] & BOUND_ROM_GEN) != 0;
        }
        if (gen > worst)
            worst = gen;
    }
    CHECK_MSG(worst <= 2, "a convex polygon got %u bounding edges", worst);
    CHECK(worst == 2);   /* and the rule does fire twice on some */
}
