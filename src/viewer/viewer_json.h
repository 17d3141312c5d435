#pragma once
// Small pieces of the viewer's wire format: a JSON text builder for flat objects and number
// arrays, base64, and the even decimation every list sent to a browser goes through.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace esdslam {

// Appends JSON to one string. Keys are plain identifiers (no escaping needed); string values
// are escaped. Numbers are written with a fixed number of decimals (NaN/inf as null).
class JsonText {
 public:
  JsonText& BeginObject();
  JsonText& EndObject();
  JsonText& BeginArray(const char* key);  // key nullptr: an array inside an array
  JsonText& EndArray();
  JsonText& Key(const char* key);          // then exactly one value or BeginObject/BeginArray
  JsonText& Number(const char* key, double value, int decimals = 3);
  JsonText& Integer(const char* key, long long value);
  JsonText& Bool(const char* key, bool value);
  JsonText& String(const char* key, const std::string& value);
  JsonText& Raw(const char* key, const std::string& json);  // value that is JSON already
  JsonText& Element(double value, int decimals = 3);  // inside an array
  const std::string& str() const { return text_; }
  std::string Take() { return std::move(text_); }

 private:
  void Separate();
  void WriteKey(const char* key);
  std::string text_;
  bool first_ = true;  // no element written yet in the innermost object or array
};

std::string Base64(const std::vector<std::uint8_t>& bytes);

// Indices 0..n-1 thinned to at most `max` (all of them when n <= max), evenly strided over the
// whole range, always in increasing order and always including index 0 when n > 0 and max > 0.
std::vector<std::size_t> EvenSample(std::size_t n, std::size_t max);

}  // namespace esdslam
