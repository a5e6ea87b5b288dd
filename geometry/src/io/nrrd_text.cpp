// The NRRD readers' shared text helpers (nrrd_header.h): trimming, words, excerpts for
// messages, and the one number parser every field goes through.
#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>
#include <system_error>

#include "io/nrrd_header.h"

namespace osteon::geometry::nrrd {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// Lowercase, runs of blanks made one space: "Unsigned  Char" -> "unsigned char".
std::string normaliseWords(const std::string& s) {
  std::string out;
  for (const char ch : trim(s)) {
    const auto c = static_cast<unsigned char>(ch);
    if (std::isspace(c)) {
      if (!out.empty() && out.back() != ' ') out += ' ';
    } else {
      out += static_cast<char>(std::tolower(c));
    }
  }
  return out;
}

std::string excerpt(const std::string& s) {
  std::string out = "'";
  for (const char c : s.substr(0, 60)) out += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  return out + (s.size() > 60 ? "...'" : "'");
}

std::vector<std::string> words(const std::string& s) {
  std::vector<std::string> out;
  std::size_t pos = 0;
  while ((pos = s.find_first_not_of(" \t\r", pos)) != std::string::npos) {
    const std::size_t end = std::min(s.find_first_of(" \t\r", pos), s.size());
    out.push_back(s.substr(pos, end - pos));
    pos = end;
  }
  return out;
}

bool parseInteger(const std::string& text, long long& v) {
  const std::string t = trim(text);
  const char* first = t.data();
  const char* last = first + t.size();
  if (first != last && *first == '+') ++first;
  const auto r = std::from_chars(first, last, v);
  return first != last && r.ec == std::errc() && r.ptr == last;
}

bool parseNumber(const std::string& token, double& v) {
  const char* first = token.data();
  const char* last = first + token.size();
  if (first != last && *first == '+') ++first;
  const auto r = std::from_chars(first, last, v);
  return r.ec == std::errc() && r.ptr == last && first != last && std::isfinite(v);
}

bool parseNumbers(std::string text, std::vector<double>& values) {
  for (char& c : text) {
    if (c == '(' || c == ')' || c == ',') c = ' ';
  }
  values.clear();
  std::size_t pos = 0;
  while ((pos = text.find_first_not_of(" \t\r\v\f", pos)) != std::string::npos) {
    const std::size_t end = std::min(text.find_first_of(" \t\r\v\f", pos), text.size());
    double v;
    if (!parseNumber(text.substr(pos, end - pos), v)) return false;
    values.push_back(v);
    pos = end;
  }
  return true;
}

}  // namespace osteon::geometry::nrrd
