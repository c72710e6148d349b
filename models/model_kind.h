#pragma once
/// \file
/// The kinds of physical model an organ or object can have (thesis §6.4, §6.5, §7.7).

#include <optional>
#include <string_view>

namespace lap::models {

/// How an object responds to contact.
enum class ModelKind {
  kRigid,       ///< does not deform: anchored, or a free rigid body given dynamics (§6.4)
  kLocal,       ///< local deformation within an influence radius (§6.5)
  kModalShell,  ///< modal-reduced shell finite elements, for the cystic duct (§7.7(2))
  kMassSpring,  ///< mass-spring-damper chain: the catheter's (§7.7(3)), refused for an organ
};

/// Scenario spelling of each kind: rigid, local, modal-shell, mass-spring.
[[nodiscard]] std::string_view to_string(ModelKind kind);
/// Parses the scenario spelling; nullopt if unknown.
[[nodiscard]] std::optional<ModelKind> parse_model_kind(std::string_view text);

}  // namespace lap::models
