// Bad parameters are rejected when a network is built, with the field and the value.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "cpg/cpg.h"

namespace climbsim::cpg {
namespace {

// Runs make() and expects std::invalid_argument whose message contains every fragment.
void ExpectInvalid(const std::function<void()>& make, const std::vector<std::string>& fragments) {
  try {
    make();
    ADD_FAILURE() << "no exception; expected one mentioning " << fragments.front();
  } catch (const std::invalid_argument& e) {
    for (const std::string& fragment : fragments) {
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)
          << "message: " << e.what() << "\nmissing: " << fragment;
    }
  }
}

PhaseNetworkParams GoodPhase() { return PhaseNetworkParamsForGait(GaitPreset("trot", 4), 1, 2); }
HopfNetworkParams GoodHopf() { return HopfNetworkParamsForGait(GaitPreset("trot", 4), 1, 2); }

TEST(CpgParams, GoodParamsBuild) {
  EXPECT_NO_THROW(PhaseNetwork{GoodPhase()});
  EXPECT_NO_THROW(HopfNetwork{GoodHopf()});
}

TEST(CpgParams, PhaseNetworkRejectsEachBadField) {
  auto with = [](const std::function<void(PhaseNetworkParams&)>& edit) {
    return [edit] {
      PhaseNetworkParams p = GoodPhase();
      edit(p);
      PhaseNetwork network(p);
    };
  };
  ExpectInvalid(with([](auto& p) { p.frequency_hz = 0.0; }),
                {"PhaseNetworkParams.frequency_hz", "> 0", "got 0"});
  ExpectInvalid(with([](auto& p) { p.frequency_hz = -2.0; }), {"frequency_hz", "got -2"});
  ExpectInvalid(with([](auto& p) { p.frequency_hz = NAN; }), {"frequency_hz", "got nan"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s = Eigen::MatrixXd::Zero(3, 4); }),
                {"PhaseNetworkParams.coupling_per_s", "must be 4x4", "got 3x4"});
  ExpectInvalid(with([](auto& p) { p.phase_bias_rad = Eigen::MatrixXd::Zero(4, 3); }),
                {"PhaseNetworkParams.phase_bias_rad", "must be 4x4", "got 4x3"});
  ExpectInvalid(with([](auto& p) { p.target_amplitude = Eigen::VectorXd::Ones(3); }),
                {"coupling_per_s", "must be 3x3", "got 4x4"});
  ExpectInvalid(with([](auto& p) { p.target_amplitude = Eigen::VectorXd(); }),
                {"target_amplitude", "at least 1"});
  ExpectInvalid(with([](auto& p) { p.target_amplitude[2] = -0.5; }),
                {"target_amplitude[2]", ">= 0", "got -0.5"});
  ExpectInvalid(with([](auto& p) { p.amplitude_rate_per_s = -1.0; }),
                {"amplitude_rate_per_s", ">= 0", "got -1"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s(1, 1) = 3.0; }),
                {"coupling_per_s(1,1)", "not coupled to itself", "got 3"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s(0, 2) = INFINITY; }),
                {"coupling_per_s(0,2)", "finite", "got inf"});
  ExpectInvalid(with([](auto& p) { p.phase_bias_rad(3, 0) = NAN; }),
                {"phase_bias_rad(3,0)", "finite"});
  ExpectInvalid(with([](auto& p) { p.stepper.abs_tol = -1e-8; }),
                {"PhaseNetworkParams.stepper.abs_tol", ">= 0", "got -1e-08"});
  ExpectInvalid(with([](auto& p) { p.stepper.rel_tol = -1.0; }),
                {"PhaseNetworkParams.stepper.rel_tol", ">= 0"});
  ExpectInvalid(with([](auto& p) {
                  p.stepper.abs_tol = 0.0;
                  p.stepper.rel_tol = 0.0;
                }),
                {"both 0"});
  ExpectInvalid(with([](auto& p) { p.stepper.type = static_cast<Stepper>(7); }),
                {"stepper.type", "got 7"});
}

TEST(CpgParams, HopfNetworkRejectsEachBadField) {
  auto with = [](const std::function<void(HopfNetworkParams&)>& edit) {
    return [edit] {
      HopfNetworkParams p = GoodHopf();
      edit(p);
      HopfNetwork network(p);
    };
  };
  ExpectInvalid(with([](auto& p) { p.stance_frequency_hz = 0.0; }),
                {"HopfNetworkParams.stance_frequency_hz", "> 0", "got 0"});
  ExpectInvalid(with([](auto& p) { p.swing_frequency_hz = -1.0; }),
                {"swing_frequency_hz", "got -1"});
  ExpectInvalid(with([](auto& p) { p.mu = 0.0; }), {"HopfNetworkParams.mu", "> 0"});
  ExpectInvalid(with([](auto& p) { p.alpha_per_s = -50.0; }), {"alpha_per_s", "got -50"});
  ExpectInvalid(with([](auto& p) { p.beta_per_s = 0.0; }), {"beta_per_s"});
  ExpectInvalid(with([](auto& p) { p.b = NAN; }), {"HopfNetworkParams.b", "got nan"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s = Eigen::MatrixXd(); }),
                {"coupling_per_s", "n >= 1", "got 0x0"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s = Eigen::MatrixXd::Zero(4, 2); }),
                {"coupling_per_s", "must be 4x4", "got 4x2"});
  ExpectInvalid(with([](auto& p) { p.phase_bias_rad = Eigen::MatrixXd::Zero(6, 6); }),
                {"HopfNetworkParams.phase_bias_rad", "must be 4x4", "got 6x6"});
  ExpectInvalid(with([](auto& p) { p.coupling_per_s(2, 2) = 1.0; }), {"coupling_per_s(2,2)"});
  ExpectInvalid(with([](auto& p) { p.stepper.rel_tol = -1e-6; }),
                {"HopfNetworkParams.stepper.rel_tol", ">= 0"});
}

TEST(CpgParams, ResetAndStepRejectCallerMistakes) {
  PhaseNetwork phase(GoodPhase());
  ExpectInvalid([&] { phase.Reset(Eigen::VectorXd::Zero(3), Eigen::VectorXd::Ones(4)); },
                {"PhaseNetwork::Reset", "4 entries", "got 3 and 4"});
  ExpectInvalid([&] { phase.Reset(Eigen::VectorXd::Zero(4), -Eigen::VectorXd::Ones(4)); },
                {"amplitude[0]", ">= 0"});
  ExpectInvalid([&] { phase.Step(-1e-3, {}); }, {"PhaseNetwork::Step: dt_s", "got -0.001"});
  const std::vector<double> three = {0.0, 0.0, 0.0};
  ExpectInvalid([&] { phase.Step(1e-3, three); },
                {"feedback_rad_per_s", "empty or have 4 entries", "got 3"});

  HopfNetwork hopf(GoodHopf());
  ExpectInvalid([&] { hopf.Reset(Eigen::VectorXd::Zero(4), Eigen::VectorXd::Zero(4)); },
                {"HopfNetwork::Reset: amplitude[0]", "> 0"});
  ExpectInvalid([&] { hopf.Step(NAN, {}); }, {"HopfNetwork::Step: dt_s"});
  ExpectInvalid([&] { hopf.Step(1e-3, three); }, {"feedback_rad_per_s", "got 3"});
  // dt_s = 0 is allowed and changes nothing.
  const double theta = hopf.phase_rad()[1];
  hopf.Step(0.0, {});
  EXPECT_EQ(hopf.phase_rad()[1], theta);
}

TEST(CpgParams, HelpersRejectBadArguments) {
  ExpectInvalid([] { AllToAllCoupling(0, 1.0); }, {"num_oscillators", ">= 1"});
  ExpectInvalid([] { AllToAllCoupling(3, NAN); }, {"weight_per_s", "finite"});
  ExpectInvalid([] { HopfFrequenciesForGait(1.0, 0.0); }, {"duty_factor", "(0, 1)"});
}

}  // namespace
}  // namespace climbsim::cpg
