// Frame images: 8-bit gray decoding with OpenCV, errors naming the file.
#include <opencv2/imgcodecs.hpp>

#include "io/run.h"

namespace fleetloc::io {

Result<cv::Mat> ReadGrayImage(const std::filesystem::path& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path.string() + ": not found");
  cv::Mat image;
  try {
    image = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
  } catch (const cv::Exception& e) {
    return InvalidInput(path.string() + ": cannot decode image: " + e.err);
  }
  if (image.empty()) {
    return InvalidInput(path.string() + ": cannot decode image (corrupt or not an image format)");
  }
  FLEETLOC_CHECK(image.type() == CV_8UC1);  // IMREAD_GRAYSCALE always converts to 8-bit gray
  return image;
}

Result<cv::Mat> ReadFrame(const FrameRef& frame, const geometry::CameraModel& camera) {
  Result<cv::Mat> image = ReadGrayImage(frame.file);
  if (!image.ok()) return image.status();
  if (image->cols != camera.width_px || image->rows != camera.height_px) {
    return InvalidInput(frame.file.string() + ": image is " + std::to_string(image->cols) + "x" +
                        std::to_string(image->rows) + " px, the camera expects " +
                        std::to_string(camera.width_px) + "x" + std::to_string(camera.height_px));
  }
  return image;
}

}  // namespace fleetloc::io
