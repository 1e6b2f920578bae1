#include "uascma/common/hash.h"

#include <fmt/format.h>

namespace uascma {

std::string Fingerprint::Hex() const { return fmt::format("{:016x}", state_); }

}  // namespace uascma
