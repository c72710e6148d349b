#include "models/model_kind.h"

namespace lap::models {

std::string_view to_string(ModelKind kind) {
  switch (kind) {
    case ModelKind::kRigid:
      return "rigid";
    case ModelKind::kLocal:
      return "local";
    case ModelKind::kModalShell:
      return "modal-shell";
    case ModelKind::kMassSpring:
      return "mass-spring";
  }
  return "rigid";
}

std::optional<ModelKind> parse_model_kind(std::string_view text) {
  for (ModelKind k :
       {ModelKind::kRigid, ModelKind::kLocal, ModelKind::kModalShell, ModelKind::kMassSpring}) {
    if (to_string(k) == text) return k;
  }
  return std::nullopt;
}

}  // namespace lap::models
