// Row-streaming image files for import and export: read any image as 8-bit gray rows, top to
// bottom, and write gray PNGs or PGMs row by row, so big images never need to be held whole in
// memory.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "base/status.h"

namespace fleetloc::mosaic {

// Delivers an image's rows as 8-bit gray; colour is converted with the weights of
// cv::COLOR_BGR2GRAY (0.299 R + 0.587 G + 0.114 B), 16-bit samples are reduced to their high byte,
// alpha is ignored.
class GrayRowReader {
 public:
  virtual ~GrayRowReader() = default;
  int width() const { return width_px_; }
  int height() const { return height_px_; }
  // True when rows are decoded on demand; false when the whole image was decoded up front.
  virtual bool streaming() const = 0;
  // Fills `row` (exactly width() bytes) with the next row. Requires fewer than height() rows read.
  // InvalidInput naming the file and row if the data is corrupt or ends early.
  virtual Status ReadRow(std::span<std::uint8_t> row) = 0;

 protected:
  int width_px_ = 0;
  int height_px_ = 0;
};

// Opens an image by content: non-interlaced PNG and binary PGM/PPM (P5/P6) stream row by row;
// anything else OpenCV can decode (JPEG, TIFF, interlaced PNG, ...) is decoded whole.
// NotFound if the file does not exist; InvalidInput naming the file if it cannot be decoded.
Result<std::unique_ptr<GrayRowReader>> OpenGrayRowReader(const std::string& path);

// The streaming decoders, used by OpenGrayRowReader (exposed for tests). They expect a file that
// starts with the format's signature.
Result<std::unique_ptr<GrayRowReader>> OpenPngRowReader(const std::string& path);
Result<std::unique_ptr<GrayRowReader>> OpenPnmRowReader(const std::string& path);

// Writes an 8-bit gray image of known size row by row. The file is complete only after Finish().
class GrayRowWriter {
 public:
  virtual ~GrayRowWriter() = default;
  // Appends the next row (exactly the width given at open). Internal error on I/O failure.
  virtual Status WriteRow(std::span<const std::uint8_t> row) = 0;
  // Ends the image; requires all rows written.
  virtual Status Finish() = 0;
};

// Creates (overwrites) a gray PNG of width × height pixels. Internal error if it cannot be created.
Result<std::unique_ptr<GrayRowWriter>> CreatePngRowWriter(const std::string& path, int width_px,
                                                          int height_px);
// Creates (overwrites) a binary 8-bit PGM (P5) of width × height pixels, uncompressed, so images of
// any size are written at disk speed. Internal error if it cannot be created.
Result<std::unique_ptr<GrayRowWriter>> CreatePgmRowWriter(const std::string& path, int width_px,
                                                          int height_px);

}  // namespace fleetloc::mosaic
