// The crack metric's six views as PNG files (crack_metric.h): a surface measured and its views
// written into one folder as one set, so a front end only names the folder.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "osteon/geometry/io/mesh.h"
#include "osteon/validation/crack_metric.h"

namespace osteon::geometry {
class OutputDir;
}

namespace osteon::validation {

// The files a folder of crack views holds: cracks_+x.png, cracks_-x.png, ... cracks_-z.png.
std::vector<std::string> crackImageNames();

// A folder of the six crack views of one surface, put in place together (output_dir.h): the
// previous views stay until write() completes.
class CrackImageFolder {
 public:
  // Refuses (InputError) a view in `folder` that would overwrite one of `inputs`: a front end
  // calls it before any work.
  static void refuseOverwriting(const std::string& folder, const std::vector<std::string>& inputs);
  // Claims the folder (`option` names it in messages, e.g. "--images"), creating it when missing.
  CrackImageFolder(const std::string& folder, const std::string& option);
  ~CrackImageFolder();
  CrackImageFolder(const CrackImageFolder&) = delete;
  CrackImageFolder& operator=(const CrackImageFolder&) = delete;

  // Measures `surface` at `pixels` per side, writes its six views and puts them in place;
  // returns the metric and fills `paths` with the files written.
  CrackMetric write(const geometry::TriangleMesh& surface, int pixels,
                    std::vector<std::string>& paths);

 private:
  std::string folder_;
  std::unique_ptr<geometry::OutputDir> dir_;
};

// Measures `surface` at `pixels` per side and writes its six views into `folder` (created when
// missing), inside a run's own output set; returns the files written.
std::vector<std::string> writeCrackImagesOf(const geometry::TriangleMesh& surface, int pixels,
                                            const std::string& folder);

}  // namespace osteon::validation
