#pragma once
/// \file
/// Writes an organ's tuned material back into its scenario YAML as text: only the lines of the
/// fields that change are rewritten (the value replaced, the key, its indentation and its trailing
/// comment kept where they were), a field the organ's block lacks is added at the end of its
/// `material:` block at that block's indentation, and every other byte — comments, blank lines,
/// key order, quoting — stays as it was. A YAML library's emitter would drop the comments that
/// carry each parameter's source (the brief: every tissue parameter cites one), hence text.
///
/// The edit works on block-style YAML, and on a one-line flow map of plain values that holds the
/// field (`shading: {enabled: true, crease_angle_deg: 40}`: the entry set or added in place).
/// What it cannot rewrite safely it refuses with a Diagnostic naming the file and line: an organ
/// written in flow style, nested, quoted or multi-line flow maps, anchors, aliases and merge
/// keys in the organ's block (an edit there would change other organs too, or nothing), block
/// scalars and multi-line values. The scenario loader checks the result before it is saved.

#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/result.h"

namespace lap::sim {

/// One value to set in an organ's `material:` block.
struct MaterialEdit {
  std::string organ;  ///< the organ's `name:`
  /// The field's path under `material`, dotted for nested blocks: `stiffness_n_per_m`,
  /// `shading.enabled`, `texture.amplitude_m`.
  std::string field;
  std::variant<double, bool> value;
};

/// The value as the file will have it: numbers in the shortest form that reads back as the same
/// double (std::to_chars), booleans as `true`/`false`.
[[nodiscard]] std::string yaml_value_text(const std::variant<double, bool>& value);

/// `text` (the contents of `file`, named in diagnostics) with every edit applied, or why not.
[[nodiscard]] Result<std::string> edit_scenario_materials(std::string_view text,
                                                          const std::filesystem::path& file,
                                                          std::span<const MaterialEdit> edits);

/// Reads `file`, applies the edits, checks that the result still loads as a scenario (when the
/// original did: a file with other problems is saved with them), and replaces the file through
/// a temporary beside it and a rename, so a failure leaves the file as it was.
[[nodiscard]] Status save_scenario_materials(const std::filesystem::path& file,
                                             std::span<const MaterialEdit> edits);

}  // namespace lap::sim
