#pragma once
// `uascma reproduce`: the dissertation's checkable results rebuilt with the library, each beside
// the value the dissertation prints, with a stated tolerance, a verdict (matches / differs) and, for every
// "differs", one sentence with its number saying why (a choice of docs/modelling-choices.md, a model's own
// error, a setting the dissertation does not print).
//
// An item is one table, figure or printed number of the dissertation. It holds quantities (ours, theirs,
// tolerance, verdict), the sample sizes it used, free data (the figures' series, a calibration's steps) and
// figure specifications that python/plots/reproduce.py draws as PNG. RunReproduce runs the selected items and
// writes DIR/results.json (every number; the timings in their own top-level field, so the same seed gives the
// same file byte for byte otherwise), DIR/index.html (one self-contained page, PNGs embedded as base64) and
// DIR/table.md (the summary table for the README).
#include <cstdint>
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace uascma::reproduce {

enum class Verdict { kMatches, kDiffers };
const char* VerdictName(Verdict verdict);  // "matches", "differs"

// One compared number (or a categorical value, e.g. an action sequence: then `ours`/`theirs` are empty and the
// texts are compared for equality).
struct Quantity {
  std::string name;
  std::optional<double> ours, theirs;
  std::string ours_text, theirs_text;  // as printed (value and unit)
  std::string unit;
  std::string tolerance;      // stated, e.g. "±20 % (§2.6.1)"
  std::string tolerance_why;  // why that tolerance
  Verdict verdict = Verdict::kMatches;
  std::string reason;  // for "differs": one sentence with its number
};

// |ours − theirs| ≤ tolerance (absolute, in `unit`).
Quantity CompareAbsolute(std::string name, double ours, double theirs, std::string unit, double tolerance,
                         std::string why, std::string reason_if_differs, int digits = 3);
// |ours − theirs| ≤ tolerance × |theirs|.
Quantity CompareRelative(std::string name, double ours, double theirs, std::string unit, double tolerance,
                         std::string why, std::string reason_if_differs, int digits = 3);
// A rate measured as k of n: matches when theirs lies in the 95 % Wilson interval of k/n.
Quantity CompareRate(std::string name, std::int64_t k, std::int64_t n, double theirs, std::string why,
                     std::string reason_if_differs);
// Equal texts.
Quantity CompareText(std::string name, std::string ours, std::string theirs, std::string why,
                     std::string reason_if_differs);

// A figure: `spec` is drawn by python/plots/reproduce.py into `file` (a PNG in the output folder).
struct Figure {
  std::string file;
  std::string caption;
  nlohmann::json spec;
};

struct Item {
  std::string id;      // "table-2.2"
  std::string title;   // "Static thrust, estimated (eqs. 2.1, 2.12)"
  std::string source;  // "§2.5.3.1, Table 2.2"
  std::vector<Quantity> quantities;
  std::vector<Figure> figures;
  nlohmann::json samples = nlohmann::json::object();  // sample sizes used
  nlohmann::json data = nlohmann::json::object();     // further numbers (steps, series)
  std::vector<std::string> notes;                     // settings and how ours was computed
  double cpu_s = 0.0;                                 // timing: kept out of the deterministic part
  double wall_s = 0.0;
  Verdict verdict() const;  // differs when any quantity differs
};

struct Options {
  std::filesystem::path out = "reproduce";
  bool quick = false;
  std::vector<std::string> only;  // item ids; empty: all
  int jobs = 0;                   // 0: every hardware thread
  std::uint64_t seed = 1;
  std::filesystem::path source_dir;  // the examples/ folder's parent (examples/scenario-1.yaml, campaign-*.yaml)
  // Draws every figure spec into DIR (the CLI runs python/plots/reproduce.py); empty: no figures drawn.
  std::function<void(const nlohmann::json& figures, const std::filesystem::path& dir)> draw;
  std::function<void(const std::string& line)> log;  // progress lines (sample sizes, calibration steps)
};

// What an item function receives.
struct Context {
  const Options& options;
  void Log(const std::string& line) const {
    if (options.log) options.log(line);
  }
};

struct ItemDefinition {
  std::string id;
  std::string title;
  std::function<Item(const Context&)> run;
};
// Every item, in the dissertation's order.
const std::vector<ItemDefinition>& AllItems();

struct Report {
  std::vector<Item> items;
  std::uint64_t seed = 1;
  bool quick = false;
};

// Checks the options (unknown --only ids, output folder not writable): InputError naming the option.
void ValidateOptions(const Options& options);
// Runs the selected items; `on_item` is called after each (the CLI prints its line).
Report RunReproduce(const Options& options, const std::function<void(const Item&)>& on_item = {});
// The deterministic JSON (no timings) and the timings.
nlohmann::json ResultsJson(const Report& report);
nlohmann::json TimingsJson(const Report& report);
// One terminal line: id, ours, theirs, verdict (of the first differing quantity, else the first).
std::string ItemLine(const Item& item);
std::string SummaryMarkdown(const Report& report);
std::string IndexHtml(const Report& report, const std::filesystem::path& dir);
// Writes results.json, table.md, draws the figures and writes index.html (atomically, file by file).
void WriteReport(const Report& report, const Options& options);

// The items themselves, one function per dissertation result, are the module's own: src/reproduce/items_*.h.

}  // namespace uascma::reproduce
