#pragma once
/// \file
/// What the readers and checks of text mesh files share (sim/setup/mesh_text_check.cpp,
/// sim/setup/ply_reader.cpp): a file read line by line as whitespace-separated tokens, numbers
/// read as a C-locale program writes them, and tokens quoted safely in messages.

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "core/diagnostic.h"
#include "core/result.h"

namespace lap::sim::mesh_text {

/// What is wrong with a token, or nothing.
using Problem = std::optional<std::string>;

/// A token as it may be shown in a message: printable, and short (a mutated file may put a
/// megabyte of binary on one line).
[[nodiscard]] std::string shown(std::string_view token);
/// A byte as two hex digits.
[[nodiscard]] std::string hex_byte(char c);
/// The token as a number (strtod in the C locale: the window's Qt sets the user's locale, where
/// the decimal separator may be a comma), or nothing when it is not one whole number.
[[nodiscard]] std::optional<double> number_value(std::string_view token);
/// `what 'token' is not a finite number` or `... is not a number`, or nothing when the token
/// is a finite number.
[[nodiscard]] Problem number_problem(std::string_view token, const std::string& what);
/// The token as a whole number (no sign other than '-', no spaces), or nothing.
[[nodiscard]] std::optional<int64_t> whole_number(std::string_view token);
/// `N what is more than the limit of L (sim/setup/mesh_limits.h)`.
[[nodiscard]] std::string over_limit(int64_t count, const char* what, int64_t limit);

/// The file's lines, split into whitespace-separated tokens, with comments removed; blank lines
/// are skipped. Tokens view the current line, valid until the next call.
class LineReader {
 public:
  LineReader(const std::filesystem::path& file, char comment)
      : in_(file, std::ios::binary), file_(file.string()), comment_(comment) {}

  bool next() {
    while (std::getline(in_, text_)) {
      ++number_;
      std::string_view v(text_);
      if (comment_ != '\0') v = v.substr(0, v.find(comment_));
      tokens_.clear();
      size_t i = 0;
      while (i < v.size()) {
        while (i < v.size() && is_space(v[i])) ++i;
        const size_t start = i;
        while (i < v.size() && !is_space(v[i])) ++i;
        if (i > start) tokens_.push_back(v.substr(start, i - start));
      }
      if (!tokens_.empty()) return true;
    }
    return false;
  }
  [[nodiscard]] const std::vector<std::string_view>& tokens() const { return tokens_; }
  [[nodiscard]] std::string_view operator[](size_t i) const { return tokens_[i]; }
  [[nodiscard]] size_t size() const { return tokens_.size(); }
  /// Whether the current line holds a comment (after its tokens: a line of only a comment is
  /// skipped).
  [[nodiscard]] bool has_comment() const {
    return comment_ != '\0' && text_.find(comment_) != std::string::npos;
  }
  /// The line after its first token, comments and all, without the spaces around it.
  [[nodiscard]] std::string_view rest() const {
    std::string_view v(text_);
    v.remove_prefix(static_cast<size_t>(tokens_[0].data() + tokens_[0].size() - text_.data()));
    while (!v.empty() && is_space(v.front())) v.remove_prefix(1);
    while (!v.empty() && (is_space(v.back()) || v.back() == '\n')) v.remove_suffix(1);
    return v;
  }
  /// The line right after its first token, as it is (spaces and all).
  [[nodiscard]] std::string_view after_first() const {
    std::string_view v(text_);
    v.remove_prefix(static_cast<size_t>(tokens_[0].data() + tokens_[0].size() - text_.data()));
    return v;
  }
  /// The byte offset just after the current line (where a binary body starts after a header).
  [[nodiscard]] std::streamoff offset_after_line() {
    return static_cast<std::streamoff>(in_.tellg());
  }
  /// The current line's number (1-based).
  [[nodiscard]] int line() const { return number_; }
  /// The problem at the current line.
  [[nodiscard]] Diagnostic problem(const std::string& field, const std::string& what) const {
    return file_diagnostic(file_, number_, field, what);
  }
  [[nodiscard]] Status fail(const std::string& field, const std::string& what) const {
    return problem(field, what);
  }

 private:
  // What C's isspace() takes in the C locale (less '\n', which ends the line): the readers the
  // checks stand in front of split with `>>`, so a form feed separates tokens for them too (a
  // face line "f\f/9" passed unseen as one token and OpenMesh's OBJ reader asserted on it).
  static bool is_space(char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  }
  std::ifstream in_;
  std::string file_;
  char comment_;
  std::string text_;
  int number_ = 0;
  std::vector<std::string_view> tokens_;
};

}  // namespace lap::sim::mesh_text
