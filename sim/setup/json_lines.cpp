#include "sim/setup/json_lines.h"

#include <cstdint>
#include <iterator>
#include <nlohmann/json.hpp>
#include <vector>

namespace lap::sim {
namespace {

/// The lines the parser has read: the current one, and the one its last token ended on
/// (whitespace after a number the parser peeked at does not count).
struct LineCount {
  int line = 1;
  int token_line = 1;
};

/// A byte iterator that counts lines as nlohmann's input adapter advances it (the adapter reads
/// each byte once, in order, dereferencing then advancing).
class CountingIterator {
 public:
  using iterator_category = std::forward_iterator_tag;
  using value_type = char;
  using difference_type = std::ptrdiff_t;
  using pointer = const char*;
  using reference = const char&;

  CountingIterator() = default;
  CountingIterator(const char* at, LineCount* count) : at_(at), count_(count) {}
  reference operator*() const { return *at_; }
  CountingIterator& operator++() {
    const char c = *at_;
    if (c == '\n') {
      ++count_->line;
    } else if (c != ' ' && c != '\t' && c != '\r') {
      count_->token_line = count_->line;
    }
    ++at_;
    return *this;
  }
  CountingIterator operator++(int) {
    CountingIterator before = *this;
    ++*this;
    return before;
  }
  bool operator==(const CountingIterator& o) const { return at_ == o.at_; }
  bool operator!=(const CountingIterator& o) const { return at_ != o.at_; }

 private:
  const char* at_ = nullptr;
  LineCount* count_ = nullptr;
};

}  // namespace

/// nlohmann's SAX events, turned into the paths of the shallow fields and their lines.
class JsonLinesHandler {
 public:
  using json = nlohmann::json;
  JsonLinesHandler(JsonLines* out, const LineCount* count, int max_depth, size_t max_entries)
      : out_(out), count_(count), max_depth_(max_depth), max_entries_(max_entries) {}

  bool null() { return value(); }
  bool boolean(bool /*v*/) { return value(); }
  bool number_integer(json::number_integer_t /*v*/) { return value(); }
  bool number_unsigned(json::number_unsigned_t /*v*/) { return value(); }
  bool number_float(json::number_float_t /*v*/, const json::string_t& /*text*/) { return value(); }
  bool string(json::string_t& /*v*/) { return value(); }
  bool binary(json::binary_t& /*v*/) { return value(); }
  bool start_object(std::size_t /*elements*/) { return open(false); }
  bool start_array(std::size_t /*elements*/) { return open(true); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(json::string_t& k) {
    if (deeper_ > 0 || frames_.empty()) return true;
    const Frame& f = frames_.back();
    // A key of more than a line's worth is not one a message would name.
    key_path_ = k.size() > 256 ? std::string() : (f.path.empty() ? k : f.path + "." + k);
    record(key_path_);
    return true;
  }
  bool parse_error(std::size_t /*position*/, const std::string& /*last_token*/,
                   const nlohmann::detail::exception& e) {
    out_->error_line_ = count_->token_line;
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 1, column 2: syntax error ..."
    if (const size_t at = what.find(": ");
        what.rfind("[json.exception.", 0) == 0 && at != std::string::npos) {
      what.erase(0, at + 2);
    }
    if (what.size() > 160) what = what.substr(0, 160) + "...";
    out_->error_ = what.empty() ? "not valid JSON" : what;
    return false;
  }

 private:
  struct Frame {
    bool array = false;
    size_t index = 0;
    std::string path;  ///< of the container itself
  };

  // The path of the value that starts now: an array's next element, or the object's last key.
  std::string value_path() {
    if (frames_.empty()) return {};
    Frame& f = frames_.back();
    if (!f.array) return key_path_;
    std::string p = f.path + "[" + std::to_string(f.index++) + "]";
    record(p);
    return p;
  }
  bool value() {
    if (deeper_ == 0) (void)value_path();
    return true;
  }
  bool open(bool array) {
    if (deeper_ > 0 || static_cast<int>(frames_.size()) >= max_depth_) {
      if (deeper_ == 0) (void)value_path();
      ++deeper_;  // below the recorded levels: only counted
      return true;
    }
    std::string path = value_path();
    frames_.push_back({array, 0, std::move(path)});
    return true;
  }
  bool close() {
    if (deeper_ > 0) {
      --deeper_;
    } else if (!frames_.empty()) {
      frames_.pop_back();
    }
    return true;
  }
  void record(const std::string& path) {
    if (path.empty() || out_->lines_.size() >= max_entries_) return;
    out_->lines_.emplace(path, count_->token_line);
  }

  JsonLines* out_;
  const LineCount* count_;
  int max_depth_;
  size_t max_entries_;
  std::vector<Frame> frames_;
  int64_t deeper_ = 0;
  std::string key_path_;
};

JsonLines JsonLines::scan(std::string_view text, int max_depth, size_t max_entries) {
  JsonLines out;
  LineCount count;
  JsonLinesHandler handler(&out, &count, max_depth, max_entries);
  const CountingIterator first(text.data(), &count);
  const CountingIterator last(text.data() + text.size(), &count);
  nlohmann::json::sax_parse(first, last, &handler);
  return out;
}

int JsonLines::line(const std::string& path, int fallback) const {
  const auto it = lines_.find(path);
  return it == lines_.end() ? fallback : it->second;
}

}  // namespace lap::sim
