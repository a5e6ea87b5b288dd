// A series' slices decoded into one volume (dicom_image.h), slices in parallel: each is an
// independent file, read by its own gdcm::ImageReader (GDCM's readers and codecs keep their
// state per instance; its dictionaries are only read).
#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <gdcmImage.h>
#include <gdcmImageReader.h>
#include <mutex>
#include <system_error>
#include <thread>
#include <vector>

#include "dicom_image.h"

namespace osteon::dicom {

namespace {

std::string name(const std::string& file) {
  return std::filesystem::path(file).filename().string();
}

// What every slice is held to, and where its values go: the first slice's size and type.
struct Layout {
  unsigned cols = 0, rows = 0;
  Pixels pixels;
  bool ownRescale = false;  // values converted to float HU slice by slice
  char* data = nullptr;
  std::size_t perSlice() const { return std::size_t(cols) * rows; }
};

// Slice k decoded into its place (`scratch`: the stored values of a rescaled slice).
void decodeSlice(const Slice& s, const gdcm::Image& image, std::size_t k, const Layout& at,
                 std::vector<char>& scratch) {
  if (image.GetDimension(0) != at.cols || image.GetDimension(1) != at.rows) {
    fail(name(s.file) + ": " + std::to_string(image.GetDimension(0)) + " x " +
         std::to_string(image.GetDimension(1)) + " pixels, the first slice " +
         std::to_string(at.cols) + " x " + std::to_string(at.rows));
  }
  const Pixels q = pixelsOf(image, s.file);
  if (std::strcmp(q.type, at.pixels.type) != 0)
    fail(name(s.file) + ": pixels of " + q.type + ", the first slice's " + at.pixels.type);
  const std::size_t perSlice = at.perSlice(), bytes = perSlice * at.pixels.bytes;
  char* to = at.ownRescale ? scratch.data() : at.data + k * bytes;
  decode(image, s.file, to, bytes);
  const auto visit = [&](auto zero) {
    using T = decltype(zero);
    keepStoredBits<T>(to, perSlice, q);
    if (!at.ownRescale) return;
    for (std::size_t i = 0; i < perSlice; ++i) {
      T stored;
      std::memcpy(&stored, to + i * sizeof(T), sizeof(T));
      const float hu = float(double(stored) * s.slope + s.intercept);
      std::memcpy(at.data + (k * perSlice + i) * sizeof(float), &hu, sizeof(float));
    }
  };
  const std::string t = at.pixels.type;
  if (t == "uint8") visit(std::uint8_t());
  if (t == "int8") visit(std::int8_t());
  if (t == "uint16") visit(std::uint16_t());
  if (t == "int16") visit(std::int16_t());
  if (t == "uint32") visit(std::uint32_t());
  if (t == "int32") visit(std::int32_t());
}

// Slices taken in order by a few threads; the refusal reported is the first slice's in stack
// order (slices after it are not started), as a read slice after slice would report it.
class SliceWork {
 public:
  SliceWork(const Stack& stack, const gdcm::Image& first, const Layout& at, const Output& out)
      : stack_(stack), first_(first), at_(at), out_(out), failedAt_(stack.slices.size()) {}

  void run() {
    const std::size_t n = stack_.slices.size();
    const unsigned cores = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::thread> threads;
    for (std::size_t t = 1; t < std::min<std::size_t>(cores, n); ++t) {
      try {
        threads.emplace_back([this] { work(); });
      } catch (const std::system_error&) {
        break;  // no thread to spare: fewer do the work
      }
    }
    work();
    for (std::thread& t : threads) t.join();
    if (failedAt_ < n) throw failure_;
  }

 private:
  void work() {
    std::vector<char> scratch(at_.ownRescale ? at_.perSlice() * at_.pixels.bytes : 0);
    for (;;) {
      const std::size_t k = next_.fetch_add(1);
      if (k >= stack_.slices.size() || k > failedAt_.load()) return;
      try {
        const Slice& s = stack_.slices[k];
        if (k == 0) {
          decodeSlice(s, first_, k, at_, scratch);
        } else {
          gdcm::ImageReader reader;
          readImage(reader, s.file);
          decodeSlice(s, reader.GetImage(), k, at_, scratch);
        }
        out_.tick();
      } catch (const Failure& f) {
        refuse(k, f);
      } catch (const std::exception& e) {
        refuse(k, Failure{2, std::string("GDCM failed: ") + e.what()});
      }
    }
  }

  void refuse(std::size_t k, const Failure& f) {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (k >= failedAt_.load()) return;
    failedAt_ = k;
    failure_ = f;
  }

  const Stack& stack_;
  const gdcm::Image& first_;
  const Layout& at_;
  const Output& out_;
  std::atomic<std::size_t> next_{0};
  std::atomic<std::size_t> failedAt_;
  std::mutex mutex_;
  Failure failure_;
};

}  // namespace

void readSeries(const Stack& stack, const Output& out) {
  gdcm::ImageReader first;
  readImage(first, stack.slices.front().file);
  const gdcm::Image& image0 = first.GetImage();
  Layout at;
  at.pixels = pixelsOf(image0, stack.slices.front().file);
  at.cols = image0.GetDimension(0);
  at.rows = image0.GetDimension(1);
  for (const Slice& s : stack.slices) {
    at.ownRescale = at.ownRescale || s.slope != stack.slices.front().slope ||
                    s.intercept != stack.slices.front().intercept;
  }
  const std::size_t n = stack.slices.size();
  osteon_dicom_volume& v = *out.volume;
  v.sizes[0] = int(at.cols);
  v.sizes[1] = int(at.rows);
  v.sizes[2] = int(n);
  std::strcpy(v.type, at.ownRescale ? "float" : at.pixels.type);
  v.slope = at.ownRescale ? 1.0 : stack.slices.front().slope;
  v.intercept = at.ownRescale ? 0.0 : stack.slices.front().intercept;
  v.slices_rescaled = at.ownRescale ? 1 : 0;
  refuseImplausible(first.GetFile(), stack.slices.front().file, at.perSlice() * at.pixels.bytes);
  at.data = out.allocate(at.perSlice() * n * (at.ownRescale ? sizeof(float) : at.pixels.bytes));
  SliceWork(stack, image0, at, out).run();
}

}  // namespace osteon::dicom
