// The LQR flight controller (gnc/lqr.h): the Riccati solution, the discretisation, and the closed loop on the
// nonlinear rigid body.
#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "uascma/common/frames.h"
#include "uascma/gnc/lqr.h"
#include "uascma/models/drag.h"
#include "uascma/models/rigid_body.h"

namespace uascma::gnc {
namespace {

using models::BodyInputs;
using models::RigidBodyState;
using models::StepRigidBody;

const models::DragTable& TractorDrag() {
  static const models::DragTable table = models::DragTable::Default(models::PropellerConfiguration::kTractor);
  return table;
}

TEST(LqrTest, DoublingAgreesWithRiccatiIterationAndStabilises) {
  const LinearModel model = DiscretizeZeroOrderHold(LinearizeHover({}), 0.005);
  StateMatrix Q = StateMatrix::Identity();
  const Eigen::Matrix4d R = Eigen::Matrix4d::Identity() * 10.0;
  const RiccatiSolution doubling = SolveDiscreteRiccati(model.A, model.B, Q, R);
  ASSERT_EQ(doubling.status, RiccatiStatus::kConverged);
  EXPECT_LT(doubling.iterations, 40);
  EXPECT_LT(doubling.residual, 1e-6 * doubling.P.cwiseAbs().maxCoeff());
  // Independent computation: the plain Riccati difference iteration, run to convergence.
  StateMatrix P = Q;
  for (int k = 0; k < 200000; ++k) {
    const Eigen::Matrix4d S = R + model.B.transpose() * P * model.B;
    const StateMatrix next = Q + model.A.transpose() * P * model.A -
                             model.A.transpose() * P * model.B * S.ldlt().solve(model.B.transpose() * P * model.A);
    const double change = (next - P).cwiseAbs().maxCoeff();
    P = next;
    if (change < 1e-10 * P.cwiseAbs().maxCoeff()) break;
  }
  EXPECT_LT((P - doubling.P).cwiseAbs().maxCoeff() / P.cwiseAbs().maxCoeff(), 1e-6);
  const StateMatrix closed = model.A - model.B * doubling.K;
  EXPECT_LT(closed.eigenvalues().cwiseAbs().maxCoeff(), 1.0);
}

TEST(LqrTest, ZeroOrderHoldMatchesTheFirstTermsOfTheExponential) {
  const LinearModel c = LinearizeHover({});
  const double dt = 0.005;
  const LinearModel d = DiscretizeZeroOrderHold(c, dt);
  // Pitch to x-position: p_x gains −g θ dt²/2 through the chain ṗ = v, v̇ = −gθ.
  EXPECT_NEAR(d.A(0, 7), -kGravity * dt * dt / 2.0, 1e-15);
  // Torque τy to x-position: −g/Iyy · dt⁴/24.
  EXPECT_NEAR(d.B(0, 2), -kGravity / 0.011 * std::pow(dt, 4) / 24.0, 1e-15);
}

TEST(LqrTest, ClosedLoopNonlinearHoverSettlesAfterAStep) {
  const LqrController controller({}, {});
  RigidBodyState state;
  state.p_WB_W = Eigen::Vector3d(0, 0, -10);
  planning::PlanReference reference;
  reference.p_W = Eigen::Vector3d(2.0, -1.0, -11.0);
  double max_tilt = 0.0;
  for (int k = 0; k < 200 * 15; ++k) {
    const Wrench w = controller.Compute(state, reference);
    BodyInputs inputs;
    inputs.total_thrust = w(0);
    inputs.torque_B = w.tail<3>();
    state = StepRigidBody({}, TractorDrag(), state, inputs, 0.005);
    max_tilt = std::max(max_tilt, TiltAngle(state.q_WB.toRotationMatrix()));
  }
  EXPECT_NEAR((state.p_WB_W - reference.p_W).norm(), 0.0, 0.02);  // m after 15 s
  EXPECT_LT(state.v_WB_W.norm(), 0.01);
  EXPECT_LT(max_tilt, 0.6);  // rad: the step never asks for an aggressive bank
}

}  // namespace
}  // namespace uascma::gnc
