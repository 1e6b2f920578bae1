#include "uascma/common/text.h"

#include <algorithm>

#include <fmt/format.h>

#include "uascma/common/error.h"

namespace uascma {
namespace {

// The length of the well-formed UTF-8 sequence starting at text[i], or 0 (RFC 3629, Table 3-7 of the Unicode
// Standard: the second byte's range depends on the first, which rules out overlong forms and surrogates).
std::size_t SequenceLength(std::string_view text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char lead = byte(i);
  if (lead <= 0x7F) return 1;
  std::size_t length = 0;
  unsigned char second_low = 0x80;
  unsigned char second_high = 0xBF;
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) second_low = 0xA0;   // overlong below U+0800
    if (lead == 0xED) second_high = 0x9F;  // surrogates U+D800–U+DFFF
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) second_low = 0x90;   // overlong below U+10000
    if (lead == 0xF4) second_high = 0x8F;  // above U+10FFFF
  } else {
    return 0;  // 0x80–0xC1 (continuation or overlong lead), 0xF5–0xFF
  }
  if (i + length > text.size()) return 0;
  if (byte(i + 1) < second_low || byte(i + 1) > second_high) return 0;
  for (std::size_t k = 2; k < length; ++k) {
    if (byte(i + k) < 0x80 || byte(i + k) > 0xBF) return 0;
  }
  return length;
}

}  // namespace

std::optional<std::size_t> FirstInvalidUtf8(std::string_view text) {
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = SequenceLength(text, i);
    if (length == 0) return i;
    i += length;
  }
  return std::nullopt;
}

std::string_view Utf8Prefix(std::string_view text, std::size_t max_bytes) {
  std::size_t end = 0;
  while (end < text.size()) {
    const std::size_t next = end + std::max<std::size_t>(SequenceLength(text, end), 1);
    if (next > max_bytes) break;
    end = next;
  }
  return text.substr(0, end);
}

void RequireUtf8(std::string_view text, const std::string& source, const std::string& field) {
  if (const auto bad = FirstInvalidUtf8(text)) {
    throw InputError(source, field,
                     fmt::format("text in UTF-8, but byte {} (0x{:02X}) of '{}' is not", *bad,
                                 static_cast<unsigned char>(text[*bad]), EscapeInvalidUtf8(text)));
  }
}

std::string EscapeInvalidUtf8(std::string_view text) {
  std::string escaped;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = SequenceLength(text, i);
    if (length == 0) {
      escaped += fmt::format("\\x{:02X}", static_cast<unsigned char>(text[i]));
      ++i;
    } else {
      escaped.append(text.substr(i, length));
      i += length;
    }
  }
  return escaped;
}

std::string EscapeForMessage(std::string_view text) {
  std::string escaped;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = SequenceLength(text, i);
    const auto byte = static_cast<unsigned char>(text[i]);
    if (length == 0 || byte < 0x20 || byte == 0x7F) {
      escaped += fmt::format("\\x{:02X}", byte);
      i += 1;
    } else {
      escaped.append(text.substr(i, length));
      i += length;
    }
  }
  return escaped;
}

std::string BriefForMessage(std::string_view text) {
  constexpr std::size_t kQuotedBytes = 60;
  if (text.size() <= kQuotedBytes) return EscapeForMessage(text);
  return EscapeForMessage(Utf8Prefix(text, kQuotedBytes - 3)) + "...";
}

}  // namespace uascma
