#include "models/model_kind.h"

#include <gtest/gtest.h>

namespace lap::models {
namespace {

TEST(ModelKind, RoundTripsEverySpelling) {
  for (ModelKind k :
       {ModelKind::kRigid, ModelKind::kLocal, ModelKind::kModalShell, ModelKind::kMassSpring}) {
    EXPECT_EQ(parse_model_kind(to_string(k)), k);
  }
  EXPECT_EQ(parse_model_kind("modal-shell"), ModelKind::kModalShell);
  EXPECT_FALSE(parse_model_kind("Rigid").has_value());
  EXPECT_FALSE(parse_model_kind("").has_value());
}

}  // namespace
}  // namespace lap::models
