// fleetctl compose-floor: places several different floor photographs side by side (each used
// once, never tiled: a tiled texture would make the floor ambiguous) into one larger gray floor
// image, cropped to a common height. The default demo floor is made this way.
#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "io/run.h"

namespace fleetloc::fleetctl {
namespace {

struct ComposeArgs {
  std::vector<std::string> images;
  std::string out;
  int height_px = 0;  // 0: the smallest input height
};

Result<std::vector<cv::Mat>> LoadAll(const std::vector<std::string>& paths) {
  std::vector<cv::Mat> images;
  for (const auto& path : paths) {
    Result<cv::Mat> image = io::ReadGrayImage(path);
    if (!image.ok()) return image.status();
    images.push_back(*image);
  }
  return images;
}

Status Compose(const ComposeArgs& args) {
  Result<std::vector<cv::Mat>> images = LoadAll(args.images);
  if (!images.ok()) return images.status();
  int height = args.height_px;
  for (const auto& image : *images) {
    if (args.height_px == 0) height = height == 0 ? image.rows : std::min(height, image.rows);
  }
  std::vector<cv::Mat> strips;
  for (size_t i = 0; i < images->size(); ++i) {
    const cv::Mat& image = (*images)[i];
    if (image.rows < height) {
      return InvalidInput(args.images[i] + ": height " + std::to_string(image.rows) +
                          " px is below the requested " + std::to_string(height) + " px");
    }
    strips.push_back(image(cv::Rect(0, (image.rows - height) / 2, image.cols, height)));
  }
  cv::Mat floor;
  cv::hconcat(strips, floor);
  try {
    if (!cv::imwrite(args.out, floor)) return Internal(args.out + ": cannot write image");
  } catch (const cv::Exception& e) {
    return InvalidInput(args.out + ": " + e.what());
  }
  spdlog::info("composed {} photos into {} ({}×{} px)", strips.size(), args.out, floor.cols,
               floor.rows);
  return Status::Ok();
}

}  // namespace

void RegisterComposeCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<ComposeArgs>();
  CLI::App* cmd = app.add_subcommand(
      "compose-floor", "Place different floor photos side by side into one gray floor image");
  cmd->add_option("images", args->images, "Floor photographs, left to right")
      ->required()
      ->expected(1, -1);
  cmd->add_option("--out", args->out, "Output image (PNG)")->required();
  cmd->add_option("--height", args->height_px, "Common height in px (default: smallest input)")
      ->check(CLI::NonNegativeNumber);
  cmd->callback([args, result] { *result = Compose(*args); });
}

}  // namespace fleetloc::fleetctl
