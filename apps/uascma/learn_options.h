#pragma once
// What `uascma learn q` (learn_command.cc) and `uascma learn transitions` (learn_transitions_command.cc) share.
#include <string>

#include <CLI/CLI.hpp>

#include "uascma/campaign/config.h"
#include "uascma/common/bounds.h"

namespace uascma::cli {

// Our bounds: enough for any study on one machine, and a typo such as 1e12 is refused.
inline constexpr Bounds kLearnJobBounds{1, 256, "threads"};
inline constexpr Bounds kLearnProbabilityBounds{0.0, 1.0, ""};

// The campaign configuration of --campaign FILE (default: the built-in one, examples/campaign.yaml's settings)
// with --seed as its seed; InputError naming the file when it is invalid.
campaign::CampaignConfig ResolveLearningCampaign(const std::string& file, const std::string& seed_text);

void AddLearnTransitions(CLI::App* learn);  // learn_transitions_command.cc

}  // namespace uascma::cli
