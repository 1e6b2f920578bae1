// The names of the termination rules (termination.h); the rules themselves are applied by the CMA's executor
// (act.cc).
#include "uascma/sim/termination.h"

#include <string>

#include "uascma/common/error.h"

namespace uascma::sim {

const char* TerminationRuleName(TerminationRule rule) {
  switch (rule) {
    case TerminationRule::kPolicy:
      return "policy";
    case TerminationRule::kNever:
      return "never";
    case TerminationRule::kLastResort:
      break;
  }
  return "last-resort";
}

TerminationRule ParseTerminationRule(const std::string& text, const std::string& source, const std::string& field) {
  for (const TerminationRule rule : {TerminationRule::kLastResort, TerminationRule::kPolicy, TerminationRule::kNever}) {
    if (text == TerminationRuleName(rule)) return rule;
  }
  throw InputError(source, field, "last-resort, policy or never, got '" + text + "'");
}

}  // namespace uascma::sim
