// The localization core without DDS: a simulated drive over a floor image (its frames and wheel
// odometry) tracked against the simulator's truth, frames waiting for odometry, and a vehicle
// without a start pose placed by global relocalization. Tiles, relocalization and the published
// poses are fakes of the core's ports.
#include "tracker_agent/localization_core.h"

#include <gtest/gtest.h>

#include <cmath>
#include <opencv2/imgcodecs.hpp>

#include "sim/run_simulator.h"

namespace fleetloc::tracker_agent {
namespace {

// The floor is in memory: no tile is ever missing; prefetch requests are only counted.
class FakeTiles : public TileSupply {
 public:
  Status Prefetch(const std::vector<mosaic::TileKey>& keys) override {
    ++prefetches;
    asked += static_cast<long long>(keys.size());
    return Status::Ok();
  }
  Result<size_t> DecodeArrived(size_t) override { return size_t{0}; }
  bool Settled() const override { return true; }
  bool Cached(const mosaic::TileKey&) const override { return false; }
  int prefetches = 0;
  long long asked = 0;
};

// Answers with `answer` (the truth at the frame's time) once ready.
class FakeRelocalization : public GlobalRelocalization {
 public:
  bool ready() const override { return answer.has_value(); }
  Result<relocalization::Relocalization> Relocalize(const cv::Mat&,
                                                    const geometry::Pose2&) override {
    ++attempts;
    relocalization::Relocalization found;
    found.found = true;
    found.base_in_map = *answer;
    return found;
  }
  void ResetTrajectory() override { ++trajectory_resets; }
  double last_ms() const override { return 0.0; }
  std::optional<geometry::PoseWithCovariance> answer;
  int attempts = 0;
  int trajectory_resets = 0;
};

class RecordedPoses : public PosePublisher {
 public:
  void PublishPose(const PoseToPublish& pose) override { poses.push_back(pose); }
  void PublishMapToOdom(double, const geometry::Pose2&, const geometry::Pose2&) override {
    ++map_to_odom;
  }
  bool WantsMapToOdom() const override { return true; }
  std::vector<PoseToPublish> FramePoses() const {
    std::vector<PoseToPublish> frames;
    for (const PoseToPublish& p : poses) {
      if (p.origin == PoseOrigin::kFrame) frames.push_back(p);
    }
    return frames;
  }
  std::vector<PoseToPublish> poses;
  int map_to_odom = 0;
};

class CountedFrames : public TrackedFrameObserver {
 public:
  void FrameTracked(double, const cv::Mat&, const tracking::FrameResult&) override { ++frames; }
  int frames = 0;
};

// A 20-frame drive over the demo floor at 0.5 mm/px, with the core and fakes around it.
class LocalizationCoreTest : public ::testing::Test {
 protected:
  void SetUp() override {
    floor_ = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/rock_dirt_2048.png",
                        cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(floor_.empty());
    source_ = std::make_unique<mosaic::ImageRasterSource>(
        floor_, geometry::Geotransform{0.0, floor_.rows * 0.0005, 0.0005});
    camera_.model = sim::DefaultSimCameraModel(320, 240, 0.0005);
    sim::SimOptions options;
    options.timing.frames = 20;
    auto simulator = sim::RunSimulator::Create(source_.get(), camera_.model, options);
    ASSERT_TRUE(simulator.ok()) << simulator.status().message();
    simulator_ = std::move(simulator).value();
  }

  std::unique_ptr<LocalizationCore> MakeCore(
      const std::optional<geometry::PoseWithCovariance>& initial) {
    const LocalizationPorts ports{&tiles_, &relocalization_, &poses_, &tracked_, &health_};
    return std::make_unique<LocalizationCore>(LocalizationOptions{}, tracking::TrackerOptions{},
                                              camera_, source_->layout(), source_.get(), initial,
                                              ports, nullptr);
  }

  geometry::PoseWithCovariance InitialPose() const {
    const Eigen::Vector3d sigma = simulator_->initial_sigma();
    return {simulator_->initial_pose(), sigma.cwiseProduct(sigma).asDiagonal()};
  }

  // Odometry and frames in time order (odometry first at equal times), as SimInput hands them out.
  void Drive(LocalizationCore* core) {
    const auto& odometry = simulator_->odometry();
    const auto& truth = simulator_->truth();
    size_t o = 0;
    int f = 0;
    while (o < odometry.size() || f < static_cast<int>(truth.size())) {
      if (o < odometry.size() &&
          (f >= static_cast<int>(truth.size()) || odometry[o].t <= truth[f].t)) {
        core->OnOdometry(odometry[o].t, odometry[o].pose);
        ++o;
      } else {
        core->AddDownwardFrame(truth[f].t, simulator_->RenderFrame(f).image,
                               {truth[f].t, 0.0, 0.0});
        ++f;
      }
    }
  }

  // The camera's distance from where the simulator put it at the pose's time, metres.
  double CameraError(const PoseToPublish& pose) const {
    const geometry::Pose2 estimated = pose.base.pose * camera_.model.mount;
    const geometry::Pose2 truth = simulator_->TruthAt(pose.t) * camera_.model.mount;
    return std::hypot(estimated.x - truth.x, estimated.y - truth.y);
  }

  cv::Mat floor_;
  std::unique_ptr<mosaic::ImageRasterSource> source_;
  run_io::CameraFile camera_;
  std::unique_ptr<sim::RunSimulator> simulator_;
  FakeTiles tiles_;
  FakeRelocalization relocalization_;
  RecordedPoses poses_;
  CountedFrames tracked_;
  HealthCounters health_;
};

TEST_F(LocalizationCoreTest, TracksSimulatedDriveWithinMillimetresOfTruth) {
  std::unique_ptr<LocalizationCore> core = MakeCore(InitialPose());
  Drive(core.get());
  const std::vector<PoseToPublish> frames = poses_.FramePoses();
  ASSERT_EQ(frames.size(), 20u);
  int tracking = 0;
  double worst_m = 0.0;
  for (const PoseToPublish& pose : frames) {
    if (pose.state != tracking::LockState::kTracking) continue;
    ++tracking;
    worst_m = std::max(worst_m, CameraError(pose));
  }
  EXPECT_EQ(tracking, 20);
  EXPECT_LT(worst_m, 0.003);  // the mosaic tracks to millimetres
  EXPECT_EQ(health_.frames(), 20);
  EXPECT_EQ(tracked_.frames, 20);
  EXPECT_EQ(core->lock_state(), tracking::LockState::kTracking);
  // Between frames: the odometry rate (100 Hz over ~4 s), each with its map -> odom.
  EXPECT_GT(poses_.poses.size(), 300u);
  EXPECT_EQ(poses_.map_to_odom, static_cast<int>(poses_.poses.size()));
  EXPECT_EQ(relocalization_.attempts, 0);
  EXPECT_GT(tiles_.asked, 0);  // the footprint asked for ahead, though nothing is ever missing
}

TEST_F(LocalizationCoreTest, FrameWaitsUntilOdometryCoversItsTime) {
  std::unique_ptr<LocalizationCore> core = MakeCore(InitialPose());
  const auto& odometry = simulator_->odometry();
  const double frame_t = simulator_->truth()[0].t;
  size_t o = 0;
  for (; odometry[o].t < frame_t; ++o) core->OnOdometry(odometry[o].t, odometry[o].pose);
  core->AddDownwardFrame(frame_t, simulator_->RenderFrame(0).image, {frame_t, 0.0, 0.0});
  EXPECT_TRUE(poses_.FramePoses().empty());  // odometry ends before the frame: it waits
  core->OnOdometry(odometry[o].t, odometry[o].pose);
  const std::vector<PoseToPublish> frames = poses_.FramePoses();
  ASSERT_EQ(frames.size(), 1u);
  EXPECT_DOUBLE_EQ(frames[0].t, frame_t);
  EXPECT_EQ(frames[0].state, tracking::LockState::kTracking);
  EXPECT_LT(CameraError(frames[0]), 0.003);
}

TEST_F(LocalizationCoreTest, WithoutStartPoseFirstFrameIsRelocalizedThenTracked) {
  const geometry::Pose2 truth = simulator_->TruthAt(simulator_->truth()[0].t);
  relocalization_.answer = geometry::PoseWithCovariance{truth, Eigen::Matrix3d::Identity() * 1e-6};
  std::unique_ptr<LocalizationCore> core = MakeCore(std::nullopt);
  Drive(core.get());
  const std::vector<PoseToPublish> frames = poses_.FramePoses();
  ASSERT_EQ(frames.size(), 20u);
  EXPECT_EQ(relocalization_.attempts, 1);
  EXPECT_EQ(frames[0].state, tracking::LockState::kRelocalized);
  EXPECT_LT(CameraError(frames[0]), 1e-9);  // the relocalized pose as found
  for (size_t i = 1; i < frames.size(); ++i) {
    EXPECT_EQ(frames[i].state, tracking::LockState::kTracking) << "frame " << i;
    EXPECT_LT(CameraError(frames[i]), 0.003) << "frame " << i;
  }
  EXPECT_EQ(relocalization_.trajectory_resets, 19);  // every tracked frame forgets the search's
}

}  // namespace
}  // namespace fleetloc::tracker_agent
