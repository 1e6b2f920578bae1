// The classification of unnecessary landings (campaign/landing_causes.h) on hand-made flights: one flight per cause,
// each paired with a NoOp twin that completed with its reserve, and counted per policy and battery-health group.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "uascma/campaign/landing_causes.h"
#include "uascma/campaign/statistics.h"

namespace uascma::campaign {
namespace {

// A landing of `policy` in run `run` whose first emergency action came at 100 s in state `state`.
RunRecord Landing(std::int64_t run, const std::string& policy, const std::string& state, const std::string& health) {
  RunRecord r;
  r.run_index = run;
  r.policy = policy;
  r.outcome = "emergency_landing";
  r.battery_health = health;
  r.first_emergency_action_s = 100.0;
  r.first_emergency_action = "LandPract";
  r.first_action_state = state;
  return r;
}

RunRecord CompletedTwin(std::int64_t run, const std::string& health) {
  RunRecord r;
  r.run_index = run;
  r.policy = kNoOpPolicy;
  r.outcome = "completed";
  r.battery_health = health;
  r.safety_margin_s = 5.0;
  r.end_reserve_s = 60.0;
  return r;
}

TEST(LandingCausesTest, EachHandMadeFlightHasItsCause) {
  // A spall from 80 s whose rotor was isolated at 95 s: the landing at 100 s came after the jam.
  RunRecord after_jam = Landing(0, "cma", "N,JF,MM0,G,RM1", "G");
  after_jam.fault = true;
  after_jam.fault_onset_s = 80.0;
  after_jam.jam_time_s = 94.0;
  after_jam.isolation_time_s = 95.0;
  EXPECT_EQ(ClassifyLandingCause(after_jam), LandingCause::kAfterJam);
  // The same spall jamming after the action: the motor margin of a real spall (RM1, MM0).
  RunRecord motor = after_jam;
  motor.jam_time_s = 110.0;
  motor.isolation_time_s = 111.0;
  motor.first_action_state = "N,SF,MM0,G,RM1";
  EXPECT_EQ(ClassifyLandingCause(motor), LandingCause::kMotorMargin);
  // RM0 lands whatever the motor: the battery margin.
  RunRecord battery = Landing(1, "cma", "N,NF,MM1,P,RM0", "P");
  EXPECT_EQ(ClassifyLandingCause(battery), LandingCause::kBatteryMargin);
  // A spall read in a flight without one, or before its onset: the indicator's false reading.
  RunRecord false_reading = Landing(2, "cma", "N,SF,MM0,M,RM1", "M");
  EXPECT_EQ(ClassifyLandingCause(false_reading), LandingCause::kFalseFaultReading);
  RunRecord early_reading = false_reading;
  early_reading.fault = true;
  early_reading.fault_onset_s = 150.0;
  EXPECT_EQ(ClassifyLandingCause(early_reading), LandingCause::kFalseFaultReading);
  // Safe quadrant and no fault read: a belief policy's own reasons.
  EXPECT_EQ(ClassifyLandingCause(Landing(3, "cma-qmdp", "N,NF,MM1,G,RM1", "G")), LandingCause::kOther);
  // No recorded state (a record from before the column): other.
  EXPECT_EQ(ClassifyLandingCause(Landing(4, "cma", "", "G")), LandingCause::kOther);
}

TEST(LandingCausesTest, CountsArePerPolicyAndHealthGroupAndOnlyForUnnecessaryLandings) {
  std::vector<RunRecord> records;
  records.push_back(Landing(0, "cma", "N,SF,MM0,G,RM1", "G"));  // a false reading (no fault), G
  records.back().fault = false;
  records.push_back(CompletedTwin(0, "G"));
  records.push_back(Landing(1, "cma", "N,NF,MM1,P,RM0", "P"));  // battery, P
  records.push_back(CompletedTwin(1, "P"));
  records.push_back(Landing(2, "cma", "N,NF,MM1,M,RM0", "M"));  // battery, but its twin failed: not unnecessary
  RunRecord failed_twin = CompletedTwin(2, "M");
  failed_twin.outcome = "failed_battery";
  failed_twin.failure = true;
  records.push_back(failed_twin);
  records.push_back(Landing(3, "cma", "N,NF,MM1,G,RM0", "G"));  // battery, but its twin kept too little reserve
  RunRecord thin_twin = CompletedTwin(3, "G");
  thin_twin.end_reserve_s = 2.0;
  records.push_back(thin_twin);
  const std::vector<LandingCauseCounts> counts = CountUnnecessaryLandingCauses(records, {"noop", "cma"});
  ASSERT_EQ(counts.size(), 4u);  // cma × all, G, M, P
  auto find = [&](const std::string& group) {
    for (const LandingCauseCounts& c : counts) {
      if (c.battery_health == group) return c;
    }
    ADD_FAILURE() << group;
    return LandingCauseCounts{};
  };
  const LandingCauseCounts all = find("all");
  EXPECT_EQ(all.total(), 2);
  EXPECT_EQ(all.count[static_cast<int>(LandingCause::kFalseFaultReading)], 1);
  EXPECT_EQ(all.count[static_cast<int>(LandingCause::kBatteryMargin)], 1);
  EXPECT_EQ(find("G").total(), 1);
  EXPECT_EQ(find("M").total(), 0);
  EXPECT_EQ(find("P").count[static_cast<int>(LandingCause::kBatteryMargin)], 1);
  const nlohmann::json json = LandingCausesJson(counts);
  EXPECT_EQ(json["cma"]["all"]["false_fault_reading"], 1);
  EXPECT_EQ(json["cma"]["P"]["battery_margin"], 1);
  // Without NoOp flights there is nothing to pair with.
  std::vector<RunRecord> alone = {Landing(0, "cma", "N,NF,MM1,P,RM0", "P")};
  EXPECT_TRUE(CountUnnecessaryLandingCauses(alone, {"cma"}).empty());
}

}  // namespace
}  // namespace uascma::campaign
