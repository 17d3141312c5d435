#pragma once
// A strict check of the report's markup for tests: every element opened is closed in order
// (void elements and "/>" excepted), attribute values are quoted, <style> content is skipped.
// Returns "" when well formed, else what is wrong and where.
#include <cctype>
#include <set>
#include <string>
#include <vector>

namespace esdslam::testing {

inline std::string CheckMarkup(const std::string& text) {
  static const std::set<std::string> kVoid = {"meta", "br", "img", "hr", "input", "link"};
  std::vector<std::string> open;
  std::size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    if (text.compare(i, 2, "<!") == 0) {
      i = text.find('>', i);
      if (i == std::string::npos) return "unterminated <!";
      continue;
    }
    const std::size_t end = text.find('>', i);
    if (end == std::string::npos) return "unterminated tag at " + std::to_string(i);
    std::string tag = text.substr(i + 1, end - i - 1);
    if (tag.find('<') != std::string::npos) return "'<' inside a tag at " + std::to_string(i);
    std::size_t quotes = 0;
    for (char c : tag) quotes += c == '"';
    if (quotes % 2 != 0) return "unbalanced quotes in <" + tag + ">";
    const bool closing = !tag.empty() && tag[0] == '/';
    const bool self_closing = !tag.empty() && tag.back() == '/';
    std::size_t name_end = closing ? 1 : 0;
    while (name_end < tag.size() && (std::isalnum(static_cast<unsigned char>(tag[name_end])) != 0)) ++name_end;
    const std::string name = tag.substr(closing ? 1 : 0, name_end - (closing ? 1 : 0));
    if (name.empty()) return "tag without a name at " + std::to_string(i);
    if (closing) {
      if (open.empty() || open.back() != name)
        return "</" + name + "> closes <" + (open.empty() ? std::string("nothing") : open.back()) + "> at " +
               std::to_string(i);
      open.pop_back();
    } else if (!self_closing && !kVoid.count(name)) {
      open.push_back(name);
      if (name == "style") {  // CSS is not markup
        const std::size_t close = text.find("</style>", end);
        if (close == std::string::npos) return "unterminated <style>";
        i = close;
        continue;
      }
    }
    i = end + 1;
  }
  if (!open.empty()) return "<" + open.back() + "> never closed";
  return "";
}

// The text of the first element carrying data-metric="name", or "" when there is none.
inline std::string MetricText(const std::string& html, const std::string& name) {
  const std::string key = "data-metric=\"" + name + "\">";
  const std::size_t at = html.find(key);
  if (at == std::string::npos) return "";
  const std::size_t begin = at + key.size();
  return html.substr(begin, html.find('<', begin) - begin);
}

inline std::size_t CountOf(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++count;
  return count;
}

}  // namespace esdslam::testing
