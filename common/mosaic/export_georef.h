// Georeference files that go with an exported mosaic image so that other tools place it in the
// map frame: an ESRI world file (GDAL, QGIS) and a Nav2 / ROS map_server map.yaml. Pure: text from
// the mosaic layout, the exported level and the pixel rectangle written (docs/formats.md).
#pragma once

#include <opencv2/core/types.hpp>
#include <string>

#include "mosaic/raster_source.h"

namespace fleetloc::mosaic {

// The world file's path beside `image_path`: .png → .pgw, .jpg/.jpeg → .jgw, .tif/.tiff → .tfw,
// .pgm → .pgmw; any other extension gets a "w" appended.
std::string WorldFilePath(const std::string& image_path);

// The six lines of a world file for `rect` (pixels of `level`) of the mosaic: pixel size in x,
// two rotation terms (0), the negative pixel size in y, and the map x, y of the centre of the
// image's top-left pixel.
std::string WorldFileText(const MosaicLayout& layout, int level, const cv::Rect& rect);

// A Nav2 map_server map.yaml for the same image: `image` (as given), `resolution` of the level,
// `origin` = map x, y of the image's bottom-left corner and yaw 0, `mode: raw` (the image is a
// floor texture, not an occupancy grid: raw keeps its gray values), the usual thresholds.
std::string Nav2MapYaml(const MosaicLayout& layout, int level, const cv::Rect& rect,
                        const std::string& image);

}  // namespace fleetloc::mosaic
