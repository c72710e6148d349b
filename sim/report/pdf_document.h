#pragma once
/// \file
/// A small PDF 1.4 writer for the session reports: pages of A4, text in the standard Helvetica
/// faces (no font embedded: every PDF reader has them), lines, polylines and filled rectangles
/// in RGB, solid or dashed. Coordinates in points (1/72 in) from the page's top-left corner, y
/// down, as a layout thinks; the writer flips them to PDF's bottom-up space. Written from the
/// PDF 1.4 reference (Adobe, 2001): §3.4 file structure, §4 graphics, §5 text.

#include <filesystem>
#include <string>
#include <vector>

#include "core/result.h"

namespace lap::sim {

struct PdfColor {
  double r = 0.0, g = 0.0, b = 0.0;  ///< 0 to 1
};

class PdfDocument {
 public:
  static constexpr double kPageWidthPt = 595.0;  ///< A4
  static constexpr double kPageHeightPt = 842.0;

  /// Starts a new page; drawing goes to the newest page (one is started by the first drawing).
  void new_page();
  [[nodiscard]] int page_count() const { return static_cast<int>(pages_.size()); }

  /// Text with its baseline's left end at (x, y); Latin-1 where it can be, '?' for the rest.
  void text(double x, double y, const std::string& utf8, double size_pt, bool bold = false,
            PdfColor color = {});
  /// The text's width in points (Helvetica's metrics, approximated per character class).
  [[nodiscard]] static double text_width(const std::string& utf8, double size_pt, bool bold);

  void line(double x0, double y0, double x1, double y1, double width_pt, PdfColor color,
            bool dashed = false);
  /// A polyline through the points (x, y interleaved); nothing for fewer than two points.
  void polyline(const std::vector<double>& xy, double width_pt, PdfColor color);
  void fill_rect(double x, double y, double w, double h, PdfColor color);

  /// The whole file's bytes.
  [[nodiscard]] std::string bytes() const;
  /// Writes the file; the diagnostic names it on failure.
  [[nodiscard]] Status save(const std::filesystem::path& file) const;

 private:
  std::string& page();
  std::vector<std::string> pages_;  ///< each page's content stream
};

}  // namespace lap::sim
