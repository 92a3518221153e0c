/* t.h — a tiny test runner: TEST(name) { CHECK(...); } registers a test;
 * the runner prints one line per failure and closes with "N passed, N failed".
 * A test passes when none of its checks failed and it made at least one. */
#ifndef ALBATROS_T_H
#define ALBATROS_T_H

#include <math.h>
#include <stdint.h>
#include <stdio.h>

typedef void (*t_fn)(void);
void t_register(const char *name, const char *file, t_fn fn);
void t_fail(const char *file, int line, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));
void t_pass(void);
/* A scratch directory for the running test (created, unique per test). */
const char *t_tmpdir(void);
/* The directory holding the albatros binary (for CLI tests). */
const char *t_bindir(void);

/* Deterministic pseudo-random numbers for seeded tests (xorshift64*). */
static inline uint64_t t_rand(uint64_t *s)
{
    *s ^= *s >> 12;
    *s ^= *s << 25;
    *s ^= *s >> 27;
    return *s * 0x2545F4914F6CDD1DULL;
}
/* Uniform in [lo, hi). */
static inline double t_uniform(uint64_t *s, double lo, double hi)
{
    return lo + (hi - lo) * (double)(t_rand(s) >> 11) * (1.0 / 9007199254740992.0);
}

#define TEST(name)                                                          \
    static void name(void);                                                 \
    __attribute__((constructor)) static void t_reg_##name(void)             \
    {                                                                       \
        t_register(#name, __FILE__, name);                                  \
    }                                                                       \
    static void name(void)

#define CHECK(cond)                                                         \
    ((cond) ? t_pass() : t_fail(__FILE__, __LINE__, "CHECK(%s)", #cond))
#define CHECK_MSG(cond, ...)                                                \
    ((cond) ? t_pass() : t_fail(__FILE__, __LINE__, __VA_ARGS__))
#define CHECK_EQ(a, b)                                                      \
    do {                                                                    \
        long long t_a_ = (long long)(a), t_b_ = (long long)(b);             \
        if (t_a_ == t_b_) t_pass();                                         \
        else t_fail(__FILE__, __LINE__, "%s == %s: %lld != %lld", #a, #b,   \
                    t_a_, t_b_);                                            \
    } while (0)
#define CHECK_NEAR(a, b, tol)                                               \
    do {                                                                    \
        double t_a_ = (a), t_b_ = (b);                                      \
        if (fabs(t_a_ - t_b_) <= (tol)) t_pass();                           \
        else t_fail(__FILE__, __LINE__, "%s ~ %s: %.17g vs %.17g (tol %g)", \
                    #a, #b, t_a_, t_b_, (double)(tol));                     \
    } while (0)
#define CHECK_STR_CONTAINS(hay, needle)                                     \
    do {                                                                    \
        const char *t_h_ = (hay), *t_n_ = (needle);                         \
        if (t_h_ && strstr(t_h_, t_n_)) t_pass();                           \
        else t_fail(__FILE__, __LINE__, "'%s' does not contain '%s'",       \
                    t_h_ ? t_h_ : "(null)", t_n_);                          \
    } while (0)

#endif
