#pragma once
// Small pieces of a self-contained HTML page (report/run_report.h): text escaping, base64 for
// embedded images (data: URLs), and tables. Everything returns text; nothing here reads files.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace esdslam {

// Text safe inside an element or a double-quoted attribute: & < > " ' escaped.
std::string EscapeHtml(const std::string& text);

// Standard base64 (RFC 4648, '+' '/', '=' padding), no line breaks.
std::string Base64Encode(const std::vector<std::uint8_t>& bytes);

// <img> whose source is the PNG bytes as a data: URL. alt is escaped.
std::string PngImageTag(const std::vector<std::uint8_t>& png, const std::string& alt, int width_px);

// One table cell: its text (escaped) and, when not empty, a data-metric attribute naming the
// value, so that a test (or a script) finds the number by name in the page.
struct HtmlCell {
  HtmlCell(std::string cell_text, std::string metric_name = {})  // implicit: a plain cell from text
      : text(std::move(cell_text)), metric(std::move(metric_name)) {}
  std::string text;
  std::string metric;
};

// <table> with a header row and body rows; every cell escaped. Rows may be shorter than the
// header (missing cells are left empty).
std::string HtmlTable(const std::vector<std::string>& header, const std::vector<std::vector<HtmlCell>>& rows,
                      const std::string& css_class = "");

}  // namespace esdslam
