// The portable elementary functions against independent references: glibc's
// x87 long-double functions (64-bit significand, not chosen per CPU), which
// are ~2^11 times finer than a double's ulp. Each test states the accuracy
// portable_math.h promises, over the range it promises it.
#include "hapsim/core/math/portable_math.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hapsim::core::pmath {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// |got - ref| in units of the last place of the double nearest ref.
double UlpError(double got, long double ref) {
  if (ref == 0.0L) return got == 0.0 ? 0.0 : std::numeric_limits<double>::infinity();
  int e = 0;
  std::frexp(static_cast<double>(ref), &e);  // |ref| in [2^(e-1), 2^e)
  const long double ulp = std::ldexp(1.0L, std::max(e - 53, -1074));
  return static_cast<double>(std::fabs(static_cast<long double>(got) - ref) / ulp);
}

// Tracks the worst error and where it happened, for the failure message.
struct Worst {
  double ulps = 0.0, x = 0.0, y = 0.0;
  void Add(double err, double at_x, double at_y = 0.0) {
    if (err > ulps) {
      ulps = err;
      x = at_x;
      y = at_y;
    }
  }
};

constexpr std::uint64_t kSeed = 20261125;

std::mt19937_64& Rng() {
  static std::mt19937_64 rng(kSeed);
  return rng;
}

double Uniform(double lo, double hi) { return std::uniform_real_distribution<double>(lo, hi)(Rng()); }

// Uniform in log scale over [lo, hi] (both > 0), random sign if `signed_`.
double LogUniform(double lo, double hi, bool signed_ = true) {
  const double v = std::exp(Uniform(std::log(lo), std::log(hi)));
  return signed_ && Uniform(0, 1) < 0.5 ? -v : v;
}

constexpr int kSamples = 200000;

TEST(PortableMath, SinAndCosAreWithinOneUlpUpToTwoToTheTwenty) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  std::vector<double> xs;
  for (int i = 0; i < kSamples; ++i) xs.push_back(Uniform(-8.0, 8.0));
  for (int i = 0; i < kSamples; ++i) xs.push_back(LogUniform(1e-9, 0x1p20));
  // The hardest arguments: doubles next to multiples of pi/2, where the
  // reduction cancels most bits.
  for (int k = 1; k < 200000; k += 7) {
    const double m = k * (std::numbers::pi_v<long double> / 2);
    for (double x = std::nextafter(m, 0.0), n = 0; n < 3; ++n, x = std::nextafter(x, kInf)) xs.push_back(x);
  }
  Worst sin_worst, cos_worst;
  for (const double x : xs) {
    double s = 0, c = 0;
    SinCos(x, s, c);
    sin_worst.Add(UlpError(s, std::sin(static_cast<long double>(x))), x);
    cos_worst.Add(UlpError(c, std::cos(static_cast<long double>(x))), x);
    ASSERT_EQ(s, Sin(x));
    ASSERT_EQ(c, Cos(x));
  }
  EXPECT_LE(sin_worst.ulps, 1.0) << "at x = " << sin_worst.x;
  EXPECT_LE(cos_worst.ulps, 1.0) << "at x = " << cos_worst.x;
  RecordProperty("sin_max_ulp", std::to_string(sin_worst.ulps));
  RecordProperty("cos_max_ulp", std::to_string(cos_worst.ulps));
}

TEST(PortableMath, AtanAtan2AndAcosAreWithinTheirPromisedUlps) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  Worst atan_worst, atan2_worst, acos_worst;
  for (int i = 0; i < kSamples; ++i) {
    const double x = LogUniform(1e-12, 1e12);
    atan_worst.Add(UlpError(Atan(x), std::atan(static_cast<long double>(x))), x);
    const double y = LogUniform(1e-6, 1e6), x2 = LogUniform(1e-6, 1e6);
    atan2_worst.Add(UlpError(Atan2(y, x2), std::atan2(static_cast<long double>(y), static_cast<long double>(x2))), x2,
                    y);
    const double c = Uniform(-1.0, 1.0);
    acos_worst.Add(UlpError(Acos(c), std::acos(static_cast<long double>(c))), c);
  }
  // Near +-1, where acos is steepest.
  for (int i = 0; i < kSamples; ++i) {
    const double c = 1.0 - LogUniform(1e-16, 0.5, false);
    acos_worst.Add(UlpError(Acos(c), std::acos(static_cast<long double>(c))), c);
    acos_worst.Add(UlpError(Acos(-c), std::acos(static_cast<long double>(-c))), -c);
  }
  EXPECT_LE(atan_worst.ulps, 2.0) << "at x = " << atan_worst.x;
  EXPECT_LE(atan2_worst.ulps, 2.0) << "at y = " << atan2_worst.y << ", x = " << atan2_worst.x;
  EXPECT_LE(acos_worst.ulps, 3.0) << "at x = " << acos_worst.x;
  RecordProperty("atan_max_ulp", std::to_string(atan_worst.ulps));
  RecordProperty("atan2_max_ulp", std::to_string(atan2_worst.ulps));
  RecordProperty("acos_max_ulp", std::to_string(acos_worst.ulps));
}

TEST(PortableMath, ExpAndLogAreWithinOneUlp) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  Worst exp_worst, log_worst;
  for (int i = 0; i < kSamples; ++i) {
    const double x = i % 2 == 0 ? Uniform(-708.0, 709.0) : Uniform(-2.0, 2.0);
    exp_worst.Add(UlpError(Exp(x), std::exp(static_cast<long double>(x))), x);
  }
  for (int i = 0; i < kSamples; ++i) {
    // Near 1, where log cancels, and over every binade of positive doubles.
    const double x = i % 2 == 0 ? 1.0 + LogUniform(1e-15, 0.5) : LogUniform(1e-300, 1e300, false);
    log_worst.Add(UlpError(Log(x), std::log(static_cast<long double>(x))), x);
  }
  EXPECT_LE(exp_worst.ulps, 1.0) << "at x = " << exp_worst.x;
  EXPECT_LE(log_worst.ulps, 1.0) << "at x = " << log_worst.x;
  RecordProperty("exp_max_ulp", std::to_string(exp_worst.ulps));
  RecordProperty("log_max_ulp", std::to_string(log_worst.ulps));
}

TEST(PortableMath, TanhAndHypotAreWithinTheirPromisedUlps) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  Worst tanh_worst, hypot_worst;
  for (int i = 0; i < kSamples; ++i) {
    const double x = i % 2 == 0 ? Uniform(-25.0, 25.0) : LogUniform(1e-10, 1.0);
    tanh_worst.Add(UlpError(Tanh(x), std::tanh(static_cast<long double>(x))), x);
    const double a = LogUniform(1e-300, 1e300), b = a * LogUniform(1e-20, 1e20);
    hypot_worst.Add(UlpError(Hypot(a, b), std::hypot(static_cast<long double>(a), static_cast<long double>(b))), a, b);
  }
  EXPECT_LE(tanh_worst.ulps, 1.5) << "at x = " << tanh_worst.x;
  EXPECT_LE(hypot_worst.ulps, 1.25) << "at " << hypot_worst.x << ", " << hypot_worst.y;
  RecordProperty("tanh_max_ulp", std::to_string(tanh_worst.ulps));
  RecordProperty("hypot_max_ulp", std::to_string(hypot_worst.ulps));
}

TEST(PortableMath, PowIsWithinItsErrorBoundThatGrowsWithYLnX) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  double worst_ratio = 0.0, at_x = 0, at_y = 0;
  for (int i = 0; i < kSamples; ++i) {
    const double x = LogUniform(1e-3, 1e3, false), y = Uniform(-8.0, 8.0);
    const long double ref = std::pow(static_cast<long double>(x), static_cast<long double>(y));
    const double bound = 1.0 + 2.0 * std::fabs(y * std::log(x));
    const double ratio = UlpError(Pow(x, y), ref) / bound;
    if (ratio > worst_ratio) worst_ratio = ratio, at_x = x, at_y = y;
  }
  EXPECT_LE(worst_ratio, 1.0) << "at x = " << at_x << ", y = " << at_y;
  // Small integer powers are products: x^2 is x*x rounded once, x^3 and
  // x^-2 round twice (relative error <= 2^-52, i.e. below 2 ulp).
  Worst cube, inverse_square;
  for (int i = 0; i < kSamples; ++i) {
    const double x = Uniform(-10.0, 10.0);
    ASSERT_EQ(Pow(x, 2.0), x * x);
    const long double xl = x;
    cube.Add(UlpError(Pow(x, 3.0), xl * xl * xl), x);
    inverse_square.Add(UlpError(Pow(x, -2.0), 1.0L / (xl * xl)), x);
  }
  EXPECT_LT(cube.ulps, 2.0) << "at x = " << cube.x;
  EXPECT_LT(inverse_square.ulps, 2.0) << "at x = " << inverse_square.x;
  RecordProperty("pow_worst_fraction_of_bound", std::to_string(worst_ratio));
}

// Special values as C99 Annex F specifies them, checked against the C
// library, which is exact for these.
TEST(PortableMath, SpecialValuesFollowTheCStandard) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  auto same = [](double a, double b) {
    return (std::isnan(a) && std::isnan(b)) || (a == b && std::signbit(a) == std::signbit(b));
  };
  const double specials[] = {0.0, -0.0, 1.0, -1.0, kInf, -kInf, kNaN, 0.5, -0.5, 2.0, 1e-310, -1e-310};
  for (const double x : specials) {
    EXPECT_TRUE(same(Sin(x), std::sin(x))) << "sin " << x;
    EXPECT_TRUE(same(Cos(x), std::cos(x))) << "cos " << x;
    EXPECT_TRUE(same(Atan(x), std::atan(x))) << "atan " << x;
    const bool not_finite = std::isnan(x) || std::isinf(x);
    if (not_finite || x == 0.0 || std::fabs(x) < 1e-300) {
      EXPECT_TRUE(same(Tanh(x), std::tanh(x))) << "tanh " << x;
    }
    if (not_finite || x == 0.0) {
      EXPECT_TRUE(same(Exp(x), std::exp(x))) << "exp " << x;
    }
    if (not_finite || x <= 0.0 || x == 1.0) {
      EXPECT_TRUE(same(Log(x), std::log(x))) << "log " << x;
    }
    if (not_finite || std::fabs(x) >= 1.0) {
      EXPECT_TRUE(same(Acos(x), std::acos(x))) << "acos " << x;
    }
    for (const double y : specials) {
      EXPECT_TRUE(same(Hypot(x, y), std::hypot(x, y))) << "hypot " << x << ", " << y;
      if (x == 0.0 || y == 0.0 || std::isinf(x) || std::isinf(y) || std::isnan(x) || std::isnan(y)) {
        EXPECT_TRUE(same(Atan2(y, x), std::atan2(y, x))) << "atan2 " << y << ", " << x;
      }
      const bool exact_pow = std::isnan(x) || std::isnan(y) || std::isinf(x) || std::isinf(y) || x == 0.0 ||
                             y == 0.0 || std::fabs(x) == 1.0 || std::fabs(y) == 1.0;
      if (exact_pow) {
        EXPECT_TRUE(same(Pow(x, y), std::pow(x, y))) << "pow " << x << ", " << y;
      }
    }
  }
  // Overflow and underflow at the edges of exp's range.
  EXPECT_EQ(Exp(710.0), kInf);
  EXPECT_EQ(Exp(-746.0), 0.0);
  EXPECT_GT(Exp(709.78), 1e308);
  EXPECT_GT(Exp(-745.0), 0.0);
  EXPECT_TRUE(std::isnan(Log(-1.0)));
  EXPECT_TRUE(std::isnan(Acos(1.5)));
  EXPECT_TRUE(std::isnan(Pow(-2.0, 0.5)));
  EXPECT_EQ(Pow(-2.0, 5.0), -32.0);
}

// The bits these functions return over a fixed sample, pinned. The test
// runs again under GLIBC_TUNABLES=glibc.cpu.hwcaps=-AVX2,-FMA (ctest
// core.determinism.glibc_variant): the same hash there means nothing here
// took glibc's per-CPU code paths. A change means the functions changed.
TEST(PortableMath, OutputsOverAFixedSampleEndInTheGoldenHash) {
  Rng().seed(kSeed);  // the same sample whichever tests run before
  std::uint64_t h = 1469598103934665603ull;  // FNV-1a over the result bits
  auto mix = [&h](double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    for (int i = 0; i < 8; ++i) h = (h ^ ((bits >> (8 * i)) & 0xffu)) * 1099511628211ull;
  };
  for (int i = 1; i <= 20000; ++i) {
    // Arguments from integers only, so the sample itself uses no libm.
    const double x = (i - 10000) * 0.0123456789;
    mix(Sin(x));
    mix(Cos(x));
    mix(Atan(x));
    mix(Atan2(x, 0.37 * i));
    mix(Acos(x / 123.456789));
    mix(Exp(x / 20.0));
    mix(Log(i * 0.0731));
    mix(Pow(i * 0.0731, x / 50.0));
    mix(Tanh(x / 10.0));
    mix(Hypot(x, 0.001 * i));
  }
  EXPECT_EQ(h, 3026989064363681362ull) << "new value: " << h << "ull";
}

}  // namespace
}  // namespace hapsim::core::pmath
