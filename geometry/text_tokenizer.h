// SPDX-License-Identifier: MIT
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

// Shared by every mesh reader: reading a file, splitting it into lines and tokens with line
// numbers, parsing numbers, and phrasing errors as "<file>: line <n>: <problem>", so that each
// reader states only what its format expects.
namespace softbench {

/// The whole file as bytes. Throws InputError "<file>: cannot open (<reason>)".
std::string read_file_bytes(const std::filesystem::path& path);

/// The extension of `path`, lower-cased (".OBJ" -> ".obj"), for dispatching on file types.
std::string lowercase_extension(const std::filesystem::path& path);

/// Throws InputError "<file>: <problem>".
[[noreturn]] void throw_file_error(std::string_view file, std::string_view problem);

/// The parts streamed one after another, for messages: concat("expected ", 3, " nodes").
template <typename... Parts>
std::string concat(const Parts&... parts) {
  std::ostringstream out;
  (out << ... << parts);
  return out.str();
}

/// A token fit for an error message: in single quotes, bytes that are not printable ASCII shown
/// as \xNN, cut after 40 characters (a binary file may have no whitespace for megabytes).
std::string quoted_token(std::string_view token);

/// One non-blank line split at whitespace. The views point into the tokenizer's buffer.
struct TextLine {
  int number = 0;
  std::vector<std::string_view> tokens;
  std::size_t size() const { return tokens.size(); }
  std::string_view operator[](std::size_t i) const { return tokens[i]; }
};

/// A cursor over a text file (or a text header followed by binary blocks, as in legacy VTK).
/// Lines end at '\n'; '\r' counts as whitespace, so CRLF files read the same. Errors name the
/// line of the last line or token read.
class TextTokenizer {
 public:
  /// Reads `path` whole. `comment` (0 for none) starts a comment that runs to the end of the line.
  explicit TextTokenizer(const std::filesystem::path& path, char comment = 0);
  /// Tokenizes `content` read elsewhere; `file` names it in messages, `first_line` numbers its
  /// first line (for text cut out of a larger file).
  TextTokenizer(std::string file, std::string content, char comment = 0, int first_line = 1);
  // The lines and tokens handed out are views into content_: it must never move.
  TextTokenizer(const TextTokenizer&) = delete;
  TextTokenizer& operator=(const TextTokenizer&) = delete;

  const std::string& file() const { return file_; }
  /// The line of the last line or token read (1 before anything is read).
  int line_number() const { return last_line_; }

  /// The next line that holds a token, or nullopt at the end of the file.
  std::optional<TextLine> next_line();
  /// The next line that holds a token; at the end of the file fails "expected <what>, found end
  /// of file".
  TextLine expect_line(std::string_view what);
  /// The next line as it is, blank or not, without its line break (for free-text lines such as
  /// a VTK title); nullopt at the end of the file.
  std::optional<std::string_view> next_raw_line();

  /// The next token, across line breaks, or nullopt at the end of the file.
  std::optional<std::string_view> next_token();
  /// The next token; at the end of the file fails "expected <what>, found end of file".
  std::string_view expect_token(std::string_view what);

  /// The text up to `delimiter`, and moves past the delimiter; nullopt (and no move) if the
  /// delimiter does not occur again.
  std::optional<std::string_view> read_until(std::string_view delimiter);

  /// `count` raw bytes starting right after the last line read (binary blocks); fails naming
  /// `what` when fewer remain.
  std::string_view read_bytes(std::size_t count, std::string_view what);
  std::size_t bytes_left() const { return content_.size() - position_; }

  /// A coordinate of, say, `owner` "vertex" number 2; fails "vertex 2 has a non-finite coordinate
  /// (nan)" or "vertex 2 has a coordinate that is not a number ('1.2.3')". The owner comes in two
  /// parts so that no message is built for the millions of coordinates that parse.
  double parse_coordinate(std::string_view token,
                          std::string_view owner,
                          std::int64_t owner_number) const;
  /// A whole number; fails "expected an integer for <what>, found '...'".
  std::int64_t parse_integer(std::string_view token, std::string_view what) const;
  /// A count or index in [0, INT_MAX] (every count ends up as an Eigen::Index of int data).
  int parse_count(std::string_view token, std::string_view what) const;

  /// Fails unless `count` items could fit in what is left of the file (each takes at least a
  /// byte), so a corrupt count cannot make a reader reserve gigabytes. The bound is loose on
  /// purpose: a file cut short by a few items gets the reader's precise "found n" message.
  /// Returns `count`.
  std::size_t check_count_fits(std::int64_t count, std::string_view what) const;
  /// Fails "expected <count> values (<layout>), found <n>" unless the line has `count` tokens.
  void require_tokens(const TextLine& line, std::size_t count, std::string_view layout) const;
  /// Fails "expected at least <count> values (<layout>), found <n>".
  void require_min_tokens(const TextLine& line, std::size_t count, std::string_view layout) const;

  /// Throws InputError "<file>: line <n>: <problem>" for the line last read.
  [[noreturn]] void fail(std::string_view problem) const;
  [[noreturn]] void fail_at(int line, std::string_view problem) const;

 private:
  void skip_blanks_and_comments();

  std::string file_;
  std::string content_;
  char comment_ = 0;
  std::size_t position_ = 0;
  int line_ = 1;       // line of the byte at position_
  int last_line_ = 1;  // line of the last line or token handed out
};

}  // namespace softbench
