// SPDX-License-Identifier: MIT
#include "geometry/text_tokenizer.h"

#include "geometry/input_error.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <system_error>
#include <utility>

namespace softbench {
namespace {

bool is_space(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// from_chars rejects a leading '+', which some exporters write.
std::string_view without_plus(std::string_view token) {
  if (token.size() > 1 && token.front() == '+') {
    token.remove_prefix(1);
  }
  return token;
}

std::string printable(std::string_view token) {
  constexpr std::size_t kMaxShown = 40;
  std::string shown;
  for (const char c : token.substr(0, kMaxShown)) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      shown += c;
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      shown += "\\x";
      shown += kHex[byte >> 4];
      shown += kHex[byte & 0xf];
    }
  }
  if (token.size() > kMaxShown) {
    shown += "...";
  }
  return shown;
}

}  // namespace

std::string read_file_bytes(const std::filesystem::path& path) {
  errno = 0;
  std::ifstream in(path, std::ios::binary | std::ios::ate);
  if (!in) {
    const int error = errno != 0 ? errno : ENOENT;
    throw_file_error(path.string(),
                     concat("cannot open (", std::generic_category().message(error), ")"));
  }
  std::error_code code;
  if (std::filesystem::is_directory(path, code)) {
    throw_file_error(path.string(), "cannot open (Is a directory)");
  }
  const std::streamoff size = in.tellg();
  std::string bytes(size > 0 ? static_cast<std::size_t>(size) : 0, '\0');
  in.seekg(0);
  if (size < 0 || !in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()))) {
    throw_file_error(path.string(), "cannot read (I/O error)");
  }
  return bytes;
}

std::string lowercase_extension(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension;
}

void throw_file_error(std::string_view file, std::string_view problem) {
  std::string message{file};
  message += ": ";
  message += problem;
  throw InputError(message);
}

std::string quoted_token(std::string_view token) {
  return concat("'", printable(token), "'");
}

TextTokenizer::TextTokenizer(const std::filesystem::path& path, char comment)
    : TextTokenizer(path.string(), read_file_bytes(path), comment) {
}

TextTokenizer::TextTokenizer(std::string file, std::string content, char comment, int first_line)
    : file_(std::move(file)),
      content_(std::move(content)),
      comment_(comment),
      line_(first_line),
      last_line_(first_line) {
}

std::optional<TextLine> TextTokenizer::next_line() {
  while (position_ < content_.size()) {
    const std::size_t newline = content_.find('\n', position_);
    const std::size_t end = newline == std::string::npos ? content_.size() : newline;
    std::string_view text(content_.data() + position_, end - position_);
    if (comment_ != 0) {
      text = text.substr(0, text.find(comment_));
    }
    TextLine line;
    line.number = line_;
    std::size_t i = 0;
    while (i < text.size()) {
      while (i < text.size() && is_space(text[i])) {
        ++i;
      }
      const std::size_t start = i;
      while (i < text.size() && !is_space(text[i])) {
        ++i;
      }
      if (i > start) {
        line.tokens.push_back(text.substr(start, i - start));
      }
    }
    position_ = newline == std::string::npos ? content_.size() : newline + 1;
    if (newline != std::string::npos) {
      ++line_;
    }
    if (!line.tokens.empty()) {
      last_line_ = line.number;
      return line;
    }
  }
  return std::nullopt;
}

TextLine TextTokenizer::expect_line(std::string_view what) {
  std::optional<TextLine> line = next_line();
  if (!line) {
    fail(concat("expected ", what, ", found end of file"));
  }
  return std::move(*line);
}

std::optional<std::string_view> TextTokenizer::next_raw_line() {
  if (position_ >= content_.size()) {
    return std::nullopt;
  }
  const std::size_t newline = content_.find('\n', position_);
  const std::size_t end = newline == std::string::npos ? content_.size() : newline;
  std::string_view text(content_.data() + position_, end - position_);
  if (!text.empty() && text.back() == '\r') {
    text.remove_suffix(1);
  }
  last_line_ = line_;
  position_ = newline == std::string::npos ? content_.size() : newline + 1;
  if (newline != std::string::npos) {
    ++line_;
  }
  return text;
}

void TextTokenizer::skip_blanks_and_comments() {
  while (position_ < content_.size()) {
    const char c = content_[position_];
    if (c == '\n') {
      ++line_;
      ++position_;
    } else if (is_space(c)) {
      ++position_;
    } else if (comment_ != 0 && c == comment_) {
      const std::size_t newline = content_.find('\n', position_);
      position_ = newline == std::string::npos ? content_.size() : newline;
    } else {
      return;
    }
  }
}

std::optional<std::string_view> TextTokenizer::next_token() {
  skip_blanks_and_comments();
  if (position_ >= content_.size()) {
    return std::nullopt;
  }
  const std::size_t start = position_;
  const auto ends_token = [this](char c) {
    return c == '\n' || is_space(c) || (comment_ != 0 && c == comment_);
  };
  while (position_ < content_.size() && !ends_token(content_[position_])) {
    ++position_;
  }
  last_line_ = line_;
  return std::string_view(content_.data() + start, position_ - start);
}

std::string_view TextTokenizer::expect_token(std::string_view what) {
  std::optional<std::string_view> token = next_token();
  if (!token) {
    fail(concat("expected ", what, ", found end of file"));
  }
  return *token;
}

std::optional<std::string_view> TextTokenizer::read_until(std::string_view delimiter) {
  const std::size_t found = content_.find(delimiter, position_);
  if (found == std::string::npos) {
    return std::nullopt;
  }
  const std::string_view text(content_.data() + position_, found - position_);
  last_line_ = line_;
  const std::size_t end = found + delimiter.size();
  line_ += static_cast<int>(std::count(content_.begin() + static_cast<std::ptrdiff_t>(position_),
                                       content_.begin() + static_cast<std::ptrdiff_t>(end), '\n'));
  position_ = end;
  return text;
}

std::string_view TextTokenizer::read_bytes(std::size_t count, std::string_view what) {
  if (count > bytes_left()) {
    fail(concat("truncated: ", what, " needs ", count, " bytes of binary data, only ", bytes_left(),
                " remain"));
  }
  const std::string_view bytes(content_.data() + position_, count);
  last_line_ = line_;
  // Keep line_ counting physical lines so that text after the block is still located right.
  line_ += static_cast<int>(std::count(bytes.begin(), bytes.end(), '\n'));
  position_ += count;
  return bytes;
}

double TextTokenizer::parse_coordinate(std::string_view token,
                                       std::string_view owner,
                                       std::int64_t owner_number) const {
  const std::string_view digits = without_plus(token);
  double value = 0.0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (end != digits.data() + digits.size() || error == std::errc::invalid_argument) {
    fail(concat(owner, " ", owner_number, " has a coordinate that is not a number (",
                quoted_token(token), ")"));
  }
  if (error == std::errc::result_out_of_range) {
    // Overflow (1e999) is non-finite; underflow (1e-400) is a legitimate, tiny number.
    value = std::strtod(std::string(digits).c_str(), nullptr);
  }
  if (!std::isfinite(value)) {
    fail(concat(owner, " ", owner_number, " has a non-finite coordinate (", printable(token), ")"));
  }
  return value;
}

std::int64_t TextTokenizer::parse_integer(std::string_view token, std::string_view what) const {
  const std::string_view digits = without_plus(token);
  std::int64_t value = 0;
  const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (error == std::errc::result_out_of_range) {
    fail(concat(what, " is out of range (", quoted_token(token), ")"));
  }
  if (error != std::errc() || end != digits.data() + digits.size()) {
    fail(concat("expected an integer for ", what, ", found ", quoted_token(token)));
  }
  return value;
}

int TextTokenizer::parse_count(std::string_view token, std::string_view what) const {
  const std::int64_t value = parse_integer(token, what);
  if (value < 0 || value > std::numeric_limits<int>::max()) {
    fail(concat(what, " must be between 0 and ", std::numeric_limits<int>::max(), ", found ",
                value));
  }
  return static_cast<int>(value);
}

std::size_t TextTokenizer::check_count_fits(std::int64_t count, std::string_view what) const {
  if (count < 0) {
    fail(concat("expected a non-negative number of ", what, ", found ", count));
  }
  const auto wanted = static_cast<std::uint64_t>(count);
  if (wanted > bytes_left()) {
    fail(concat("truncated file or wrong count: ", count, " ", what, " cannot fit in the ",
                bytes_left(), " bytes left in the file"));
  }
  return static_cast<std::size_t>(wanted);
}

void TextTokenizer::require_tokens(const TextLine& line,
                                   std::size_t count,
                                   std::string_view layout) const {
  if (line.size() != count) {
    fail_at(line.number, concat("expected ", count, " values (", layout, "), found ", line.size()));
  }
}

void TextTokenizer::require_min_tokens(const TextLine& line,
                                       std::size_t count,
                                       std::string_view layout) const {
  if (line.size() < count) {
    fail_at(line.number,
            concat("expected at least ", count, " values (", layout, "), found ", line.size()));
  }
}

void TextTokenizer::fail(std::string_view problem) const {
  fail_at(last_line_, problem);
}

void TextTokenizer::fail_at(int line, std::string_view problem) const {
  throw_file_error(file_, concat("line ", line, ": ", problem));
}

}  // namespace softbench
