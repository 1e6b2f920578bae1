// The approximate footprint (dissertation §5.3.1, Algorithm 1): the PMP closed form against its own necessary
// conditions and against a direct numerical optimum (KKT system), the exact step-7 integration against a
// fine-step reference, the Maclaurin option against the exact exponentials, orderings of the bounded footprint,
// the region and its world placement.
#include "uascma/planning/footprint.h"

#include <gtest/gtest.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "uascma/common/error.h"
#include "uascma/common/frames.h"
#include "uascma/models/drag.h"

namespace uascma::planning {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMass = 1.3;        // kg, docs/defaults.md#vehicle
constexpr double kDragSlope = 0.55;  // N·s/m, ≈ ρ f v of the default table at 9 m/s
constexpr double kSpeed = 9.0;       // m/s, Fig. 5.4

// Tolerances, each named for what it covers.
constexpr double kRoundOff = 1e-10;           // relative: closed-form identities evaluated in double
constexpr double kFiniteDifference = 1e-6;    // relative: central differences with step 1e-4 t_f
constexpr double kConstantsAgreement = 1e-8;  // relative: the 4×4 system against the reduced closed form
constexpr double kFineStep = 1e-6;            // m + relative 1e-8: RK4 with a 1 ms step against the exact pieces

AxisProblem MakeProblem(double v0, double vf, double eod, double drag_slope = kDragSlope) {
  AxisProblem p;
  p.initial_position = 3.0;  // m: a nonzero x0 catches a dropped C4
  p.initial_velocity = v0;
  p.final_velocity = vf;
  p.final_time = eod;
  p.mass = kMass;
  p.drag_slope = drag_slope;
  return p;
}

// The three cases of Algorithm 1 at v_init = 9 m/s, and a long EOD and a drag-free variant.
std::vector<AxisProblem> Problems() {
  return {MakeProblem(kSpeed, kSpeed, 20.0),   MakeProblem(kSpeed, -kSpeed, 20.0), MakeProblem(0.0, kSpeed, 20.0),
          MakeProblem(kSpeed, -kSpeed, 300.0), MakeProblem(4.0, -4.0, 7.0, 0.0),   MakeProblem(2.0, 5.0, 1.5)};
}

double Hamiltonian(const AxisOptimalState& s, const AxisProblem& p) {  // eq. 5.4
  const double a = p.drag_slope / p.mass;
  return 0.5 * s.control * s.control + s.costate_position * s.velocity +
         s.costate_velocity * (s.control / p.mass - a * s.velocity);
}

// --- the PMP closed form against its own conditions ------------------------------------------------------------------
TEST(FootprintPmpTest, ClosedFormMeetsBoundaryConditions) {
  for (const AxisProblem& p : Problems()) {
    const AxisOptimalSolution solution(p);
    ASSERT_EQ(solution.status(), PmpStatus::kSolved);
    const AxisOptimalState start = solution.At(0.0);
    const AxisOptimalState end = solution.At(p.final_time);
    const double scale = std::abs(p.initial_velocity) + std::abs(p.final_velocity);
    EXPECT_NEAR(start.position, p.initial_position, kRoundOff * (1.0 + std::abs(p.initial_position)));
    EXPECT_NEAR(start.velocity, p.initial_velocity, kRoundOff * scale);
    EXPECT_NEAR(end.velocity, p.final_velocity, kRoundOff * scale) << "x2(t_f), eqs. 5.10/5.11";
    EXPECT_NEAR(end.costate_velocity, 0.0, kRoundOff * std::abs(start.costate_velocity)) << "λ2(t_f) = 0";
  }
}

TEST(FootprintPmpTest, StateAndCostateSatisfyTheHamiltonianSystem) {
  for (const AxisProblem& p : Problems()) {
    const AxisOptimalSolution solution(p);
    const double a = p.drag_slope / p.mass;
    const double step = 1e-4 * p.final_time;
    const double h0 = Hamiltonian(solution.At(0.0), p);
    for (double fraction : {0.1, 0.37, 0.5, 0.81, 0.97}) {
      const double t = fraction * p.final_time;
      const AxisOptimalState s = solution.At(t);
      const AxisOptimalState ahead = solution.At(t + step);
      const AxisOptimalState behind = solution.At(t - step);
      auto rate = [&](double AxisOptimalState::*member) { return (ahead.*member - behind.*member) / (2 * step); };
      const double velocity_scale = std::abs(s.velocity) + std::abs(p.initial_velocity) + 1.0;
      const double force_scale = std::abs(s.control) / p.mass + a * velocity_scale + 1.0;
      // ẋ = ∂H/∂λ (eq. 5.2).
      EXPECT_NEAR(rate(&AxisOptimalState::position), s.velocity, kFiniteDifference * velocity_scale);
      EXPECT_NEAR(rate(&AxisOptimalState::velocity), s.control / p.mass - a * s.velocity,
                  kFiniteDifference * force_scale);
      // λ̇ = −∂H/∂x: λ̇1 = 0, λ̇2 = −λ1 + a λ2.
      const double costate_scale = std::abs(s.costate_position) * (1.0 + p.final_time) + 1.0;
      EXPECT_NEAR(rate(&AxisOptimalState::costate_position), 0.0, kFiniteDifference * costate_scale);
      EXPECT_NEAR(rate(&AxisOptimalState::costate_velocity), -s.costate_position + a * s.costate_velocity,
                  kFiniteDifference * costate_scale);
      // ∂H/∂u = u + λ2/m = 0, and H is constant along the optimum (time-invariant problem).
      EXPECT_NEAR(s.control + s.costate_velocity / p.mass, 0.0, kRoundOff * costate_scale);
      EXPECT_NEAR(Hamiltonian(s, p), h0, kFiniteDifference * (std::abs(h0) + s.control * s.control + 1.0));
    }
  }
}

TEST(FootprintPmpTest, LinearSystemForConstantsMatchesTheReducedClosedForm) {
  // Moderate a t_f (≈ 8.5): e^{a t_f} is representable and the 4×4 system of the dissertation well posed.
  for (const AxisProblem& p : {MakeProblem(kSpeed, kSpeed, 20.0), MakeProblem(kSpeed, -kSpeed, 20.0),
                               MakeProblem(0.0, kSpeed, 20.0), MakeProblem(2.0, -1.0, 0.7)}) {
    const AxisOptimalSolution solution(p);
    const PmpConstants solved = SolvePmpConstants(p, 0);
    ASSERT_TRUE(solved.defined);
    ASSERT_TRUE(solution.constants().defined);
    const PmpConstants& derived = solution.constants();
    EXPECT_NEAR(solved.c1, derived.c1, kConstantsAgreement * std::abs(derived.c1));
    EXPECT_NEAR(solved.c2, derived.c2, kConstantsAgreement * std::abs(derived.c2));
    EXPECT_NEAR(solved.c3, derived.c3, kConstantsAgreement * (std::abs(derived.c3) + 1.0));
    EXPECT_NEAR(solved.c4, derived.c4, kConstantsAgreement * (std::abs(derived.c4) + 1.0));
    // Eqs. 5.5–5.9 from the solved constants reproduce the stable evaluation.
    for (double fraction : {0.0, 0.25, 0.6, 1.0}) {
      const double t = fraction * p.final_time;
      const AxisOptimalState printed = EvaluatePmpEquations(solved, p, t, 0);
      const AxisOptimalState stable = solution.At(t);
      const double x_scale = std::abs(stable.position) + 1.0;
      EXPECT_NEAR(printed.position, stable.position, kConstantsAgreement * x_scale * 10);
      EXPECT_NEAR(printed.velocity, stable.velocity, kConstantsAgreement * (std::abs(stable.velocity) + 1.0) * 10);
      EXPECT_NEAR(printed.control, stable.control, kConstantsAgreement * (std::abs(solution.Control(0)) + 1.0) * 10);
      EXPECT_NEAR(printed.costate_velocity, stable.costate_velocity,
                  kConstantsAgreement * (std::abs(solution.At(0).costate_velocity) + 1.0) * 10);
    }
  }
}

TEST(FootprintPmpTest, Eq55AsPrintedViolatesKinematicsAndTheCorrectionDoesNot) {
  // The printed C3 term of eq. 5.5 is −(C3/d_x) m e^{−a t}; ours is +. d/dt of the printed x1 misses x2 by
  // 2 C3 e^{−a t}, which the test sees; the corrected one matches x2.
  const AxisProblem p = MakeProblem(kSpeed, -kSpeed, 6.0);
  const PmpConstants c = SolvePmpConstants(p, 0);
  ASSERT_TRUE(c.defined);
  const double a = p.drag_slope / p.mass, t = 2.0, step = 1e-4;
  auto printed_position = [&](double time) {
    return EvaluatePmpEquations(c, p, time, 0).position - 2 * p.mass * c.c3 / p.drag_slope * std::exp(-a * time);
  };
  const double velocity = EvaluatePmpEquations(c, p, t, 0).velocity;
  const double corrected_rate =
      (EvaluatePmpEquations(c, p, t + step, 0).position - EvaluatePmpEquations(c, p, t - step, 0).position) /
      (2 * step);
  const double printed_rate = (printed_position(t + step) - printed_position(t - step)) / (2 * step);
  EXPECT_NEAR(corrected_rate, velocity, kFiniteDifference * 10);
  EXPECT_NEAR(printed_rate - velocity, 2 * c.c3 * std::exp(-a * t), kFiniteDifference * 10);
  EXPECT_GT(std::abs(printed_rate - velocity), 1.0);  // m/s: the printed sign is not a round-off matter
}

// --- the closed form against a direct numerical optimum --------------------------------------------------------------
// Discretise u on N equal intervals (piecewise constant). The final state is affine in u:
//   x2(t_f) = e^{−a t_f} v0 + b_v·u,   x1(t_f) = x0 + ψ(t_f) v0 + b_x·u,
// with b_v,i = (1/m) ∫_cell e^{−a(t_f − s)} ds and b_x,i = (1/m) ∫_cell (1 − e^{−a(t_f − s)})/a ds (here with
// plain std::exp, independent of the library's kernels). Conditions 5.10/5.11 (x2(t_f) = v_f together with
// λ2(t_f) = 0) describe: minimise ½ ∫ u² subject to x1(t_f) = X, x2(t_f) free — for the X at which the optimum
// arrives with x2(t_f) = v_f. Its KKT system, with X as one more unknown fixed by the speed condition:
//   Δ u − μ b_x = 0,   b_x·u − X = −x1_free,   b_v·u = v_f − x2_free.
struct DiscreteOptimum {
  Eigen::VectorXd control;  // N, per interval
  double final_position = 0.0;
};

DiscreteOptimum SolveKkt(const AxisProblem& p, int intervals) {
  const double a = p.drag_slope / p.mass, tf = p.final_time, dt = tf / intervals;
  Eigen::VectorXd b_v(intervals), b_x(intervals);
  for (int i = 0; i < intervals; ++i) {
    const double early = std::exp(-a * (tf - i * dt)), late = std::exp(-a * (tf - (i + 1) * dt));
    b_v(i) = (late - early) / (a * p.mass);
    b_x(i) = (dt / p.mass - b_v(i)) / a;
  }
  const double x2_free = std::exp(-a * tf) * p.initial_velocity;
  const double x1_free = p.initial_position + (1 - std::exp(-a * tf)) / a * p.initial_velocity;
  const int n = intervals + 2;
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n, n);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n);
  kkt.topLeftCorner(intervals, intervals) = dt * Eigen::MatrixXd::Identity(intervals, intervals);
  kkt.block(0, intervals, intervals, 1) = -b_x;
  kkt.block(intervals, 0, 1, intervals) = b_x.transpose();
  kkt(intervals, intervals + 1) = -1.0;
  rhs(intervals) = -x1_free;
  kkt.block(intervals + 1, 0, 1, intervals) = b_v.transpose();
  rhs(intervals + 1) = p.final_velocity - x2_free;
  const Eigen::VectorXd solution = kkt.partialPivLu().solve(rhs);
  return {solution.head(intervals), solution(intervals + 1)};
}

// Largest control error (N) and final-position error (m) of the N-interval discrete optimum.
struct KktErrors {
  double control = 0.0;
  double position = 0.0;
};

KktErrors CompareWithKkt(const AxisOptimalSolution& solution, int intervals) {
  const AxisProblem& p = solution.problem();
  const DiscreteOptimum discrete = SolveKkt(p, intervals);
  const double dt = p.final_time / intervals;
  KktErrors errors;
  for (int i = 0; i < intervals; ++i) {
    errors.control = std::max(errors.control, std::abs(discrete.control(i) - solution.Control((i + 0.5) * dt)));
  }
  errors.position = std::abs(discrete.final_position - solution.At(p.final_time).position);
  return errors;
}

TEST(FootprintPmpTest, ClosedFormEqualsTheDiscreteKktOptimum) {
  // Piecewise-constant controls make a second-order error, Δ² times the curvature of the solution (the
  // midpoint rule's 1/24 for the cell average of u*, and the same order in the multiplier μ).
  constexpr int kIntervals = 400;
  constexpr double kSecondOrderConstant = 0.2;  // per Δ² × curvature; the midpoint rule alone gives 1/24
  for (const AxisProblem& p :
       {MakeProblem(kSpeed, kSpeed, 20.0), MakeProblem(kSpeed, -kSpeed, 20.0), MakeProblem(0.0, kSpeed, 20.0),
        MakeProblem(kSpeed, -kSpeed, 100.0), MakeProblem(3.0, 3.0, 2.0)}) {
    const AxisOptimalSolution solution(p);
    const double a = p.drag_slope / p.mass;
    const double dt = p.final_time / kIntervals;
    const double largest = std::abs(solution.Control(0.0));  // |u*| is largest at t = 0
    const double position = std::abs(solution.At(p.final_time).position) + 1.0;
    const double control_curvature = std::abs(solution.gain()) * a + a * a * largest;  // N/s², bounds |ü*| + a²|u*|
    const KktErrors fine = CompareWithKkt(solution, kIntervals);
    const KktErrors coarse = CompareWithKkt(solution, kIntervals / 2);
    const std::string label = "t_f " + std::to_string(p.final_time) + " v_f " + std::to_string(p.final_velocity);
    EXPECT_LT(fine.control, kSecondOrderConstant * dt * dt * control_curvature + kRoundOff * largest) << label;
    EXPECT_LT(fine.position, kSecondOrderConstant * (a * dt) * (a * dt) * position + kRoundOff * position) << label;
    // Halving Δ divides the errors by four: the discrete optimum converges to the closed form.
    if (coarse.position > 1e-8 * position) {
      EXPECT_NEAR(coarse.position / fine.position, 4.0, 0.5) << label;
      EXPECT_NEAR(coarse.control / fine.control, 4.0, 0.5) << label;
    }
    // The unbounded step 7 is the same closed form.
    const double closed_position = solution.At(p.final_time).position;
    const double simulated = SimulateBoundedAxis(solution, std::numeric_limits<double>::infinity()).final_position;
    EXPECT_NEAR(simulated, closed_position, kRoundOff * position);
  }
}

TEST(FootprintPmpTest, DragFreeLimitsHaveTheirHandDerivedValues) {
  // d_x = 0: forward u* ≡ 0 → v T; backward u* = −(4 m v/T²)(T − t) → −v T/3; lateral u* = (2 m v/T²)(T − t)
  // from rest → 2 v T/3.
  FootprintParams params;
  params.initial_speed = 4.0;
  params.eod = 10.0;
  params.drag_slope = 0.0;
  const FootprintResult r = CalcFootprint(params);
  ASSERT_TRUE(r.ok()) << r.message;
  EXPECT_NEAR(r.unbounded_forward_limit, 40.0, kRoundOff * 40);
  EXPECT_NEAR(r.unbounded_backward_limit, -40.0 / 3.0, kRoundOff * 40);
  EXPECT_NEAR(r.unbounded_lateral_limit, 80.0 / 3.0, kRoundOff * 40);
  // Peak |u*| = 4 m v/T = 2.08 N < u_max = m g tan 30° = 7.36 N: the bounds are inactive.
  EXPECT_NEAR(r.backward_limit, r.unbounded_backward_limit, kRoundOff * 40);
  EXPECT_NEAR(r.backward.saturation_time, 0.0, kRoundOff);
  EXPECT_NEAR(r.max_control_force, kMass * kGravity * std::tan(30.0 / 180.0 * kPi), 1e-9);
}

// --- step 7: exact pieces against a fine-step reference
// -----------------------------------------------------------------
double Rk4FinalPosition(const AxisOptimalSolution& solution, double max_force, double dt) {
  const AxisProblem& p = solution.problem();
  const double a = p.drag_slope / p.mass;
  auto force = [&](double t) { return std::clamp(solution.Control(std::min(t, p.final_time)), -max_force, max_force); };
  auto derivative = [&](double t, const Eigen::Vector2d& x) {
    return Eigen::Vector2d(x(1), force(t) / p.mass - a * x(1));
  };
  Eigen::Vector2d x(p.initial_position, p.initial_velocity);
  const int steps = static_cast<int>(std::ceil(p.final_time / dt));
  const double h = p.final_time / steps;
  for (int i = 0; i < steps; ++i) {
    const double t = i * h;
    const Eigen::Vector2d k1 = derivative(t, x);
    const Eigen::Vector2d k2 = derivative(t + h / 2, x + h / 2 * k1);
    const Eigen::Vector2d k3 = derivative(t + h / 2, x + h / 2 * k2);
    const Eigen::Vector2d k4 = derivative(t + h, x + h * k3);
    x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return x(0);
}

TEST(FootprintStepSevenTest, ExactPiecesMatchFineStepIntegration) {
  const double u_max = kMass * kGravity * std::tan(20.0 / 180.0 * kPi);  // 4.64 N: saturates every case below
  struct Case {
    AxisProblem problem;
    int order;
    double dt;
  };
  const std::vector<Case> cases = {
      {MakeProblem(kSpeed, kSpeed, 20.0), 0, 1e-3}, {MakeProblem(kSpeed, -kSpeed, 20.0), 0, 1e-3},
      {MakeProblem(0.0, kSpeed, 20.0), 0, 1e-3},    {MakeProblem(kSpeed, -kSpeed, 300.0), 0, 5e-3},
      {MakeProblem(kSpeed, -kSpeed, 5.0), 5, 1e-3}, {MakeProblem(0.0, kSpeed, 3.0), 5, 1e-3},
      {MakeProblem(kSpeed, kSpeed, 30.0), 5, 1e-3}, {MakeProblem(kSpeed, -kSpeed, 8.0), 12, 1e-3},
      {MakeProblem(3.0, -3.0, 6.0, 0.05), 0, 1e-3}};
  for (const Case& c : cases) {
    const AxisOptimalSolution solution(c.problem, c.order);
    ASSERT_EQ(solution.status(), PmpStatus::kSolved);
    const BoundedAxisResult exact = SimulateBoundedAxis(solution, u_max);
    const double reference = Rk4FinalPosition(solution, u_max, c.dt);
    EXPECT_NEAR(exact.final_position, reference, kFineStep + 1e-8 * std::abs(reference))
        << "t_f " << c.problem.final_time << " order " << c.order;
    // The unbounded series law is integrated by the polynomial pieces alone.
    const double infinity = std::numeric_limits<double>::infinity();
    const double free_reference = Rk4FinalPosition(solution, infinity, c.dt);
    EXPECT_NEAR(SimulateBoundedAxis(solution, infinity).final_position, free_reference,
                kFineStep + 1e-8 * std::abs(free_reference));
    if (c.order == 0 && c.problem.drag_slope == kDragSlope) {
      EXPECT_GT(exact.saturation_time, 0.0);
    }
  }
}

TEST(FootprintStepSevenTest, SaturationTimeIsWhereTheOptimalControlMeetsTheBound) {
  const double u_max = 4.0;
  for (int order : {0, 5}) {
    const AxisOptimalSolution solution(MakeProblem(kSpeed, -kSpeed, 4.0), order);
    const BoundedAxisResult r = SimulateBoundedAxis(solution, u_max);
    ASSERT_GT(r.saturation_time, 0.0);
    ASSERT_LT(r.saturation_time, 4.0);
    EXPECT_NEAR(std::abs(solution.Control(r.saturation_time)), u_max, 1e-9) << "order " << order;
    EXPECT_GT(std::abs(r.peak_control), u_max);
    // Eqs. 5.12–5.13 at t = 0: deceleration (u < 0) needs nose-up pitch in FRD.
    EXPECT_GT(r.peak_pitch, 0.0);
    EXPECT_NEAR(r.peak_thrust * std::cos(r.peak_pitch), kMass * kGravity, 1e-9);
    EXPECT_NEAR(-r.peak_thrust * std::sin(r.peak_pitch), r.peak_control, 1e-9);
  }
}

// --- the Maclaurin option ------------------------------------------------------------------------------------------
TEST(FootprintMaclaurinTest, SeriesIsTheTruncatedExponential) {
  EXPECT_NEAR(MaclaurinExp(1.0, 5), 1 + 1 + 1 / 2.0 + 1 / 6.0 + 1 / 24.0 + 1 / 120.0, 1e-15);
  EXPECT_NEAR(MaclaurinExp(-3.0, 5), 1 - 3 + 4.5 - 4.5 + 3.375 - 2.025, 1e-13);  // negative: not an exponential
  EXPECT_NEAR(MaclaurinExp(0.7, 30), std::exp(0.7), 1e-15);
}

FootprintParams Fig54Params(double eod, int order) {
  FootprintParams params;
  params.initial_speed = kSpeed;
  params.eod = eod;
  params.drag_slope = kDragSlope;
  params.maclaurin_order = order;
  return params;
}

TEST(FootprintMaclaurinTest, SeriesAgreesWithExactWhenDragTimeIsSmallAndPartsWhenLarge) {
  // T_n(±a t_f) errs by (a t_f)^{n+1}/(n+1)!; the constants C1…C3 cancel to order (a t_f)², which amplifies it.
  struct Case {
    double eod;  // s; a t_f = 0.42 × EOD
    int order;
    double tolerance;  // relative
  };
  for (const Case& c : {Case{0.1, 5, 1e-7}, Case{0.5, 5, 1e-4}, Case{0.5, 10, 1e-9}, Case{10.0, 30, 1e-6}}) {
    const FootprintResult exact = CalcFootprint(Fig54Params(c.eod, 0));
    const FootprintResult series = CalcFootprint(Fig54Params(c.eod, c.order));
    ASSERT_TRUE(series.ok()) << series.message;
    for (auto limit : {&FootprintResult::forward_limit, &FootprintResult::backward_limit,
                       &FootprintResult::lateral_limit, &FootprintResult::unbounded_forward_limit,
                       &FootprintResult::unbounded_backward_limit, &FootprintResult::unbounded_lateral_limit}) {
      EXPECT_NEAR(series.*limit, exact.*limit, c.tolerance * (std::abs(exact.*limit) + 1))
          << "EOD " << c.eod << " order " << c.order;
    }
  }
  // The dissertation's n = 5 at a t_f ≈ 8.5 (EOD 20 s, inside Fig. 5.4's range): the series optimum is almost
  // u* ≡ 0 and the footprint collapses to a coasting line, far from the exact one.
  const FootprintResult exact = CalcFootprint(Fig54Params(20.0, 0));
  const FootprintResult series = CalcFootprint(Fig54Params(20.0, 5));
  ASSERT_TRUE(series.ok()) << series.message;
  EXPECT_LT(series.lateral_limit, 0.1 * exact.lateral_limit);
  EXPECT_LT(series.forward_limit, 0.9 * exact.forward_limit);
}

TEST(FootprintMaclaurinTest, SeriesNeedsDrag) {
  EXPECT_EQ(AxisOptimalSolution(MakeProblem(1.0, 1.0, 5.0, 0.0), 5).status(), PmpStatus::kSingular);
  FootprintParams params = Fig54Params(5.0, 5);
  params.drag_slope = 0.0;
  std::string error, field;
  EXPECT_FALSE(params.IsValid(&error, &field));
  EXPECT_EQ(field, "drag_slope");
}

// --- orderings of the bounded footprint ------------------------------------------------------------------------------
void ExpectShrinksAlong(const std::vector<FootprintResult>& growing, const std::string& what) {
  constexpr double kOrdering = 1e-9;  // m: round-off allowance for equal limits
  bool changed = false;
  for (std::size_t i = 1; i < growing.size(); ++i) {
    const FootprintResult& small = growing[i - 1];
    const FootprintResult& large = growing[i];
    EXPECT_LE(small.forward_limit, large.forward_limit + kOrdering) << what << " step " << i;
    EXPECT_GE(small.backward_limit, large.backward_limit - kOrdering) << what << " step " << i;
    EXPECT_LE(small.lateral_limit, large.lateral_limit + kOrdering) << what << " step " << i;
    EXPECT_LE(small.region.Area(), large.region.Area() + kOrdering) << what << " step " << i;
    // Bounding never adds reach.
    EXPECT_LE(small.forward_limit, small.unbounded_forward_limit + kOrdering);
    EXPECT_GE(small.backward_limit, small.unbounded_backward_limit - kOrdering);
    EXPECT_LE(small.lateral_limit, small.unbounded_lateral_limit + kOrdering);
    changed = changed || large.forward_limit - small.forward_limit > 1.0;
  }
  EXPECT_TRUE(changed) << what << ": the bound never became active";
}

TEST(FootprintOrderingTest, ShrinksWithTheAttitudeLimit) {
  std::vector<FootprintResult> results;
  for (double degrees : {5.0, 10.0, 20.0, 30.0, 45.0, 60.0}) {
    FootprintParams params = Fig54Params(20.0, 0);
    params.max_tilt = degrees / 180.0 * kPi;
    params.available_thrust = 100.0;
    results.push_back(CalcFootprint(params));
  }
  ExpectShrinksAlong(results, "max tilt");
}

TEST(FootprintOrderingTest, ShrinksWithTheAvailableThrust) {
  std::vector<FootprintResult> results;
  for (double thrust : {12.8, 13.0, 13.5, 14.5, 17.0, 26.85}) {  // m g = 12.75 N
    FootprintParams params = Fig54Params(20.0, 0);
    params.max_tilt = 80.0 / 180.0 * kPi;
    params.available_thrust = thrust;
    results.push_back(CalcFootprint(params));
    EXPECT_LT(results.back().effective_max_tilt, params.max_tilt);
  }
  ExpectShrinksAlong(results, "available thrust");
}

TEST(FootprintOrderingTest, GrowsWithTheEndOfDischarge) {
  std::vector<double> eods = {0.0, 0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 300.0};
  std::vector<FootprintResult> results;
  for (double eod : eods) results.push_back(CalcFootprint(Fig54Params(eod, 0)));
  for (std::size_t i = 1; i < results.size(); ++i) {
    const FootprintResult& shorter = results[i - 1];
    const FootprintResult& longer = results[i];
    EXPECT_LT(shorter.forward_limit, longer.forward_limit) << "EOD " << eods[i];
    EXPECT_LT(shorter.lateral_limit, longer.lateral_limit) << "EOD " << eods[i];
    EXPECT_LT(shorter.region.semi_axis_x, longer.region.semi_axis_x) << "EOD " << eods[i];
    EXPECT_LT(shorter.region.Area(), longer.region.Area()) << "EOD " << eods[i];
  }
  // The cone of Fig. 5.4: at 9 m/s with 1 s left the vehicle cannot turn back, so the footprint is ahead…
  EXPECT_GT(results[2].backward_limit, 0.0);
  // …and with minutes left it can reach well behind.
  EXPECT_LT(results.back().backward_limit, -100.0);
}

TEST(FootprintOrderingTest, ZeroEodIsThePointUnderTheVehicle) {
  const FootprintResult r = CalcFootprint(Fig54Params(0.0, 0));
  ASSERT_TRUE(r.ok());
  EXPECT_NEAR(r.forward_limit, 0.0, kRoundOff);
  EXPECT_NEAR(r.backward_limit, 0.0, kRoundOff);
  EXPECT_NEAR(r.lateral_limit, 0.0, kRoundOff);
  EXPECT_NEAR(r.region.Area(), 0.0, kRoundOff);
  EXPECT_TRUE(r.region.Contains(Eigen::Vector2d::Zero()));
  EXPECT_FALSE(r.region.Contains(Eigen::Vector2d(1e-3, 0.0)));
  EXPECT_FALSE(r.region.Contains(Eigen::Vector2d(0.0, 1e-3)));
}

TEST(FootprintOrderingTest, ThrustBelowWeightCannotHoldAltitude) {
  FootprintParams params = Fig54Params(20.0, 0);
  params.available_thrust = 0.9 * kMass * kGravity;
  const FootprintResult r = CalcFootprint(params);
  EXPECT_EQ(r.status, FootprintStatus::kCannotHoldAltitude);
  EXPECT_FALSE(r.message.empty());
  EXPECT_FALSE(r.region.Contains(Eigen::Vector2d(1.0, 0.0)));
  // At exactly the weight the vehicle can only coast: no tilt, every case the same drag-decayed glide.
  params.available_thrust = kMass * kGravity;
  const FootprintResult coast = CalcFootprint(params);
  ASSERT_TRUE(coast.ok());
  const double glide = kSpeed * (1 - std::exp(-kDragSlope / kMass * 20.0)) / (kDragSlope / kMass);
  EXPECT_NEAR(coast.forward_limit, glide, kRoundOff * glide);
  EXPECT_NEAR(coast.backward_limit, glide, kRoundOff * glide);
  EXPECT_NEAR(coast.lateral_limit, 0.0, kRoundOff);
}

// --- the region and its placement in W -------------------------------------------------------------------------------
TEST(FootprintRegionTest, EllipseInscribedInTheLimits) {
  const FootprintResult r = CalcFootprint(Fig54Params(20.0, 0));
  ASSERT_TRUE(r.ok());
  const FootprintRegion& e = r.region;
  EXPECT_NEAR(e.center_x, 0.5 * (r.forward_limit + r.backward_limit), kRoundOff * r.forward_limit);
  EXPECT_NEAR(e.semi_axis_x, 0.5 * (r.forward_limit - r.backward_limit), kRoundOff * r.forward_limit);
  EXPECT_NEAR(e.semi_axis_y, r.lateral_limit, kRoundOff * r.forward_limit);
  constexpr double kEdge = 1e-6;  // m
  EXPECT_TRUE(e.Contains({r.forward_limit - kEdge, 0.0}));
  EXPECT_FALSE(e.Contains({r.forward_limit + kEdge, 0.0}));
  EXPECT_TRUE(e.Contains({r.backward_limit + kEdge, 0.0}));
  EXPECT_FALSE(e.Contains({r.backward_limit - kEdge, 0.0}));
  EXPECT_TRUE(e.Contains({e.center_x, -r.lateral_limit + kEdge}));
  EXPECT_FALSE(e.Contains({e.center_x, r.lateral_limit + kEdge}));
  EXPECT_FALSE(e.Contains({r.forward_limit, r.lateral_limit}));  // box corners are out
  EXPECT_TRUE(e.Contains({r.forward_limit, r.lateral_limit}, 1e4));
  for (const Eigen::Vector2d& point : e.Boundary(16)) {
    EXPECT_TRUE(e.Contains(point, kEdge));
    EXPECT_FALSE(e.Contains(point + (point - Eigen::Vector2d(e.center_x, 0)).normalized() * 1e-3));
  }
  EXPECT_THROW(e.Boundary(2), InputError);
}

TEST(FootprintRegionTest, UnboundedRegionIsACircleByLinearity) {
  // k_fwd − k_bwd = 2 k_lat, so without bounds x_f − x_b = 2 y_l for any EOD and drag. A bound active in all
  // three cases for nearly the whole flight (±u_max) nearly keeps it; a shorter saturation breaks it by a few
  // per cent.
  for (double eod : {0.5, 3.0, 20.0, 300.0}) {
    for (double drag_slope : {0.0, 0.2, kDragSlope}) {
      FootprintParams params = Fig54Params(eod, 0);
      params.drag_slope = drag_slope;
      const FootprintResult r = CalcFootprint(params);
      const double semi_axis_x = 0.5 * (r.unbounded_forward_limit - r.unbounded_backward_limit);
      EXPECT_NEAR(semi_axis_x, r.unbounded_lateral_limit, kRoundOff * (r.unbounded_lateral_limit + 1.0))
          << "EOD " << eod << " d_x " << drag_slope;
    }
  }
  const FootprintResult partly = CalcFootprint(Fig54Params(1.0, 0));
  EXPECT_GT(std::abs(partly.region.semi_axis_x - partly.region.semi_axis_y), 0.03 * partly.region.semi_axis_y);
  FootprintParams always = Fig54Params(3.0, 0);
  always.max_tilt = 2.0 / 180.0 * kPi;
  const FootprintResult saturated = CalcFootprint(always);
  ASSERT_GT(saturated.lateral.saturation_time, 0.9 * 3.0);
  EXPECT_NEAR(saturated.region.semi_axis_x, saturated.region.semi_axis_y, 1e-3 * saturated.lateral_limit);
}

TEST(FootprintRegionTest, HeadingFrameMapsToNed) {
  HeadingFrame east;
  east.origin_NE = {100.0, -50.0};
  east.heading = kPi / 2;  // flying east
  const Eigen::Vector3d ahead = east.ToWorld({10.0, 0.0});
  const Eigen::Vector3d right = east.ToWorld({0.0, 4.0});
  constexpr double kMetres = 1e-12;
  EXPECT_NEAR(ahead.x(), 100.0, kMetres * 100);
  EXPECT_NEAR(ahead.y(), -40.0, kMetres * 100);
  EXPECT_NEAR(ahead.z(), 0.0, kMetres);
  EXPECT_NEAR(right.x(), 96.0, kMetres * 100);  // right of east is south
  EXPECT_NEAR(right.y(), -50.0, kMetres * 100);
  const Eigen::Vector2d back = east.FromWorld(Eigen::Vector3d(83.0, 12.0, -30.0));
  EXPECT_NEAR((east.ToWorld(back).head<2>() - Eigen::Vector2d(83.0, 12.0)).norm(), 0.0, kMetres * 100);

  const HeadingFrame from_state =
      HeadingFrame::FromState(Eigen::Vector3d(1, 2, -10), Eigen::Vector3d(-3.0, 3.0, 0.5), 0.2);
  EXPECT_NEAR(from_state.heading, 3 * kPi / 4, 1e-12);  // course north-west… of (−3, 3): 135°
  EXPECT_NEAR(HeadingFrame::FromState(Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0, 2), 0.2).heading, 0.2, 1e-15);

  // A world point in the footprint of a vehicle flying east.
  const FootprintResult r = CalcFootprint(Fig54Params(20.0, 0));
  const Eigen::Vector3d centre_W = east.ToWorld({r.region.center_x, 0.0});
  EXPECT_TRUE(r.Contains(east, centre_W));
  const Eigen::Vector3d north_of_centre = centre_W + Eigen::Vector3d(r.lateral_limit * 1.01, 0.0, 0.0);
  EXPECT_FALSE(r.Contains(east, north_of_centre));
  EXPECT_TRUE(r.Contains(east, centre_W + Eigen::Vector3d(r.lateral_limit * 0.99, 0.0, 0.0)));
}

// --- parameters ---------------------------------------------------------------------------------------------------
TEST(FootprintParamsTest, EachInvalidFieldIsNamed) {
  struct Case {
    std::function<void(FootprintParams&)> spoil;
    const char* field;
  };
  const std::vector<Case> cases = {
      {[](FootprintParams& p) { p.initial_speed = -1; }, "initial_speed"},
      {[](FootprintParams& p) { p.eod = std::nan(""); }, "eod"},
      {[](FootprintParams& p) { p.mass = 0; }, "mass"},
      {[](FootprintParams& p) { p.available_thrust = -2; }, "available_thrust"},
      {[](FootprintParams& p) { p.max_tilt = kPi / 2; }, "max_tilt"},
      {[](FootprintParams& p) { p.drag_slope = -0.1; }, "drag_slope"},
      {[](FootprintParams& p) { p.maclaurin_order = 31; }, "maclaurin_order"},
  };
  for (const Case& c : cases) {
    FootprintParams params = Fig54Params(10.0, 0);
    c.spoil(params);
    std::string error, field;
    EXPECT_FALSE(params.IsValid(&error, &field));
    EXPECT_EQ(field, c.field);
    EXPECT_EQ(error.rfind(c.field, 0), 0u) << error;
    EXPECT_THROW(CalcFootprint(params), InputError);
  }
  EXPECT_TRUE(FootprintParams{}.IsValid(nullptr));
}

TEST(FootprintParamsTest, DefaultDragSlopeIsTheCruiseSlopeOfTheDefaultTable) {
  const models::DragTable table = models::DragTable::Default(models::PropellerConfiguration::kTractor);
  constexpr double kDefaultCruiseSpeed = 5.0;  // m/s, planning::PlanLimits
  const double slope = CruiseDragSlope(table, kDefaultCruiseSpeed, kMass);
  EXPECT_NEAR(FootprintParams{}.drag_slope, slope, 1e-4 * slope);
  // Level flight at pitch 0 would give ρ f(0) v = 0.306; the trim pitch (≈ −3.8°) adds drag area.
  EXPECT_GT(slope, kAirDensity * 0.05 * kDefaultCruiseSpeed);
  // D ∝ v²: the slope grows with the cruise speed.
  EXPECT_LT(CruiseDragSlope(table, 1.0, kMass), slope);
  EXPECT_LT(slope, CruiseDragSlope(table, 9.0, kMass));
  EXPECT_THROW(CruiseDragSlope(table, -1.0, kMass), InputError);
}

}  // namespace
}  // namespace uascma::planning
