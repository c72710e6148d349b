#include "sim/report/pdf_document.h"

#include <cmath>
#include <cstdio>
#include <fstream>

namespace lap::sim {

namespace {

std::string num(double v) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.2f", std::isfinite(v) ? v : 0.0);
  return text;
}

std::string rgb(PdfColor c, bool stroke) {
  return num(c.r) + " " + num(c.g) + " " + num(c.b) + (stroke ? " RG\n" : " rg\n");
}

/// UTF-8 to Latin-1 bytes (WinAnsi agrees on 0xA0-0xFF), anything else '?'.
std::string latin1(const std::string& utf8) {
  std::string out;
  for (size_t i = 0; i < utf8.size(); ++i) {
    const auto c = static_cast<unsigned char>(utf8[i]);
    if (c < 0x80) {
      out.push_back(c >= 0x20 ? static_cast<char>(c) : ' ');
    } else if ((c & 0xE0) == 0xC0 && i + 1 < utf8.size()) {
      const unsigned code = ((c & 0x1Fu) << 6) | (static_cast<unsigned char>(utf8[i + 1]) & 0x3Fu);
      out.push_back(code >= 0xA0 && code <= 0xFF ? static_cast<char>(code) : '?');
      ++i;
    } else {
      out.push_back('?');
      while (i + 1 < utf8.size() && (static_cast<unsigned char>(utf8[i + 1]) & 0xC0) == 0x80) ++i;
    }
  }
  return out;
}

/// A PDF literal string: parentheses and backslashes escaped (§3.2.3).
std::string literal(const std::string& bytes) {
  std::string out = "(";
  for (const char c : bytes) {
    if (c == '(' || c == ')' || c == '\\') out.push_back('\\');
    out.push_back(c);
  }
  return out + ")";
}

}  // namespace

void PdfDocument::new_page() { pages_.emplace_back(); }

std::string& PdfDocument::page() {
  if (pages_.empty()) new_page();
  return pages_.back();
}

void PdfDocument::text(double x, double y, const std::string& utf8, double size_pt, bool bold,
                       PdfColor color) {
  page() += rgb(color, false) + "BT /" + (bold ? "F2 " : "F1 ") + num(size_pt) + " Tf " + num(x) +
            " " + num(kPageHeightPt - y) + " Td " + literal(latin1(utf8)) + " Tj ET\n";
}

double PdfDocument::text_width(const std::string& utf8, double size_pt, bool bold) {
  // Helvetica's advance widths (per 1000 em) by class: narrow (i, l, punctuation), capitals and
  // wide lower case (m, w), and the rest; within a few percent for labels.
  double em = 0.0;
  for (const char c : latin1(utf8)) {
    if (std::string_view("il.,:;|!'() ").find(c) != std::string_view::npos) {
      em += 278.0;
    } else if ((c >= 'A' && c <= 'Z') || c == 'm' || c == 'w') {
      em += 700.0;
    } else {
      em += 556.0;
    }
  }
  return em * size_pt / 1000.0 * (bold ? 1.05 : 1.0);
}

void PdfDocument::line(double x0, double y0, double x1, double y1, double width_pt, PdfColor color,
                       bool dashed) {
  page() += rgb(color, true) + num(width_pt) + " w " + (dashed ? "[4 3] 0 d " : "[] 0 d ") +
            num(x0) + " " + num(kPageHeightPt - y0) + " m " + num(x1) + " " +
            num(kPageHeightPt - y1) + " l S\n";
}

void PdfDocument::polyline(const std::vector<double>& xy, double width_pt, PdfColor color) {
  if (xy.size() < 4) return;
  std::string& p = page();
  p += rgb(color, true) + num(width_pt) + " w [] 0 d 1 j " + num(xy[0]) + " " +
       num(kPageHeightPt - xy[1]) + " m\n";
  for (size_t i = 2; i + 1 < xy.size(); i += 2) {
    p += num(xy[i]) + " " + num(kPageHeightPt - xy[i + 1]) + " l\n";
  }
  p += "S\n";
}

void PdfDocument::fill_rect(double x, double y, double w, double h, PdfColor color) {
  page() += rgb(color, false) + num(x) + " " + num(kPageHeightPt - y - h) + " " + num(w) + " " +
            num(h) + " re f\n";
}

std::string PdfDocument::bytes() const {
  // Objects: 1 catalog, 2 page tree, 3 and 4 the fonts, then per page its page and its content.
  std::vector<std::string> objects;
  std::string kids;
  const size_t pages = std::max<size_t>(pages_.size(), 1);
  for (size_t i = 0; i < pages; ++i) kids += std::to_string(5 + 2 * i) + " 0 R ";
  objects.push_back("<< /Type /Catalog /Pages 2 0 R >>");
  objects.push_back("<< /Type /Pages /Kids [" + kids + "] /Count " + std::to_string(pages) + " >>");
  objects.push_back(
      "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica /Encoding /WinAnsiEncoding >>");
  objects.push_back(
      "<< /Type /Font /Subtype /Type1 /BaseFont /Helvetica-Bold /Encoding /WinAnsiEncoding >>");
  for (size_t i = 0; i < pages; ++i) {
    const std::string content = i < pages_.size() ? pages_[i] : std::string();
    objects.push_back("<< /Type /Page /Parent 2 0 R /MediaBox [0 0 " + num(kPageWidthPt) + " " +
                      num(kPageHeightPt) + "] /Resources << /Font << /F1 3 0 R /F2 4 0 R >> >> " +
                      "/Contents " + std::to_string(6 + 2 * i) + " 0 R >>");
    objects.push_back("<< /Length " + std::to_string(content.size()) + " >>\nstream\n" + content +
                      "endstream");
  }
  std::string out = "%PDF-1.4\n%\xE2\xE3\xCF\xD3\n";
  std::vector<size_t> offsets;
  for (size_t i = 0; i < objects.size(); ++i) {
    offsets.push_back(out.size());
    out += std::to_string(i + 1) + " 0 obj\n" + objects[i] + "\nendobj\n";
  }
  const size_t xref = out.size();
  out += "xref\n0 " + std::to_string(objects.size() + 1) + "\n0000000000 65535 f \n";
  for (const size_t o : offsets) {
    char entry[32];
    std::snprintf(entry, sizeof(entry), "%010zu 00000 n \n", o);
    out += entry;
  }
  out += "trailer\n<< /Size " + std::to_string(objects.size() + 1) +
         " /Root 1 0 R >>\nstartxref\n" + std::to_string(xref) + "\n%%EOF\n";
  return out;
}

Status PdfDocument::save(const std::filesystem::path& file) const {
  std::ofstream f(file, std::ios::binary);
  const std::string b = bytes();
  f.write(b.data(), static_cast<std::streamsize>(b.size()));
  f.flush();
  if (!f) return file_diagnostic(file.string(), 0, "", "cannot write the PDF report");
  return {};
}

}  // namespace lap::sim
