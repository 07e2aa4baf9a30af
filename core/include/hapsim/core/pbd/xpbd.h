// Extended position-based dynamics (XPBD; Macklin, Müller, Chentanez 2016)
// for the vascular paper's constraints (Zhang et al. 2021, §2.2). Def -> Build ->
// State -> Step, no allocation in a step.
//
// Departure from the paper, and why: the paper projects its constraints with
// plain PBD, Δp_i = -s w_i ∇_i C with s = C / Σ w_j |∇_j C|², whose effective
// stiffness depends on the iteration count and the time step (more
// iterations or smaller steps make the same material stiffer). XPBD gives
// each constraint a compliance α (the inverse of its stiffness, [m/N] for a
// distance) and keeps a Lagrange multiplier λ per constraint in the state:
//   Δλ = (-C - α̃ λ) / (Σ w_j |∇_j C|² + α̃),  α̃ = α / h²,  Δp_i = w_i ∇_i C Δλ,
// which converges to the implicit-Euler solution of the elastic energy
// ½ C² / α — a stiffness fixed by α alone. α = 0 is the paper's rigid
// constraint (plain PBD's projection), so both are one code path;
// `plain_pbd_stiffness` reproduces the paper's k-scaled projection for the
// baseline comparison.
#pragma once
#include <array>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace hapsim::core {

// Stretching constraint between two nodes (paper §2.2.1): C = |p_i - p_j| - d.
struct DistanceConstraint {
  std::int32_t i = 0, j = 0;
  double rest_m = 0.0;
  double compliance_m_per_N = 0.0;  // α = 1/k; 0: inextensible
};

struct XpbdDef {
  Eigen::Matrix3Xd x0_m;                    // rest positions (3 x n)
  std::vector<double> mass_kg;              // (n)
  std::vector<std::uint8_t> fixed;          // (n) 1: held; empty: none
  std::vector<DistanceConstraint> distance;
  Eigen::Vector3d gravity_W_m_per_s2 = Eigen::Vector3d::Zero();
  int iterations = 10;                      // Gauss-Seidel sweeps per step
  double damping_per_s = 0.0;               // velocity decay v *= max(0, 1 - c h) per step
  // Plain PBD instead of XPBD (the paper's baseline): λ is not kept, and each
  // projection is scaled by this stiffness k in (0, 1] as in Müller et al.
  // 2007 (0: XPBD, the default).
  double plain_pbd_stiffness = 0.0;
};

struct XpbdModel {
  std::int32_t n = 0;
  Eigen::Matrix3Xd x0_m;
  Eigen::VectorXd inv_mass_per_kg;  // 0 for fixed nodes
  std::vector<DistanceConstraint> distance;
  Eigen::Vector3d gravity_W_m_per_s2 = Eigen::Vector3d::Zero();
  int iterations = 10;
  double damping_per_s = 0.0;
  double plain_pbd_stiffness = 0.0;
};

struct XpbdState {
  Eigen::Matrix3Xd x_m, v_m_per_s, f_ext_N;  // (3 x n)
  Eigen::Matrix3Xd x_start_m;                // scratch: positions at the step's start
  Eigen::VectorXd lambda;                    // (constraints) Lagrange multipliers of the last step [N s²]
  double time_s = 0.0;
};

// Throws std::invalid_argument naming the problem (sizes, masses, a
// constraint naming a missing node or with a negative rest length or
// compliance, iterations outside [1, 1000], stiffness outside [0, 1]).
XpbdModel BuildXpbdModel(const XpbdDef& def);
XpbdState MakeXpbdState(const XpbdModel& model);

// Constraints a caller projects in each sweep besides the model's own
// distance constraints: a tool's contact, a floor, tethers. StepXpbd calls
// BeginStep once after its prediction and Project once per sweep, after the
// distance constraints; Project may move only nodes with inverse mass > 0.
class XpbdExtraConstraints {
 public:
  virtual ~XpbdExtraConstraints() = default;
  virtual void BeginStep() = 0;  // reset the step's multipliers
  virtual void Project(Eigen::Matrix3Xd& x_m, const Eigen::VectorXd& inv_mass_per_kg, double h_s) = 0;
};

// One step of h seconds: predict with velocities, gravity and f_ext, project
// the constraints (the model's, then `extra`'s) `iterations` times, derive
// velocities from the positions.
void StepXpbd(const XpbdModel& model, XpbdState& state, double h_s, XpbdExtraConstraints* extra = nullptr);

// Reorders constraints by a greedy colouring of the constraint graph: each
// colour's constraints share no node, colours follow one another, the order
// within a colour is kept. A Gauss-Seidel sweep in this order is still a
// Gauss-Seidel sweep (it converges to the same solution), but neighbouring
// projections no longer wait on each other's positions, so the CPU overlaps
// their square roots and divisions (2-3x faster sweeps on a lattice whose
// natural order chains every constraint to the previous one).
// Throws std::invalid_argument for a node index outside [0, n_nodes);
// returns the number of colours.
int OrderByColour(std::vector<DistanceConstraint>& constraints, std::int32_t n_nodes);

// One XPBD projection of the distance constraint C = |x_i - x_j| - rest with
// inverse masses w_i, w_j and α̃ = α / h²: moves both nodes, adds Δλ to
// *lambda. With `unilateral`, only C < 0 is enforced (λ stays >= 0: a contact
// that pushes, never pulls). Shared by StepXpbd and the vessel scene.
inline void ProjectDistanceXpbd(Eigen::Matrix3Xd& x_m, std::int32_t i, const Eigen::Vector3d& target_j, double wi,
                                double wj, double rest_m, double alpha_tilde, double* lambda, bool unilateral,
                                Eigen::Vector3d* move_j) {
  const Eigen::Vector3d delta = x_m.col(i) - target_j;
  const double length = delta.norm();
  if (length < 1e-15 || wi + wj == 0.0) return;  // direction undefined / nothing can move
  const double C = length - rest_m;
  if (unilateral && C >= 0.0 && *lambda == 0.0) return;
  double dlambda = (-C - alpha_tilde * *lambda) / (wi + wj + alpha_tilde);
  if (unilateral && *lambda + dlambda < 0.0) dlambda = -*lambda;
  *lambda += dlambda;
  const Eigen::Vector3d n = delta / length;
  x_m.col(i) += wi * dlambda * n;
  if (move_j) *move_j = -wj * dlambda * n;
}

// One plain-PBD projection of C = |x_i - x_j| - rest (the paper's baseline):
// both nodes move `stiffness` of the way to the rest length, split by inverse
// mass; no multiplier, so the result depends on sweeps and step.
inline void ProjectDistancePlainPbd(Eigen::Matrix3Xd& x_m, std::int32_t i, std::int32_t j, double wi, double wj,
                                    double rest_m, double stiffness) {
  const Eigen::Vector3d d = x_m.col(i) - x_m.col(j);
  const double length = d.norm();
  if (length < 1e-15 || wi + wj == 0.0) return;
  const Eigen::Vector3d step = (stiffness * (length - rest_m) / ((wi + wj) * length)) * d;
  x_m.col(i) -= wi * step;
  x_m.col(j) += wj * step;
}

// Elastic-potential-energy constraint of one virtual tetrahedron (paper
// §2.2.2): its four nodes joined pairwise by virtual springs (the six edges),
//   U = sum over edges ½ k_e (|p_i - p_j| - l_e)².
// Projected the XPBD way with C = sqrt(2 U) and unit compliance [1/J], so the
// energy XPBD converges to is exactly U and the springs' k_e set the
// stiffness (the paper's plain-PBD projection s = C / sum w |grad C|² with
// C = U has no such fixed point). At rest (U ~ 0) the gradient of sqrt(2U)
// is undefined and nothing is done.
struct TetEnergyConstraint {
  std::array<std::int32_t, 4> node{};
  std::array<double, 6> rest_m{};       // edges (0,1) (0,2) (0,3) (1,2) (1,3) (2,3)
  std::array<double, 6> k_N_per_m{};
};
inline constexpr std::array<std::array<int, 2>, 6> kTetEdges = {{{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

// The tetrahedron's spring energy [J] at positions x.
double TetSpringEnergy_J(const TetEnergyConstraint& tet, const Eigen::Matrix3Xd& x_m);
// One XPBD projection (unit compliance, α̃ = 1 / h²); *lambda accumulates.
void ProjectTetEnergyXpbd(Eigen::Matrix3Xd& x_m, const TetEnergyConstraint& tet, const Eigen::VectorXd& inv_mass_per_kg,
                          double h_s, double* lambda);
// A tetrahedron with the springs of its six edges at rest in x0 (k = stiffness).
TetEnergyConstraint MakeTetEnergyConstraint(const Eigen::Matrix3Xd& x0_m, std::array<std::int32_t, 4> nodes,
                                            double stiffness_N_per_m);

// Force the constraint exerts on node i at the end of the last step [N]:
// λ / h² along the constraint (XPBD's constraint force), for checks.
double DistanceConstraintForce_N(const XpbdState& state, std::size_t constraint, double h_s);

}  // namespace hapsim::core
