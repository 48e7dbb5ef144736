// Register, fit, blend, rebuild the pyramid.
#include "mapping/remap.h"

#include <Eigen/Eigenvalues>
#include <set>

#include "mosaic/pyramid_builder.h"
#include "tracking/predicted_view.h"

namespace fleetloc::mapping {
namespace {

using mosaic::TileKey;

bool Cancelled(const std::atomic<bool>* cancel) { return cancel != nullptr && cancel->load(); }

double PositionSigmaPx(const Eigen::Matrix3d& covariance, double resolution) {
  const Eigen::Matrix2d position = covariance.topLeftCorner<2, 2>();
  return std::sqrt(std::max(0.0, Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(position)
                                     .eigenvalues()
                                     .maxCoeff())) /
         resolution;
}

// The mosaic as the patch's camera would see it at `pose` (for the photometric fit).
cv::Mat MosaicUnder(mosaic::RasterSource* mosaic, const cv::Mat& image, const geometry::Pose2& pose) {
  geometry::CameraModel camera;
  camera.width_px = image.cols, camera.height_px = image.rows;
  camera.cx_px = image.cols / 2.0, camera.cy_px = image.rows / 2.0;
  camera.resolution_m = mosaic->layout().geo.resolution;
  const auto warp = tracking::FrameMosaicWarp::For(pose, camera, mosaic->layout().geo);
  return tracking::RenderPredictedView(mosaic, {0, 0, image.cols, image.rows}, warp, 0);
}

// Level-0 pixel rectangle covered by a placed patch.
cv::Rect FootprintPx(const PlacedPatch& p, const geometry::Geotransform& geo) {
  double min_u = 1e300, min_v = 1e300, max_u = -1e300, max_v = -1e300;
  const double ha = p.image.rows * geo.resolution / 2, hb = p.image.cols * geo.resolution / 2;
  for (const auto& [a, b] : {std::pair{ha, hb}, {ha, -hb}, {-ha, hb}, {-ha, -hb}}) {
    const Eigen::Vector2d m = p.pose * Eigen::Vector2d(a, b);
    const double u = (m.x() - geo.origin_x) / geo.resolution, v = (geo.origin_y - m.y()) / geo.resolution;
    min_u = std::min(min_u, u), max_u = std::max(max_u, u);
    min_v = std::min(min_v, v), max_v = std::max(max_v, v);
  }
  return cv::Rect(cv::Point(static_cast<int>(std::floor(min_u)) - 1, static_cast<int>(std::floor(min_v)) - 1),
                  cv::Point(static_cast<int>(std::ceil(max_u)) + 1, static_cast<int>(std::ceil(max_v)) + 1));
}

}  // namespace

Result<RemapTiles> ComputeRemap(mosaic::RasterSource* mosaic, const TileFetch& fetch,
                                const std::vector<Patch>& patches, const RemapOptions& options,
                                const std::function<void(const RemapStep&)>& progress,
                                const std::atomic<bool>* cancel) {
  const mosaic::MosaicLayout& layout = mosaic->layout();
  const auto report = [&](const char* phase, int done, int total) {
    if (progress) progress({phase, done, total});
  };
  RemapTiles out;
  PatchRegistrar registrar(mosaic, options.tracker);
  std::vector<PlacedPatch> placed;
  std::vector<cv::Rect> footprints;
  for (size_t i = 0; i < patches.size(); ++i) {
    if (Cancelled(cancel)) return InvalidInput("cancelled");
    const Registration r = registrar.Register(patches[i]);
    const bool usable = r.registered || PositionSigmaPx(patches[i].covariance, layout.geo.resolution) <=
                                            options.max_unregistered_sigma_px;
    out.registrations.push_back(r);
    out.used.push_back(usable);
    if (!usable) {
      ++out.rejected;
    } else {
      PlacedPatch p{patches[i].image, r.pose};
      std::tie(p.gain, p.bias) = PhotometricFit(p.image, MosaicUnder(mosaic, p.image, r.pose));
      footprints.push_back(FootprintPx(p, layout.geo));
      placed.push_back(std::move(p));
    }
    report("register", static_cast<int>(i + 1), static_cast<int>(patches.size()));
  }
  std::set<TileKey> level0;
  for (const cv::Rect& f : footprints) {
    mosaic::TilesCovering(layout, 0, f).ForEach([&](const TileKey& k) { level0.insert(k); });
  }
  int done = 0;
  for (const TileKey& key : level0) {
    if (Cancelled(cancel)) return InvalidInput("cancelled");
    const cv::Rect tile_rect = mosaic::TilePixelRect(layout, key);
    std::vector<PlacedPatch> touching;
    for (size_t i = 0; i < placed.size(); ++i) {
      if ((footprints[i] & tile_rect).area() > 0) touching.push_back(placed[i]);
    }
    cv::Mat blended = BlendTile(fetch(key), tile_rect.tl(), layout.geo, touching, options.mode,
                                options.feather_px);
    // Padding past the mosaic's edge stays 0, as the importer leaves it.
    const cv::Rect inside = (tile_rect & cv::Rect(0, 0, layout.width_px, layout.height_px)) - tile_rect.tl();
    cv::Mat clean = cv::Mat::zeros(blended.size(), CV_8UC1);
    blended(inside).copyTo(clean(inside));
    out.tiles[key] = clean;
    report("blend", ++done, static_cast<int>(level0.size()));
  }
  std::set<TileKey> changed = level0;
  for (int level = 1; level < layout.levels && !changed.empty(); ++level) {
    if (Cancelled(cancel)) return InvalidInput("cancelled");
    std::set<TileKey> parents;
    for (const TileKey& k : changed) parents.insert({level, k.col / 2, k.row / 2});
    for (const TileKey& parent : parents) {
      out.tiles[parent] = mosaic::DownsampleTile(layout, parent, [&](const TileKey& child) {
        const auto it = out.tiles.find(child);
        return it != out.tiles.end() ? it->second : fetch(child);
      });
    }
    report("pyramid", level, layout.levels - 1);
    changed = std::move(parents);
  }
  return out;
}

}  // namespace fleetloc::mapping
