// SPDX-License-Identifier: LGPL-2.1-or-later
#include "caustic/json_text.hpp"

#include <fcntl.h>
#include <linux/magic.h>
#include <sys/stat.h>
#include <sys/vfs.h>
#include <unistd.h>

#include <algorithm>
#include <optional>
#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

namespace caustic {
namespace {

using json = nlohmann::json;

// Builds the DOM like the library's own SAX DOM parser, counting depth and
// stopping the parse (return false) at the first problem.
class LimitedDom : public nlohmann::json_sax<json> {
 public:
  explicit LimitedDom(int max_depth) : max_depth_(max_depth) {}

  bool null() override { return put(json(nullptr)); }
  bool boolean(bool v) override { return put(json(v)); }
  bool number_integer(number_integer_t v) override { return put(json(v)); }
  bool number_unsigned(number_unsigned_t v) override { return put(json(v)); }
  bool number_float(number_float_t v, const string_t&) override { return put(json(v)); }
  bool string(string_t& v) override { return put(json(std::move(v))); }
  bool binary(binary_t&) override { return fail("binary values are not JSON"); }
  bool start_object(std::size_t) override { return open(json::object()); }
  bool key(string_t& k) override {
    key_ = std::move(k);
    if (watch && key_ == *watch) ++watched;
    return true;
  }
  bool end_object() override { return close(); }
  bool start_array(std::size_t) override { return open(json::array()); }
  bool end_array() override { return close(); }
  bool parse_error(std::size_t position, const std::string&, const nlohmann::detail::exception& e) override {
    // The library's message ends in "last read: '<input>'", which would echo
    // the client's bytes; keep only its own words before that.
    const std::string what = e.what();
    const auto from = what.find("syntax error while parsing");
    std::string message = "not valid JSON";
    // JSON's grammar has no bound on a number, a double has (1e309 was "not
    // valid JSON" with no word of why).
    if (e.id == 406) message = "a number beyond the range of a double (magnitude at most about 1.8e308)";
    if (from != std::string::npos) {
      message = what.substr(from, what.find("; last read", from) - from);
      for (char& ch : message)
        if (static_cast<unsigned char>(ch) < 0x20 || static_cast<unsigned char>(ch) >= 0x7f) ch = '?';
    }
    error_ = {message, position ? position - 1 : 0};
    return false;
  }

  json result;
  JsonTextError error_{"", 0};
  bool failed = false;
  bool too_deep = false;  // a failure of its own: the nesting limit
  bool too_many = false;  // another: kMaxJsonValues
  std::optional<string_t> duplicate;  // the other: a key written twice
  // Keys named `watch` seen so far: a second parse, made only to say where
  // a duplicate stands, counts them up to it (the first keeps no count).
  std::optional<string_t> watch;
  std::size_t watched = 0;

 private:
  bool fail(const std::string& why) {
    failed = true;
    if (error_.message.empty()) error_.message = why;
    return false;
  }
  bool open(json value) {
    if (static_cast<int>(stack_.size()) >= max_depth_)
      return too_deep = true, fail("nested deeper than " + std::to_string(max_depth_) + " levels");
    if (!put(std::move(value))) return false;
    stack_.push_back(last_);
    return true;
  }
  bool close() {
    stack_.pop_back();
    return true;
  }
  bool put(json value) {
    if (++values_ > kMaxJsonValues)
      return too_many = true, fail("more than " + std::to_string(kMaxJsonValues) + " values in one JSON text");
    if (stack_.empty()) {
      result = std::move(value);
      last_ = &result;
    } else if (stack_.back()->is_object()) {
      // Written twice, one of the two would be dropped unsaid (RFC 8259
      // leaves it to the reader): refused, naming the key.
      if (stack_.back()->contains(key_)) {
        duplicate = key_;
        return fail("the key \"" + printable_name(key_, 64) + "\" is written twice in one object");
      }
      last_ = &((*stack_.back())[key_] = std::move(value));
    } else {
      stack_.back()->push_back(std::move(value));
      last_ = &stack_.back()->back();
    }
    return true;
  }

  int max_depth_;
  std::vector<json*> stack_;
  json* last_ = nullptr;
  string_t key_;
  std::size_t values_ = 0;
};

// Where the text first opens a bracket deeper than `max_depth`: the SAX
// callbacks carry no position, so the brackets are counted again (outside
// strings) for the error to say where.
std::size_t too_deep_at(std::string_view text, int max_depth) {
  int depth = 0;
  bool in_string = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    if (in_string) {
      if (ch == '\\') ++i;
      else if (ch == '"') in_string = false;
    } else if (ch == '"') {
      in_string = true;
    } else if (ch == '[' || ch == '{') {
      if (++depth > max_depth) return i;
    } else if (ch == ']' || ch == '}') {
      --depth;
    }
  }
  return 0;
}

// JSON's whitespace (RFC 8259: space, tab, line feed, carriage return).
bool json_space(char ch) { return ch == ' ' || ch == '\t' || ch == '\n' || ch == '\r'; }

// Where the value after the first `max` begins, for the error to say (the
// SAX callbacks carry no position): values are counted as the parser takes
// them, a string being a key when a colon follows it.
std::size_t too_many_at(std::string_view text, std::size_t max) {
  std::size_t values = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char ch = text[i];
    const std::size_t start = i;
    if (ch == '"') {
      for (++i; i < text.size() && text[i] != '"'; ++i)
        if (text[i] == '\\') ++i;
      std::size_t after = i + 1;
      while (after < text.size() && json_space(text[after])) ++after;
      if (after < text.size() && text[after] == ':') continue;  // a key
    } else if (ch == '-' || (ch >= '0' && ch <= '9') || (ch >= 'a' && ch <= 'z')) {
      while (i + 1 < text.size() && text[i + 1] != ',' && text[i + 1] != ']' && text[i + 1] != '}' && !json_space(text[i + 1]))
        ++i;
    } else if (ch != '{' && ch != '[') {
      continue;
    }
    if (++values > max) return start;
  }
  return 0;
}

// Where the `nth` key named `key` is written: a quoted name (plain, without
// escapes) followed by a colon; 0 when it is not found so (the error still
// names the key).
std::size_t key_at(std::string_view text, const std::string& key, std::size_t nth) {
  const std::string quoted = "\"" + key + "\"";
  for (std::size_t at = text.find(quoted); at != std::string_view::npos; at = text.find(quoted, at + 1)) {
    std::size_t after = at + quoted.size();
    while (after < text.size() && json_space(text[after])) ++after;
    if (after < text.size() && text[after] == ':' && --nth == 0) return at;
  }
  return 0;
}

}  // namespace

std::optional<nlohmann::json> parse_json_text(std::string_view text, JsonTextError* error, int max_depth) {
  if (const auto nul = text.find('\0'); nul != std::string_view::npos) {
    if (error) *error = {"a NUL byte is not allowed in JSON text", nul};
    return std::nullopt;
  }
  LimitedDom dom(max_depth);
  bool ok = false;
  try {
    ok = json::sax_parse(text.begin(), text.end(), &dom, nlohmann::detail::input_format_t::json, true);
  } catch (const std::exception&) {
    ok = false;  // the SAX interface reports through parse_error; this is belt and braces
  }
  if (!ok) {
    if (error) {
      *error = dom.error_;
      if (error->message.empty()) error->message = "not valid JSON";
      if (dom.too_deep) error->offset = too_deep_at(text, max_depth);
      if (dom.too_many) error->offset = too_many_at(text, kMaxJsonValues);
      if (dom.duplicate) {
        LimitedDom again(max_depth);  // stops at the same duplicate, having counted its name's keys
        again.watch = dom.duplicate;
        try {
          json::sax_parse(text.begin(), text.end(), &again, nlohmann::detail::input_format_t::json, true);
        } catch (const std::exception&) {
        }
        error->offset = key_at(text, *dom.duplicate, again.watched);
      }
    }
    return std::nullopt;
  }
  return std::move(dom.result);
}

std::string where_json_broke(std::string_view text, const JsonTextError& error) {
  const std::string_view before = text.substr(0, std::min(text.size(), error.offset));
  const std::size_t line = 1 + static_cast<std::size_t>(std::count(before.begin(), before.end(), '\n'));
  const std::size_t last_newline = before.rfind('\n');
  const std::size_t line_start = last_newline == std::string_view::npos ? 0 : last_newline + 1;
  return error.message + " at line " + std::to_string(line) + ", column " +
         std::to_string(before.size() - line_start + 1) + " (byte " + std::to_string(error.offset) + ")";
}

std::string dump_json(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string why_unread(const FileText& read) {
  return read.error ? std::string(" (") + std::strerror(read.error) + ")" : std::string();
}

std::string printable_name(std::string_view name, std::size_t max_bytes) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  for (std::size_t i = 0; i < name.size() && i < max_bytes; ++i) {
    const auto ch = static_cast<unsigned char>(name[i]);
    if (ch >= 0x20 && ch < 0x7f) {
      out += static_cast<char>(ch);
    } else {
      out += "\\x";
      out += kHex[ch >> 4];
      out += kHex[ch & 15];
    }
  }
  if (name.size() > max_bytes) out += "...";
  if (out.empty()) out = "\"\"";  // an empty key still reads as a key
  return out;
}

namespace {

// A file of the kernel's (/proc, /sys) says it is regular, yet a read may
// wait for what never comes (/proc/kmsg) or take what another reader was
// owed (the kernel's log, once read, is gone): never a scene, a mesh or a
// configuration, so it is not read at all.
bool kernel_file(int fd) {
  struct statfs fs {};
  if (::fstatfs(fd, &fs) != 0) return false;
  return fs.f_type == PROC_SUPER_MAGIC || fs.f_type == SYSFS_MAGIC || fs.f_type == DEBUGFS_MAGIC ||
         fs.f_type == TRACEFS_MAGIC;
}

}  // namespace

FileText read_file_text(const std::filesystem::path& file, std::size_t limit) {
  FileText out;
  // A folder reads as nothing, opening a pipe or a socket waits for a
  // writer that may never come, and a device (a terminal, a serial line)
  // for input that may never come: only regular files are read. Opened
  // without waiting and then looked at, so that a file swapped for a pipe
  // between a look and the open cannot hold the reader.
  const int fd = ::open(file.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC | O_NOCTTY);
  if (fd < 0) {
    out.error = errno;
    std::error_code ec;
    const auto type = std::filesystem::status(file, ec).type();
    out.not_a_file = !ec && type != std::filesystem::file_type::regular;
    return out;
  }
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode) || kernel_file(fd)) {
    out.not_a_file = true;
    ::close(fd);
    return out;
  }
  out.opened = true;
  out.text.reserve(static_cast<std::size_t>(std::min<std::uintmax_t>(static_cast<std::uintmax_t>(st.st_size), limit + 1)));
  char piece[1 << 16];
  while (out.text.size() <= limit) {
    const ssize_t n = ::read(fd, piece, sizeof piece);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {  // an I/O error part way: not the whole file, so none of it
      out.error = errno;
      out.opened = false;
      out.text.clear();
      break;
    }
    if (n == 0) break;
    out.text.append(piece, static_cast<std::size_t>(n));
  }
  ::close(fd);
  out.too_large = out.text.size() > limit;
  return out;
}

}  // namespace caustic
