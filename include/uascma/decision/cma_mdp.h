#pragma once
// The contingency-management (CMA) MDP of dissertation §5.3.2.
//
// States (§5.3.2.1): 108 tuples FS,MH,MM,BH,RM with FS ∈ {N, ELASAP, ELPRACT}, MH ∈ {NF, SF, JF},
// MM ∈ {MM0, MM1}, BH ∈ {G, M, P}, RM ∈ {RM0, RM1}, then the terminal states C, T, FL, E (112).
// Actions (§5.3.2.2): NoOp, Terminate, LandASAP, LandPract, available by flight status
// (docs/modelling-choices.md#action-availability): N → all; ELPRACT → {NoOp, Terminate, LandASAP};
// ELASAP → {NoOp, Terminate}; C, T, FL, E → all four, each moving to E with probability 1.
// Transitions: Tables 5.1–5.7 as printed, composed per eqs. 5.16–5.19 and
// docs/modelling-choices.md#transition-composition, #landing-loads-motor. Rewards: eqs. 5.20–5.29, R(S, A) = R(S) +
// R(A) for every state (docs/modelling-choices.md#rewards).
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "uascma/common/bounds.h"
#include "uascma/decision/factored_mdp.h"
#include "uascma/decision/finite_mdp.h"

namespace uascma::decision {

// Feature value indices (the order of the state labels FS, MH, MM, BH, RM, §5.3.2).
enum class FlightStatus { kN = 0, kElAsap = 1, kElPract = 2 };
enum class MotorHealth { kNF = 0, kSF = 1, kJF = 2 };
enum class MotorMargin { kMM0 = 0, kMM1 = 1 };
enum class BatteryHealth { kG = 0, kM = 1, kP = 2 };
enum class ReachMargin { kRM0 = 0, kRM1 = 1 };
enum class CmaAction { kNoOp = 0, kTerminate = 1, kLandAsap = 2, kLandPract = 3 };
enum class CmaTerminal { kC = 0, kT = 1, kFL = 2, kE = 3 };

inline constexpr int kCmaNumTupleStates = 108;
inline constexpr int kCmaNumStates = 112;
inline constexpr int kCmaNumActions = 4;

// The abstract state the executor computes at 1 Hz (docs/modelling-choices.md#margins to #outcomes).
struct CmaState {
  FlightStatus fs = FlightStatus::kN;
  MotorHealth mh = MotorHealth::kNF;
  MotorMargin mm = MotorMargin::kMM1;
  BatteryHealth bh = BatteryHealth::kG;
  ReachMargin rm = ReachMargin::kRM1;
  bool operator==(const CmaState&) const = default;
};

StateIndex CmaStateIndex(const CmaState& state);
StateIndex CmaTerminalIndex(CmaTerminal terminal);
std::string CmaStateLabel(const CmaState& state);
// The label of value `value` of state feature `feature` (0 FS, 1 MH, 2 MM, 3 BH, 4 RM), as CmaStateLabel writes it:
// CmaFeatureValueName(0, static_cast<int>(FlightStatus::kElAsap)) is "ELASAP".
const std::string& CmaFeatureValueName(int feature, int value);
const char* CmaActionName(CmaAction action);
// Parses "N,NF,MM0,G,RM0"; throws InputError naming `source` when malformed.
CmaState ParseCmaState(const std::string& label, const std::string& source);
// Parses an action name; throws InputError naming `source` and listing the valid names.
CmaAction ParseCmaAction(const std::string& name, const std::string& source);

// Reward weights of eqs. 5.28–5.29; the defaults are the dissertation's final values.
struct CmaWeights {
  // w_E(S) for the terminal states (eq. 5.28).
  double C = 0.163;
  double FL = 0.408;
  double T = 0.0;
  double E = 0.0;
  // w_A(A) (eq. 5.28).
  double NoOp = 0.082;
  double Terminate = 0.0;
  double LandASAP = 0.02;
  double LandPract = 0.041;
  // w_S, ordered [FS, MH, MM, BH, RM] (eq. 5.29, docs/modelling-choices.md#rewards).
  double FS = 0.0;
  double MH = 0.0;
  double MM = 0.082;
  double BH = 0.041;
  double RM = 0.163;

  static const std::vector<std::string>& Names();  // "C", "FL", …, "RM" in the order above
  double Get(const std::string& name) const;       // InputError on an unknown name
  void Set(const std::string& name, double value);
  double Sum() const;
  bool IsValid(std::string* error) const;  // every weight within kCmaWeightBounds
  // The renormalisation of Fig. 5.10: `name` takes `value` and the other weights keep their
  // proportions, scaled so that all weights sum to one (eq. 5.22).
  CmaWeights WithRenormalised(const std::string& name, double value) const;
};

struct CmaConfig {
  CmaWeights weights;
  double gamma = 0.95;  // docs/modelling-choices.md#discount
};

// Plausibility bounds (common/bounds.h). Each weight is a share of the total reward, which
// the dissertation's weights split to a sum of one (eqs. 5.22, 5.28-5.29): 0 to 1. The discount factor:
// 0 to 0.999 (our bound; docs/modelling-choices.md#discount uses 0.95, and gamma -> 1 makes the values of eq. 5.15
// diverge as 1 / (1 - gamma)).
inline constexpr Bounds kCmaWeightBounds{0.0, 1.0, ""};
inline constexpr Bounds kGammaBounds{0.0, 0.999, ""};

// Reads a YAML file of the form
//   gamma: 0.95            # optional, default 0.95
//   weights:
//     end_states: {C: 0.163, FL: 0.408, T: 0, E: 0}
//     actions: {NoOp: 0.082, Terminate: 0, LandASAP: 0.02, LandPract: 0.041}
//     state_features: {FS: 0, MH: 0, MM: 0.082, BH: 0.041, RM: 0.163}
// Every weight is required; InputError names the file and key of a missing or bad one.
CmaConfig LoadCmaConfig(const std::filesystem::path& path);
std::string CmaConfigYaml(const CmaConfig& config);
// The weights as JSON (policy files): decision/cma_weights_json.h.

// A row as the dissertation prints Tables 5.1-5.7: probabilities in its column order NoOp, LandASAP, LandPract,
// Terminate, stored in the builder's (NoOp, Terminate, LandASAP, LandPract).
ConditionalRow PrintedCmaRow(std::string next, std::vector<std::string> parents, double noop, double land_asap,
                             double land_pract, double terminate);
// Table 5.5 as printed: P(MM_{t+1} | MM_t, MH_t, A_t).
ConditionalTable CmaMotorMarginTable();

// The factored model (features, Tables 5.1–5.7, availability) and the composed MDP.
FactoredMdpBuilder MakeCmaFactoredModel();
FiniteMdp BuildCmaMdp(const CmaWeights& weights);
// R(S, A) of eqs. 5.20–5.27 for a state of the factored model.
double CmaReward(const CmaWeights& weights, const FactoredState& state, ActionIndex action);

// The quadrant view of Fig. 5.9. Rows: FS × MH × BH (27, FS slowest); columns: Quad I (RM1, MM1,
// safe), Quad II (RM1, MM0, hazardous), Quad III (RM0, MM0, hyper-critical), Quad IV (RM0, MM1,
// critical), numbered counter-clockwise from the safe quadrant as §5.3.2.5 does.
struct QuadrantCell {
  CmaState state;
  ActionIndex action = 0;
  double value = 0.0;
};
struct QuadrantRow {
  FlightStatus fs;
  MotorHealth mh;
  BatteryHealth bh;
  std::array<QuadrantCell, 4> quadrants;  // I, II, III, IV
};
inline constexpr std::array<const char*, 4> kQuadrantNames = {"I", "II", "III", "IV"};
CmaState QuadrantState(FlightStatus fs, MotorHealth mh, BatteryHealth bh, int quadrant);
std::vector<QuadrantRow> CmaQuadrantView(const std::vector<ActionIndex>& action, const std::vector<double>& value);

}  // namespace uascma::decision
