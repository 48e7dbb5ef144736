// Tyre marks and debris on the floor, which the mosaic does not have: occluders of other shapes
// than the dust blobs (long curved bands with a tread pattern; small hard-edged pieces with their
// own shading), for testing the trackers on data they were not tuned on. Like the dust they are
// drawn per map cell from the seed, so every visit to a spot sees the same marks.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "sim/sim_options.h"

namespace fleetloc::sim {

// A tyre mark: a band of width `width_m` along an arc of radius `radius_m` (curving left for a
// positive radius, right for a negative one) centred at `centre_m`, where its direction is
// `angle_rad`; `half_length_m` of arc on each side of the centre.
struct TyreMark {
  Eigen::Vector2d centre_m;
  double angle_rad = 0.0;
  double radius_m = 1.0;
  double half_length_m = 0.1;
  double width_m = 0.01;
  double tread_period_m = 0.004;  // the tread's stripes across the band
  double opacity = 0.5;
  double level_dn = 30.0;  // rubber's brightness
};

// A piece of debris: a hard-edged polygon (vertices relative to the centre) of one material with a
// linear shading across it.
struct Debris {
  Eigen::Vector2d centre_m;
  std::vector<Eigen::Vector2d> vertices_m;
  double level_dn = 128.0;
  Eigen::Vector2d shading_dn_per_m = Eigen::Vector2d::Zero();
};

class FloorMarks {
 public:
  // Tyre marks covering `options.tyre_mark_fraction` and debris covering `options.debris_fraction`
  // of the floor on average, sizes scaled to pixels of `pixel_size_m`.
  FloorMarks(const RenderOptions& options, double pixel_size_m, std::uint64_t seed);

  // Composites the marks onto `image` (CV_32FC1, DN), whose continuous pixel (u, v) lies at map
  // point pixel_to_map · (u, v, 1). Returns the share of the pixels of `count_region` covered by
  // a mark.
  double Apply(const Eigen::Matrix<double, 2, 3>& pixel_to_map, const cv::Rect& count_region,
               cv::Mat* image) const;

  std::vector<TyreMark> TyreMarksNear(const Eigen::Vector2d& min_m,
                                      const Eigen::Vector2d& max_m) const;
  std::vector<Debris> DebrisNear(const Eigen::Vector2d& min_m, const Eigen::Vector2d& max_m) const;

 private:
  TyreMark DrawTyreMark(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const;
  Debris DrawDebris(cv::RNG& rng, const Eigen::Vector2d& cell_origin_m) const;

  RenderOptions options_;
  double pixel_size_m_;
  std::uint64_t seed_;
  double cell_m_ = 0.0;
  double tyre_reach_m_ = 0.0, debris_reach_m_ = 0.0;  // largest distance of a mark from its centre
  double tyre_marks_per_cell_ = 0.0, debris_per_cell_ = 0.0;
};

// The vehicle's own shadow on the floor: a multiplicative light field of `size` that is
// 1 − depth over `fraction` of the frame beyond a straight soft edge at `angle_rad` (the vehicle
// is on that side), 1 elsewhere; the penumbra is `edge_px` wide. Empty (no change) for fraction 0.
cv::Mat ShadowField(cv::Size size, double fraction, double depth, double angle_rad, double edge_px);

}  // namespace fleetloc::sim
