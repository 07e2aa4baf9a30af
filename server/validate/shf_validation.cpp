// hapsim-validate shf: spherical-harmonic surfaces. Writes
//   fit_error.csv  body,lmax,k,samples,condition_number,rms_residual_mm,
//                  max_residual_mm,holdout_rms_error_mm,holdout_max_error_mm,
//                  site_max_error_mm (held-out directions within 30° of the
//                  body's +y axis: the acupuncture site of the scene)
//     for the built-in limb segment, an ellipsoid in the radial
//     parametrisation, the same ellipsoid in its natural parametrisation
//     (exact from Lmax = 1) and a star-shaped OBJ mesh (star.obj, written
//     here and parsed back), against held-out analytic surface points;
//   sh_values.csv  l,m,theta_rad,phi_rad,value  (for the scipy cross-check);
//   summary.md.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "hapsim/core/math/portable_math.h"
#include "hapsim/core/mesh/triangle_mesh.h"
#include "hapsim/core/shf/layered_sh_body.h"
#include "hapsim/core/shf/limb_segment.h"
#include "hapsim/core/shf/sh_fit.h"
#include "hapsim/io/obj_reader.h"
#include "validate_command.h"

namespace hapsim::validate {
namespace {

using namespace hapsim::core;

constexpr double kA = 0.05, kB = 0.03, kC = 0.02;  // ellipsoid semi-axes [m]
// Each step adds at least one odd degree: x = r(u)·u_x of a mirror-symmetric
// body has only odd-degree terms, so an even-only step would tie.
constexpr int kLmaxes[] = {1, 3, 5, 7, 9, 12, 16, 20};
constexpr int kHoldout = 1999;  // directions not among the samples

double EllipsoidRadius(const Eigen::Vector3d& u) {
  const Eigen::Vector3d v = u.normalized();
  return 1.0 /
         std::sqrt(core::pmath::Pow(v.x() / kA, 2) + core::pmath::Pow(v.y() / kB, 2) + core::pmath::Pow(v.z() / kC, 2));
}
// Star shape of the OBJ test mesh: a bumpy sphere, radius in direction u.
double StarRadius(const Eigen::Vector3d& u) {
  const Eigen::Vector3d v = u.normalized();
  return 0.05 * (1.0 + 0.15 * v.x() * v.y() + 0.1 * core::pmath::Pow(v.z(), 3) + 0.05 * core::pmath::Sin(3 * v.x()));
}

std::string StarObj(int n_theta, int n_phi) {
  std::ostringstream obj;
  obj.precision(10);
  obj << "# star-shaped test mesh (hapsim-validate shf)\n";
  for (int i = 0; i <= n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const Eigen::Vector3d u = AnglesToDirection(std::numbers::pi * i / n_theta, 2 * std::numbers::pi * j / n_phi);
      const Eigen::Vector3d p = StarRadius(u) * u;
      obj << "v " << p.x() << " " << p.y() << " " << p.z() << "\n";
    }
  for (int i = 0; i < n_theta; ++i)
    for (int j = 0; j < n_phi; ++j) {
      const int a = i * n_phi + j + 1, b = i * n_phi + (j + 1) % n_phi + 1;
      obj << "f " << a << " " << a + n_phi << " " << b + n_phi << " " << b << "\n";
    }
  return obj.str();
}

struct Row {
  std::string body;
  int lmax, k, samples;
  double cond, rms_m, max_m, holdout_rms_m, holdout_m, site_m;
};

// Radially parametrised fit of points, held-out max radius error against radius_fn.
Row RadialFit(const std::string& body, int lmax, const Eigen::Matrix3Xd& p,
              const std::function<double(const Eigen::Vector3d&)>& radius_fn) {
  const ShFitResult fit = FitShSurface(lmax, RadialAngles(p, Eigen::Vector3d::Zero()), p);
  LayeredShBodyDef def;
  def.surfaces.push_back(fit.surface);
  LayeredShBody sh(def);
  const Eigen::Matrix3Xd probe = FibonacciDirections(kHoldout);
  double worst = 0.0, sum2 = 0.0, site = 0.0;
  for (int i = 0; i < probe.cols(); ++i) {
    const double e = std::abs(sh.Radius_m(0, probe.col(i)) - radius_fn(probe.col(i)));
    worst = std::max(worst, e);
    sum2 += e * e;
    if (probe(1, i) > core::pmath::Cos(std::numbers::pi / 6)) site = std::max(site, e);
  }
  return {body, lmax, static_cast<int>(fit.surface.coeffs_m.rows()), static_cast<int>(p.cols()),
          fit.condition_number, fit.rms_residual_m, fit.max_residual_m, std::sqrt(sum2 / probe.cols()), worst, site};
}

// Natural parametrisation: x = a sinθcosφ, ... — degree 1 exactly. Fitted
// from n Fibonacci directions, held-out error against the exact points.
Row NaturalEllipsoidFit(int lmax, int k, int n) {
  const Eigen::Matrix3Xd u = FibonacciDirections(n);
  Eigen::Matrix2Xd tp(2, n);
  Eigen::Matrix3Xd q(3, n);
  for (int i = 0; i < n; ++i) {
    DirectionToAngles(u.col(i), tp(0, i), tp(1, i));
    q.col(i) << kA * u(0, i), kB * u(1, i), kC * u(2, i);
  }
  const ShFitResult fit = FitShSurface(lmax, tp, q);
  const RealShBasis basis(lmax);
  Eigen::VectorXd y(basis.Size());
  const Eigen::Matrix3Xd probe = FibonacciDirections(kHoldout);
  double worst = 0.0, sum2 = 0.0, site = 0.0;
  for (int i = 0; i < kHoldout; ++i) {
    basis.EvaluateDirection(probe.col(i), y);
    const Eigen::Vector3d exact(kA * probe(0, i), kB * probe(1, i), kC * probe(2, i));
    const double err_m = (ShSurfacePoint(fit.surface, y) - exact).norm();
    worst = std::max(worst, err_m);
    sum2 += err_m * err_m;
    if (probe(1, i) > core::pmath::Cos(std::numbers::pi / 6)) site = std::max(site, err_m);
  }
  return {"ellipsoid_natural",        lmax,  k,   n, fit.condition_number, fit.rms_residual_m, fit.max_residual_m,
          std::sqrt(sum2 / kHoldout), worst, site};
}

// Every body fitted at every Lmax of kLmaxes.
std::vector<Row> FitEveryBody(const TriangleMesh& obj) {
  std::vector<Row> rows;
  const LimbSegmentDef limb;
  for (int lmax : kLmaxes) {
    const int k = (lmax + 1) * (lmax + 1);
    const int n = std::max(600, 3 * k);
    rows.push_back(RadialFit("limb_segment", lmax, SampleLimbSegment_m(limb, n),
                             [&](const Eigen::Vector3d& u) { return LimbSegmentRadius_m(limb, u); }));
    Eigen::Matrix3Xd e = FibonacciDirections(n);
    for (int i = 0; i < n; ++i) e.col(i) *= EllipsoidRadius(e.col(i));
    rows.push_back(RadialFit("ellipsoid_radial", lmax, e, EllipsoidRadius));
    rows.push_back(RadialFit("obj_star", lmax, obj.vertices_m, StarRadius));
    rows.push_back(NaturalEllipsoidFit(lmax, k, n));
  }
  return rows;
}

void WriteFitErrorCsv(const std::filesystem::path& out, const std::vector<Row>& rows) {
  std::ofstream f(out / "fit_error.csv");
  f << "body,lmax,k,samples,condition_number,rms_residual_mm,max_residual_mm,holdout_rms_error_mm,"
       "holdout_max_error_mm,site_max_error_mm\n";
  for (const auto& r : rows) {
    char line[256];
    std::snprintf(line, sizeof line, "%s,%d,%d,%d,%.10e,%.10e,%.10e,%.10e,%.10e,%.10e\n", r.body.c_str(), r.lmax, r.k,
                  r.samples, r.cond, 1e3 * r.rms_m, 1e3 * r.max_m, 1e3 * r.holdout_rms_m, 1e3 * r.holdout_m,
                  1e3 * r.site_m);
    f << line;
  }
}

// Basis values at random points (sh_values.csv), and the same check in C++
// against std::sph_legendre: the worst difference.
double WriteShValuesAgainstSphLegendre(const std::filesystem::path& out) {
  double worst_value = 0.0;
  std::ofstream f(out / "sh_values.csv");
  f << "l,m,theta_rad,phi_rad,value\n";
  constexpr int kL = 30;
  const RealShBasis basis(kL);
  Eigen::VectorXd y(basis.Size());
  std::mt19937 rng(2026);
  std::uniform_real_distribution<double> th(0.0, std::numbers::pi), ph(0.0, 2 * std::numbers::pi);
  for (int trial = 0; trial < 40; ++trial) {
    const double theta = th(rng), phi = ph(rng);
    basis.Evaluate(theta, phi, y);
    for (int l = 0; l <= kL; ++l)
      for (int m = -l; m <= l; ++m) {
        const double p = std::sph_legendre(static_cast<unsigned>(l), static_cast<unsigned>(std::abs(m)), theta);
        const double ref =
            m == 0 ? p : std::numbers::sqrt2 * p * (m > 0 ? core::pmath::Cos(m * phi) : core::pmath::Sin(-m * phi));
        worst_value = std::max(worst_value, std::abs(y[RealShBasis::Index(l, m)] - ref));
        char line[128];
        std::snprintf(line, sizeof line, "%d,%d,%.17g,%.17g,%.17g\n", l, m, theta, phi, y[RealShBasis::Index(l, m)]);
        f << line;
      }
  }
  return worst_value;
}

// What FitShSurface says when given fewer samples than coefficients.
std::string TooFewSamplesMessage() {
  std::string too_few_message;
  try {
    FitShSurface(10, Eigen::Matrix2Xd::Zero(2, 100), Eigen::Matrix3Xd::Zero(3, 100));
  } catch (const std::invalid_argument& e) {
    too_few_message = e.what();
  }
  return too_few_message;
}

struct ShfCheck {
  std::string claim;
  bool ok;
  std::string detail;
};

// RMS error must fall with Lmax until it reaches the data's round-off
// floor (1 nm: the OBJ text keeps 10 digits).
void CheckErrorFallsWithLmax(const std::vector<Row>& rows, std::vector<ShfCheck>* checks) {
  constexpr double kFloor_m = 1e-9;
  for (const std::string body : {"limb_segment", "ellipsoid_radial", "obj_star"}) {
    std::vector<double> err;
    for (const auto& r : rows)
      if (r.body == body) err.push_back(r.holdout_rms_m);
    bool falls = err.back() < 0.01 * err.front();
    for (std::size_t i = 1; i < err.size(); ++i) falls = falls && (err[i] <= err[i - 1] * (1 + 1e-9) || err[i] < kFloor_m);
    checks->push_back({body + ": held-out RMS error falls as Lmax grows", falls,
                       std::to_string(1e3 * err.front()) + " mm at Lmax 1 -> " + std::to_string(1e3 * err.back()) +
                           " mm at Lmax 20"});
  }
}

// summary.md and stdout; true if every check holds.
bool ReportShfChecks(const std::filesystem::path& out, const std::vector<ShfCheck>& checks) {
  bool all = true;
  std::ofstream md(out / "summary.md");
  md << "# shf validation\n\n| claim | ok | detail |\n|---|---|---|\n";
  for (const auto& c : checks) {
    md << "| " << c.claim << " | " << (c.ok ? "yes" : "**NO**") << " | " << c.detail << " |\n";
    std::printf("%-72s %s  %s\n", c.claim.c_str(), c.ok ? "ok  " : "FAIL", c.detail.c_str());
    all = all && c.ok;
  }
  return all;
}

int Run(const std::filesystem::path& out) {
  const std::string obj_text = StarObj(40, 80);
  std::ofstream(out / "star.obj") << obj_text;
  const TriangleMesh obj = io::ParseObj(obj_text);
  const bool obj_star = IsStarShapedAbout(obj, Eigen::Vector3d::Zero());
  const std::vector<Row> rows = FitEveryBody(obj);
  WriteFitErrorCsv(out, rows);
  const double worst_value = WriteShValuesAgainstSphLegendre(out);
  const std::string too_few_message = TooFewSamplesMessage();

  std::vector<ShfCheck> checks;
  checks.push_back({"real SH = std::sph_legendre construction to 1e-12 (Lmax 30, 40 random points)",
                    worst_value < 1e-12, std::to_string(worst_value)});
  double natural_worst = 0.0;
  for (const auto& r : rows)
    if (r.body == "ellipsoid_natural") natural_worst = std::max(natural_worst, r.holdout_m);
  checks.push_back({"ellipsoid (natural parametrisation) fitted exactly from Lmax = 1", natural_worst < 1e-15,
                    std::to_string(natural_worst) + " m"});
  CheckErrorFallsWithLmax(rows, &checks);
  checks.push_back(
      {"OBJ mesh is star-shaped about its centre", obj_star, std::to_string(obj.triangles.size()) + " triangles"});
  checks.push_back(
      {"too few samples is reported", too_few_message.find("need at least k") != std::string::npos, too_few_message});
  return ReportShfChecks(out, checks) ? 0 : 1;
}

}  // namespace

HAPSIM_VALIDATE_COMMAND("shf", "spherical-harmonic surfaces: basis values, fit error vs Lmax (limb, ellipsoid, OBJ)", &Run);

}  // namespace hapsim::validate
