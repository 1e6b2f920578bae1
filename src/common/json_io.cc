#include "uascma/common/json_io.h"

#include <fmt/format.h>

#include "uascma/common/error.h"
#include "uascma/common/files.h"

namespace uascma {

nlohmann::json ParseJsonText(std::string_view text, const std::string& source) {
  try {
    return nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(source, fmt::format("byte {}", e.byte), "valid JSON");
  } catch (const nlohmann::json::exception& e) {  // out_of_range: a number like 1e999
    throw InputError(source, "JSON", fmt::format("valid JSON ({})", e.what()));
  }
}

nlohmann::json ReadJsonFile(const std::filesystem::path& path) { return ParseJsonText(ReadFile(path), path.string()); }

}  // namespace uascma
