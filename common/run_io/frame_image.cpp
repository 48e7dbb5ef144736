// Frame images: header checked, then 8-bit gray decoding with OpenCV; errors naming the file.
#include <fstream>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "mosaic/image_header.h"
#include "run_io/run.h"

namespace fleetloc::run_io {

namespace {

Status WrongSize(const FrameRef& frame, long long width, long long height,
                 const geometry::CameraModel& camera) {
  return InvalidInput(frame.file.string() + ": image is " + std::to_string(width) + "x" +
                      std::to_string(height) + " px, the camera expects " +
                      std::to_string(camera.width_px) + "x" + std::to_string(camera.height_px));
}

constexpr size_t kHeaderBytes = 256 * 1024;  // a JPEG's frame header may follow its EXIF block

// The header of the image file at `path` (read from its first bytes); InvalidInput naming the file
// when it is not a PNG, JPEG, BMP or binary PNM.
Result<mosaic::ImageHeader> HeaderOf(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::vector<std::uint8_t> head(kHeaderBytes);
  in.read(reinterpret_cast<char*>(head.data()), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<size_t>(in.gcount()));
  const std::optional<mosaic::ImageHeader> header = mosaic::ReadImageHeader(head);
  if (!header)
    return InvalidInput(path.string() +
                        ": not a PNG, JPEG, BMP or binary PNM image (or its header is cut)");
  return *header;
}

}  // namespace

Result<cv::Mat> ReadGrayImage(const std::filesystem::path& path, long long max_pixels) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) return NotFound(path.string() + ": not found");
  // Checked before decoding: a small file may declare an image of gigabytes.
  Result<mosaic::ImageHeader> header = HeaderOf(path);
  if (!header.ok()) return header.status();
  if (header->width < 1 || header->height < 1 || header->pixels() > max_pixels) {
    return InvalidInput(path.string() + ": image is " + header->Describe() + ", more than " +
                        std::to_string(max_pixels) + " pixels");
  }
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
  std::error_code ec;
  if (!std::filesystem::is_regular_file(frame.file, ec))
    return NotFound(frame.file.string() + ": not found");
  // The frame's size is checked in its header, before anything is decoded.
  Result<mosaic::ImageHeader> header = HeaderOf(frame.file);
  if (!header.ok()) return header.status();
  if (header->width != camera.width_px || header->height != camera.height_px) {
    return WrongSize(frame, header->width, header->height, camera);
  }
  Result<cv::Mat> image = ReadGrayImage(frame.file, header->pixels());
  if (!image.ok()) return image.status();
  if (image->cols != camera.width_px || image->rows != camera.height_px) {
    return WrongSize(frame, image->cols, image->rows, camera);
  }
  return image;
}

}  // namespace fleetloc::run_io
