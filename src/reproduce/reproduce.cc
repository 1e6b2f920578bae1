// `uascma reproduce` (reproduce/reproduce.h): comparisons, the item list and loop, results.json, table.md and the
// self-contained index.html; the items are items_*.cc.
#include "uascma/reproduce/reproduce.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <set>
#include <sstream>

#include <fmt/format.h>

#include "items_campaign.h"
#include "items_cma.h"
#include "items_learning.h"
#include "items_models.h"
#include "uascma/campaign/statistics.h"
#include "uascma/common/cpu_time.h"
#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma::reproduce {
namespace {

std::string Number(double value, int digits) { return fmt::format("{:.{}g}", value, digits); }

std::string WithUnit(double value, const std::string& unit, int digits) {
  return unit.empty() ? Number(value, digits) : Number(value, digits) + " " + unit;
}

Quantity Numeric(std::string name, double ours, double theirs, std::string unit, std::string tolerance, std::string why,
                 bool matches, std::string reason, int digits) {
  Quantity q;
  q.name = std::move(name);
  q.ours = ours;
  q.theirs = theirs;
  q.ours_text = WithUnit(ours, unit, digits);
  q.theirs_text = WithUnit(theirs, unit, digits);
  q.unit = std::move(unit);
  q.tolerance = std::move(tolerance);
  q.tolerance_why = std::move(why);
  q.verdict = matches ? Verdict::kMatches : Verdict::kDiffers;
  if (!matches) q.reason = std::move(reason);
  return q;
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      default:
        out += c;
    }
  }
  return out;
}

std::string Base64(const std::string& bytes) {
  static constexpr char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], kAlphabet[(v >> 6) & 63], kAlphabet[v & 63]};
  }
  if (i + 1 == bytes.size()) {
    const unsigned v = static_cast<unsigned char>(bytes[i]) << 16;
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == bytes.size()) {
    const unsigned v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8);
    out += {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63], kAlphabet[(v >> 6) & 63], '='};
  }
  return out;
}

const Quantity* Headline(const Item& item) {
  for (const Quantity& q : item.quantities) {
    if (q.verdict == Verdict::kDiffers) return &q;
  }
  return item.quantities.empty() ? nullptr : &item.quantities.front();
}

nlohmann::json QuantityJson(const Quantity& q) {
  nlohmann::json j = {{"name", q.name},
                      {"ours_text", q.ours_text},
                      {"theirs_text", q.theirs_text},
                      {"unit", q.unit},
                      {"tolerance", q.tolerance},
                      {"tolerance_why", q.tolerance_why},
                      {"verdict", VerdictName(q.verdict)},
                      {"reason", q.reason}};
  j["ours"] = q.ours ? nlohmann::json(*q.ours) : nlohmann::json(nullptr);
  j["theirs"] = q.theirs ? nlohmann::json(*q.theirs) : nlohmann::json(nullptr);
  return j;
}

}  // namespace

const char* VerdictName(Verdict verdict) { return verdict == Verdict::kMatches ? "matches" : "differs"; }

Verdict Item::verdict() const {
  for (const Quantity& q : quantities) {
    if (q.verdict == Verdict::kDiffers) return Verdict::kDiffers;
  }
  return Verdict::kMatches;
}

Quantity CompareAbsolute(std::string name, double ours, double theirs, std::string unit, double tolerance,
                         std::string why, std::string reason_if_differs, int digits) {
  const bool matches = std::isfinite(ours) && std::abs(ours - theirs) <= tolerance;
  return Numeric(std::move(name), ours, theirs, unit, fmt::format("±{}", WithUnit(tolerance, unit, 3)), std::move(why),
                 matches, std::move(reason_if_differs), digits);
}

Quantity CompareRelative(std::string name, double ours, double theirs, std::string unit, double tolerance,
                         std::string why, std::string reason_if_differs, int digits) {
  const bool matches = std::isfinite(ours) && std::abs(ours - theirs) <= tolerance * std::abs(theirs);
  return Numeric(std::move(name), ours, theirs, std::move(unit), fmt::format("±{:g} % of theirs", 100.0 * tolerance),
                 std::move(why), matches, std::move(reason_if_differs), digits);
}

Quantity CompareRate(std::string name, std::int64_t k, std::int64_t n, double theirs, std::string why,
                     std::string reason_if_differs) {
  const campaign::Interval wilson = campaign::WilsonInterval(k, n);
  const double rate = n > 0 ? static_cast<double>(k) / static_cast<double>(n) : std::nan("");
  const bool matches = n > 0 && theirs >= wilson.low && theirs <= wilson.high;
  Quantity q = Numeric(std::move(name), 100.0 * rate, 100.0 * theirs, "%",
                       fmt::format("95 % Wilson interval of {} of {}: [{:.1f}, {:.1f}] %", k, n, 100.0 * wilson.low,
                                   100.0 * wilson.high),
                       std::move(why), matches, std::move(reason_if_differs), 3);
  q.ours_text = fmt::format("{:.1f} % ({} of {})", 100.0 * rate, k, n);
  return q;
}

Quantity CompareText(std::string name, std::string ours, std::string theirs, std::string why,
                     std::string reason_if_differs) {
  Quantity q;
  q.name = std::move(name);
  q.verdict = ours == theirs ? Verdict::kMatches : Verdict::kDiffers;
  q.ours_text = std::move(ours);
  q.theirs_text = std::move(theirs);
  q.tolerance = "equal";
  q.tolerance_why = std::move(why);
  if (q.verdict == Verdict::kDiffers) q.reason = std::move(reason_if_differs);
  return q;
}

const std::vector<ItemDefinition>& AllItems() {
  static const std::vector<ItemDefinition> items = {
      {"table-2.2", "Static thrust estimated at Table 2.2's four points", ReproduceTable22},
      {"battery-eod", "Battery model (Tables 3.1-3.2) and pack EOD (§3.3.2.1)", ReproduceBatteryEod},
      {"motor-rul", "Motor RUL (§3.4.1) and Table 5.4's spall-to-jam probability", ReproduceMotorRul},
      {"battery-mdp", "Battery MDP state space (§4.3.2, 289 states)", ReproduceBatteryMdpSize},
      {"battery-cases",
       "Battery policies: Fig. 4.5's tree and Table 4.5's case studies "
       "(docs/modelling-choices.md#battery-case-study-flight-time)",
       ReproduceBatteryCaseStudies},
      {"cma-tables", "CMA transition model composed from Tables 5.1-5.7 (eqs. 5.16-5.19)", ReproduceCmaTables},
      {"cma-policy", "CMA policy by quadrant (Fig. 5.9, Fig. 5.13)", ReproduceCmaPolicy},
      {"sensitivity", "Reward-weight sensitivity (Figs. 5.10-5.12)", ReproduceSensitivity},
      {"q-learning", "Q-learning curve (§5.3.3, Fig. 5.14)", ReproduceQLearning},
      {"scenario-1", "Scenario I timeline (§5.5.1, Figs. 5.18-5.24)", ReproduceScenarioOne},
      {"scenario-2", "Scenario II timeline (§5.5.2, Figs. 5.25-5.29)", ReproduceScenarioTwo},
      {"campaign-default", "Monte Carlo campaign, default profile (ours; §5.5.3, Figs. 5.30-5.32)",
       ReproduceCampaignDefault},
      {"campaign-dissertation",
       "Monte Carlo campaign, dissertation profile (docs/modelling-choices.md#dissertation-profile; abstract, Figs. "
       "5.30-5.32)",
       ReproduceCampaignDissertation},
  };
  return items;
}

void ValidateOptions(const Options& options) {
  std::set<std::string> known;
  for (const ItemDefinition& d : AllItems()) known.insert(d.id);
  std::string ids;
  for (const ItemDefinition& d : AllItems()) ids += (ids.empty() ? "" : ", ") + d.id;
  for (const std::string& id : options.only) {
    if (known.count(id) == 0) throw InputError("--only", id, "one of the items " + ids);
  }
  if (options.jobs < 0 || options.jobs > 1024) {
    throw InputError("--jobs", "value", fmt::format("0 (all cores) to 1024 threads, got {}", options.jobs));
  }
  if (options.out.empty()) throw InputError("--out", "value", "a folder to write the report into");
  std::error_code ec;
  if (std::filesystem::exists(options.out, ec) && !std::filesystem::is_directory(options.out, ec)) {
    throw InputError("--out", options.out.string(), "a folder (it is a file)");
  }
}

Report RunReproduce(const Options& options, const std::function<void(const Item&)>& on_item) {
  ValidateOptions(options);
  Report report;
  report.seed = options.seed;
  report.quick = options.quick;
  const Context context{options};
  for (const ItemDefinition& definition : AllItems()) {
    if (!options.only.empty() &&
        std::find(options.only.begin(), options.only.end(), definition.id) == options.only.end()) {
      continue;
    }
    const double cpu0 = ProcessCpuSeconds();
    const auto wall0 = std::chrono::steady_clock::now();
    Item item = definition.run(context);
    item.id = definition.id;
    if (item.title.empty()) item.title = definition.title;
    item.cpu_s = ProcessCpuSeconds() - cpu0;
    item.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (on_item) on_item(item);
    report.items.push_back(std::move(item));
  }
  return report;
}

nlohmann::json ResultsJson(const Report& report) {
  nlohmann::json items = nlohmann::json::array();
  for (const Item& item : report.items) {
    nlohmann::json quantities = nlohmann::json::array();
    for (const Quantity& q : item.quantities) quantities.push_back(QuantityJson(q));
    nlohmann::json figures = nlohmann::json::array();
    for (const Figure& f : item.figures) figures.push_back({{"file", f.file}, {"caption", f.caption}});
    items.push_back({{"id", item.id},
                     {"title", item.title},
                     {"source", item.source},
                     {"verdict", VerdictName(item.verdict())},
                     {"quantities", quantities},
                     {"figures", figures},
                     {"samples", item.samples},
                     {"data", item.data},
                     {"notes", item.notes}});
  }
  int differs = 0;
  for (const Item& item : report.items) differs += item.verdict() == Verdict::kDiffers ? 1 : 0;
  return {{"tool", "uascma reproduce"},         {"seed", report.seed},     {"quick", report.quick},
          {"items_total", report.items.size()}, {"items_differ", differs}, {"items", items}};
}

nlohmann::json TimingsJson(const Report& report) {
  nlohmann::json timings = nlohmann::json::object();
  double cpu = 0.0, wall = 0.0;
  for (const Item& item : report.items) {
    timings[item.id] = {{"cpu_s", item.cpu_s}, {"wall_s", item.wall_s}};
    cpu += item.cpu_s;
    wall += item.wall_s;
  }
  timings["total"] = {{"cpu_s", cpu}, {"wall_s", wall}};
  return timings;
}

std::string ItemLine(const Item& item) {
  const Quantity* q = Headline(item);
  const std::string name = q == nullptr ? "" : q->name + ": ";
  return fmt::format("{:<22} {:<9} {}ours {} | theirs {}", item.id, VerdictName(item.verdict()), name,
                     q == nullptr ? "-" : q->ours_text, q == nullptr ? "-" : q->theirs_text);
}

// A table cell: '|' would end it.
static std::string MarkdownCell(const std::string& text) {
  std::string out;
  for (char c : text) out += c == '|' ? std::string("\\|") : std::string(1, c);
  return out;
}

std::string SummaryMarkdown(const Report& report) {
  std::string out = fmt::format("| item | source | ours | dissertation | verdict |\n|---|---|---|---|---|\n");
  for (const Item& item : report.items) {
    const Quantity* q = Headline(item);
    out += fmt::format("| {} | {} | {} | {} | {}{} |\n", item.id, MarkdownCell(item.source),
                       MarkdownCell(q ? q->name + ": " + q->ours_text : "-"), MarkdownCell(q ? q->theirs_text : "-"),
                       VerdictName(item.verdict()), MarkdownCell(q && !q->reason.empty() ? " — " + q->reason : ""));
  }
  out += fmt::format("\n(`uascma reproduce{} --seed {}`; every number in results.json.)\n",
                     report.quick ? " --quick" : "", report.seed);
  return out;
}

std::string IndexHtml(const Report& report, const std::filesystem::path& dir) {
  std::ostringstream html;
  html << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
          "<title>uascma reproduce</title><style>"
          "body{font-family:sans-serif;max-width:1100px;margin:2em auto;line-height:1.4}"
          "table{border-collapse:collapse;margin:0.5em 0}td,th{border:1px solid #bbb;padding:3px 6px;"
          "font-size:90%;vertical-align:top}.matches{color:#176b2c;font-weight:bold}"
          ".differs{color:#a33;font-weight:bold}img{max-width:100%}section{border-top:2px solid #444;"
          "margin-top:2em}</style></head><body>\n";
  html << "<h1>The dissertation's results, rebuilt by uascma</h1>\n<p>Seed " << report.seed
       << (report.quick ? ", <b>--quick</b> sample sizes (smaller than the dissertation's; see each item)"
                        : ", the dissertation's sample sizes")
       << ". Every number is in <code>results.json</code>. A verdict <span class=\"differs\">differs</span> carries "
          "its reason. The only setting calibrated to a published figure is the dissertation profile's plan-length "
          "range "
          "(item <a href=\"#item-campaign-dissertation\">campaign-dissertation</a>).</p>\n";
  html << "<table id=\"summary\"><tr><th>item</th><th>source</th><th>ours</th><th>dissertation</th>"
          "<th>verdict</th></tr>\n";
  for (const Item& item : report.items) {
    const Quantity* q = Headline(item);
    html << "<tr><td><a href=\"#item-" << item.id << "\">" << HtmlEscape(item.id) << "</a></td><td>"
         << HtmlEscape(item.source) << "</td><td>" << HtmlEscape(q ? q->name + ": " + q->ours_text : "-") << "</td><td>"
         << HtmlEscape(q ? q->theirs_text : "-") << "</td><td class=\"" << VerdictName(item.verdict()) << "\">"
         << VerdictName(item.verdict()) << "</td></tr>\n";
  }
  html << "</table>\n";
  for (const Item& item : report.items) {
    html << "<section id=\"item-" << item.id << "\" data-item=\"" << item.id << "\"><h2>" << HtmlEscape(item.title)
         << "</h2>\n<p>" << HtmlEscape(item.source) << " — verdict: <span class=\"verdict "
         << VerdictName(item.verdict()) << "\" data-verdict=\"" << VerdictName(item.verdict()) << "\">"
         << VerdictName(item.verdict()) << "</span></p>\n";
    html << "<table class=\"quantities\"><tr><th>quantity</th><th>ours</th><th>dissertation</th><th>tolerance</th>"
            "<th>verdict</th><th>why (tolerance; difference)</th></tr>\n";
    for (const Quantity& q : item.quantities) {
      html << "<tr><td>" << HtmlEscape(q.name) << "</td><td>" << HtmlEscape(q.ours_text) << "</td><td>"
           << HtmlEscape(q.theirs_text) << "</td><td>" << HtmlEscape(q.tolerance) << "</td><td class=\""
           << VerdictName(q.verdict) << "\">" << VerdictName(q.verdict) << "</td><td>" << HtmlEscape(q.tolerance_why)
           << (q.reason.empty() ? "" : "<br><b>Differs:</b> " + HtmlEscape(q.reason)) << "</td></tr>\n";
    }
    html << "</table>\n";
    if (!item.samples.empty()) html << "<p>Sample sizes: <code>" << HtmlEscape(item.samples.dump()) << "</code></p>\n";
    if (!item.notes.empty()) {
      html << "<ul>";
      for (const std::string& note : item.notes) html << "<li>" << HtmlEscape(note) << "</li>";
      html << "</ul>\n";
    }
    for (const Figure& figure : item.figures) {
      std::error_code ec;
      const std::filesystem::path png = dir / figure.file;
      html << "<figure data-figure=\"" << HtmlEscape(figure.file) << "\">";
      if (std::filesystem::is_regular_file(png, ec)) {
        html << "<img alt=\"" << HtmlEscape(figure.caption) << "\" src=\"data:image/png;base64,"
             << Base64(ReadFile(png)) << "\">";
      } else {
        html << "<p>(figure not drawn: no plotting)</p>";
      }
      html << "<figcaption>" << HtmlEscape(figure.caption) << "</figcaption></figure>\n";
    }
    html << "</section>\n";
  }
  html << "</body></html>\n";
  return html.str();
}

void WriteReport(const Report& report, const Options& options) {
  std::filesystem::create_directories(options.out);
  if (options.draw) {
    nlohmann::json figures = nlohmann::json::array();
    for (const Item& item : report.items) {
      for (const Figure& f : item.figures) {
        nlohmann::json spec = f.spec;
        spec["file"] = f.file;
        spec["caption"] = f.caption;
        figures.push_back(spec);
      }
    }
    if (!figures.empty()) options.draw(figures, options.out);
  }
  nlohmann::json results = ResultsJson(report);
  results["timings"] = TimingsJson(report);  // the only field that differs between runs of one seed
  WriteFileAtomically(options.out / "results.json", results.dump(1) + "\n");
  WriteFileAtomically(options.out / "table.md", SummaryMarkdown(report));
  WriteFileAtomically(options.out / "index.html", IndexHtml(report, options.out));
}

}  // namespace uascma::reproduce
