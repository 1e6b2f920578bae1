#pragma once
// The campaign configuration's checks (config.cc, config_fields.cc) report "field: expected …" through one helper.
#include <string>
#include <utility>

namespace uascma::campaign::internal {

// Sets *error (when given) to `message`; false, so that a check reads `return ok || Fail(error, "…")`.
inline bool Fail(std::string* error, std::string message) {
  if (error) *error = std::move(message);
  return false;
}

}  // namespace uascma::campaign::internal
