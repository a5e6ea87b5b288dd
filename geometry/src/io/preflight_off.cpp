// OFF files checked before OpenMesh reads them (preflight.h): the counts line, each vertex and
// face record as the reader will take it.
#include <cctype>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "osteon/core/error.h"
#include "preflight.h"
#include "text_scan.h"

namespace osteon::geometry::detail {

namespace {

bool isInteger(const std::string& token) {
  std::size_t i = token[0] == '-' || token[0] == '+' ? 1 : 0;
  if (i >= token.size()) return false;
  for (; i < token.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(token[i]))) return false;
  }
  return true;
}

std::vector<std::string> tokensOf(const std::string& line) {
  std::istringstream words(line);
  std::vector<std::string> tokens;
  for (std::string t; words >> t;) tokens.push_back(t);
  return tokens;
}

// A face record: its corner count (3 to kMaxCorners) matches the indices on its line, each an
// unsigned vertex index, and nothing follows them.
void checkFaceLine(const std::string& path, std::size_t lineNo,
                   const std::vector<std::string>& tokens) {
  if (!isInteger(tokens[0]) || tokens[0][0] == '-' || tokens[0].size() > 6 ||
      std::stoll(tokens[0]) > kMaxCorners || std::stoll(tokens[0]) + 1 > (long long)tokens.size()) {
    throw InputError(path + ": line " + std::to_string(lineNo) + ": face corner count '" +
                     tokens[0] + "' does not match the indices on the line");
  }
  if (std::stoll(tokens[0]) < 3) {  // fewer sends OpenMesh's reader astray (it allocated 2 GB)
    throw InputError(path + ": line " + std::to_string(lineNo) + ": a face needs 3 corners, not " +
                     tokens[0]);
  }
  // OpenMesh reads faces as one stream of numbers, not by line: anything after the indices (a
  // face colour) would be taken for the next face's corner count.
  if ((long long)tokens.size() > std::stoll(tokens[0]) + 1) {
    throw InputError(path + ": line " + std::to_string(lineNo) + ": " +
                     std::to_string((long long)tokens.size() - std::stoll(tokens[0]) - 1) +
                     " value(s) after the face's " + tokens[0] +
                     " corners (face colours are not supported)");
  }
  // The reader extracts unsigned indices; anything else fails its stream for all that follows.
  for (long long k = 1; k <= std::stoll(tokens[0]); ++k) {
    if (classifyInteger(tokens[std::size_t(k)], 0, std::numeric_limits<std::uint32_t>::max()) !=
        IntegerToken::Integer) {
      throw InputError(path + ": line " + std::to_string(lineNo) + ": face index '" +
                       lineExcerpt(tokens[std::size_t(k)]) + "' is not a vertex index");
    }
  }
}

}  // namespace

bool preflightOff(const std::string& path, std::uint64_t fileBytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open for reading");
  std::string line;
  std::getline(in, line);
  std::size_t lineNo = 1;
  const std::size_t off = line.find("OFF");
  if (off == std::string::npos) {
    throw InputError(path + ": not an OFF file (first line lacks the OFF keyword)");
  }
  if (line.find("BINARY") != std::string::npos) {
    throw InputError(path + ": binary OFF is not supported; save it as ASCII OFF or PLY");
  }
  // The reader takes the counts from the first numbers after the OFF line: counts on the OFF
  // line itself are skipped and a comment before them fails it, so both are refused here.
  std::vector<std::string> counts = tokensOf(line.substr(off + 3));
  if (!counts.empty() && counts[0][0] != '#') {
    throw InputError(path + ": line 1: OFF counts must be on the line after 'OFF', not on it");
  }
  counts.clear();
  while (counts.empty()) {
    if (!std::getline(in, line)) throw InputError(path + ": OFF header has no element counts");
    ++lineNo;
    counts = tokensOf(line);
  }
  if (counts[0][0] == '#') {
    throw InputError(path + ": line " + std::to_string(lineNo) +
                     ": a comment before the OFF counts (the reader needs the counts first)");
  }
  // OpenMesh reads exactly three counts (vertices, faces, edges) as numbers of a stream: with
  // two it takes the first coordinate for the third, with four the rest of the line for a vertex.
  if (counts.size() != 3) {
    throw InputError(path + ": line " + std::to_string(lineNo) +
                     ": OFF counts must be 3 numbers (vertices faces edges), not '" + line + "'");
  }
  if (!isInteger(counts[0]) || !isInteger(counts[1]) || counts[0][0] == '-' ||
      counts[1][0] == '-' || counts[0].size() > 12 || counts[1].size() > 12) {
    throw InputError(path + ": OFF header counts are missing or negative: '" + line + "'");
  }
  const long long vertices = std::stoll(counts[0]);
  const long long faces = std::stoll(counts[1]);
  // Smallest possible records: "0 0 0\n" and "3 0 1 2\n".
  if (6.0L * vertices + 8.0L * faces > static_cast<long double>(fileBytes)) {
    throw InputError(path + ": OFF header promises " + std::to_string(vertices) + " vertices and " +
                     std::to_string(faces) + " faces, more than its " + std::to_string(fileBytes) +
                     " bytes can hold (truncated file?)");
  }
  // One record per line: vertices with finite coordinates, faces whose corner count the line
  // actually lists (the parser trusts that count and would loop or allocate on it).
  long long seenVertices = 0, seenFaces = 0;
  while ((seenVertices < vertices || seenFaces < faces) && std::getline(in, line)) {
    ++lineNo;
    const std::vector<std::string> tokens = tokensOf(line);
    if (tokens.empty()) continue;
    if (tokens[0][0] == '#') {  // OpenMesh reads it as a vertex or a face, and goes astray
      throw InputError(
          path + ": line " + std::to_string(lineNo) +
          ": a comment among the OFF vertices and faces (the reader does not skip it)");
    }
    if (seenVertices < vertices) {
      // x y z first; normals, colours or texture coordinates may follow.
      const std::vector<std::string_view> views(tokens.begin(), tokens.end());
      checkVertexLine(path, lineNo, views, 0, false);
      ++seenVertices;
      continue;
    }
    checkFaceLine(path, lineNo, tokens);
    ++seenFaces;
  }
  // OpenMesh would repeat its last face for each one missing.
  if (seenVertices < vertices || seenFaces < faces) {
    throw InputError(path + ": OFF header promises " + std::to_string(vertices) + " vertices and " +
                     std::to_string(faces) + " faces, the file ends after " +
                     std::to_string(seenVertices) + " and " + std::to_string(seenFaces) +
                     " (truncated file?)");
  }
  return false;
}

}  // namespace osteon::geometry::detail
