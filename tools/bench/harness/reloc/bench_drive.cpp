// The relocalization bench's vehicle (see bench_drive.h).
#include "harness/reloc/bench_drive.h"

#include <cmath>

namespace fleetloc::bench {
namespace {

// How far the vehicle at `start` may drive straight ahead (sign 1) or back (sign -1), up to
// `limit_m`, with the whole frame on the mosaic (bisection: the frame fits along an interval).
double DrivableM(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
                 const geometry::Pose2& start, double sign, double limit_m) {
  double fits = 0.0, leaves = limit_m;
  for (int i = 0; i < 30; ++i) {
    const double mid = 0.5 * (fits + leaves);
    (FrameFits(layout, camera, start * geometry::Pose2{sign * mid, 0.0, 0.0}) ? fits : leaves) =
        mid;
  }
  return fits;
}

}  // namespace

// Whether the whole frame stays on the mosaic at any heading.
bool FrameFits(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
               const geometry::Pose2& base) {
  const geometry::Pose2 cam = base * camera.mount;
  const Eigen::Vector2d px = layout.geo.MapToPixel({cam.x, cam.y});
  const double r = 0.5 * std::hypot(camera.width_px, camera.height_px);
  return px.x() >= r && px.y() >= r && px.x() <= layout.width_px - r &&
         px.y() <= layout.height_px - r;
}

// The vehicle's pose at frame `k`, after k steps of driving from `start`: ahead when one step
// fits ahead, else backwards (the direction is the trial's, not the frame's). Where the floor is
// too short for k steps (a floor a few frames across) it drives to and fro along its heading,
// reversing where the frame would leave the mosaic, so that the frames of a trajectory see
// different parts of the floor; until session 46 it stood still at `start` there, every such
// frame a copy of the first one's place. It stands only where it cannot move at all.
geometry::Pose2 PoseAtFrame(const mosaic::MosaicLayout& layout, const geometry::CameraModel& camera,
                            const geometry::Pose2& start, int k, double step_m) {
  const double sign =
      FrameFits(layout, camera, start * geometry::Pose2{step_m, 0.0, 0.0}) ? 1.0 : -1.0;
  const double travel_m = k * step_m;
  const geometry::Pose2 straight = start * geometry::Pose2{sign * travel_m, 0.0, 0.0};
  if (FrameFits(layout, camera, straight)) return straight;
  // Room ahead and behind in the direction of travel; neither is needed beyond travel_m.
  const double ahead_m = DrivableM(layout, camera, start, sign, travel_m);
  const double behind_m = DrivableM(layout, camera, start, -sign, travel_m);
  const double lane_m = ahead_m + behind_m;
  if (lane_m < 1e-3) return start;
  // Unfolded, the to-and-fro drive is a straight one along a lane of twice the length.
  const double along = std::fmod(behind_m + travel_m, 2.0 * lane_m);
  const double at_m = (along <= lane_m ? along : 2.0 * lane_m - along) - behind_m;
  return start * geometry::Pose2{sign * at_m, 0.0, 0.0};
}

}  // namespace fleetloc::bench
