// The forward camera model (see forward_camera.h): OpenCV does the lens distortion, Eigen the
// mount geometry.
#include "mapmatch/forward_camera.h"

#include <Eigen/Geometry>
#include <cmath>
#include <opencv2/calib3d.hpp>

namespace fleetloc::mapmatch {
namespace {

// Rays closer to the horizon than this (the z component of a unit ray) do not meet the floor.
constexpr double kMinDownwardRay = 1e-9;

std::optional<ParamProblem> FindIntrinsicsProblem(const ForwardCameraParams& p) {
  if (p.width_px <= 0) return ParamProblem{"width", "must be a positive integer"};
  if (p.height_px <= 0) return ParamProblem{"height", "must be a positive integer"};
  for (double k : p.K) {
    if (!std::isfinite(k)) return ParamProblem{"K", "must be finite numbers"};
  }
  if (p.K[0] <= 0 || p.K[4] <= 0) {
    return ParamProblem{"K", "focal lengths K[0] and K[4] must be positive"};
  }
  if (p.K[1] != 0 || p.K[3] != 0 || p.K[6] != 0 || p.K[7] != 0 || p.K[8] != 1) {
    return ParamProblem{"K", "must be [fx,0,cx, 0,fy,cy, 0,0,1]"};
  }
  for (double d : p.dist) {
    if (!std::isfinite(d)) return ParamProblem{"dist", "must be finite numbers"};
  }
  return std::nullopt;
}

std::optional<ParamProblem> FindMountProblem(const ForwardMount& m) {
  const std::pair<const char*, double> finite[] = {
      {"mount.x", m.x_m}, {"mount.y", m.y_m}, {"mount.yaw", m.yaw_rad}, {"mount.roll", m.roll_rad}};
  for (const auto& [name, value] : finite) {
    if (!std::isfinite(value)) return ParamProblem{name, "must be a finite number"};
  }
  if (!(std::isfinite(m.height_m) && m.height_m > 0)) {
    return ParamProblem{"mount.height", "must be a positive number (metres above the floor)"};
  }
  if (!(std::abs(m.pitch_rad) < M_PI / 2)) {
    return ParamProblem{"mount.pitch", "must be in (-pi/2, pi/2)"};
  }
  return std::nullopt;
}

// Optical frame (x right, y down, z forward) → base_link-aligned (x forward, y left, z up).
Eigen::Matrix3d OpticalToBody() {
  Eigen::Matrix3d m;
  m << 0, 0, 1,  //
      -1, 0, 0,  //
      0, -1, 0;
  return m;
}

Status AboveHorizon(const std::string& what, const Eigen::Vector2d& where) {
  return InvalidInput("forward camera: " + what + " (" + std::to_string(where.x()) + ", " +
                      std::to_string(where.y()) +
                      ") is at or above the horizon: its ray misses the floor");
}

}  // namespace

std::optional<ParamProblem> FindProblem(const ForwardCameraParams& params) {
  if (auto problem = FindIntrinsicsProblem(params)) return problem;
  return FindMountProblem(params.mount);
}

Result<ForwardCamera> ForwardCamera::Create(const ForwardCameraParams& params) {
  if (auto problem = FindProblem(params)) {
    return InvalidInput("forward camera: field '" + problem->field + "': " + problem->what);
  }
  return ForwardCamera(params);
}

ForwardCamera::ForwardCamera(const ForwardCameraParams& params) : params_(params) {
  const ForwardMount& m = params.mount;
  center_ = {m.x_m, m.y_m, m.height_m};
  rotation_ = (Eigen::AngleAxisd(m.yaw_rad, Eigen::Vector3d::UnitZ()) *
               Eigen::AngleAxisd(m.pitch_rad, Eigen::Vector3d::UnitY()) *
               Eigen::AngleAxisd(m.roll_rad, Eigen::Vector3d::UnitX()))
                  .toRotationMatrix() *
              OpticalToBody();
}

cv::Matx33d ForwardCamera::CameraMatrix() const { return cv::Matx33d(params_.K.data()); }

cv::Vec<double, 5> ForwardCamera::DistCoeffs() const {
  return cv::Vec<double, 5>(params_.dist.data());
}

Result<Eigen::Vector2d> ForwardCamera::Project(const Eigen::Vector3d& point_base) const {
  const Eigen::Vector3d p = rotation_.transpose() * (point_base - center_);
  if (!(p.z() > kMinDownwardRay * p.norm())) {
    return InvalidInput("forward camera: the point is not in front of the camera");
  }
  // Far outside the image the distortion polynomial may fold back into it: refuse such points.
  const Eigen::Vector2d ideal = NormalizedToIdealPixel(p.head<2>() / p.z());
  const double w = params_.width_px, h = params_.height_px;
  if (ideal.x() < -w / 2 || ideal.x() > 1.5 * w || ideal.y() < -h / 2 || ideal.y() > 1.5 * h) {
    return InvalidInput("forward camera: the point is far outside the field of view");
  }
  const std::vector<cv::Point3d> object{{p.x(), p.y(), p.z()}};
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d::zeros(), cv::Vec3d::zeros(), CameraMatrix(), DistCoeffs(),
                    image);
  return Eigen::Vector2d(image[0].x, image[0].y);
}

std::vector<Eigen::Vector2d> ForwardCamera::Undistort(
    std::span<const Eigen::Vector2d> pixels) const {
  std::vector<cv::Point2d> in(pixels.size()), out;
  for (std::size_t i = 0; i < pixels.size(); ++i) in[i] = {pixels[i].x(), pixels[i].y()};
  if (in.empty()) return {};
  // Iterate until the step is negligible (the default stops after 5 iterations, ~1e-4 px off).
  const cv::TermCriteria converged(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 100, 1e-15);
  cv::undistortPoints(in, out, CameraMatrix(), DistCoeffs(), cv::noArray(), cv::noArray(),
                      converged);
  std::vector<Eigen::Vector2d> normalized(out.size());
  for (std::size_t i = 0; i < out.size(); ++i) normalized[i] = {out[i].x, out[i].y};
  return normalized;
}

Eigen::Vector2d ForwardCamera::IdealPixelToNormalized(const Eigen::Vector2d& ideal_px) const {
  const auto& K = params_.K;
  return {(ideal_px.x() - K[2]) / K[0], (ideal_px.y() - K[5]) / K[4]};
}

Eigen::Vector2d ForwardCamera::NormalizedToIdealPixel(const Eigen::Vector2d& normalized) const {
  const auto& K = params_.K;
  return {K[0] * normalized.x() + K[2], K[4] * normalized.y() + K[5]};
}

Eigen::Vector3d ForwardCamera::RayDirection(const Eigen::Vector2d& normalized) const {
  return rotation_ * Eigen::Vector3d(normalized.x(), normalized.y(), 1.0);
}

Result<Eigen::Vector2d> ForwardCamera::PixelToFloor(const Eigen::Vector2d& pixel) const {
  Result<Eigen::Vector2d> floor = NormalizedToFloor(Undistort(std::span(&pixel, 1))[0]);
  if (!floor.ok()) return AboveHorizon("pixel", pixel);
  return floor;
}

Result<Eigen::Vector2d> ForwardCamera::IdealPixelToFloor(const Eigen::Vector2d& ideal_px) const {
  Result<Eigen::Vector2d> floor = NormalizedToFloor(IdealPixelToNormalized(ideal_px));
  if (!floor.ok()) return AboveHorizon("ideal pixel", ideal_px);
  return floor;
}

Result<Eigen::Vector2d> ForwardCamera::NormalizedToFloor(const Eigen::Vector2d& normalized) const {
  const Eigen::Vector3d ray = RayDirection(normalized);
  if (!(ray.z() < -kMinDownwardRay * ray.norm())) {
    return AboveHorizon("normalized point", normalized);
  }
  const Eigen::Vector3d floor = center_ + ray * (-center_.z() / ray.z());
  return Eigen::Vector2d(floor.x(), floor.y());
}

Eigen::Vector3d ForwardCamera::NadirVanishingPoint() const {
  const Eigen::Vector3d down_optical = rotation_.transpose() * Eigen::Vector3d(0, 0, -1);
  const auto& K = params_.K;
  return {K[0] * down_optical.x() + K[2] * down_optical.z(),
          K[4] * down_optical.y() + K[5] * down_optical.z(), down_optical.z()};
}

}  // namespace fleetloc::mapmatch
