// A simulated vehicle driving live on the host clock: its drive planned over a real floor (the
// simulator `--sim-floor` uses) with frame times on a grid of the frame period (where Aravis's fake
// camera fires), its frames rendered ahead; its wheel odometry published as ROS 2 nav_msgs/Odometry
// over DDS at its own times; a fake GigE Vision camera (Aravis's ArvGvFakeCamera on 127.0.0.1)
// serving the last frame due over GVCP/GVSP, stamped by a device clock that counts from the
// camera's power-up. For the live-agent tests and `fleetctl bench agent --source aravis`.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <optional>
#include <thread>
#include <vector>

#include "mosaic/raster_source.h"
#include "run_io/run.h"
#include "sim/run_simulator.h"
#include "transport/ros_types.h"
#include "transport/typed_io.h"

// Aravis's own forward declarations, spelled as its headers spell them.
// NOLINTBEGIN(modernize-use-using,bugprone-reserved-identifier)
typedef struct _ArvGvFakeCamera ArvGvFakeCamera;
typedef struct _ArvBuffer ArvBuffer;
// NOLINTEND(modernize-use-using,bugprone-reserved-identifier)

namespace fleetloc::live_sim {

void SleepUntilHost(double t);

class PlannedDrive {
 public:
  // The vehicle stands still from `start_t` and drives from start_t + lead_s (on the frame-period
  // grid), its first frame then; odometry covers both, frames before the drive show where it
  // stands (so a camera serving them before the drive shows the truth). 640×480 at
  // `resolution_m`. InvalidInput when the simulator refuses the plan.
  static Result<std::unique_ptr<PlannedDrive>> Create(const cv::Mat& floor, double resolution_m,
                                                      int frames, double rate_hz, double start_t,
                                                      double lead_s, double speed_px_s,
                                                      uint64_t seed);
  const run_io::CameraFile& camera() const { return camera_; }
  // base_link in odom from start_t: standing still, then the simulator's wheel odometry.
  const std::vector<geometry::StampedPose>& odometry() const { return odometry_; }
  // base_link in map at host time t (where it stands before the drive).
  geometry::Pose2 TruthAt(double t) { return sim_->TruthAt(std::max(t, first_frame_t())); }
  sim::RunSimulator& sim() { return *sim_; }
  double first_frame_t() const { return sim_->truth().front().t; }
  double last_frame_t() const { return sim_->truth().back().t; }
  // The planned frame nearest to host time t (clamped to the drive).
  int FrameAt(double t) const;
  // The planned frame a camera firing on the frame-period grid has exposed by host time t: the last
  // one at or before t, whatever the delay since; none before the first frame or a period after
  // the last.
  std::optional<int> FrameCapturedBy(double t) const;
  const cv::Mat& image(int i) const { return images_[i]; }
  double frame_t(int i) const { return sim_->truth()[i].t; }
  int frame_count() const { return static_cast<int>(images_.size()); }

 private:
  PlannedDrive(const cv::Mat& floor, double resolution_m, double rate_hz)
      : floor_(floor, {0.0, floor.rows * resolution_m, resolution_m}), rate_hz_(rate_hz) {}
  mosaic::ImageRasterSource floor_;
  double rate_hz_;
  run_io::CameraFile camera_;
  std::unique_ptr<sim::RunSimulator> sim_;
  std::vector<cv::Mat> images_;
  std::vector<geometry::StampedPose> odometry_;
};

// Publishes odometry samples (base_link in odom) on `topic` at each sample's own host time,
// stamped with it, from a thread; `mangle` may change a sample before it goes or skip it (false).
class OdometryPublisher {
 public:
  using Mangle = std::function<bool(size_t index, nav_msgs_msg_dds__Odometry_* message)>;
  // `min_gap_s`: at least this long between two writes (samples stamped in the past go out at this
  // pace instead of in one burst).
  static Result<std::unique_ptr<OdometryPublisher>> Create(
      const transport::Participant& p, std::vector<geometry::StampedPose> samples,
      Mangle mangle = nullptr, double min_gap_s = 0.0, const std::string& topic = "rt/odom");
  ~OdometryPublisher();
  bool done() const { return done_; }
  int MatchedReaders() const { return writer_->MatchedReaders(); }  // e.g. the agent's

 private:
  OdometryPublisher() = default;
  void Run();
  std::vector<geometry::StampedPose> samples_;
  Mangle mangle_;
  double min_gap_s_ = 0.0;
  std::unique_ptr<transport::Topic<nav_msgs_msg_dds__Odometry_>> topic_;
  std::unique_ptr<transport::Writer<nav_msgs_msg_dds__Odometry_>> writer_;
  std::atomic<bool> stop_{false}, done_{false};
  std::thread thread_;
};

// Aravis's fake GigE Vision camera on 127.0.0.1 (GVCP port 3956: one at a time per host), each
// buffer filled with the drive's last frame due by its fill time and stamped on a device clock
// `device_epoch` seconds behind the host's Unix time. `gvsp_lost_ratio`: share of GVSP packets
// it drops (the fake camera does not resend them: those frames arrive incomplete).
class FakeGigECamera {
 public:
  FakeGigECamera(const PlannedDrive* drive, double device_epoch, double gvsp_lost_ratio = 0.0);
  ~FakeGigECamera();
  bool running() const;
  long long filled() const { return filled_; }

 private:
  static void Fill(ArvBuffer* buffer, void* self, unsigned exposure_us, unsigned gain,
                   unsigned pixel_format);
  const PlannedDrive* drive_;
  double device_epoch_;
  ArvGvFakeCamera* camera_ = nullptr;
  std::atomic<long long> filled_{0};
};

}  // namespace fleetloc::live_sim
