#include "viewer/viewer_json.h"

#include <cmath>

#include <fmt/format.h>

namespace esdslam {

void JsonText::Separate() {
  if (!first_) text_ += ',';
  first_ = false;
}

void JsonText::WriteKey(const char* key) {
  Separate();
  if (key == nullptr) return;
  text_ += '"';
  text_ += key;
  text_ += "\":";
}

JsonText& JsonText::BeginObject() {
  if (!text_.empty() && text_.back() != ':') Separate();
  text_ += '{';
  first_ = true;
  return *this;
}

JsonText& JsonText::EndObject() {
  text_ += '}';
  first_ = false;
  return *this;
}

JsonText& JsonText::BeginArray(const char* key) {
  WriteKey(key);
  text_ += '[';
  first_ = true;
  return *this;
}

JsonText& JsonText::EndArray() {
  text_ += ']';
  first_ = false;
  return *this;
}

JsonText& JsonText::Key(const char* key) {
  WriteKey(key);
  first_ = true;  // the value that follows needs no comma
  return *this;
}

JsonText& JsonText::Number(const char* key, double value, int decimals) {
  WriteKey(key);
  if (!std::isfinite(value)) {
    text_ += "null";
  } else {
    text_ += fmt::format("{:.{}f}", value, decimals);
  }
  return *this;
}

JsonText& JsonText::Integer(const char* key, long long value) {
  WriteKey(key);
  text_ += std::to_string(value);
  return *this;
}

JsonText& JsonText::Bool(const char* key, bool value) {
  WriteKey(key);
  text_ += value ? "true" : "false";
  return *this;
}

JsonText& JsonText::String(const char* key, const std::string& value) {
  WriteKey(key);
  text_ += '"';
  for (const char c : value) {
    if (c == '"' || c == '\\') {
      text_ += '\\';
      text_ += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      text_ += fmt::format("\\u{:04x}", static_cast<int>(c));
    } else {
      text_ += c;
    }
  }
  text_ += '"';
  return *this;
}

JsonText& JsonText::Raw(const char* key, const std::string& json) {
  WriteKey(key);
  text_ += json;
  return *this;
}

JsonText& JsonText::Element(double value, int decimals) { return Number(nullptr, value, decimals); }

std::string Base64(const std::vector<std::uint8_t>& bytes) {
  static const char kAlphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < bytes.size(); i += 3) {
    const unsigned v = (bytes[i] << 16) | (bytes[i + 1] << 8) | bytes[i + 2];
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += kAlphabet[(v >> 6) & 63];
    out += kAlphabet[v & 63];
  }
  const std::size_t rest = bytes.size() - i;
  if (rest > 0) {
    const unsigned v = (bytes[i] << 16) | (rest == 2 ? bytes[i + 1] << 8 : 0);
    out += kAlphabet[(v >> 18) & 63];
    out += kAlphabet[(v >> 12) & 63];
    out += rest == 2 ? kAlphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

std::vector<std::size_t> EvenSample(std::size_t n, std::size_t max) {
  std::vector<std::size_t> indices;
  if (n == 0 || max == 0) return indices;
  const std::size_t count = n < max ? n : max;
  indices.reserve(count);
  // Index k of count: floor(k * n / count), strictly increasing since n >= count.
  for (std::size_t k = 0; k < count; ++k) indices.push_back(k * n / count);
  return indices;
}

}  // namespace esdslam
