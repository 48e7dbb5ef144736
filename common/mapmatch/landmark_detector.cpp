// Landmark detection pipeline (see landmark_detector.h).
#include "mapmatch/landmark_detector.h"

#include <cmath>
#include <opencv2/imgproc.hpp>
#include <string>

namespace fleetloc::mapmatch {
namespace {

Status Bad(const std::string& field, const std::string& what) {
  return InvalidInput("landmark detector: " + field + " " + what);
}

// Refined edges whose lines are this close are the same edge.
constexpr double kSameEdgePx = 1.0;
// Edges closer than this to the sensor's border are not trusted (smoothing reaches past it).
constexpr int kBorderMarginPx = 3;

bool Positive(double value) { return std::isfinite(value) && value > 0; }

Status ValidateRefinement(const EdgeRefinement& r) {
  if (!(r.search_px >= 1 && r.search_px <= 10))
    return Bad("refinement.search_px", "must be in [1, 10]");
  if (!Positive(r.foot_search_px)) return Bad("refinement.foot_search_px", "must be > 0");
  if (!(r.fade_fraction > 0 && r.fade_fraction < 1)) {
    return Bad("refinement.fade_fraction", "must be in (0, 1)");
  }
  if (!(r.end_strength_fraction > 0 && r.end_strength_fraction < 1)) {
    return Bad("refinement.end_strength_fraction", "must be in (0, 1)");
  }
  if (!(r.step_px > 0 && r.step_px <= 1)) return Bad("refinement.step_px", "must be in (0, 1]");
  return Status::Ok();
}

}  // namespace

Status Validate(const LandmarkDetectorOptions& o) {
  if (!(o.smoothing_sigma_px >= 0 && o.smoothing_sigma_px <= 10)) {
    return Bad("smoothing_sigma_px", "must be in [0, 10]");
  }
  if (!(Positive(o.canny_low) && o.canny_high >= o.canny_low)) {
    return Bad("canny_low/canny_high", "must satisfy 0 < canny_low <= canny_high");
  }
  if (!Positive(o.hough_rho_px)) return Bad("hough_rho_px", "must be > 0");
  if (!(Positive(o.hough_theta_rad) && o.hough_theta_rad < 0.1)) {
    return Bad("hough_theta_rad", "must be in (0, 0.1)");
  }
  if (o.hough_votes < 1) return Bad("hough_votes", "must be >= 1");
  if (!Positive(o.min_line_length_px)) return Bad("min_line_length_px", "must be > 0");
  if (!(Positive(o.min_boundary_length_px) && o.min_boundary_length_px <= o.min_line_length_px)) {
    return Bad("min_boundary_length_px", "must be in (0, min_line_length_px]");
  }
  if (!(o.max_line_gap_px >= 0)) return Bad("max_line_gap_px", "must be >= 0");
  if (!(Positive(o.max_vertical_deviation_rad) && o.max_vertical_deviation_rad < 0.5)) {
    return Bad("max_vertical_deviation_rad", "must be in (0, 0.5)");
  }
  if (!(o.min_boundary_angle_rad > o.max_vertical_deviation_rad &&
        o.min_boundary_angle_rad <= M_PI / 2)) {
    return Bad("min_boundary_angle_rad", "must be in (max_vertical_deviation_rad, pi/2]");
  }
  if (!(o.merge_distance_px >= 0) || !(o.merge_gap_px >= 0)) {
    return Bad("merge_distance_px/merge_gap_px", "must be >= 0");
  }
  FLEETLOC_RETURN_IF_ERROR(ValidateRefinement(o.refinement));
  if (!(o.min_range_m >= 0 && o.max_range_m > o.min_range_m && std::isfinite(o.max_range_m))) {
    return Bad("min_range_m/max_range_m", "must satisfy 0 <= min_range_m < max_range_m");
  }
  if (!Positive(o.foot_sigma_px)) return Bad("foot_sigma_px", "must be > 0");
  if (!Positive(o.reference_sigma_m)) return Bad("reference_sigma_m", "must be > 0");
  if (!Positive(o.full_support_length_px)) return Bad("full_support_length_px", "must be > 0");
  return Status::Ok();
}

Result<LandmarkDetector> LandmarkDetector::Create(const ForwardCamera& camera,
                                                  const LandmarkDetectorOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(Validate(options));
  return LandmarkDetector(camera, options);
}

LandmarkDetector::LandmarkDetector(const ForwardCamera& camera,
                                   const LandmarkDetectorOptions& options)
    : camera_(camera), options_(options), view_(camera, kBorderMarginPx) {}

Status LandmarkDetector::CheckImage(const cv::Mat& image) const {
  if (image.empty()) return InvalidInput("landmark detector: the image is empty");
  if (image.size() != camera_.image_size()) {
    return InvalidInput("landmark detector: the image is " + std::to_string(image.cols) + "×" +
                        std::to_string(image.rows) + " px, the camera's is " +
                        std::to_string(camera_.image_size().width) + "×" +
                        std::to_string(camera_.image_size().height));
  }
  if (image.type() != CV_8UC1 && image.type() != CV_8UC3) {
    return InvalidInput("landmark detector: the image must be 8-bit gray or BGR");
  }
  return Status::Ok();
}

cv::Mat LandmarkDetector::IdealImage(const cv::Mat& image) const {
  cv::Mat gray = image;
  if (image.channels() == 3) cv::cvtColor(image, gray, cv::COLOR_BGR2GRAY);
  // In floating point from here: 8-bit rounding would cost the foot its sub-pixel precision.
  gray.convertTo(gray, CV_32F);
  cv::Mat ideal = view_.Undistort(gray);
  if (options_.smoothing_sigma_px > 0) {
    cv::GaussianBlur(ideal, ideal, cv::Size(), options_.smoothing_sigma_px);
  }
  return ideal;
}

Result<std::vector<EdgeSegment>> LandmarkDetector::DetectEdges(const cv::Mat& image) const {
  FLEETLOC_RETURN_IF_ERROR(CheckImage(image));
  const cv::Mat ideal = IdealImage(image);
  Gradients gradients;
  cv::Sobel(ideal, gradients.dx, CV_32F, 1, 0);
  cv::Sobel(ideal, gradients.dy, CV_32F, 0, 1);
  cv::Mat dx16, dy16, edges;
  gradients.dx.convertTo(dx16, CV_16S);
  gradients.dy.convertTo(dy16, CV_16S);
  cv::Canny(dx16, dy16, edges, options_.canny_low, options_.canny_high, /*L2gradient=*/true);
  edges.setTo(0, view_.valid_mask() == 0);  // the canvas beyond the sensor is made up
  std::vector<cv::Vec4i> segments;
  cv::HoughLinesP(edges, segments, options_.hough_rho_px, options_.hough_theta_rad,
                  options_.hough_votes, options_.min_boundary_length_px, options_.max_line_gap_px);
  const SortedSegments sorted =
      SortSegments(segments, CanvasNadirVanishingPoint(), options_.max_vertical_deviation_rad,
                   options_.min_boundary_angle_rad);
  std::vector<EdgeSegment> boundaries;
  for (const EdgeSegment& segment : sorted.boundaries) {
    if (auto line = FitEdgeLine(gradients, segment, options_.refinement.search_px)) {
      boundaries.push_back(*line);
    }
  }
  std::vector<EdgeSegment> refined;
  for (const EdgeSegment& edge :
       MergeCollinear(sorted.vertical, options_.merge_distance_px, options_.merge_gap_px)) {
    if (auto r = RefineEdge(gradients, edge, boundaries, options_.refinement))
      refined.push_back(*r);
  }
  // Pieces of one edge that Hough split refine to the same line and foot: keep one.
  std::vector<EdgeSegment> merged = MergeCollinear(std::move(refined), kSameEdgePx, 0.0);
  for (EdgeSegment& edge : merged) edge.point -= view_.offset();  // canvas → ideal pixels
  return merged;
}

Eigen::Vector3d LandmarkDetector::CanvasNadirVanishingPoint() const {
  const Eigen::Vector3d vp = camera_.NadirVanishingPoint();
  return {vp.x() + view_.offset().x() * vp.z(), vp.y() + view_.offset().y() * vp.z(), vp.z()};
}

std::optional<FloorPointDetection> LandmarkDetector::ToFloor(const EdgeSegment& edge) const {
  const Eigen::Vector2d foot = edge.EndPixel();
  Result<Eigen::Vector2d> point = camera_.IdealPixelToFloor(foot);
  if (!point.ok()) return std::nullopt;
  const double range = (*point - camera_.center().head<2>()).norm();
  if (range < options_.min_range_m || range > options_.max_range_m) return std::nullopt;
  // Sensitivity of the floor point to the foot's position along the edge.
  Result<Eigen::Vector2d> shifted =
      camera_.IdealPixelToFloor(foot - options_.foot_sigma_px * edge.direction);
  if (!shifted.ok()) return std::nullopt;
  FloorPointDetection d;
  d.point = *point;
  d.foot_px = foot;
  d.edge_length_px = edge.Length();
  d.range_m = range;
  d.sigma_m = (*shifted - *point).norm();
  const double precision = 1.0 / (1.0 + std::pow(d.sigma_m / options_.reference_sigma_m, 2));
  d.quality = precision * std::min(1.0, d.edge_length_px / options_.full_support_length_px);
  return d;
}

Result<std::vector<FloorPointDetection>> LandmarkDetector::Detect(const cv::Mat& image) const {
  Result<std::vector<EdgeSegment>> edges = DetectEdges(image);
  if (!edges.ok()) return edges.status();
  std::vector<FloorPointDetection> detections;
  for (const EdgeSegment& edge : *edges) {
    if (auto d = ToFloor(edge)) detections.push_back(*d);
  }
  return detections;
}

}  // namespace fleetloc::mapmatch
