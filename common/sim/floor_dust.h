// Dust and grime lying on the floor: soft, darker or lighter blobs and thin streaks at random map
// positions. They are generated procedurally per map cell from the seed, so every visit to a spot
// sees the same dirt (the floor differs from the mosaic in the same way on every pass), and any
// floor size costs no memory.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "geometry/camera_model.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

struct DustBlob {
  Eigen::Vector2d centre_m;  // map
  double semi_major_m = 0.0;
  double semi_minor_m = 0.0;
  double angle_rad = 0.0;  // major axis direction in map
  double softness = 0.5;   // edge width as a fraction of the radius (opacity ramps across it)
  double opacity = 0.5;    // 0..1 at the blob's core
  double level_dn = 0.0;   // the dirt's own brightness
};

class FloorDust {
 public:
  // Dust covering `options.dust_fraction` of the floor on average (the union of the blobs'
  // nominal ellipses), with sizes in pixels of `pixel_size_m`.
  FloorDust(const RenderOptions& options, double pixel_size_m, std::uint64_t seed);

  // The blobs that may touch the axis-aligned map box [min_m, max_m], in a fixed order.
  std::vector<DustBlob> BlobsNear(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) const;

  // Composites the dust onto `image` (CV_32FC1, DN), whose continuous pixel (u, v) lies at map
  // point pixel_to_map · (u, v, 1) (pixel (i, j) has its centre at (i + 0.5, j + 0.5)). Returns
  // the share of the pixels of `count_region` whose centre lies inside a blob's nominal ellipse.
  double Apply(const Eigen::Matrix<double, 2, 3>& pixel_to_map, const cv::Rect& count_region,
               cv::Mat* image) const;

  // Blobs per square metre (Poisson density) giving the configured coverage.
  double density_per_m2() const { return density_per_m2_; }

 private:
  DustBlob DrawBlob(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const;
  void Composite(const DustBlob& blob, const Eigen::Matrix<double, 2, 3>& map_to_pixel,
                 cv::Mat* image, cv::Mat* covered) const;

  RenderOptions options_;
  double pixel_size_m_;
  std::uint64_t seed_;
  double cell_m_ = 0.0;
  double max_extent_m_ = 0.0;
  double density_per_m2_ = 0.0;
};

}  // namespace fleetloc::sim
