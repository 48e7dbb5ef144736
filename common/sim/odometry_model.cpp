// Odometry error model.
#include "sim/odometry_model.h"

#include <cmath>
#include <opencv2/core.hpp>

#include "sim/random.h"

namespace fleetloc::sim {

std::vector<geometry::StampedPose> SimulateOdometry(const std::vector<geometry::StampedPose>& truth,
                                                    const OdometryOptions& options,
                                                    std::uint64_t seed) {
  std::vector<geometry::StampedPose> odom;
  if (truth.empty()) return odom;
  cv::RNG rng(MixSeed(seed, 0x6f646f6d));  // "odom"
  odom.reserve(truth.size());
  odom.push_back({truth.front().t, options.start_pose.value_or(truth.front().pose)});
  for (size_t k = 1; k < truth.size(); ++k) {
    const geometry::Pose2 step = geometry::Between(truth[k - 1].pose, truth[k].pose);
    const double dt = truth[k].t - truth[k - 1].t;
    const double distance = std::hypot(step.x, step.y);
    double scale = 1.0 + options.distance_scale_error;
    if (distance > 0 && options.distance_noise_m_per_sqrt_m > 0) {
      scale += rng.gaussian(options.distance_noise_m_per_sqrt_m * std::sqrt(distance)) / distance;
    }
    double turn =
        step.theta * (1.0 + options.heading_scale_error) + options.heading_drift_rad_s * dt;
    if (options.heading_noise_rad_per_sqrt_s > 0) {
      turn += rng.gaussian(options.heading_noise_rad_per_sqrt_s * std::sqrt(dt));
    }
    const geometry::Pose2 measured{step.x * scale, step.y * scale, turn};
    odom.push_back({truth[k].t, odom.back().pose * measured});
  }
  return odom;
}

}  // namespace fleetloc::sim
