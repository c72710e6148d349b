// The project's one error type (core/): how a Diagnostic prints, and what a Result holds.

#include "core/result.h"

#include <gtest/gtest.h>

#include <memory>
#include <stdexcept>
#include <string>

namespace lap {
namespace {

TEST(Diagnostic, PrintsFileLineFieldAndMessageLeavingOutWhatDoesNotApply) {
  EXPECT_EQ((Diagnostic{"a.yaml", 12, "organs[1].name", "expected a string"}).to_string(),
            "a.yaml:12: organs[1].name: expected a string");
  EXPECT_EQ((Diagnostic{"a.yaml", 0, "tools", "expected a list"}).to_string(),
            "a.yaml: tools: expected a list");
  EXPECT_EQ((Diagnostic{"m.obj", 0, "", "the file contains no triangles"}).to_string(),
            "m.obj: the file contains no triangles");
  EXPECT_EQ(diagnostic("no device for the left tool").to_string(), "no device for the left tool");
  EXPECT_EQ(to_string(std::vector<Diagnostic>{diagnostic("one"), diagnostic("two")}), "one\ntwo");
}

TEST(Result, HoldsAValueOrTheDiagnosticsThatSayWhyNot) {
  Result<std::unique_ptr<int>> good(std::make_unique<int>(7));
  ASSERT_TRUE(good.ok());
  EXPECT_TRUE(good.diagnostics().empty());
  EXPECT_EQ(*good.value(), 7);
  const std::unique_ptr<int> taken = std::move(good).value();
  EXPECT_EQ(*taken, 7);

  const Result<int> bad(Diagnostic{"s.yaml", 3, "rate", "expected a positive number"});
  ASSERT_FALSE(bad.ok());
  EXPECT_FALSE(static_cast<bool>(bad));
  EXPECT_EQ(bad.message(), "s.yaml:3: rate: expected a positive number");
  // Asking for a value that is not there is the caller's mistake, reported with the reason.
  try {
    (void)bad.value();
    FAIL() << "value() of a failed Result must throw";
  } catch (const std::runtime_error& e) {
    EXPECT_EQ(std::string(e.what()), bad.message());
  }
  // An empty list of diagnostics still makes a failure, never a silent success.
  const Result<int> empty(std::vector<Diagnostic>{});
  EXPECT_FALSE(empty.ok());
  EXPECT_FALSE(empty.message().empty());
}

TEST(Status, IsSuccessOrDiagnostics) {
  const Status fine;
  EXPECT_TRUE(fine.ok());
  const Status failed(diagnostic("cannot write"));
  EXPECT_FALSE(failed.ok());
  EXPECT_EQ(failed.message(), "cannot write");
}

}  // namespace
}  // namespace lap
