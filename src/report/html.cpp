#include "report/html.h"

#include <algorithm>

#include <fmt/format.h>

namespace esdslam {

std::string EscapeHtml(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string Base64Encode(const std::vector<std::uint8_t>& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::size_t left = bytes.size() - i;
    // Three bytes (zero-filled at the end) as one 24-bit group, four 6-bit digits.
    const std::uint32_t group = (std::uint32_t{bytes[i]} << 16) | (left > 1 ? std::uint32_t{bytes[i + 1]} << 8 : 0u) |
                                (left > 2 ? std::uint32_t{bytes[i + 2]} : 0u);
    out += kAlphabet[(group >> 18) & 63];
    out += kAlphabet[(group >> 12) & 63];
    out += left > 1 ? kAlphabet[(group >> 6) & 63] : '=';
    out += left > 2 ? kAlphabet[group & 63] : '=';
  }
  return out;
}

std::string PngImageTag(const std::vector<std::uint8_t>& png, const std::string& alt, int width_px) {
  return fmt::format("<img width=\"{}\" alt=\"{}\" src=\"data:image/png;base64,{}\"/>", width_px, EscapeHtml(alt),
                     Base64Encode(png));
}

std::string HtmlTable(const std::vector<std::string>& header, const std::vector<std::vector<HtmlCell>>& rows,
                      const std::string& css_class) {
  std::string html = css_class.empty() ? "<table>\n" : "<table class=\"" + EscapeHtml(css_class) + "\">\n";
  html += "<thead><tr>";
  for (const std::string& name : header) html += "<th>" + EscapeHtml(name) + "</th>";
  html += "</tr></thead>\n<tbody>\n";
  for (const std::vector<HtmlCell>& row : rows) {
    html += "<tr>";
    for (std::size_t i = 0; i < std::max(row.size(), header.size()); ++i) {
      if (i >= row.size()) {
        html += "<td></td>";
        continue;
      }
      const HtmlCell& cell = row[i];
      html += cell.metric.empty() ? "<td>" : "<td data-metric=\"" + EscapeHtml(cell.metric) + "\">";
      html += EscapeHtml(cell.text) + "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</tbody>\n</table>\n";
}

}  // namespace esdslam
