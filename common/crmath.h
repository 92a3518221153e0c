/* crmath.h — correctly rounded sin, cos, tan and hypot in IEEE binary64, built
 * from the basic operations (+ - * / and sqrt, which IEEE 754 rounds
 * correctly) and integer arithmetic alone, so that the GP's camera maths gives
 * the same bits under any C library (docs/number-formats.md §0).  Internal to
 * the library: the GP and the reference tools call it. */
#ifndef ALBATROS_CRMATH_H
#define ALBATROS_CRMATH_H

/* Round to nearest even of sin x, cos x, tan x for |x| < 2^30 (radians); NaN
 * for infinities, NaNs and larger arguments, which the GP never passes (its
 * angles are degrees reduced by cr_deg_reduce, its field of view below 180
 * degrees).  sin(-0) = -0, tan(-0) = -0. */
double cr_sin(double x);
double cr_cos(double x);
double cr_tan(double x);

/* Round to nearest even of sqrt(x^2 + y^2), without overflow or underflow in
 * between, for results in the normal range (a subnormal result may be off by
 * the rounding of its last bits); an infinite argument gives +inf, else a NaN
 * gives NaN. */
double cr_hypot(double x, double y);

/* deg reduced modulo 360 exactly (the sign of deg, magnitude below 360): an
 * angle of 720 degrees is the angle of 0.  Values below 360 in magnitude are
 * returned as they are. */
double cr_deg_reduce(double deg);

/* For tests: one step of the Ziv loop behind cr_sin ('s'), cr_cos ('c') and
 * cr_tan ('t'), at `limbs` 32-bit limbs of fraction (4..64): 0 with *out if
 * its rounding test decided the result at that precision, -1 if it needs
 * more (or x is outside the domain or tiny: those never reach the loop). */
int cr_trig_step(char fn, double x, unsigned limbs, double *out);

#endif
