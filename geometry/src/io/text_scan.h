// Token-level checks for the text mesh formats: numbers as the C++ stream extraction in
// OpenMesh's readers accepts them, and whitespace-separated tokens with line numbers.
#pragma once

#include <cstddef>
#include <istream>
#include <string>
#include <string_view>
#include <vector>

namespace osteon::geometry::detail {

enum class FloatToken { Number, NotNumber, NonFinite };

// [sign] digits [. digits] [e [sign] digits]: Number when finite and within single precision
// (OpenMesh stores floats); NonFinite for nan/inf spellings and values beyond float.
FloatToken classifyFloat(std::string_view token);

enum class IntegerToken { Integer, NotInteger, OutOfRange };

// [sign] digits, within [lo, hi].
IntegerToken classifyInteger(std::string_view token, long long lo, long long hi);

// Splits on blanks (space, \t, \r, \v, \f); the views point into `line`.
void splitTokens(std::string_view line, std::vector<std::string_view>& tokens);

// The line as a short printable excerpt for messages.
std::string lineExcerpt(std::string_view line);

// Tokens of a stream, line by line, remembering the line number; memory is one line.
class TokenReader {
 public:
  // lineNo: the number of the line before the first one read.
  TokenReader(std::istream& in, std::size_t lineNo) : in_(in), lineNo_(lineNo) {}

  // The next token, reading on to further lines; false at the end of the stream.
  bool next(std::string_view& token);
  // True when the current line has tokens not yet read.
  bool moreOnLine() const { return at_ < tokens_.size(); }
  std::size_t lineNo() const { return lineNo_; }

 private:
  std::istream& in_;
  std::size_t lineNo_;
  std::string line_;
  std::vector<std::string_view> tokens_;
  std::size_t at_ = 0;
};

}  // namespace osteon::geometry::detail
