#include "text_scan.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <limits>

namespace osteon::geometry::detail {
namespace {

bool isBlank(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

bool isDigit(char c) {
  return c >= '0' && c <= '9';
}

bool nanOrInfSpelling(std::string_view t) {
  if (!t.empty() && (t[0] == '+' || t[0] == '-')) t.remove_prefix(1);
  std::string lower;
  for (char c : t.substr(0, 9))
    lower += static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return lower == "nan" || lower == "inf" || lower == "infinity" || lower.rfind("nan(", 0) == 0;
}

}  // namespace

FloatToken classifyFloat(std::string_view t) {
  std::size_t i = !t.empty() && (t[0] == '+' || t[0] == '-') ? 1 : 0;
  std::size_t digits = 0;
  for (; i < t.size() && isDigit(t[i]); ++i) ++digits;
  if (i < t.size() && t[i] == '.') {
    for (++i; i < t.size() && isDigit(t[i]); ++i) ++digits;
  }
  if (digits > 0 && i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
    ++i;
    if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
    std::size_t exponentDigits = 0;
    for (; i < t.size() && isDigit(t[i]); ++i) ++exponentDigits;
    if (exponentDigits == 0) digits = 0;
  }
  if (digits == 0 || i != t.size()) {
    return nanOrInfSpelling(t) ? FloatToken::NonFinite : FloatToken::NotNumber;
  }
  // The grammar above is plain decimal, which strtod reads alike in the C locale we run in.
  const std::string text(t);
  const double value = std::strtod(text.c_str(), nullptr);
  return std::isfinite(value) && std::abs(value) <= double(std::numeric_limits<float>::max())
             ? FloatToken::Number
             : FloatToken::NonFinite;
}

IntegerToken classifyInteger(std::string_view t, long long lo, long long hi) {
  if (!t.empty() && t[0] == '+') t.remove_prefix(1);
  const std::size_t sign = !t.empty() && t[0] == '-' ? 1 : 0;
  if (t.size() == sign) return IntegerToken::NotInteger;
  for (std::size_t i = sign; i < t.size(); ++i) {
    if (!isDigit(t[i])) return IntegerToken::NotInteger;
  }
  long long value = 0;
  const auto r = std::from_chars(t.data(), t.data() + t.size(), value);
  if (r.ec != std::errc() || value < lo || value > hi) return IntegerToken::OutOfRange;
  return IntegerToken::Integer;
}

void splitTokens(std::string_view line, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && isBlank(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !isBlank(line[i])) ++i;
    if (i > start) tokens.push_back(line.substr(start, i - start));
  }
}

std::string lineExcerpt(std::string_view line) {
  while (!line.empty() && isBlank(line.front())) line.remove_prefix(1);
  while (!line.empty() && isBlank(line.back())) line.remove_suffix(1);
  std::string out;
  for (const char ch : line.substr(0, 60)) {
    const auto c = static_cast<unsigned char>(ch);
    out += std::isprint(c) ? static_cast<char>(c) : '?';
  }
  return line.size() > 60 ? out + "..." : out;
}

bool TokenReader::next(std::string_view& token) {
  while (at_ == tokens_.size()) {
    if (!std::getline(in_, line_)) return false;
    ++lineNo_;
    splitTokens(line_, tokens_);
    at_ = 0;
  }
  token = tokens_[at_++];
  return true;
}

}  // namespace osteon::geometry::detail
