// Line-by-line checks of ASCII STL and OBJ, before OpenMesh's readers see them: both readers
// parse with streams that skip or shift a record silently when a token is not a number.
#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <istream>
#include <limits>
#include <vector>

#include "osteon/core/error.h"
#include "preflight.h"
#include "text_scan.h"

namespace osteon::geometry::detail {
namespace {

bool isControl(unsigned char c) {
  const bool blank = c == '\t' || c == '\n' || c == '\r' || c == '\v' || c == '\f';
  return (c < 0x20 && !blank) || c == 0x7f;
}

bool equalsNoCase(std::string_view token, std::string_view word) {
  if (token.size() != word.size()) return false;
  for (std::size_t i = 0; i < word.size(); ++i) {
    if (std::tolower(static_cast<unsigned char>(token[i])) != word[i]) return false;
  }
  return true;
}

// True when only NUL bytes and whitespace remain in `rest` and in the stream after it.
bool onlyPaddingFollows(std::string_view rest, std::istream& in) {
  const auto padding = [](unsigned char c) { return c == 0 || std::isspace(c); };
  for (const char ch : rest) {
    const auto c = static_cast<unsigned char>(ch);
    if (!padding(c)) return false;
  }
  for (int c; (c = in.get()) != EOF;) {
    if (!padding(static_cast<unsigned char>(c))) return false;
  }
  return true;
}

bool startsWithNoCase(std::string_view token, std::string_view word) {
  return token.size() >= word.size() && equalsNoCase(token.substr(0, word.size()), word);
}

}  // namespace

void checkVertexLine(const std::string& path, std::size_t lineNo,
                     const std::vector<std::string_view>& tokens, std::size_t first,
                     bool exactlyThree) {
  const std::size_t count = tokens.size() - std::min(first, tokens.size());
  if (count < 3 || (exactlyThree && count != 3)) {
    throw InputError(path + ": line " + std::to_string(lineNo) + ": a vertex needs " +
                     (exactlyThree ? "exactly " : "") + "3 coordinates");
  }
  for (std::size_t k = first; k < first + 3; ++k) {
    const FloatToken kind = classifyFloat(tokens[k]);
    if (kind == FloatToken::NotNumber) {
      throw InputError(path + ": line " + std::to_string(lineNo) + ": vertex coordinate '" +
                       lineExcerpt(tokens[k]) + "' is not a number");
    }
    if (kind == FloatToken::NonFinite) {
      throw InputError(path + ": line " + std::to_string(lineNo) +
                       " has a non-finite coordinate '" + lineExcerpt(tokens[k]) +
                       "' (NaN, Inf or beyond single precision)");
    }
  }
}

bool looksLikeAsciiStl(const std::string& head) {
  std::string_view text(head);
  while (!text.empty() &&
         (text.back() == '\0' || std::isspace(static_cast<unsigned char>(text.back())))) {
    text.remove_suffix(1);
  }
  std::string lower;
  std::size_t controls = 0;
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    lower += static_cast<char>(std::tolower(c));
    if (isControl(c)) ++controls;
  }
  // Binary STL records are full of small and zero bytes; text has few or none.
  return lower.find("facet") != std::string::npos && lower.find("vertex") != std::string::npos &&
         controls * 16 <= text.size();
}

// Throws `error` for a control byte in an ASCII STL line; NUL padding after the last line, as
// some exporters write it, ends the file: the line is cut there and true returned.
template <typename Error>
bool cutAtPadding(std::string_view& text, std::istream& in, const Error& error) {
  for (std::size_t i = 0; i < text.size(); ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (!isControl(c)) continue;
    if (c == 0 && onlyPaddingFollows(text.substr(i), in)) {
      text = text.substr(0, i);
      return true;
    }
    char hex[8];
    std::snprintf(hex, sizeof(hex), "0x%02x", c);
    throw error(std::string("control byte ") + hex + " in an ASCII STL");
  }
  return false;
}

void checkAsciiStl(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  // OpenMesh starts a triangle at any line holding "outer" or "OUTER" and takes the next
  // three lines as its corners, whatever they say; the grammar here keeps it to real loops.
  enum class State { Start, Solid, Outer, Vertex, EndLoop, EndFacet, AfterSolid };
  State state = State::Start;
  int corners = 0;
  std::string line;
  std::vector<std::string_view> tokens;
  std::size_t lineNo = 0;
  const auto error = [&](const std::string& why) {
    return InputError(path + ": line " + std::to_string(lineNo) + ": " + why);
  };
  bool end = false;
  while (!end && std::getline(in, line)) {
    ++lineNo;
    std::string_view text(line);
    if (lineNo == 1 && text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
    end = cutAtPadding(text, in, error);
    splitTokens(text, tokens);
    const auto found = [&](const std::string& expected) {
      return error("expected " + expected + ", found '" + lineExcerpt(text) + "'");
    };
    // A solid's name is free text, but OpenMesh would start a loop at "outer" in it.
    const auto checkName = [&] {
      if (text.find("outer") != std::string_view::npos ||
          text.find("OUTER") != std::string_view::npos) {
        throw error(
            "the solid name contains 'outer', which the STL reader would take for a facet loop");
      }
    };
    if (tokens.empty() && state != State::Vertex) continue;
    switch (state) {
      case State::Start:
      case State::AfterSolid:
        if (!startsWithNoCase(tokens[0], "solid")) {
          // OpenMesh would read on, but a file neither binary nor headed 'solid' is more
          // likely damaged (a lost head, a wrong extension) than a valid export.
          if (state == State::Start) throw error("an ASCII STL must begin with 'solid'");
          throw found("'solid' or the end of the file");
        }
        checkName();
        state = State::Solid;
        break;
      case State::Solid:
        if (startsWithNoCase(tokens[0], "endsolid")) {
          checkName();
          state = State::AfterSolid;
          break;
        }
        // The normal is not used (some exporters write NaN for degenerate facets), but it
        // must be three numbers.
        if (!equalsNoCase(tokens[0], "facet")) throw found("'facet normal nx ny nz' or 'endsolid'");
        if (tokens.size() != 5 || !equalsNoCase(tokens[1], "normal") ||
            classifyFloat(tokens[2]) == FloatToken::NotNumber ||
            classifyFloat(tokens[3]) == FloatToken::NotNumber ||
            classifyFloat(tokens[4]) == FloatToken::NotNumber) {
          throw found("'facet normal nx ny nz'");
        }
        state = State::Outer;
        break;
      case State::Outer:
        // Lower or upper case only: OpenMesh looks for "outer" and "OUTER".
        if (tokens.size() != 2 || !((tokens[0] == "outer" && tokens[1] == "loop") ||
                                    (tokens[0] == "OUTER" && tokens[1] == "LOOP"))) {
          throw found("'outer loop' (lower or upper case)");
        }
        state = State::Vertex;
        corners = 0;
        break;
      case State::Vertex:
        // The three lines after "outer loop" are read as corners, blank or not.
        if (tokens.empty() || !equalsNoCase(tokens[0], "vertex")) throw found("'vertex x y z'");
        checkVertexLine(path, lineNo, tokens, 1, true);
        if (++corners == 3) state = State::EndLoop;
        break;
      case State::EndLoop:
        if (tokens.size() != 1 || !equalsNoCase(tokens[0], "endloop")) throw found("'endloop'");
        state = State::EndFacet;
        break;
      case State::EndFacet:
        if (tokens.size() != 1 || !equalsNoCase(tokens[0], "endfacet")) throw found("'endfacet'");
        state = State::Solid;
        break;
    }
  }
  if (state == State::Start) throw error("an ASCII STL must begin with 'solid'");
  if (state == State::Solid) throw error("the file ends without 'endsolid' (truncated?)");
  if (state != State::AfterSolid) throw error("the file ends inside a facet (truncated?)");
}

void checkObj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string line;
  std::vector<std::string_view> tokens;
  std::size_t lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    splitTokens(line, tokens);
    if (tokens.empty()) continue;
    if (tokens[0] == "v") {
      // x y z, then an optional w or colour that OpenMesh reads if it can.
      checkVertexLine(path, lineNo, tokens, 1, false);
    } else if (tokens[0] == "f") {
      // OpenMesh's OBJ reader asserts on a face without a usable corner.
      if (tokens.size() < 4) {
        throw InputError(path + ": line " + std::to_string(lineNo) + ": a face needs 3 corners");
      }
      // v, v/vt, v//vn or v/vt/vn: the reader parses v as an int and drops a face whose v
      // overflows, so a corner must be an integer of that range.
      for (std::size_t k = 1; k < tokens.size(); ++k) {
        const std::string_view v = tokens[k].substr(0, tokens[k].find('/'));
        const IntegerToken kind = classifyInteger(v, std::numeric_limits<int>::min() + 1,
                                                  std::numeric_limits<int>::max());
        if (kind != IntegerToken::Integer) {
          throw InputError(path + ": line " + std::to_string(lineNo) + ": face corner '" +
                           lineExcerpt(tokens[k]) +
                           (kind == IntegerToken::OutOfRange ? "' is beyond any vertex index"
                                                             : "' is not a vertex index"));
        }
      }
    }
  }
}

}  // namespace osteon::geometry::detail
