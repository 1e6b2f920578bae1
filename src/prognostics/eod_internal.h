#pragma once
// What the exact EOD propagation (eod.cc) and the fixed-step references (eod_reference.cc) share.
#include "uascma/prognostics/eod.h"

namespace uascma::prognostics::eod_internal {

// InputError "EOD options: …" unless options.IsValid().
void RequireValid(const EodOptions& options);
// A result of `status` at `eod_s`, with no limiting cell and no cost figures.
EodResult Ended(EodStatus status, double eod_s);

}  // namespace uascma::prognostics::eod_internal
