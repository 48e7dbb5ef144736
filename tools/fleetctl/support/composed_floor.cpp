// Streaming composition of a floor image to PGM.
#include "support/composed_floor.h"

#include <spdlog/spdlog.h>

#include <charconv>
#include <filesystem>
#include <span>

#include "mosaic/row_image_io.h"
#include "runtime/progress_log.h"
#include "support/floor_images.h"

namespace fleetloc::fleetctl {
namespace {

// Writes every block row of `composer` to `writer`, row by row.
Status WriteAllRows(const sim::FloorComposer& composer, mosaic::GrayRowWriter& writer,
                    const std::string& name) {
  runtime::PercentLog progress("compose " + name, "block rows", 5);
  for (int block_row = 0; block_row < composer.block_rows(); ++block_row) {
    const cv::Mat strip = composer.RenderBlockRow(block_row);
    for (int y = 0; y < strip.rows; ++y) {
      FLEETLOC_RETURN_IF_ERROR(
          writer.WriteRow(std::span(strip.ptr(y), static_cast<std::size_t>(strip.cols))));
    }
    progress(block_row + 1, composer.block_rows());
  }
  return writer.Finish();
}

}  // namespace

Result<cv::Size> ParsePixelSize(const std::string& text, const std::string& option) {
  int width = 0, height = 0;
  const char* end = text.data() + text.size();
  const auto [x_at, ec1] = std::from_chars(text.data(), end, width);
  bool ok = ec1 == std::errc() && x_at != end && *x_at == 'x';
  if (ok) {
    const auto [at, ec2] = std::from_chars(x_at + 1, end, height);
    ok = ec2 == std::errc() && at == end;
  }
  if (!ok || width <= 0 || height <= 0) {
    return InvalidInput(option + ": expected WIDTHxHEIGHT in pixels, e.g. 32768x32768, got '" +
                        text + "'");
  }
  return cv::Size(width, height);
}

Status ComposeFloorPgm(const std::vector<std::string>& photos,
                       const sim::FloorComposerOptions& options, const std::string& out_pgm) {
  if (std::filesystem::path(out_pgm).extension() != ".pgm") {
    return InvalidInput(out_pgm + ": a composed floor is written as binary PGM; name it *.pgm");
  }
  Result<std::vector<cv::Mat>> images = LoadGrayImages(photos);
  if (!images.ok()) return images.status();
  Result<sim::FloorComposer> composer =
      sim::FloorComposer::Create(std::move(images).value(), options);
  if (!composer.ok()) return InvalidInput("compose-floor: " + composer.status().message());
  const std::string partial = out_pgm + ".partial";
  Result<std::unique_ptr<mosaic::GrayRowWriter>> writer =
      mosaic::CreatePgmRowWriter(partial, options.width_px, options.height_px);
  if (!writer.ok()) return writer.status();
  Status written = WriteAllRows(*composer, **writer, out_pgm);
  writer->reset();  // closes the file
  std::error_code ec;
  if (written.ok()) {
    std::filesystem::rename(partial, out_pgm, ec);
    if (ec) written = Internal(out_pgm + ": cannot move the composed floor into place");
  }
  if (!written.ok()) std::filesystem::remove(partial, ec);
  return written;
}

}  // namespace fleetloc::fleetctl
