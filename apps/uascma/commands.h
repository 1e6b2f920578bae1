#pragma once
// Each `uascma <command>` lives in its own file and adds itself to the application here.
// A command's callback throws uascma::InputError for bad input; main() turns it into exit code 2.
#include <CLI/CLI.hpp>

namespace uascma::cli {

void AddPolicyCommand(CLI::App& app);     // policy_command.cc

}  // namespace uascma::cli
