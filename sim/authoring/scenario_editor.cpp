#include "sim/authoring/scenario_editor.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <fstream>
#include <optional>
#include <sstream>
#include <system_error>

#include "sim/setup/scenario_loader.h"

namespace lap::sim {

std::string yaml_value_text(const std::variant<double, bool>& value) {
  if (const bool* b = std::get_if<bool>(&value)) return *b ? "true" : "false";
  const double x = std::get<double>(value);
  std::array<char, 64> buf{};
  const auto r = std::to_chars(buf.data(), buf.data() + buf.size(), x);
  return {buf.data(), r.ptr};
}

namespace {

bool is_space(char c) { return c == ' ' || c == '\t'; }

/// One line of the file as the scanner sees it (block YAML only).
struct ScannedLine {
  bool ignorable = true;   ///< blank or a comment only
  int column = 0;          ///< where its key starts (after `- ` on an item's first line)
  bool item = false;       ///< starts a sequence item (`- `)
  int dash_column = 0;     ///< item: where the dash is
  std::string key;         ///< the key at `column`, "" when the line is no `key:` line
  size_t value_begin = 0;  ///< the value's span in the line (trimmed), before any comment
  size_t value_end = 0;
  size_t comment_begin = std::string::npos;  ///< where `#` starts, if a comment follows
};

/// Where a comment starts in `s` (npos: none): a `#` at the start or after a space, outside
/// quotes.
size_t comment_start(std::string_view s) {
  char quote = 0;
  for (size_t i = 0; i < s.size(); ++i) {
    const char c = s[i];
    if (quote != 0) {
      if (c == quote) quote = 0;
      continue;
    }
    if (c == '\'' || c == '"') {
      if (i == 0 || is_space(s[i - 1]) || s[i - 1] == ':' || s[i - 1] == '-') quote = c;
      continue;
    }
    if (c == '#' && (i == 0 || is_space(s[i - 1]))) return i;
  }
  return std::string_view::npos;
}

ScannedLine scan(std::string_view s) {
  ScannedLine l;
  const size_t first = s.find_first_not_of(" \t");
  if (first == std::string_view::npos || s[first] == '#') return l;
  l.ignorable = false;
  l.comment_begin = comment_start(s);
  size_t end = std::min(l.comment_begin, s.size());
  while (end > first && is_space(s[end - 1])) --end;
  size_t pos = first;
  if (s[pos] == '-' && (pos + 1 == end || is_space(s[pos + 1]))) {
    l.item = true;
    l.dash_column = static_cast<int>(pos);
    ++pos;
    while (pos < end && is_space(s[pos])) ++pos;
  }
  l.column = static_cast<int>(pos);
  l.value_begin = l.value_end = end;
  // A plain key: letters, digits, `_`, `-`, `<`, `.`; then `:` and a space or the end.
  size_t k = pos;
  while (k < end && s[k] != ':' && !is_space(s[k])) ++k;
  if (k < end && s[k] == ':' && (k + 1 == end || is_space(s[k + 1])) && k > pos) {
    l.key = std::string(s.substr(pos, k - pos));
    size_t v = k + 1;
    while (v < end && is_space(s[v])) ++v;
    l.value_begin = v;
  } else {
    l.value_begin = pos;  // an item's bare value, or a line continuing a value
  }
  return l;
}

std::string unquote(std::string_view v) {
  if (v.size() >= 2 && (v.front() == '"' || v.front() == '\'') && v.back() == v.front()) {
    return std::string(v.substr(1, v.size() - 2));
  }
  return std::string(v);
}

class ScenarioText {
 public:
  ScenarioText(std::string_view text, std::string file) : file_(std::move(file)) {
    size_t start = 0;
    while (start < text.size()) {
      size_t nl = text.find('\n', start);
      const bool last = nl == std::string_view::npos;
      const size_t stop = last ? text.size() : nl;
      std::string_view line = text.substr(start, stop - start);
      const bool cr = !line.empty() && line.back() == '\r';
      if (cr) line.remove_suffix(1);
      std::string eol = cr ? "\r" : "";
      if (!last) eol += '\n';
      lines_.emplace_back(line);
      eols_.push_back(std::move(eol));
      start = last ? text.size() : nl + 1;
    }
  }

  [[nodiscard]] std::string text() const {
    std::string out;
    for (size_t i = 0; i < lines_.size(); ++i) {
      out += lines_[i];
      out += eols_[i];
    }
    return out;
  }

  /// Applies one edit; diagnostics on refusal.
  Status apply(const MaterialEdit& edit) {
    std::vector<std::string> path;
    {
      std::string part;
      std::istringstream in(edit.field);
      while (std::getline(in, part, '.')) {
        if (part.empty()) return problem(0, "material." + edit.field, "an empty field name");
        path.push_back(part);
      }
      if (path.empty()) return problem(0, "material", "no field to edit");
    }
    scanned_.clear();
    for (const std::string& l : lines_) scanned_.push_back(scan(l));

    // The top-level `organs:` block.
    int organs = -1;
    for (int i = 0; i < size(); ++i) {
      const ScannedLine& l = at(i);
      if (!l.ignorable && l.column == 0 && !l.item && l.key == "organs") {
        organs = i;
        break;
      }
    }
    if (organs < 0) return problem(0, "organs", "the scenario has no block-style `organs:` key");
    if (has_value(organs)) {
      return problem(organs + 1, "organs",
                     "written in flow style or inline: only a block list (`- name: ...` on "
                     "lines of their own) can be edited without rewriting the file");
    }
    const int organs_end = block_end(organs, 0);

    // The organ's item.
    int item = -1;
    int item_end = -1;
    int index = 0;
    int dash = -1;
    int flow_item = -1;  // an organ written as `- {name: ...}`: its name is not read here
    for (int i = organs + 1; i < organs_end; ++i) {
      const ScannedLine& l = at(i);
      if (l.ignorable || !l.item) continue;
      if (dash < 0) dash = l.dash_column;
      if (l.dash_column != dash) continue;
      int end = i + 1;
      while (end < organs_end && (at(end).ignorable || !at(end).item || at(end).dash_column > dash))
        ++end;
      if (l.key.empty() && l.value_begin < l.value_end && flow_item < 0) flow_item = i;
      const int name = find_key(i, end, item_column(i, end), "name");
      if (name >= 0 && unquote(value(name)) == edit.organ) {
        item = i;
        item_end = end;
        break;
      }
      ++index;
      i = end - 1;
    }
    if (item < 0 && flow_item >= 0) {
      return problem(flow_item + 1, "organs",
                     "no block-style organ named '" + edit.organ +
                         "', and this one is in flow style: only a block mapping can be edited "
                         "in place");
    }
    if (item < 0) {
      return problem(organs + 1, "organs", "no organ named '" + edit.organ + "'");
    }
    const std::string organ_field = "organs[" + std::to_string(index) + "]";
    if (Status s = refuse_anchors(item, item_end, organ_field); !s) return s;

    // Down the path: material, then each part.
    int column = item_column(item, item_end);
    int begin = item;
    int end = item_end;
    std::string field = organ_field;
    std::vector<std::string> full{"material"};
    full.insert(full.end(), path.begin(), path.end());
    for (size_t p = 0; p < full.size(); ++p) {
      field += '.';
      field += full[p];
      const bool leaf = p + 1 == full.size();
      const int at_line = find_key(begin, end, column, full[p]);
      if (at_line < 0) {
        insert(begin, end, column, std::span(full).subspan(p), edit.value);
        return {};
      }
      if (leaf) return replace(at_line, end, field, edit.value);
      // A one-line flow map holding the leaf (the shipped scenarios' `shading: {enabled: true,
      // crease_angle_deg: 40}`): its entry is set, or added, in place.
      if (p + 2 == full.size() && value(at_line).starts_with('{')) {
        return set_in_flow_map(at_line, field + '.' + full[p + 1], full[p + 1], edit.value);
      }
      if (has_value(at_line)) {
        return problem(at_line + 1, field,
                       "written in flow style or inline: only a block mapping can be edited "
                       "in place (write it as `" +
                           full[p] + ":` with each field on its own line)");
      }
      const int child_end = block_end(at_line, column);
      begin = at_line;
      end = child_end;
      column = child_column(at_line, child_end, column);
    }
    return {};
  }

 private:
  [[nodiscard]] int size() const { return static_cast<int>(lines_.size()); }
  [[nodiscard]] const ScannedLine& at(int i) const { return scanned_[static_cast<size_t>(i)]; }
  [[nodiscard]] std::string_view value(int i) const {
    const ScannedLine& l = at(i);
    return std::string_view(lines_[static_cast<size_t>(i)])
        .substr(l.value_begin, l.value_end - l.value_begin);
  }
  [[nodiscard]] bool has_value(int i) const { return !value(i).empty(); }

  Status problem(int line, const std::string& field, const std::string& message) const {
    return Status(file_diagnostic(file_, line, field, message));
  }

  /// The first line after `from` whose content starts at or left of `column`.
  [[nodiscard]] int block_end(int from, int column) const {
    int i = from + 1;
    while (i < size() &&
           (at(i).ignorable || (at(i).item ? at(i).dash_column : at(i).column) > column)) {
      ++i;
    }
    return i;
  }

  /// The column of an item's keys: after its dash, or on the next line when the dash is alone.
  [[nodiscard]] int item_column(int item, int end) const {
    if (!at(item).key.empty()) return at(item).column;
    for (int i = item + 1; i < end; ++i) {
      if (!at(i).ignorable) return at(i).column;
    }
    return at(item).dash_column + 2;
  }

  /// The column of a block's children (two deeper than `column` when it has none yet).
  [[nodiscard]] int child_column(int parent, int end, int column) const {
    for (int i = parent + 1; i < end; ++i) {
      if (!at(i).ignorable) return at(i).item ? at(i).dash_column : at(i).column;
    }
    return column + 2;
  }

  /// The line of `key` at `column` within [begin, end) (begin itself included: an item's first
  /// key is on its dash's line), or -1.
  [[nodiscard]] int find_key(int begin, int end, int column, const std::string& key) const {
    for (int i = begin; i < end; ++i) {
      const ScannedLine& l = at(i);
      if (!l.ignorable && l.column == column && l.key == key && (i == begin || !l.item)) return i;
    }
    return -1;
  }

  Status refuse_anchors(int begin, int end, const std::string& field) const {
    for (int i = begin; i < end; ++i) {
      const ScannedLine& l = at(i);
      if (l.ignorable) continue;
      const std::string_view v = value(i);
      if (l.key == "<<" || (!v.empty() && (v.front() == '&' || v.front() == '*')) ||
          (!l.key.empty() && (l.key.front() == '&' || l.key.front() == '*'))) {
        return problem(i + 1, field,
                       "uses an anchor, an alias or a merge key: an edit here could change "
                       "other organs too (or nothing), so it is not made; write the values out");
      }
    }
    return {};
  }

  Status replace(int line, int end, const std::string& field,
                 const std::variant<double, bool>& value_in) {
    const std::string_view v = value(line);
    if (v.empty()) {
      return problem(line + 1, field, "is a block, not a single value: it cannot be set");
    }
    if (v.front() == '|' || v.front() == '>' || v.front() == '{' || v.front() == '[' ||
        v.front() == '!') {
      return problem(line + 1, field,
                     "a block scalar, a flow collection or a tagged value: only a plain value "
                     "on its own line can be replaced");
    }
    for (int i = line + 1; i < end; ++i) {
      if (at(i).ignorable) continue;
      if ((at(i).item ? at(i).dash_column : at(i).column) > at(line).column) {
        return problem(line + 1, field,
                       "its value continues on the next line: only a one-line value can be "
                       "replaced");
      }
      break;
    }
    set_value_text(line, yaml_value_text(value_in));
    return {};
  }

  /// `key: value` set in the one-line flow map that is line `line`'s value: the entry's value
  /// replaced, or the entry added before the closing brace. Other entries keep their text.
  Status set_in_flow_map(int line, const std::string& field, const std::string& key,
                         const std::variant<double, bool>& value_in) {
    const std::string map(value(line));
    const auto refuse = [&](const char* why) {
      return problem(line + 1, field,
                     std::string(why) +
                         ": only a one-line flow map of plain values can be "
                         "edited in place (or write it in block style, each "
                         "field on its own line)");
    };
    if (map.size() < 2 || map.back() != '}') return refuse("a flow map over several lines");
    if (map.find_first_of("{}[]\"'&*!", 1) != map.size() - 1) {
      return refuse("a nested, quoted or tagged flow map");
    }
    const std::string new_value = yaml_value_text(value_in);
    const auto trim = [](size_t b, size_t e, const std::string& t) {
      while (b < e && (t[b] == ' ' || t[b] == '\t')) ++b;
      while (e > b && (t[e - 1] == ' ' || t[e - 1] == '\t')) --e;
      return std::pair{b, e};
    };
    size_t begin = 1;
    while (begin < map.size() - 1) {
      size_t end = map.find(',', begin);
      if (end == std::string::npos) end = map.size() - 1;
      const auto [b, e] = trim(begin, end, map);
      // Each entry `key: value` (YAML reads `a:1` as one plain key, `a` alone as a key without
      // a value): anything else is not edited by guesswork.
      const size_t colon = map.find(": ", b);
      if (b < e && (colon >= e || colon == b)) return refuse("an entry that is not `key: value`");
      if (b < e) {
        const auto [kb, ke] = trim(b, colon, map);
        if (map.compare(kb, ke - kb, key) == 0) {
          const auto [vb, ve] = trim(colon + 1, e, map);
          if (vb == ve) return refuse("the entry has no value");
          set_value_text(line, map.substr(0, vb) + new_value + map.substr(ve));
          return {};
        }
      }
      begin = end + 1;
    }
    const auto [b, tail] = trim(1, map.size() - 1, map);
    size_t e = tail;  // the last entry's end; `tail` after its trailing comma, if any
    if (e > b && map[e - 1] == ',') e = trim(b, e - 1, map).second;  // `{a: 1, }`
    const std::string entry = key + ": " + new_value;
    set_value_text(line,
                   b == e ? "{" + entry + "}" : map.substr(0, e) + ", " + entry + map.substr(tail));
    return {};
  }

  /// Line `line`'s value replaced by `new_value`; its comment kept, in its column when the new
  /// value leaves room.
  void set_value_text(int line, const std::string& new_value) {
    const ScannedLine& l = at(line);
    std::string& text = lines_[static_cast<size_t>(line)];
    std::string out = text.substr(0, l.value_begin) + new_value;
    if (l.comment_begin != std::string::npos) {
      // The comment stays in its column when the new value leaves room, as aligned comments do.
      const size_t stop = l.value_begin + new_value.size();
      const size_t gap = l.comment_begin > stop ? l.comment_begin - stop : 1;
      out += std::string(gap, ' ') + text.substr(l.comment_begin);
    }
    text = out;
  }

  /// Adds the missing `parts` (the first one absent from the block [begin, end) at `column`)
  /// after the block's last line of content.
  void insert(int begin, int end, int column, std::span<const std::string> parts,
              const std::variant<double, bool>& value_in) {
    int after = begin;
    for (int i = begin; i < end; ++i) {
      if (!at(i).ignorable) after = i;
    }
    int child = column;
    std::vector<std::string> added;
    added.reserve(parts.size());
    for (size_t p = 0; p < parts.size(); ++p) {
      std::string line(static_cast<size_t>(child), ' ');
      line += parts[p];
      line += ':';
      if (p + 1 == parts.size()) {
        line += ' ';
        line += yaml_value_text(value_in);
      }
      added.push_back(std::move(line));
      child += 2;
    }
    // A file that had no final newline after this line keeps none after the added ones.
    const bool no_final_newline = eols_[static_cast<size_t>(after)].empty();
    const std::string eol = !no_final_newline        ? eols_[static_cast<size_t>(after)]
                            : !eols_.front().empty() ? eols_.front()  // the file's own
                                                     : std::string("\n");
    if (no_final_newline) eols_[static_cast<size_t>(after)] = eol;
    const std::ptrdiff_t pos = static_cast<std::ptrdiff_t>(after) + 1;
    lines_.insert(lines_.begin() + pos, added.begin(), added.end());
    eols_.insert(eols_.begin() + pos, added.size(), eol);
    if (no_final_newline) eols_.back() = "";
  }

  std::string file_;
  std::vector<std::string> lines_;
  std::vector<std::string> eols_;
  std::vector<ScannedLine> scanned_;
};

}  // namespace

Result<std::string> edit_scenario_materials(std::string_view text,
                                            const std::filesystem::path& file,
                                            std::span<const MaterialEdit> edits) {
  ScenarioText scenario(text, file.string());
  std::vector<Diagnostic> problems;
  for (const MaterialEdit& edit : edits) {
    Status s = scenario.apply(edit);
    for (const Diagnostic& d : s.diagnostics()) problems.push_back(d);
  }
  if (!problems.empty()) return problems;
  return scenario.text();
}

Status save_scenario_materials(const std::filesystem::path& file,
                               std::span<const MaterialEdit> edits) {
  std::string text;
  {
    std::ifstream in(file, std::ios::binary);
    if (!in) return file_diagnostic(file.string(), 0, "", "cannot be read");
    std::ostringstream ss;
    ss << in.rdbuf();
    text = ss.str();
  }
  Result<std::string> edited = edit_scenario_materials(text, file, edits);
  if (!edited) return std::move(edited).diagnostics();
  // The edit is refused when it breaks a scenario that loaded: the user's file stays good.
  if (load_scenario(file).ok()) {
    ScenarioLoadResult after = parse_scenario(edited.value(), file);
    if (!after) {
      std::vector<Diagnostic> d = std::move(after).diagnostics();
      d.insert(d.begin(), file_diagnostic(file.string(), 0, "",
                                          "not saved: with the new values the scenario would "
                                          "not load"));
      return d;
    }
  }
  std::filesystem::path tmp = file;
  tmp += ".saving";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out << edited.value();
    out.close();
    if (!out) {
      std::error_code ec;
      std::filesystem::remove(tmp, ec);
      return file_diagnostic(tmp.string(), 0, "", "cannot be written");
    }
  }
  std::error_code ec;
  std::filesystem::rename(tmp, file, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    return file_diagnostic(file.string(), 0, "", "cannot be replaced: " + ec.message());
  }
  return {};
}

}  // namespace lap::sim
