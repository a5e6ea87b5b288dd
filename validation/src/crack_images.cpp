#include "osteon/validation/crack_images.h"

#include <filesystem>

#include "osteon/geometry/io/output_dir.h"
#include "osteon/geometry/io/output_file.h"

namespace osteon::validation {

std::vector<std::string> crackImageNames() {
  std::vector<std::string> names;
  for (const char* view : {"+x", "-x", "+y", "-y", "+z", "-z"})
    names.push_back(std::string("cracks_") + view + ".png");
  return names;
}

void CrackImageFolder::refuseOverwriting(const std::string& folder,
                                         const std::vector<std::string>& inputs) {
  std::vector<std::string> views;
  for (const std::string& name : crackImageNames()) views.push_back(folder + "/" + name);
  geometry::refuseOverwritingInputs(views, inputs);
}

CrackImageFolder::CrackImageFolder(const std::string& folder, const std::string& option)
    : folder_(folder),
      dir_(std::make_unique<geometry::OutputDir>(folder, crackImageNames(), option)) {}

CrackImageFolder::~CrackImageFolder() = default;

CrackMetric CrackImageFolder::write(const geometry::TriangleMesh& surface, int pixels,
                                    std::vector<std::string>& paths) {
  CrackMetricOptions options;
  options.pixels = pixels;
  options.keepImages = true;
  const CrackMetric metric = measureCracks(surface, options);
  paths = writeCrackImages(metric, folder_);
  dir_->commit();
  return metric;
}

std::vector<std::string> writeCrackImagesOf(const geometry::TriangleMesh& surface, int pixels,
                                            const std::string& folder) {
  CrackMetricOptions options;
  options.pixels = pixels;
  options.keepImages = true;
  std::filesystem::create_directories(folder);
  return writeCrackImages(measureCracks(surface, options), folder);
}

}  // namespace osteon::validation
