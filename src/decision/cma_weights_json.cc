#include "uascma/decision/cma_weights_json.h"

#include "uascma/common/bounds.h"
#include "uascma/common/error.h"

namespace uascma::decision {

nlohmann::json CmaWeightsJson(const CmaWeights& weights) {
  nlohmann::json json = nlohmann::json::object();
  for (const auto& name : CmaWeights::Names()) json[name] = weights.Get(name);
  return json;
}

CmaWeights CmaWeightsFromJson(const nlohmann::json& json, const std::string& source) {
  CmaWeights weights;
  for (const auto& name : CmaWeights::Names()) {
    if (!json.is_object() || !json.contains(name) || !json.at(name).is_number()) {
      throw InputError(source, "model_config.weights." + name, "a number");
    }
    const double value = json.at(name).get<double>();
    RequireWithin(value, kCmaWeightBounds, source, "model_config.weights." + name);
    weights.Set(name, value);
  }
  return weights;
}

}  // namespace uascma::decision
