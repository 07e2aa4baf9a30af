#include "hapsim/core/math/portable_math.h"

// Only correctly rounded or exact <cmath> operations are used here: sqrt,
// fabs, nearbyint, ldexp, frexp, remquo, copysign, signbit, isnan, isinf.
#include <cmath>
#include <limits>
#include <utility>

namespace hapsim::core::pmath {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Printed by derive_constants.py (beside this file) from exact decimals.
// pi/2 in three 33-bit parts and a tail: k * part is exact for |k| < 2^20.
constexpr double kPio2Part0 = 0x1.921fb54400000p+0;
constexpr double kPio2Part1 = 0x1.0b4611a600000p-34;
constexpr double kPio2Part2 = 0x1.3198a2e000000p-69;
constexpr double kPio2Part3 = 0x1.b839a252049c1p-104;
constexpr double kTwoOverPi = 0x1.45f306dc9c883p-1;
// ln 2 in a 32-bit part and a tail: k * kLn2Hi is exact for |k| < 2^21.
constexpr double kLn2Hi = 0x1.62e42ff000000p-1;
constexpr double kLn2Lo = -0x1.718432a1b0e26p-35;
constexpr double kInvLn2 = 0x1.71547652b82fep+0;
// Nearest double and the nearest double to the rest.
constexpr double kPiHi = 0x1.921fb54442d18p+1, kPiLo = 0x1.1a62633145c07p-53;
constexpr double kPio2Hi = 0x1.921fb54442d18p+0, kPio2Lo = 0x1.1a62633145c07p-54;
constexpr double kPio4 = 0x1.921fb54442d18p-1;
constexpr double kThreePio4 = 0x1.2d97c7f3321d2p+1;
constexpr double kSqrtHalf = 0x1.6a09e667f3bcdp-1;
constexpr double kLnDblMax = 0x1.62e42fefa39efp+9;           // exp overflows above
constexpr double kLnHalfMinSubnormal = -0x1.74910d52d3052p+9;  // exp rounds to 0 below
// atan(j/8) for j = 0..8.
constexpr double kAtanHi[9] = {0.0,
                               0.12435499454676144,
                               0.24497866312686414,
                               0.35877067027057225,
                               0.4636476090008061,
                               0.5585993153435624,
                               0.6435011087932844,
                               0.7188299996216245,
                               0.7853981633974483};
constexpr double kAtanLo[9] = {0.0,
                               -3.1253241424539383e-18,
                               1.0698755618734451e-17,
                               -2.4623815582638635e-17,
                               2.2698777452961687e-17,
                               -5.4556305485916264e-18,
                               1.5834785051444286e-17,
                               -2.1478388444456983e-17,
                               3.061616997868383e-17};

// Polynomials are truncated Taylor series: on the reduced ranges below the
// first dropped term is under 2^-60 of the result, so truncation costs
// nothing next to rounding, and the coefficients need no fitting tool.
// Coefficients are rounded once, at compile time.
constexpr double InvFactorial(int n) {
  double f = 1.0;
  for (int i = 2; i <= n; ++i) f *= i;
  return 1.0 / f;
}

// Horner's rule: c[0] + z (c[1] + z (c[2] + ...)).
template <int N>
double Horner(const double (&c)[N], double z) {
  double p = c[N - 1];
  for (int i = N - 2; i >= 0; --i) p = p * z + c[i];
  return p;
}

// sin y = y + y^3 S(y^2): S's coefficients are (-1)^(i+1) / (2i+3)!, to y^19
// ((pi/4)^20 / 21! < 2^-60).
template <int N>
struct SinTail {
  double c[N];
  constexpr SinTail() : c() {
    for (int i = 0; i < N; ++i) c[i] = (i % 2 == 0 ? -1.0 : 1.0) * InvFactorial(2 * i + 3);
  }
};
// cos y = 1 - y^2/2 + y^4 C(y^2): C's coefficients are (-1)^i / (2i+4)!, to y^20.
template <int N>
struct CosTail {
  double c[N];
  constexpr CosTail() : c() {
    for (int i = 0; i < N; ++i) c[i] = (i % 2 == 0 ? 1.0 : -1.0) * InvFactorial(2 * i + 4);
  }
};
// e^r = 1 + r + r^2 E(r): E's coefficients are 1 / (i+2)!, to r^15 for |r| <= ln2/2.
template <int N>
struct ExpTail {
  double c[N];
  constexpr ExpTail() : c() {
    for (int i = 0; i < N; ++i) c[i] = InvFactorial(i + 2);
  }
};
// atan t = t + t^3 A(t^2): A's coefficients are (-1)^(i+1) / (2i+3), to t^23 for |t| <= 1/16.
template <int N>
struct AtanTail {
  double c[N];
  constexpr AtanTail() : c() {
    for (int i = 0; i < N; ++i) c[i] = (i % 2 == 0 ? -1.0 : 1.0) / (2 * i + 3);
  }
};
// log(1+f) = 2 atanh s with s = f/(2+f): R(z) = 2/3 + 2z/5 + ..., z = s^2 <= 0.0295, to z^12.
template <int N>
struct LogTail {
  double c[N];
  constexpr LogTail() : c() {
    for (int i = 0; i < N; ++i) c[i] = 2.0 / (2 * i + 3);
  }
};

constexpr SinTail<9> kSin;
constexpr CosTail<9> kCos;
constexpr ExpTail<14> kExp;
constexpr AtanTail<11> kAtan;
constexpr LogTail<13> kLog;
// tanh x = x + x^3 T(x^2): T's coefficients are 2^2n (2^2n - 1) B_2n / (2n)!
// (B: Bernoulli numbers) for n = 2..23, exact fractions rounded by
// derive_constants.py; to x^45 for |x| <= 0.55 (ratio of terms ~0.12).
constexpr double kTanhTail[22] = {
    -0.3333333333333333,     0.13333333333333333,    -0.05396825396825397,    0.021869488536155203,
    -0.008863235529902197,   0.003592128036572481,   -0.0014558343870513183,  0.000590027440945586,
    -0.00023912911424355248, 9.691537956929451e-05,  -3.927832388331683e-05,  1.5918905069328964e-05,
    -6.451689215655431e-06,  2.6147711512907546e-06, -1.0597268320104654e-06, 4.294911078273806e-07,
    -1.7406618963571648e-07, 7.054636946400968e-08,  -2.859136662305254e-08,  1.1587644432798853e-08,
    -4.6962953982309016e-09, 1.903336833931276e-09};

// sin(y + y_lo) for |y| <= ~pi/4 and |y_lo| <= ulp(y): sin y + y_lo cos y.
double KernelSin(double y, double y_lo) {
  const double z = y * y;
  return y + (y * z * Horner(kSin.c, z) + y_lo * (1.0 - 0.5 * z));
}

// cos(y + y_lo) for |y| <= ~pi/4: cos y - y_lo sin y. 1 - z/2 is split so
// that its rounding error is carried (w is exact to the bit, (1-w)-hz exact).
double KernelCos(double y, double y_lo) {
  const double z = y * y;
  const double hz = 0.5 * z;
  const double w = 1.0 - hz;
  return w + (((1.0 - w) - hz) + (z * z * Horner(kCos.c, z) - y * y_lo));
}

// x = quadrant * pi/2 + (hi + lo), |hi + lo| <= ~pi/4 (Cody-Waite: each
// k * part is exact, so only the tail's product rounds).
struct ReducedAngle {
  int quadrant;  // 0..3
  double hi, lo;
};

ReducedAngle ReduceByHalfPi(double x) {
  if (std::fabs(x) <= kPio4) return {0, x, 0.0};
  if (!(std::fabs(x) < 0x1p20)) {
    // Beyond the promised range: the exact IEEE remainder by the double
    // nearest pi/2. Deterministic, not accurate.
    int q = 0;
    const double r = std::remquo(x, kPio2Hi, &q);
    return {q & 3, r, 0.0};
  }
  const double k = std::nearbyint(x * kTwoOverPi);
  const double t = x - k * kPio2Part0;  // exact (Sterbenz)
  const double w = k * kPio2Part1;      // exact
  // Two-sum t - w = r + err exactly.
  const double r = t - w;
  const double b = r - t;
  const double err = (t - (r - b)) - (w + b);
  const double lo = err - k * kPio2Part2 - k * kPio2Part3;
  const double hi = r + lo;
  return {static_cast<int>(static_cast<long long>(k) & 3), hi, lo - (hi - r)};
}

// atan a for 0 <= a <= 1: atan(j/8) + atan t with t = (a - j/8)/(1 + a j/8),
// |t| <= 1/16.
double AtanUnit(double a) {
  const int j = static_cast<int>(std::nearbyint(a * 8.0));
  if (j == 0) return a + a * (a * a) * Horner(kAtan.c, a * a);
  const double c = j * 0.125;
  const double t = (a - c) / (1.0 + c * a);
  const double z = t * t;
  return kAtanHi[j] + (kAtanLo[j] + (t + t * z * Horner(kAtan.c, z)));
}

// x^n by repeated squaring, for small |n| only: the relative error doubles
// with every squaring.
double SmallIntegerPower(double x, int n) {
  unsigned u = static_cast<unsigned>(n < 0 ? -n : n);
  double result = 1.0, base = x;
  while (u != 0) {
    if (u & 1u) result *= base;
    u >>= 1;
    if (u != 0) base *= base;
  }
  return n < 0 ? 1.0 / result : result;
}

}  // namespace

void SinCos(double x_rad, double& sin_out, double& cos_out) {
  if (std::isnan(x_rad) || std::isinf(x_rad)) {
    sin_out = cos_out = kNaN;
    return;
  }
  if (std::fabs(x_rad) < 0x1p-27) {  // x^3/6 and x^2/2 are below half an ulp
    sin_out = x_rad;
    cos_out = 1.0;
    return;
  }
  const ReducedAngle r = ReduceByHalfPi(x_rad);
  const double s = KernelSin(r.hi, r.lo), c = KernelCos(r.hi, r.lo);
  switch (r.quadrant) {
    case 0: sin_out = s; cos_out = c; break;
    case 1: sin_out = c; cos_out = -s; break;
    case 2: sin_out = -s; cos_out = -c; break;
    default: sin_out = -c; cos_out = s; break;
  }
}

namespace {

// sin (want_sin) or cos of x, with only the kernel that quadrant needs.
double SinOrCos(double x_rad, bool want_sin) {
  if (std::isnan(x_rad) || std::isinf(x_rad)) return kNaN;
  if (std::fabs(x_rad) < 0x1p-27) return want_sin ? x_rad : 1.0;
  const ReducedAngle r = ReduceByHalfPi(x_rad);
  const int q = want_sin ? r.quadrant : r.quadrant + 1;  // cos x = sin(x + pi/2)
  const double v = (q & 1) ? KernelCos(r.hi, r.lo) : KernelSin(r.hi, r.lo);
  return (q & 2) ? -v : v;
}

}  // namespace

double Sin(double x_rad) { return SinOrCos(x_rad, true); }

double Cos(double x_rad) { return SinOrCos(x_rad, false); }

double Atan(double x) {
  if (std::isnan(x)) return x;
  const double a = std::fabs(x);
  double result;
  if (a <= 1.0) {
    result = AtanUnit(a);
  } else if (a < 0x1p60) {
    result = kPio2Hi - (AtanUnit(1.0 / a) - kPio2Lo);  // atan a = pi/2 - atan(1/a)
  } else {
    result = kPio2Hi;
  }
  return std::copysign(result, x);
}

double Atan2(double y, double x) {
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  if (y == 0.0) return std::signbit(x) ? std::copysign(kPiHi, y) : y;
  if (std::isinf(x)) {
    if (std::isinf(y)) return std::copysign(std::signbit(x) ? kThreePio4 : kPio4, y);
    return std::copysign(std::signbit(x) ? kPiHi : 0.0, y);
  }
  if (x == 0.0 || std::isinf(y)) return std::copysign(kPio2Hi, y);
  const double ax = std::fabs(x), ay = std::fabs(y);
  // The angle of (|x|, |y|) from the nearest axis, then one rounding per octant.
  double a;
  if (ay <= ax) {
    const double t = AtanUnit(ay / ax);
    a = std::signbit(x) ? kPiHi - (t - kPiLo) : t;
  } else {
    const double t = AtanUnit(ax / ay);
    a = std::signbit(x) ? kPio2Hi + (t + kPio2Lo) : kPio2Hi - (t - kPio2Lo);
  }
  return std::copysign(a, y);
}

double Acos(double x) {
  if (std::isnan(x) || std::fabs(x) > 1.0) return kNaN;
  return Atan2(std::sqrt((1.0 - x) * (1.0 + x)), x);
}

double Exp(double x) {
  if (std::isnan(x)) return x;
  if (x > kLnDblMax) return kInf;
  if (x < kLnHalfMinSubnormal) return 0.0;
  if (std::fabs(x) < 0x1p-54) return 1.0 + x;
  // x = k ln2 + r, |r| <= ln2/2; r = hi - lo with hi exact.
  const double k = std::nearbyint(x * kInvLn2);
  const double hi = x - k * kLn2Hi;
  const double lo = k * kLn2Lo;
  const double r = hi - lo;
  const double c = r * r * Horner(kExp.c, r);
  const double y = 1.0 + (hi - (lo - c));
  return std::ldexp(y, static_cast<int>(k));
}

double Log(double x) {
  if (std::isnan(x)) return x;
  if (x < 0.0) return kNaN;
  if (x == 0.0) return -kInf;
  if (std::isinf(x)) return x;
  int e = 0;
  double m = std::frexp(x, &e);  // x = m 2^e, m in [1/2, 1), exact (subnormals too)
  if (m < kSqrtHalf) {
    m *= 2.0;
    --e;
  }
  // log x = e ln2 + log(1 + f), f in [sqrt(1/2) - 1, sqrt(2) - 1].
  const double f = m - 1.0;  // exact (Sterbenz)
  const double s = f / (2.0 + f);
  const double z = s * s;
  const double r = z * Horner(kLog.c, z);
  // log(1+f) = 2s + s R = f - hfsq + s (hfsq + R), with hfsq = f^2/2.
  const double hfsq = 0.5 * f * f;
  const double k = e;
  return k * kLn2Hi + (f - (hfsq - (s * (hfsq + r) + k * kLn2Lo)));
}

double Pow(double x, double y) {
  if (y == 0.0 || x == 1.0) return 1.0;
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  if (std::isinf(y)) {
    const double ax = std::fabs(x);
    if (ax == 1.0) return 1.0;
    return (ax > 1.0) == (y > 0.0) ? kInf : 0.0;
  }
  const bool y_is_integer = std::nearbyint(y) == y;
  if (y_is_integer && std::fabs(y) <= 4.0) return SmallIntegerPower(x, static_cast<int>(y));
  const bool y_is_odd = y_is_integer && std::fabs(y) < 0x1p53 && static_cast<long long>(std::fabs(y)) % 2 == 1;
  if (x == 0.0 || std::isinf(x)) {
    const double magnitude = (x == 0.0) == (y > 0.0) ? 0.0 : kInf;
    return std::signbit(x) && y_is_odd ? -magnitude : magnitude;
  }
  if (x < 0.0) {
    if (!y_is_integer) return kNaN;
    const double magnitude = Pow(-x, y);
    return y_is_odd ? -magnitude : magnitude;
  }
  return Exp(y * Log(x));
}

double Tanh(double x) {
  if (std::isnan(x)) return x;
  const double a = std::fabs(x);
  if (a < 0x1p-28) return x;  // x^3/3 is below half an ulp
  double t;
  if (a < 0.55) {
    t = a + a * (a * a) * Horner(kTanhTail, a * a);
  } else if (a < 22.0) {
    t = 1.0 - 2.0 / (Exp(2.0 * a) + 1.0);
  } else {
    t = 1.0;  // 1 - tanh 22 < 2^-63
  }
  return std::copysign(t, x);
}

double Hypot(double x, double y) {
  if (std::isinf(x) || std::isinf(y)) return kInf;
  if (std::isnan(x) || std::isnan(y)) return kNaN;
  double a = std::fabs(x), b = std::fabs(y);
  if (a < b) std::swap(a, b);
  if (a == 0.0) return 0.0;
  // Scale by a power of two (exact) so the squares neither overflow nor underflow.
  int scale = 0;
  if (a > 0x1p500) scale = 600;
  if (a < 0x1p-500) scale = -600;
  a = std::ldexp(a, -scale);
  b = std::ldexp(b, -scale);
  return std::ldexp(std::sqrt(a * a + b * b), scale);
}

}  // namespace hapsim::core::pmath
