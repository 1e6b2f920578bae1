#pragma once
// LandPract (§5.3.2.2, Fig. 5.6: "pre-calculated trajectories to reachable emergency landing sites from
// checkpoints located along the nominal flight plan … checkpoints are selected to equally divide flight plan
// length … Based on current UAS location and its proximity to a checkpoint in the nominal flight plan, an
// emergency landing site from the list of pre-planned emergency landing trajectories with the maximum RM is
// selected"). Before the flight, LandPractDatabase::Build places N checkpoints (docs/defaults.md#guidance-and-control:
// 5) at the arc lengths k L / (N + 1), k = 1 … N, of the whole nominal plan (take-off, cruise out, return and landing:
// on an out-and-back route the return leg has its own checkpoints, the green trajectories of Fig. 5.6), and stores for
// each the best paths (LandingPath) to the sites within a radius, sorted by flight time. At run time:
//  * the checkpoint is the NEAREST one to the vehicle's position ("its proximity to a checkpoint"); not the
//    nearest one ahead: the time to reach the checkpoint is part of t_flight, and flying back a few metres beats
//    flying on to the next checkpoint up to L/(N + 1) away. Checkpoints that coincide (an out-and-back route
//    passes the same point twice) are told apart by the time along the nominal plan closest to the vehicle's;
//  * t_flight = the time from the current position to the checkpoint (a climb-over, closed form after one
//    TallestBuildingUnder query) + the stored path's time; that first term is the same for every site of the
//    checkpoint, so the largest RM is the first stored path (the RM tie rule scans the few after it);
//  * the plan flies current position → checkpoint → the stored path.
// The look-up (LandPractDatabase::Lookup) takes well under a microsecond (bench/landing_bench.cc); Plan adds the
// FlightPlan (about a microsecond more).
//
// Thread safety: the database is immutable after construction; every query is const, allocates its own scratch
// space, and may run on many threads. It keeps a copy of the planner, and so a pointer to the CityMap, which must
// outlive it.
#include <Eigen/Core>

#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "uascma/planning/city_map.h"
#include "uascma/planning/emergency_landing.h"
#include "uascma/planning/flight_plan.h"
#include "uascma/planning/landing_path.h"

namespace uascma::planning {

struct LandPractParams {
  int checkpoint_count = 5;  // docs/defaults.md#guidance-and-control, "checkpoints for LandPract"
  // m: the sites whose centre is within this horizontal distance of a checkpoint are its candidates. Our
  // estimate: 500 m is 100 s at the default 5 m/s cruise, longer than the EOD left when the CMA calls for an
  // emergency landing in the dissertation's scenarios (Figs. 5.22, 5.27), and a few Manhattan blocks (Fig. 5.6).
  double site_search_radius = 500.0;
  double max_flight_time = std::numeric_limits<double>::infinity();  // s: a flight-time budget, none by default
  // Paths stored per checkpoint, fastest first. Our estimate: 20, more than Fig. 5.6 draws per checkpoint; only
  // the fastest few are ever chosen (the first, or a tie).
  int trajectories_per_checkpoint = 20;
  bool IsValid(std::string* error) const;
};

struct Checkpoint {
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // m
  double route_distance = 0.0;                    // m along the nominal plan
  double plan_time = 0.0;                         // s: when the nominal plan passes it
};

struct StoredTrajectory {
  int site = -1;
  double risk = 0.0;         // the site's risk (copied: the look-up reads only this array)
  double flight_time = 0.0;  // s, checkpoint → site
  LandingPath path;
};

// The choice of the look-up, before the FlightPlan is built.
struct LandPractChoice {
  LandingStatus status = LandingStatus::kNoStoredTrajectory;
  int checkpoint = -1;
  int entry = -1;  // index into trajectories(checkpoint)
  int site = -1;
  double time_to_checkpoint = 0.0;                               // s, climb-over from the vehicle to the checkpoint
  double transit_altitude = 0.0;                                 // m, of that climb-over
  double flight_time = std::numeric_limits<double>::infinity();  // s, to the checkpoint + stored
  double reach_margin = -std::numeric_limits<double>::infinity();
  int scanned = 0;  // stored paths looked at (1 + the RM ties)
};

// The first LandPract checkpoint (k L / (N + 1) along `nominal_plan`, §5.3.2.2) inside a building of `map`,
// 0-based, with its position; nothing when all are clear (LandPractDatabase::Build refuses such a plan).
struct CheckpointInBuilding {
  int checkpoint = 0;
  Eigen::Vector3d p_W = Eigen::Vector3d::Zero();  // m
};
std::optional<CheckpointInBuilding> FirstCheckpointInBuilding(const CityMap& map, const FlightPlan& nominal_plan,
                                                              const LandPractParams& params = {});

class LandPractDatabase {
 public:
  LandPractDatabase() = default;
  // Places the checkpoints on `nominal_plan` and plans their paths (offline; InputError on invalid params or an
  // empty plan). Keeps a copy of the planner (and so a pointer to its map).
  static LandPractDatabase Build(const LandingPathPlanner& planner, const FlightPlan& nominal_plan,
                                 const LandPractParams& params = {});

  const std::vector<Checkpoint>& checkpoints() const { return checkpoints_; }
  std::span<const StoredTrajectory> trajectories(int checkpoint) const { return trajectories_[checkpoint]; }
  const LandPractParams& params() const { return params_; }
  bool empty() const { return checkpoints_.empty(); }

  // The checkpoint nearest to p_W (3-D distance), coinciding ones told apart by |plan_time − plan_elapsed|
  // (the lower index when plan_elapsed is NaN). −1 for an empty database.
  int NearestCheckpoint(const Eigen::Vector3d& p_W, double plan_elapsed) const;
  // The site choice (header comment); no FlightPlan is built. InputError on a non-finite request.
  LandPractChoice Lookup(const LandingRequest& request) const;
  // Lookup, then the path current position → checkpoint → stored path and its FlightPlan (verified).
  LandingResult Plan(const LandingRequest& request) const;

 private:
  std::vector<Checkpoint> checkpoints_;
  std::vector<std::vector<StoredTrajectory>> trajectories_;
  LandPractParams params_;
  std::vector<LandingPathPlanner> planner_;  // one copy (a vector so that the database is default-constructible)
};

}  // namespace uascma::planning
