// SPDX-License-Identifier: LGPL-2.1-or-later
// Every JSON text that comes from outside (request bodies, signalling
// messages, scene and calibration files) is parsed here, never with
// json::parse directly, because the library's own parser has three traits
// that an exposed server cannot live with:
// - it treats a NUL byte as the end of the input, so "{...}\0junk" parses;
// - it nests without limit, and every later recursive walk (merge patch,
//   dump, destruction) then needs stack in proportion;
// - it builds any number of values, at up to ~130 bytes each where the
//   text spends 3 ("[{},{},..."): a 16 MiB scene file held 750 MB;
// - it throws, and an exception that crosses a C callback kills the process.
#pragma once

#include <nlohmann/json.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>

namespace caustic {

/// Nesting deeper than any scene, patch or signalling message needs.
inline constexpr int kMaxJsonDepth = 32;
/// Values (objects, arrays, strings, numbers, literals) in one text: a
/// scene, calibration or report holds a few hundred to a few thousand.
inline constexpr std::size_t kMaxJsonValues = 100000;

struct JsonTextError {
  std::string message;  ///< ASCII only: never echoes the input's bytes
  std::size_t offset;   ///< byte offset where the text broke (0-based)
};

/// Parses `text`; arrays and objects may nest at most `max_depth` deep and
/// hold kMaxJsonValues values in all. NUL bytes, invalid UTF-8, trailing
/// content, excess depth and excess values are errors.
/// Never throws: returns std::nullopt and fills `*error` (when given).
std::optional<nlohmann::json> parse_json_text(std::string_view text, JsonTextError* error = nullptr,
                                              int max_depth = kMaxJsonDepth);

/// Where `text` broke, as an editor counts (1-based line and column) and
/// by byte: "<message> at line 3, column 7 (byte 41)". Quotes none of the
/// text's bytes.
std::string where_json_broke(std::string_view text, const JsonTextError& error);

/// A file's bytes, read in pieces up to one byte past `limit`, so that a
/// file (or a device such as /dev/zero) that never ends is refused instead
/// of read whole. `opened` is false when the file cannot be opened or is
/// `not_a_file`;
/// `too_large` is true (and `text` cut) when it holds more than `limit`.
struct FileText {
  bool not_a_file = false;  ///< a folder, pipe, socket, device or kernel (/proc, /sys) file: not read
  bool opened = false;
  bool too_large = false;
  int error = 0;  ///< errno of the open or read that failed, for the message to say why
  std::string text;
};
FileText read_file_text(const std::filesystem::path& file, std::size_t limit);

/// Why a file was not read, as " (No such file or directory)", or "".
std::string why_unread(const FileText& read);

/// `value.dump()` that never throws: invalid UTF-8 in strings is replaced.
std::string dump_json(const nlohmann::json& value);

/// A name the client chose (an unknown key), made safe to quote in an error
/// message: printable ASCII is kept, every other byte becomes \xNN (a NUL
/// would cut a C string, raw control bytes would garble a log line), and at
/// most `max_bytes` of the name are shown, then "...".
std::string printable_name(std::string_view name, std::size_t max_bytes = 64);

}  // namespace caustic
