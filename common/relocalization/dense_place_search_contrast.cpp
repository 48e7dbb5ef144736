// Dense global place search: a place told from a rival where the mosaic's views from the two
// differ (see DensePlaceSearch::ContrastTwins in dense_place_search.h).
#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/imgproc.hpp>

#include "relocalization/dense_place_search.h"
#include "relocalization/dense_place_search_parts.h"

namespace fleetloc::relocalization {

namespace {

// A level's normalized mosaic as a camera at `camera_in_map` sees it, in the pixels of a frame of
// `size` at that level (the inverse of RotatedFrame's placement), and where it falls inside the
// mosaic itself, not its zero border (255).
struct View {
  cv::Mat pixels, inside;
};

View ViewAt(const cv::Mat& normalized, int pad_px, const geometry::Geotransform& geo,
            const geometry::CameraModel& camera, const geometry::Pose2& camera_in_map,
            cv::Size size) {
  const Eigen::Matrix2d l = FrameToMosaic(camera, geo, camera_in_map.theta);
  const Eigen::Vector2d centre_ground =
      camera.PixelToGround({0.5 * camera.width_px, 0.5 * camera.height_px});
  const Eigen::Vector2d at = geo.MapToPixel(camera_in_map * centre_ground);
  // Index coordinates (centres at integers): mosaic = L·(frame + ½ − c_f) + at − ½.
  const Eigen::Vector2d half(0.5 * size.width, 0.5 * size.height);
  const Eigen::Vector2d offset =
      l * (Eigen::Vector2d(0.5, 0.5) - half) + at - Eigen::Vector2d(0.5, 0.5);
  const cv::Matx23d m(l(0, 0), l(0, 1), offset.x(), l(1, 0), l(1, 1), offset.y());
  View v;
  cv::warpAffine(normalized, v.pixels, m, size, cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_CONSTANT, 0);
  v.inside = cv::Mat::zeros(size, CV_8UC1);
  const double low = pad_px, high_x = normalized.cols - pad_px - 1.0,
               high_y = normalized.rows - pad_px - 1.0;
  for (int y = 0; y < size.height; ++y) {
    for (int x = 0; x < size.width; ++x) {
      const Eigen::Vector2d p = l * Eigen::Vector2d(x, y) + offset;
      if (p.x() >= low && p.x() <= high_x && p.y() >= low && p.y() <= high_y)
        v.inside.at<uchar>(y, x) = 255;
    }
  }
  return v;
}

// Σ F·V / √(Σ F² · Σ V²) over the mask (the dense search's masked correlation); 0 when either is
// zero there.
double CorrelationWithin(const cv::Mat& f, const cv::Mat& v, const cv::Mat& mask) {
  const double fv = cv::mean(f.mul(v), mask)[0];
  const double ff = cv::mean(f.mul(f), mask)[0];
  const double vv = cv::mean(v.mul(v), mask)[0];
  return ff > 0 && vv > 0 ? fv / std::sqrt(ff * vv) : 0.0;
}

}  // namespace

DensePlaceSearch::TwinContrast DensePlaceSearch::ContrastTwins(const cv::Mat& frame,
                                                               const geometry::Pose2& own,
                                                               const geometry::Pose2& rival,
                                                               double differing_mean_square) const {
  const Level& f = *fine_;
  const cv::Mat normalized = NormalizedFrame(frame, SweepLevel::kRefine);
  const View a = ViewAt(f.normalized, f.pad_px, f.geo, camera_, own, normalized.size());
  const View b = ViewAt(f.normalized, f.pad_px, f.geo, camera_, rival, normalized.size());
  cv::Mat difference = a.pixels - b.pixels;
  cv::Mat mean_square;
  const int window = options_.normalize_window_px;
  cv::boxFilter(difference.mul(difference), mean_square, CV_32F, cv::Size(window, window),
                cv::Point(-1, -1), true, cv::BORDER_REFLECT);
  const cv::Mat differing = (mean_square >= differing_mean_square) & a.inside & b.inside;
  TwinContrast c;
  c.pixels = cv::countNonZero(differing);
  c.share = c.pixels / static_cast<double>(normalized.total());
  if (c.share == 0) return c;
  c.own = CorrelationWithin(normalized, a.pixels, differing);
  c.rival = CorrelationWithin(normalized, b.pixels, differing);
  return c;
}

}  // namespace fleetloc::relocalization
