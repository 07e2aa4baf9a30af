// Elementary functions that give the same bits on every x86-64 CPU.
//
// glibc picks its sin/cos/exp/log/pow/atan2/tanh/hypot implementation per
// CPU when a program loads (FMA and non-FMA variants), and the variants
// differ in the last bit. A step that calls them therefore ends in another
// state hash on another machine (or on this one with
// GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA). These functions use only
// IEEE-754 +, -, *, /, sqrt and exact scaling (ldexp, frexp), which round
// identically everywhere; the core is built with -ffp-contract=off, so the
// compiler cannot fuse them either. Anything in core that affects
// state calls these, never <cmath>'s transcendental functions.
//
// Accuracy (measured against x87 long-double references in
// tests/core/portable_math_test.cpp; 1 ulp = one unit in the last place of
// the correctly rounded result):
//   Sin, Cos, SinCos   <= 1 ulp for |x| <= 2^20 (inputs beyond: still
//                      deterministic, accuracy not promised)
//   Atan, Atan2        <= 2 ulp
//   Acos               <= 3 ulp (Atan2 of a rounded sqrt((1-x)(1+x)))
//   Exp, Log           <= 1 ulp
//   Tanh               <= 1.5 ulp
//   Hypot              <= 1.25 ulp
//   Pow(x, y)          <= (1 + 2 |y ln x|) ulp as exp(y log x); for integer
//                      |y| <= 4 a product instead (x^2 correctly rounded,
//                      the others < 2 ulp)
// Special values follow C99 Annex F for the cases the tests list (NaN in,
// NaN out; infinities; signed zeros of Atan2).
#pragma once

namespace hapsim::core::pmath {

double Sin(double x_rad);
double Cos(double x_rad);
// Both at the cost of one argument reduction.
void SinCos(double x_rad, double& sin_out, double& cos_out);
double Atan(double x);
// The angle of (x, y) in (-pi, pi], as std::atan2(y, x).
double Atan2(double y, double x);
double Acos(double x);
double Exp(double x);
double Log(double x);
double Pow(double x, double y);
double Tanh(double x);
// sqrt(x^2 + y^2) without overflow or underflow in the squares.
double Hypot(double x, double y);

}  // namespace hapsim::core::pmath
