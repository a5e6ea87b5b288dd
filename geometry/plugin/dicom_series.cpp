#include "dicom_series.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gdcmCommand.h>
#include <gdcmProgressEvent.h>
#include <gdcmScanner.h>
#include <gdcmTag.h>
#include <gdcmTransferSyntax.h>
#include <map>
#include <sstream>

#include "osteon/core/error.h"

namespace osteon::dicom {

namespace fs = std::filesystem;

namespace {

const gdcm::Tag kSopClass(0x0008, 0x0016), kDescription(0x0008, 0x103e), kSeriesUid(0x0020, 0x000e),
    kPosition(0x0020, 0x0032), kOrientation(0x0020, 0x0037), kFrames(0x0028, 0x0008),
    kPixelSpacing(0x0028, 0x0030), kIntercept(0x0028, 0x1052), kSlope(0x0028, 0x1053);

std::string trimmed(const char* text) {
  std::string s = text ? text : "";
  while (!s.empty() && (s.back() == ' ' || s.back() == '\0')) s.pop_back();
  while (!s.empty() && s.front() == ' ') s.erase(s.begin());
  return s;
}

// A DICOM multi-valued decimal string "a\b\c" into exactly `count` numbers; false otherwise.
bool decimals(const char* text, double* out, int count) {
  const std::string s = trimmed(text);
  if (s.empty()) return false;
  std::stringstream in(s);
  std::string item;
  int n = 0;
  while (std::getline(in, item, '\\')) {
    if (n == count) return false;
    char* end = nullptr;
    const double v = std::strtod(item.c_str(), &end);
    if (end == item.c_str() || !std::isfinite(v)) return false;
    out[n++] = v;
  }
  return n == count;
}

std::vector<std::string> folderFiles(const std::string& folder) {
  std::vector<std::string> files;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    std::error_code typeError;
    if (it->is_regular_file(typeError) && it->path().filename() != "DICOMDIR")
      files.push_back(it->path().string());
  }
  if (ec) fail("cannot list the folder (" + ec.message() + ")");
  std::sort(files.begin(), files.end());
  return files;
}

Slice sliceOf(const gdcm::Scanner& scanner, const std::string& file) {
  const char* f = file.c_str();
  Slice s;
  s.file = file;
  const char* frames = scanner.GetValue(f, kFrames);
  if (frames) s.frames = std::max(1, std::atoi(trimmed(frames).c_str()));
  double v = 0.0;
  if (decimals(scanner.GetValue(f, kSlope), &v, 1)) s.slope = v;
  if (decimals(scanner.GetValue(f, kIntercept), &v, 1)) s.intercept = v;
  s.placed = decimals(scanner.GetValue(f, kPosition), s.position, 3) &&
             decimals(scanner.GetValue(f, kOrientation), s.orientation, 6) &&
             decimals(scanner.GetValue(f, kPixelSpacing), s.pixelSpacing, 2);
  return s;
}

// The file meta group (0002,xxxx), explicit VR little endian after "DICM", checked before
// GDCM reads it: Debian's GDCM is built with assertions, and an unknown VR there aborts the
// process instead of failing the read.
// Returns the transfer syntax UID ("" when the file has no DICM preamble or names none).
std::string refuseMalformedMeta(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::string head(65536, '\0');
  in.read(&head[0], std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  if (head.size() < 132 || head.compare(128, 4, "DICM") != 0) return {};
  std::string syntax;
  static const std::string kLongVrs = "OB OD OF OL OV OW SQ UC UN UR UT SV UV";
  const auto byte = [&head](std::size_t i) {
    return std::size_t(static_cast<unsigned char>(head[i]));
  };
  const std::string name = fs::path(file).filename().string();
  std::size_t at = 132;
  for (; at + 8 <= head.size() && byte(at) == 2 && byte(at + 1) == 0;) {
    const std::string vr = head.substr(at + 4, 2);
    if (!isVr(vr))
      fail(name + ": a corrupt file meta header (element at byte " + std::to_string(at) +
           " has no valid VR)");
    std::size_t length = 0, next = 0;
    if (kLongVrs.find(vr) != std::string::npos) {
      if (at + 12 > head.size()) break;
      length = byte(at + 8) | byte(at + 9) << 8 | byte(at + 10) << 16 | byte(at + 11) << 24;
      next = at + 12;
    } else {
      length = byte(at + 6) | byte(at + 7) << 8;
      next = at + 8;
    }
    if (length == 0xffffffff || length > head.size() - next)
      fail(name + ": a corrupt file meta header (an element's length runs past it)");
    if (byte(at + 2) == 0x10 && byte(at + 3) == 0) {
      syntax = head.substr(next, length);
      while (!syntax.empty() && (syntax.back() == '\0' || syntax.back() == ' ')) syntax.pop_back();
    }
    at = next + length;
  }
  // A few bytes after the last element, too few for another: GDCM asserts reading them.
  if (at < head.size() && head.size() < 65536 && at + 8 > head.size())
    fail(name + ": truncated: " + std::to_string(head.size() - at) +
         " stray bytes after its file meta header");
  return syntax;
}

// A file GDCM passed over: not DICOM (no "DICM" after the 128-byte preamble), or DICOM that GDCM
// cannot parse, which is refused, naming its transfer syntax when GDCM does not know it.
void refuseUnparsed(const std::string& file) {
  std::ifstream in(file, std::ios::binary);
  std::string head(4096, '\0');
  in.read(&head[0], std::streamsize(head.size()));
  head.resize(std::size_t(in.gcount()));
  if (head.size() < 132 || head.compare(128, 4, "DICM") != 0) return;
  const std::string name = fs::path(file).filename().string();
  // (0002,0010) UI, explicit VR little endian as the file meta always is.
  const std::size_t at = head.find(std::string("\x02\x00\x10\x00UI", 6), 132);
  if (at != std::string::npos && at + 8 <= head.size()) {
    const std::size_t length = std::size_t(static_cast<unsigned char>(head[at + 6])) |
                               std::size_t(static_cast<unsigned char>(head[at + 7])) << 8;
    std::string uid = head.substr(at + 8, std::min(length, std::size_t(64)));
    while (!uid.empty() && (uid.back() == '\0' || uid.back() == ' ')) uid.pop_back();
    if (gdcm::TransferSyntax::GetTSType(uid.c_str()) == gdcm::TransferSyntax::TS_END)
      fail(name + ": transfer syntax " + uid + " is not one GDCM knows");
  }
  fail(name + ": a DICOM file GDCM cannot parse (a corrupt header?)");
}

// The scanner's progress, an event a file, as the caller's heartbeat: a folder of thousands of
// slices on a slow disk is one long Scan call.
class Beat : public gdcm::Command {
 public:
  explicit Beat(const std::function<void()>& tick) : tick_(tick) {}
  void Execute(gdcm::Subject*, const gdcm::Event& event) override { beat(event); }
  void Execute(const gdcm::Subject*, const gdcm::Event& event) override { beat(event); }

 private:
  void beat(const gdcm::Event& event) {
    if (gdcm::ProgressEvent().CheckEvent(&event)) tick_();
  }
  const std::function<void()>& tick_;
};

}  // namespace

std::vector<Series> scanSeries(const std::string& path, const std::function<void()>& tick) {
  std::error_code ec;
  const bool folder = fs::is_directory(path, ec);
  const std::vector<std::string> files = folder ? folderFiles(path) : std::vector{path};
  for (const std::string& file : files) {
    refuseLyingLengths(file, refuseMalformedMeta(file));
    tick();
  }
  const gdcm::SmartPointer<Beat> beat = new Beat(tick);
  gdcm::Scanner scanner;
  scanner.AddObserver(gdcm::ProgressEvent(), beat);
  for (const gdcm::Tag& t : {kSopClass, kDescription, kSeriesUid, kPosition, kOrientation, kFrames,
                             kPixelSpacing, kIntercept, kSlope})
    scanner.AddTag(t);
  if (!scanner.Scan(files)) fail("GDCM could not scan the files");
  std::string onlyUid;
  if (!folder) {
    if (!scanner.IsKey(path.c_str())) {
      refuseUnparsed(path);
      fail("not a DICOM file");
    }
    const Slice s = sliceOf(scanner, path);
    onlyUid = trimmed(scanner.GetValue(path.c_str(), kSeriesUid));
    if (s.frames == 1) {
      // One slice of a series: the series is read from the files beside it.
      std::vector<Series> beside =
          scanSeries(fs::path(path).parent_path().empty() ? std::string(".")
                                                          : fs::path(path).parent_path().string(),
                     tick);
      for (Series& series : beside) {
        if (series.uid == onlyUid) return {std::move(series)};
      }
      fail("its series " + onlyUid + " is not found in its folder");
    }
  }
  std::map<std::string, Series> byUid;
  for (const std::string& file : files) {
    if (!scanner.IsKey(file.c_str())) {
      refuseUnparsed(file);
      continue;  // not DICOM: other files of the folder
    }
    const std::string uid = trimmed(scanner.GetValue(file.c_str(), kSeriesUid));
    Series& series = byUid[uid];
    if (series.slices.empty()) {
      series.uid = uid;
      series.description = trimmed(scanner.GetValue(file.c_str(), kDescription));
      series.sopClass = trimmed(scanner.GetValue(file.c_str(), kSopClass));
    }
    series.slices.push_back(sliceOf(scanner, file));
  }
  if (byUid.empty()) fail(folder ? "no DICOM file in the folder" : "not a DICOM file");
  std::vector<Series> all;
  for (auto& [uid, series] : byUid) all.push_back(std::move(series));
  return all;
}

std::string describeSeries(const std::vector<Series>& all) {
  std::string text;
  for (const Series& s : all) {
    if (!text.empty()) text += ", ";
    text += (s.uid.empty() ? std::string("(no UID)") : s.uid) + " (" +
            std::to_string(s.slices.size()) + (s.slices.size() == 1 ? " slice" : " slices") +
            (s.description.empty() ? "" : ", " + s.description) + ")";
  }
  return text;
}

const Series& pickSeries(const std::vector<Series>& all, const std::string& uid) {
  if (!uid.empty()) {
    for (const Series& s : all) {
      if (s.uid == uid) return s;
    }
    fail(optionRef("volume.series") + " " + uid +
         " is not among its series: " + describeSeries(all));
  }
  const Series* best = &all.front();
  bool tie = false;
  for (const Series& s : all) {
    if (&s == best) continue;
    if (s.slices.size() > best->slices.size()) {
      best = &s;
      tie = false;
    } else if (s.slices.size() == best->slices.size()) {
      tie = true;
    }
  }
  if (tie) {
    fail("several series of " + std::to_string(best->slices.size()) +
         " slices each (mixed series): give " + optionRef("volume.series") + " UID, one of " +
         describeSeries(all));
  }
  return *best;
}

}  // namespace osteon::dicom
