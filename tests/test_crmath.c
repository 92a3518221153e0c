/* test_crmath.c — the GP's correctly rounded sin, cos, tan and hypot
 * (common/crmath.c) against values computed independently with 500-bit
 * arithmetic (Python's mpmath, each checked to be the nearest double): the
 * first rows are arguments glibc 2.36 rounds the wrong way, the others
 * borders of the algorithm (the tiny-argument cut-offs, multiples of pi/2,
 * the end of the domain, the GP's usual field-of-view angles). */
#include "t.h"
#include "../common/crmath.h"
#include "../common/vec3.h"
#include "../gp/gp_internal.h"

#include <math.h>
#include <string.h>

static const double trig_table[][4] = {
    {0x1.2370b80258514p+2, -0x1.f992415646c79p-1, -0x1.43859aee90a99p-3, 0x1.900dd86539208p+2},
    {0x1.d5eb444233820p-3, 0x1.d1ce7215e3d13p-3, 0x1.f294bd0cd3e02p-1, 0x1.de57e345abfa3p-3},
    {-0x1.9f6297741ceccp+2, -0x1.a5548f6d7b523p-3, 0x1.f50c466f050a2p-1, -0x1.ae8a351a0b7f3p-3},
    {0x1.836c1e5482170p+2, -0x1.d2527cf6d3cf7p-3, 0x1.f28d0618a30a2p-1, -0x1.dee6e4ef94e5cp-3},
    {0x1.4db180be63a18p-1, 0x1.3690f03b637a7p-1, 0x1.970dba9ead2f1p-1, 0x1.86a2dd0b617d7p-1},
    {0x1.2c2f7d9a1b4a0p-2, 0x1.27e789c9ab5c1p-2, 0x1.ea2842337a219p-1, 0x1.35173b912ece5p-2},
    {0x1.3ee005e8080a7p-1, 0x1.2aa8256c0d123p-1, 0x1.9fdecbbb51d10p-1, 0x1.6fb1387803e65p-1},
    {-0x1.9bb591a575480p-3, -0x1.98f118a532f15p-3, 0x1.f5b06648e5b9dp-1, -0x1.a158b6b3268f1p-3},
    {0x1.8d147015f0650p-2, 0x1.8333f9afd2eb5p-2, 0x1.d9fc578403584p-1, 0x1.a241d9e135691p-2},
    {0x1.36d216ce8b39cp-4, 0x1.3685becf687bbp-4, 0x1.fe86ccde18d8ep-1, 0x1.376b2c5357c51p-4},
    {0x1.4b0ad11392d6ep+2, -0x1.cabee222e3bb2p-1, 0x1.c6bcad67aa7d1p-2, -0x1.0241b73a45be1p+1},
    {0x1.9d6ba21740496p+2, 0x1.679dd2558dce3p-3, 0x1.f80b7dc122fe5p-1, 0x1.6d4acaac564fbp-3},
    {0x1.105ea1c970358p+1, 0x1.b29571ca923f7p-1, -0x1.0eb45cda73235p-1, -0x1.9afa35da29546p+0},
    {0x1.a9e841a86428cp+2, 0x1.73d607022f8d7p-2, 0x1.dd0d478364b2ep-1, 0x1.8f1382b5211c3p-2},
    {0x1.263e02ece529dp-2, 0x1.2235b336f3763p-2, 0x1.eb01f964e6ebfp-1, 0x1.2e9e03a6cceaap-2},
    {0x1.10688bc4b6446p+0, 0x1.bfaad4bffcf9ap-1, 0x1.f0f14c928e83ep-2, 0x1.cd3b4fd8da115p+0},
    {0x1.362e0f6633873p-4, 0x1.35e22fff34049p-4, 0x1.fe885a62a1992p-1, 0x1.36c632afb820fp-4},
    {-0x1.17b18ff833f3ep+2, 0x1.e2515032a1240p-1, -0x1.57974f97243e9p-2, -0x1.675c7b17603c2p+1},
    {0x1.f7c311eec8500p+1, -0x1.6d2819187e83fp-1, -0x1.66e4c48cbb2fbp-1, 0x1.0477a925ee5d1p+0},
    {0x1.e58567386fadap-1, 0x1.9ff4f693fcf31p-1, 0x1.2a8944f4fb7dcp-1, 0x1.64b0b60fb3d83p+0},
    {0x1.28a51f7d204a3p+0, 0x1.d526b9197fb1ap-1, 0x1.9a14186414435p-2, 0x1.24e09d2043229p+1},
    {-0x1.114ce7317d204p+1, -0x1.b09a97d535658p-1, -0x1.11db7f88e1c09p-1, 0x1.9465246d60f86p+0},
    {-0x1.3743869f030fap+2, 0x1.fa2a6e58dfd24p-1, 0x1.344aaf78b9305p-3, 0x1.a44fa245413e6p+2},
    {0x1.b95ae30356e80p+0, 0x1.f9ffecdd9c8d6p-1, -0x1.389f51ae1eb49p-3, -0x1.9e5a4d9973608p+2},
    {0x1.0000000000000p-26, 0x1.0000000000000p-26, 0x1.fffffffffffffp-1, 0x1.0000000000000p-26},
    {0x1.0000000000001p-26, 0x1.0000000000001p-26, 0x1.fffffffffffffp-1, 0x1.0000000000001p-26},
    {0x1.0000000000000p-27, 0x1.0000000000000p-27, 0x1.0000000000000p+0, 0x1.0000000000000p-27},
    {0x1.0000000000001p-27, 0x1.0000000000001p-27, 0x1.0000000000000p+0, 0x1.0000000000001p-27},
    {0x1.fffffffffffffp-28, 0x1.fffffffffffffp-28, 0x1.0000000000000p+0, 0x1.fffffffffffffp-28},
    {0x1.921fb54442d18p+0, 0x1.0000000000000p+0, 0x1.1a62633145c07p-54, 0x1.d02967c31cdb5p+53},
    {0x1.921fb54442d18p+1, 0x1.1a62633145c07p-53, -0x1.0000000000000p+0, -0x1.1a62633145c07p-53},
    {0x1.2d97c7f3321d2p+2, -0x1.0000000000000p+0, -0x1.a79394c9e8a0ap-53, 0x1.3570efd768923p+52},
    {0x1.921fb54442d18p+2, -0x1.1a62633145c07p-52, 0x1.0000000000000p+0, -0x1.1a62633145c07p-52},
    {0x1.0c152382d7365p-1, 0x1.fffffffffffffp-2, 0x1.bb67ae8584cabp-1, 0x1.279a74590331cp-1},
    {0x1.9219fd2da879bp+0, 0x1.ffffffdf4abd8p-1, 0x1.6e05a68e29cacp-14, 0x1.66193f3aa1aa6p+13},
    {0x1.0000000000000p-1, 0x1.eaee8744b05f0p-2, 0x1.c1528065b7d50p-1, 0x1.17b4f5bf3474ap-1},
    {0x1.0000000000000p+0, 0x1.aed548f090ceep-1, 0x1.14a280fb5068cp-1, 0x1.8eb245cbee3a6p+0},
    {0x1.0000000000000p+1, 0x1.d18f6ead1b446p-1, -0x1.aa22657537205p-2, -0x1.17af62e0950f8p+1},
    {-0x1.921fb54442d18p-1, -0x1.6a09e667f3bccp-1, 0x1.6a09e667f3bcdp-1, -0x1.fffffffffffffp-1},
    {0x1.fffffffffffffp+29, -0x1.3c12385cbf55dp-1, 0x1.92cb4430fba6ap-1, -0x1.91c3c79d80b42p-1},
    {0x1.d6f3454000000p+26, 0x1.faf0521c8dc5cp-1, 0x1.1f4077c91589fp-3, 0x1.c3c92fa621ffcp+2},
    {0x1.921fb54442d18p-1, 0x1.6a09e667f3bccp-1, 0x1.6a09e667f3bcdp-1, 0x1.fffffffffffffp-1},
    {0x1.921fb54442d18p+0, 0x1.0000000000000p+0, 0x1.1a62633145c07p-54, 0x1.d02967c31cdb5p+53},
    {0x1.0c152382d7365p-1, 0x1.fffffffffffffp-2, 0x1.bb67ae8584cabp-1, 0x1.279a74590331cp-1},
};

static const double hypot_table[][3] = {
    {-0x1.78a4c4306c7cep+1, 0x1.ff77319712170p+0, 0x1.c7420056ab979p+1},
    {-0x1.79b23f3247a48p+0, -0x1.7985a4a940804p+0, 0x1.0b028fafcbd46p+1},
    {0x1.51ddb318080aap+1, 0x1.788b11d3838f6p+1, 0x1.f9e74593451c1p+1},
    {0x1.82c6d5d782270p+1, 0x1.caf8a835a1828p+0, 0x1.c1bbae0e97a26p+1},
    {0x1.9e1833ac53054p+1, 0x1.708e85a6f5ad8p-1, 0x1.a838b6e441ae6p+1},
    {0x1.e7aa3cd6f844cp+0, -0x1.2d5e651da8d8cp+1, 0x1.83a8027a92db1p+1},
    {0x1.639f4c6a5df36p+1, -0x1.334eedc7f29e4p+1, 0x1.d60185e809dfbp+1},
    {-0x1.c98c30501b064p+1, -0x1.ca4bbe0e58948p+1, 0x1.43ccb79151e81p+2},
    {0x1.8000000000000p+1, 0x1.0000000000000p+2, 0x1.4000000000000p+2},
    {0x1.7e43c8800759cp+996, 0x1.7e43c8800759cp+996, 0x1.0e4d50f99b211p+997},
    {0x1.56e1fc2f8f359p-997, 0x1.56e1fc2f8f359p-997, 0x1.e4e8d12762225p-997},
    {0x1.0000000000000p+0, 0x1.0000000000000p-60, 0x1.0000000000000p+0},
    {0x1.0000000000000p+0, 0x1.0000000000000p-27, 0x1.0000000000000p+0},
    {0x1.fffffffffffffp+1023, 0x1.0000000000000p+0, 0x1.fffffffffffffp+1023},
    {0x1.0000000000000p-1000, 0x1.0000000000000p-1001, 0x1.1e3779b97f4a8p-1000},
};

TEST(crmath_sin_cos_tan_table)
{
    for (size_t i = 0; i < sizeof trig_table / sizeof trig_table[0]; i++) {
        const double *r = trig_table[i];
        CHECK_MSG(cr_sin(r[0]) == r[1], "sin(%a) = %a, expected %a", r[0], cr_sin(r[0]), r[1]);
        CHECK_MSG(cr_cos(r[0]) == r[2], "cos(%a) = %a, expected %a", r[0], cr_cos(r[0]), r[2]);
        CHECK_MSG(cr_tan(r[0]) == r[3], "tan(%a) = %a, expected %a", r[0], cr_tan(r[0]), r[3]);
        /* odd and even */
        CHECK(cr_sin(-r[0]) == -r[1] && cr_cos(-r[0]) == r[2] && cr_tan(-r[0]) == -r[3]);
    }
}

TEST(crmath_hypot_table)
{
    for (size_t i = 0; i < sizeof hypot_table / sizeof hypot_table[0]; i++) {
        const double *r = hypot_table[i];
        CHECK_MSG(cr_hypot(r[0], r[1]) == r[2], "hypot(%a, %a) = %a, expected %a", r[0], r[1],
                  cr_hypot(r[0], r[1]), r[2]);
        CHECK(cr_hypot(-r[1], r[0]) == r[2]);
    }
    CHECK(cr_hypot(INFINITY, NAN) == INFINITY && cr_hypot(NAN, -INFINITY) == INFINITY);
    CHECK(isnan(cr_hypot(NAN, 1)));
    CHECK(cr_hypot(0, 0) == 0 && cr_hypot(0, -2) == 2);
}

TEST(crmath_special_values)
{
    CHECK(cr_sin(0) == 0 && !signbit(cr_sin(0)) && signbit(cr_sin(-0.0)));
    CHECK(signbit(cr_tan(-0.0)) && cr_cos(-0.0) == 1);
    CHECK(isnan(cr_sin(INFINITY)) && isnan(cr_cos(NAN)) && isnan(cr_tan(-INFINITY)));
    CHECK(isnan(cr_sin(0x1p30)));   /* outside the documented domain */
    CHECK(cr_sin(1e-300) == 1e-300 && cr_cos(1e-300) == 1 && cr_tan(-1e-300) == -1e-300);
    /* degrees: exact reduction modulo 360, sign kept, small values as given */
    CHECK(cr_deg_reduce(720) == 0 && cr_deg_reduce(-370.5) == -10.5);
    CHECK(cr_deg_reduce(359.75) == 359.75 && cr_deg_reduce(-30) == -30);
    CHECK(cr_deg_reduce(1e300) >= 0 && cr_deg_reduce(1e300) < 360);
    CHECK(cr_deg_reduce(360.0 * 0x1p40 + 0.125) == 0.125);
    CHECK(isnan(cr_deg_reduce(INFINITY)));
}

/* Every step of the Ziv loop that decides must decide the same double: a
 * wrong error bound at 128 bits would show as a disagreement with 1024. */
TEST(crmath_precisions_agree)
{
    uint64_t s = 17;
    unsigned decided = 0;
    for (int i = 0; i < 3000; i++) {
        double x = i % 3 ? t_uniform(&s, -7, 7) : t_uniform(&s, -1e6, 1e6);
        static const char fn[] = "sct";
        for (int f = 0; f < 3; f++) {
            double lo, hi;
            if (cr_trig_step(fn[f], x, 4, &lo))
                continue;
            decided++;
            CHECK_MSG(!cr_trig_step(fn[f], x, 32, &hi) && lo == hi,
                      "%c(%a): 128 bits give %a, 1024 bits %a", fn[f], x, lo, hi);
        }
    }
    CHECK(decided > 8900);   /* the first step nearly always decides */
}

/* gp_polygon_turns: convexity and winding without atan2 */
static gp_turns turns_of(double (*v)[2], unsigned n, double tol, unsigned *k)
{
    double ex[16], ey[16];
    for (unsigned i = 0; i < n; i++) {
        ex[i] = v[(i + 1) % n][0] - v[i][0];
        ey[i] = v[(i + 1) % n][1] - v[i][1];
    }
    return gp_polygon_turns(ex, ey, n, tol, k);
}

TEST(polygon_turns_without_angles)
{
    unsigned k;
    double square[4][2] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    CHECK(turns_of(square, 4, 1e-9, &k) == GP_TURNS_CONVEX && k == 1);
    /* clockwise: every turn is a right angle to the right */
    double cw[4][2] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    CHECK(turns_of(cw, 4, 1e-9, &k) == GP_TURNS_REFLEX && k == 0);
    /* a pentagram turns left at every vertex and winds twice */
    double star[5][2];
    for (int i = 0; i < 5; i++) {
        double a = 2 * VEC3_PI * (2 * i) / 5;
        star[i][0] = cr_cos(a);
        star[i][1] = cr_sin(a);
    }
    CHECK(turns_of(star, 5, 1e-9, &k) == GP_TURNS_NOT_SIMPLE && k == 2);
    /* a vertex pushed in by a sine of 1e-10 passes a tolerance of 1e-9, by
     * 1e-8 it does not, and is named */
    double dent[4][2] = {{0, 0}, {0.5, 1e-10}, {1, 0}, {0.5, 1}};
    CHECK(turns_of(dent, 4, 1e-9, &k) == GP_TURNS_CONVEX);
    dent[1][1] = 2e-8;
    CHECK(turns_of(dent, 4, 1e-9, &k) == GP_TURNS_REFLEX && k == 1);
    /* an edge that doubles back on its neighbour */
    double back[4][2] = {{0, 0}, {2, 0}, {1, 0}, {1, 1}};
    CHECK(turns_of(back, 4, 1e-9, &k) == GP_TURNS_REFLEX && k == 1);   /* at (2, 0) */
    /* a triangle crossing the reference direction both ways turns once */
    double tri[3][2] = {{-1, -1}, {1, -1}, {0, 1}};
    CHECK(turns_of(tri, 3, 0, &k) == GP_TURNS_CONVEX);
}
