// libFuzzer harness: campaign YAML (campaign::ParseCampaignConfig). A file that parses must
// also round-trip through CampaignConfigYaml, which the results store relies on.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

#include "fuzz_support.h"
#include "uascma/campaign/config.h"
#include "uascma/common/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace uascma::campaign;
  CampaignConfig config;
  try {
    config = ParseCampaignConfig(std::string(uascma::fuzz::AsText(data, size)), "fuzz.yaml");
  } catch (const uascma::InputError&) {
    return 0;
  }
  // The store keeps CampaignConfigYaml(config) and parses it back: that must always succeed.
  const CampaignConfig again = ParseCampaignConfig(CampaignConfigYaml(config), "round-trip.yaml");
  if (CampaignConfigYaml(again) != CampaignConfigYaml(config)) std::abort();
  return 0;
}
