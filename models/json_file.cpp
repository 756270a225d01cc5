// SPDX-License-Identifier: MIT
#include "models/json_file.h"

#include "geometry/input_error.h"
#include "geometry/text_format.h"

#include <algorithm>
#include <cstddef>
#include <fstream>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

namespace softbench {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::json;

// "line L, column C" of the byte at `offset` in `text` (both 1-based, as nlohmann counts).
std::string line_and_column(const std::string& text, std::size_t offset) {
  offset = std::min(offset, text.size());
  std::size_t line = 1;
  std::size_t line_start = 0;
  for (std::size_t i = 0; i < offset; ++i) {
    if (text[i] == '\n') {
      ++line;
      line_start = i + 1;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(offset - line_start + 1);
}

// One JSON pointer token (RFC 6901: '~' and '/' escaped), on one line.
std::string pointer_token(const std::string& key) {
  std::string token;
  for (const char c : key) {
    token += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  }
  return one_line(token);
}

// Builds the document as nlohmann's own DOM parser does, but refuses to open a container
// deeper than kMaxJsonDepth, so the result can never nest deep enough for nlohmann's recursive
// dump and comparison to overflow the stack. It stops the parse (returns false) rather than
// throwing through the parser, and keeps the error for read_json_file to report.
class BoundedDomBuilder : public Json::json_sax_t {
 public:
  explicit BoundedDomBuilder(Json& root) : root_(root) {}

  bool null() override { return add(nullptr) != nullptr; }
  bool boolean(bool value) override { return add(value) != nullptr; }
  bool number_integer(number_integer_t value) override { return add(value) != nullptr; }
  bool number_unsigned(number_unsigned_t value) override { return add(value) != nullptr; }
  bool number_float(number_float_t value, const string_t& /*text*/) override {
    return add(value) != nullptr;
  }
  bool string(string_t& value) override { return add(std::move(value)) != nullptr; }
  bool binary(binary_t& value) override { return add(Json::binary(std::move(value))) != nullptr; }

  bool start_object(std::size_t /*elements*/) override { return open(Json::value_t::object); }
  bool start_array(std::size_t /*elements*/) override { return open(Json::value_t::array); }
  bool end_object() override { return close(); }
  bool end_array() override { return close(); }

  bool key(string_t& key) override {
    if (open_.size() == 1) {
      outermost_ = "/" + pointer_token(key);
    }
    member_ = &(*open_.back())[key];
    return true;
  }

  bool parse_error(std::size_t position,
                   const std::string& last_token,
                   const nlohmann::detail::exception& error) override {
    error_position_ = position;
    error_token_ = last_token;
    error_message_ = error.what();
    error_id_ = error.id;
    return false;
  }

  bool too_deep() const { return too_deep_; }
  const std::string& outermost() const { return outermost_; }
  std::size_t error_position() const { return error_position_; }
  const std::string& error_token() const { return error_token_; }
  const std::string& error_message() const { return error_message_; }
  int error_id() const { return error_id_; }

 private:
  template <typename Value>
  Json* add(Value&& value) {
    if (open_.empty()) {
      root_ = Json(std::forward<Value>(value));
      return &root_;
    }
    Json& parent = *open_.back();
    if (parent.is_array()) {
      if (open_.size() == 1) {
        outermost_ = "/" + std::to_string(parent.size());
      }
      parent.emplace_back(std::forward<Value>(value));
      return &parent.back();
    }
    *member_ = Json(std::forward<Value>(value));
    return member_;
  }

  bool open(Json::value_t type) {
    if (open_.size() >= static_cast<std::size_t>(kMaxJsonDepth)) {
      too_deep_ = true;
      return false;
    }
    open_.push_back(add(type));
    return true;
  }

  bool close() {
    open_.pop_back();
    return true;
  }

  Json& root_;
  std::vector<Json*> open_;  // the containers being filled, outermost first
  Json* member_ = nullptr;   // the object member the next value goes to
  std::string outermost_;    // the pointer to the root's member being read ("/description")
  bool too_deep_ = false;
  std::size_t error_position_ = 0;
  std::string error_token_;
  std::string error_message_;
  int error_id_ = 0;
};

}  // namespace

Json read_json_file(const fs::path& path, std::string_view what) {
  const std::string name = path.string();
  std::error_code error;
  if (fs::is_directory(path, error)) {
    throw InputError(name + ": is a folder, not a " + std::string(what));
  }
  if (!fs::exists(path, error)) {
    throw InputError(name + ": no such file");
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw InputError(name + ": cannot open (not readable)");
  }
  std::stringstream buffer;
  buffer << in.rdbuf();
  return parse_json_text(buffer.str(), name);
}

Json parse_json_text(const std::string& text, const std::string& name) {
  Json result;
  BoundedDomBuilder builder(result);
  if (Json::sax_parse(text, &builder, Json::input_format_t::json, /*strict=*/true,
                      /*ignore_comments=*/true)) {
    return result;
  }
  if (builder.too_deep()) {
    throw InputError(name + ": " + builder.outermost() + ": nested deeper than "
                     + std::to_string(kMaxJsonDepth)
                     + " levels of arrays and objects (the limit)");
  }
  // nlohmann reports a number beyond a double (1e400) as out_of_range 406, with neither line
  // nor column: give them, at the number's first character.
  constexpr int kNumberOverflow = 406;
  if (builder.error_id() == kNumberOverflow) {
    const std::string& token = builder.error_token();
    const std::size_t end = builder.error_position();
    const std::size_t start = end >= token.size() ? end - token.size() : 0;
    throw InputError(name + ": invalid JSON: number out of range at "
                     + line_and_column(text, start) + ": " + token + " (beyond a double)");
  }
  // The parser's message carries "line L, column C"; keep it after the file name.
  const std::string& message = builder.error_message();
  const auto at = message.find("parse error");
  throw InputError(name + ": invalid JSON: "
                   + message.substr(at == std::string::npos ? 0 : at));
}

}  // namespace softbench
