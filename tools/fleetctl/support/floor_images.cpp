// Floor photograph discovery and loading.
#include "support/floor_images.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "run_io/run.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

bool IsImageFile(const fs::path& path) {
  static const std::set<std::string> kExtensions{".png", ".jpg", ".jpeg", ".pgm",
                                                 ".ppm", ".tif", ".tiff", ".bmp"};
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return kExtensions.count(ext) > 0;
}

}  // namespace

fs::path DefaultFloorsDir() {
  std::error_code ec;
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  fs::path beside = exe.parent_path().parent_path().parent_path() / kFloorsSubdir;
  if (!ec && fs::is_directory(beside, ec)) return beside;
  return fs::path(FLEETLOC_SOURCE_DIR) / kFloorsSubdir;
}

Result<std::vector<fs::path>> ListFloorImages(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) {
    return NotFound(dir.string() + ": no such directory (" + option + ")");
  }
  std::vector<fs::path> images;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (entry.is_regular_file() && IsImageFile(entry.path())) images.push_back(entry.path());
  }
  std::sort(images.begin(), images.end());
  if (images.empty()) return InvalidInput(dir.string() + ": no floor images (" + option + ")");
  return images;
}

Result<std::vector<cv::Mat>> LoadGrayImages(const std::vector<std::string>& paths) {
  std::vector<cv::Mat> images;
  for (const auto& path : paths) {
    Result<cv::Mat> image = run_io::ReadGrayImage(path);
    if (!image.ok()) return image.status();
    images.push_back(*image);
  }
  return images;
}

}  // namespace fleetloc::fleetctl
