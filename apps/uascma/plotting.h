#pragma once
// Drawing results: the CLI writes the data, then runs one of the matplotlib scripts in python/plots/ with
// Debian's interpreter (/usr/bin/python3, scripts/install-deps.sh). Scripts are found in
// $UASCMA_PLOTS_DIR, else the source tree this binary was built from, else <prefix>/share/uascma/plots.
#include <string>

#include <nlohmann/json.hpp>
#include <vector>

namespace uascma::cli {

// Runs `script` (a file name in the plots folder) with `arguments`; throws InputError when the
// interpreter or script is missing or the script fails (its stderr is passed through).
void RunPlotScript(const std::string& script, const std::vector<std::string>& arguments);

// Writes `data` to a temporary JSON file, runs `script DATA.json target`, and removes the file whatever
// happens: the pattern of every command that draws what it computed.
void PlotJson(const std::string& script, const nlohmann::json& data, const std::string& target);

// PlotJson drawn beside `target` (".uascma-plot-PID-NAME") and renamed over it, so a failed drawing leaves
// nothing behind and an earlier picture stays whole until the new one replaces it. Check the target first
// (CheckOutputFile, output.h) so that a bad path is refused before any work.
void PlotJsonWhole(const std::string& script, const nlohmann::json& data, const std::string& target);

}  // namespace uascma::cli
