// vbits.h — bits of a Verilator signal, whatever C++ type Verilator gave it
// (an integer up to 64 bits, an array of 32-bit words beyond), and the reset
// of alb_bench_top: shared by the cosim bench (cosim.cpp) and the RTL board
// (rtl/board/rtl_vp.cpp).
#ifndef ALB_VBITS_H
#define ALB_VBITS_H

#include <cstdint>
#include <type_traits>

// Bits [lo, lo + w) of v, w at most 64.
template <typename T> static inline uint64_t bits(const T &v, unsigned lo, unsigned w)
{
    uint64_t r = 0;
    if constexpr (std::is_integral_v<T>) {
        r = (uint64_t)v >> lo;
    } else {
        for (unsigned i = 0; i < w && i < 64; i++) {
            unsigned b = lo + i;
            r |= (uint64_t)(v[b / 32] >> (b % 32) & 1) << i;
        }
    }
    return w >= 64 ? r : r & ((1ull << w) - 1);
}

// alb_bench_top reset: two clocks in reset, no word offered, the clock left
// low and the outputs settled.
template <typename Top> static inline void bench_reset(Top &top)
{
    top.clk = 0;
    top.rst = 1;
    top.in_valid = 0;
    top.in_data = 0;
    top.eval();
    for (int i = 0; i < 2; i++) {
        top.clk = 1;
        top.eval();
        top.clk = 0;
        top.eval();
    }
    top.rst = 0;
    top.eval();
}

#endif
