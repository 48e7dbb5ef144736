// fleetctl compose-floor: places several different floor photographs side by side (each used
// once, never tiled: a tiled texture would make the floor ambiguous) into one larger gray floor
// image, cropped to a common height. The default demo floor is made this way. With --size it
// instead composes a floor of any size (gigapixels) from varied blocks of the photos, streamed to
// a binary PGM (composed_floor.h); its blocks reuse photo content (varied by crop, orientation and
// gain), so it serves storage benchmarks at scale, not judging how the tracker copes with
// ambiguity — unless --non-repeating also rotates and scales every block by a random amount.
#include <spdlog/spdlog.h>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "commands.h"
#include "support/composed_floor.h"
#include "support/floor_images.h"

namespace fleetloc::fleetctl {
namespace {

struct ComposeArgs {
  std::vector<std::string> images;
  std::string out;
  int height_px = 0;  // 0: the smallest input height
  std::string size;   // "WxH": compose blocks of the photos to this size instead
  sim::FloorComposerOptions blocks;
};

Status ComposeSideBySide(const ComposeArgs& args) {
  Result<std::vector<cv::Mat>> images = LoadGrayImages(args.images);
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

Status ComposeBlocks(ComposeArgs args) {
  Result<cv::Size> size = ParsePixelSize(args.size, "--size");
  if (!size.ok()) return size.status();
  args.blocks.width_px = size->width;
  args.blocks.height_px = size->height;
  FLEETLOC_RETURN_IF_ERROR(ComposeFloorPgm(args.images, args.blocks, args.out));
  spdlog::info("composed {} photos into {} ({}x{} px, {} px blocks, seed {})", args.images.size(),
               args.out, size->width, size->height, args.blocks.block_px, args.blocks.seed);
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
  cmd->add_option("--out", args->out, "Output image (PNG; PGM with --size)")->required();
  CLI::Option* height =
      cmd->add_option("--height", args->height_px, "Common height in px (default: smallest input)")
          ->check(CLI::NonNegativeNumber);
  cmd->add_option("--size", args->size,
                  "Compose a WxH floor of varied blocks of the photos instead (binary PGM, "
                  "streamed; e.g. 32768x32768)")
      ->excludes(height);
  cmd->add_option("--block", args->blocks.block_px, "Block side in px for --size")
      ->capture_default_str();
  cmd->add_option("--seed", args->blocks.seed, "Block placement seed for --size")
      ->capture_default_str();
  cmd->add_flag("--non-repeating", args->blocks.free_rotation_and_scale,
                "With --size: rotate each block by a random angle and scale it by a random factor "
                "in [0.8, 1.25], so reused photo content never recurs at the same orientation and "
                "scale (for place recognition)");
  cmd->callback([args, result] {
    *result = args->size.empty() ? ComposeSideBySide(*args) : ComposeBlocks(*args);
  });
}

}  // namespace fleetloc::fleetctl
