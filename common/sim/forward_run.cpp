// The simulated forward-camera drive (see forward_run.h).
#include "sim/forward_run.h"

#include <cmath>

#include "sim/odometry_model.h"
#include "sim/random.h"

namespace fleetloc::sim {
namespace {

constexpr double kEndClearanceM = 2.0;
constexpr std::uint64_t kOdometryStream = 0x0d0;

bool Positive(double value) { return std::isfinite(value) && value > 0; }

}  // namespace

Status Validate(const ForwardRunOptions& o) {
  FLEETLOC_RETURN_IF_ERROR(Validate(o.scene));
  if (o.frames < 2) return InvalidInput("forward run: frames must be >= 2");
  if (!Positive(o.frame_rate_hz)) return InvalidInput("forward run: frame_rate_hz must be > 0");
  if (!(Positive(o.odometry_rate_hz) && o.odometry_rate_hz >= o.frame_rate_hz)) {
    return InvalidInput("forward run: odometry_rate_hz must be >= frame_rate_hz");
  }
  if (!Positive(o.speed_m_s)) return InvalidInput("forward run: speed_m_s must be > 0");
  if (!Positive(o.weave_wavelength_m)) {
    return InvalidInput("forward run: weave_wavelength_m must be > 0");
  }
  if (!(o.weave_amplitude_m >= 0 && o.weave_amplitude_m <= o.scene.width_m / 2 - 0.5)) {
    return InvalidInput("forward run: weave_amplitude_m must be in [0, half the width - 0.5 m]");
  }
  const double end_x = o.start_x_m + o.speed_m_s * (o.frames - 1) / o.frame_rate_hz;
  if (!(o.start_x_m >= 0.5 && end_x <= o.scene.length_m - kEndClearanceM)) {
    return InvalidInput(
        "forward run: start_x_m must be >= 0.5 and the drive must end 2 m before "
        "the end wall (it ends at x = " +
        std::to_string(end_x) + ")");
  }
  return Status::Ok();
}

geometry::Pose2 ForwardRoutePose(const ForwardRunOptions& o, double t) {
  const double x = o.start_x_m + o.speed_m_s * t;
  const double k = 2 * M_PI / o.weave_wavelength_m;
  const double y = o.weave_amplitude_m * std::sin(k * x);
  const double slope = o.weave_amplitude_m * k * std::cos(k * x);
  return {x, y, std::atan(slope)};
}

ForwardRunPlan PlanForwardRun(const ForwardRunOptions& o) {
  FLEETLOC_CHECK(Validate(o).ok());
  ForwardRunPlan plan;
  const double duration = (o.frames - 1) / o.frame_rate_hz;
  for (int i = 0; i < o.frames; ++i) {
    const double t = i / o.frame_rate_hz;
    plan.frame_truth.push_back({t, ForwardRoutePose(o, t)});
  }
  std::vector<geometry::StampedPose> truth;
  const int samples = static_cast<int>(std::ceil(duration * o.odometry_rate_hz)) + 1;
  for (int i = 0; i < samples; ++i) {
    const double t = std::min(duration, i / o.odometry_rate_hz);
    truth.push_back({t, ForwardRoutePose(o, t)});
  }
  plan.odometry = SimulateOdometry(truth, o.odometry, MixSeed(o.seed, kOdometryStream));
  return plan;
}

}  // namespace fleetloc::sim
