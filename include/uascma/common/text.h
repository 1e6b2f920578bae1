#pragma once
// Text that enters uascma from a user (names in YAML files, file and folder names used as names) is UTF-8
// or refused where it enters: every writer (JSON summaries, SQLite, plots) can then carry
// it losslessly, and none fails half-way with a JSON type error.
#include <cstddef>
#include <optional>
#include <string>
#include <string_view>

namespace uascma {

// The byte offset of the first byte that does not start a well-formed UTF-8 sequence (RFC 3629: no overlong
// forms, no surrogates U+D800–U+DFFF, nothing above U+10FFFF), or nothing when all of `text` is UTF-8.
std::optional<std::size_t> FirstInvalidUtf8(std::string_view text);
inline bool IsValidUtf8(std::string_view text) { return !FirstInvalidUtf8(text).has_value(); }

// Throws InputError(source, field, "text in UTF-8, but byte N (0xHH) is not") unless `text` is UTF-8.
void RequireUtf8(std::string_view text, const std::string& source, const std::string& field);

// `text` with every byte that is not UTF-8 written as \xHH, for messages about such text.
std::string EscapeInvalidUtf8(std::string_view text);

// `text` for a one-line message: every byte that is not UTF-8 and every control character (U+0000–U+001F,
// U+007F: a newline, a carriage return or a terminal escape would break the line or the terminal) written as
// \xHH; everything else as it is.
std::string EscapeForMessage(std::string_view text);

// EscapeForMessage of the first 60 bytes of `text` (ours: one line stays readable), "..." after a cut: for
// quoting a value from a user's file in a message.
std::string BriefForMessage(std::string_view text);

// The longest prefix of `text` of at most `max_bytes` bytes that ends between two UTF-8 sequences (a byte that
// starts no well-formed sequence counts as one), for shortening text in messages without cutting a character.
std::string_view Utf8Prefix(std::string_view text, std::size_t max_bytes);

}  // namespace uascma
