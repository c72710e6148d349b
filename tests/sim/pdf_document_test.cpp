// The PDF writer (sim/report/pdf_document.h): the file's cross-reference table points at each
// object, strings are escaped, text is Latin-1, and pages are counted.

#include "sim/report/pdf_document.h"

#include <gtest/gtest.h>

#include <string>

namespace lap::sim {
namespace {

TEST(PdfDocument, TheCrossReferenceTablePointsAtEachObject) {
  PdfDocument doc;
  doc.text(50, 60, "a (title) \\ here", 12.0, true);
  doc.line(50, 100, 300, 100, 1.0, {1, 0, 0}, true);
  doc.new_page();
  doc.polyline({10, 10, 20, 30, 40, 5}, 1.0, {0, 0, 1});
  doc.fill_rect(10, 10, 100, 50, {0.5, 0.5, 0.5});
  EXPECT_EQ(doc.page_count(), 2);
  const std::string pdf = doc.bytes();
  EXPECT_EQ(pdf.rfind("%PDF-1.4\n", 0), 0U);
  const size_t startxref = pdf.rfind("startxref\n");
  ASSERT_NE(startxref, std::string::npos);
  const size_t xref = std::stoul(pdf.substr(startxref + 10));
  ASSERT_EQ(pdf.compare(xref, 5, "xref\n"), 0);
  // 4 shared objects and 2 per page: 8, and the free entry 0.
  EXPECT_EQ(pdf.compare(xref, 13, "xref\n0 9\n0000"), 0);
  for (int i = 1; i <= 8; ++i) {
    const size_t entry = xref + 9 + 20 * static_cast<size_t>(i);
    const size_t offset = std::stoul(pdf.substr(entry, 10));
    EXPECT_EQ(pdf.compare(offset, std::to_string(i).size() + 6, std::to_string(i) + " 0 obj"), 0)
        << i;
  }
  EXPECT_NE(pdf.find("/Count 2"), std::string::npos);
  EXPECT_NE(pdf.find("(a \\(title\\) \\\\ here) Tj"), std::string::npos);  // escaped
  EXPECT_NE(pdf.find("[4 3] 0 d"), std::string::npos);                     // dashed
  EXPECT_EQ(pdf.substr(pdf.size() - 6), "%%EOF\n");
}

TEST(PdfDocument, TextIsLatin1AndTheRestAQuestionMark) {
  PdfDocument doc;
  doc.text(0, 0, "30\xc2\xb0 \xc3\xa9 \xe2\x88\x9a \xf0\x9f\x98\x80 \x01", 10.0);
  const std::string pdf = doc.bytes();
  EXPECT_NE(pdf.find("(30\xb0 \xe9 ? ?  ) Tj"), std::string::npos) << pdf;
}

TEST(PdfDocument, TextWidthGrowsWithTheTextAndTheSize) {
  EXPECT_DOUBLE_EQ(PdfDocument::text_width("", 10.0, false), 0.0);
  EXPECT_NEAR(PdfDocument::text_width("nnnn", 10.0, false), 4 * 5.56, 1e-9);
  EXPECT_GT(PdfDocument::text_width("MMMM", 10.0, false),
            PdfDocument::text_width("iiii", 10.0, false));
  EXPECT_GT(PdfDocument::text_width("abc", 10.0, true),
            PdfDocument::text_width("abc", 10.0, false));
}

}  // namespace
}  // namespace lap::sim
