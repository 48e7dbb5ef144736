// The global position update in the live agent: `fleetctl sim-forward` drives a vehicle down a
// rendered corridor for 32.5 s (13 m) with a forward camera, drifting odometry and no downward
// frames; a tracker_agent replays it (a map_server on some mosaic only because the agent needs one
// to start). Its published poses must stay within centimetres of the truth while the odometry
// alone drifts decimetres away. And bad input: a malformed forward_camera.json or a landmark file
// with NaN stops the agent at start with one message naming the file and the field.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <opencv2/imgproc.hpp>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 94;

double PositionError(const geometry::Pose2& a, const geometry::Pose2& b) {
  return std::hypot(a.x - b.x, a.y - b.y);
}

// The odometry sample at time t (the forward images are taken at odometry sample times).
const geometry::Pose2* OdometryAt(const run_io::Run& run, double t) {
  for (const geometry::StampedPose& sample : run.odometry) {
    if (std::abs(sample.t - t) < 1e-9) return &sample.pose;
  }
  return nullptr;
}

// Any floor will do: the run has no downward frames.
cv::Mat SomeFloor() {
  cv::Mat floor(1024, 1024, CV_8UC1);
  cv::randu(floor, 0, 255);
  cv::GaussianBlur(floor, floor, {0, 0}, 2.0);
  return floor;
}

std::string WriteForwardRun(const std::filesystem::path& dir) {
  std::string run_dir = (dir / "run").string();
  const testing::CommandResult sim =
      testing::RunFleetctl("sim-forward --frames 66 --seed 4 --out " + testing::Quote(run_dir));
  EXPECT_EQ(sim.exit_code, 0) << sim.err;
  return run_dir;
}

// Runs tracker_agent on `run_dir` (no map server needed: it refuses before looking for one) and
// returns its exit status; its log is in `log`.
int RunAgentExpectingRefusal(const std::string& run_dir, const std::string& log) {
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent", {"--run", run_dir, "--fast", "--domain", std::to_string(kDomain)}, log);
  EXPECT_TRUE(Eventually([&] { return !agent.Running(); }, 30));
  return agent.Wait(std::chrono::seconds(1));
}

TEST(AgentGlobalPosition, CorridorDriveStaysWithinCentimetresWhileOdometryDrifts) {
  testing::MapServerFixture server("agent_global_position", SomeFloor(), kDomain);
  const std::string run_dir = WriteForwardRun(server.dir());
  Result<run_io::Run> run = run_io::ReadRun(run_dir);
  ASSERT_TRUE(run.ok()) << run.status().message();
  ASSERT_TRUE(run->frames.empty()) << "a drive without downward frames";
  ASSERT_TRUE(run->forward.has_value());
  const std::vector<geometry::StampedPose>& truth = run->forward->truth;
  ASSERT_EQ(truth.size(), 66u);

  transport::Participant& p = server.participant();
  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto pose_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, transport::Qos().Reliable().KeepAll());
  auto health_topic =
      transport::Topic<fleetloc_VehicleHealth>::Create(p, transport::topics::kVehicleHealth);
  auto health_reader = transport::VehicleStreamReader<fleetloc_VehicleHealth>::Create(
      p, *health_topic, transport::Qos().Reliable().KeepAll());
  std::string update_issue;  // the newest health report's position update line
  fleetloc_LockState health_state = fleetloc_LOCK_LOST;
  auto take_health = [&] {
    (void)health_reader->TakeAll([&](const fleetloc_VehicleHealth& h, const dds_sample_info_t&) {
      health_state = h.lock_state;
      update_issue.clear();
      for (uint32_t i = 0; i < h.issues._length; ++i) {
        const std::string name = transport::GetBounded(h.issues._buffer[i].name);
        if (name.starts_with("position_update"))
          update_issue = name + ": " + transport::GetBounded(h.issues._buffer[i].message);
      }
    });
  };
  const std::string summary_path = (server.dir() / "summary.json").string();
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--run", run_dir, "--fast", "--domain", std::to_string(kDomain), "--vehicle-id", "agv-6",
       "--outbox", (server.dir() / "outbox.db").string(), "--summary", summary_path},
      (server.dir() / "agent.log").string());
  std::vector<transport::PoseReport> published;
  ASSERT_TRUE(Eventually(
      [&] {
        testing::TakePoses(*pose_reader, &published);
        take_health();
        return !agent.Running();
      },
      120));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  testing::TakePoses(*pose_reader, &published);
  take_health();

  // At every forward image: the agent's pose and the odometry alone (the initial pose, which is
  // the truth, propagated with odometry) against the truth.
  const geometry::Pose2* odom0 = OdometryAt(*run, truth.front().t);
  ASSERT_NE(odom0, nullptr);
  double worst_agent = 0.0, final_agent = 0.0, worst_odometry = 0.0, final_odometry = 0.0;
  int compared = 0;
  for (const geometry::StampedPose& at : truth) {
    const geometry::Pose2* odom = OdometryAt(*run, at.t);
    ASSERT_NE(odom, nullptr) << "t=" << at.t;
    final_odometry = PositionError(run->initial_pose * odom0->Inverse() * *odom, at.pose);
    worst_odometry = std::max(worst_odometry, final_odometry);
    const transport::PoseReport* pose = testing::PoseAt(published, at.t);
    if (pose == nullptr) continue;
    ++compared;
    // Coasting from the initial pose until the first fit (t = 1 s), then corrected. At a fit's time
    // the odometry-rate pose comes first (the image waits for the odometry sample), then the
    // corrected one: PoseAt finds the former, so the errors are those before each fit.
    EXPECT_EQ(pose->state,
              at.t <= 1.0 ? tracking::LockState::kCoasting : tracking::LockState::kRelocalized)
        << "at t=" << at.t;
    const double error = PositionError(pose->base_in_map.pose, at.pose);
    worst_agent = std::max(worst_agent, error);
    final_agent = error;
    EXPECT_LT(error, 0.05) << "at t=" << at.t;  // the unit tests' bound (2-3 cm per fit, < 5 cm)
  }
  std::printf(
      "forward drive: agent worst %.1f mm over %d images, at the end %.1f mm; odometry alone "
      "worst %.1f mm, at the end %.1f mm\n",
      worst_agent * 1000, compared, final_agent * 1000, worst_odometry * 1000,
      final_odometry * 1000);
  EXPECT_GE(compared, 64) << "a pose at (nearly) every image, the start pose included";
  EXPECT_GT(final_odometry, 0.25) << "odometry alone drifts visibly";
  EXPECT_GT(worst_odometry, 5 * worst_agent);

  std::ifstream in(summary_path);
  ASSERT_TRUE(in.good()) << "no summary";
  const nlohmann::json update = nlohmann::json::parse(in)["position_update"];
  EXPECT_TRUE(update.value("enabled", false)) << update.dump();
  EXPECT_EQ(update.value("images", 0), 66) << update.dump();
  EXPECT_EQ(update.value("images_rejected", -1), 0) << update.dump();
  EXPECT_EQ(update.value("attempted", 0), 32) << update.dump();  // one per second after the first
  EXPECT_GE(update.value("applied", 0), 28) << update.dump();
  EXPECT_LT(update.value("max_correction_m", 1.0), 0.05) << update.dump();
  // The health says so too: the lock state, and a warning while the newest fit was rejected (at
  // the end of this drive: facing the end wall).
  EXPECT_EQ(health_state, fleetloc_LOCK_RELOCALIZED);
  if (update.value("last_rejected", false)) {
    EXPECT_NE(update_issue.find("position_update_rejected: "), std::string::npos) << update_issue;
    EXPECT_NE(update_issue.find(" of 32 position updates applied"), std::string::npos)
        << update_issue;
  } else {
    EXPECT_EQ(update_issue, "");
  }
}

TEST(AgentGlobalPosition, MalformedForwardCameraOrLandmarksStopTheAgentWithTheFileAndField) {
  testing::ScratchDir dir("agent_global_position_bad");
  const std::string run_dir =
      testing::RunFleetctl("sim-forward --frames 2 --out " + dir / "run").exit_code == 0
          ? dir / "run"
          : "";
  ASSERT_FALSE(run_dir.empty());
  const std::filesystem::path camera_json =
      std::filesystem::path(run_dir) / "forward" / "forward_camera.json";
  const std::string good_camera = testing::ReadWhole(camera_json);
  nlohmann::json camera = nlohmann::json::parse(good_camera);
  camera["mount"]["pitch"] = "down";
  std::ofstream(camera_json, std::ios::trunc) << camera.dump();
  const std::string log1 = dir / "agent1.log";
  EXPECT_EQ(RunAgentExpectingRefusal(run_dir, log1), 2);
  const std::string said1 = testing::ReadWhole(log1);
  EXPECT_NE(said1.find("forward/forward_camera.json: field 'mount.pitch'"), std::string::npos)
      << said1;

  std::ofstream(camera_json, std::ios::trunc) << good_camera;
  std::ofstream(std::filesystem::path(run_dir) / "landmarks.csv", std::ios::trunc)
      << "id,x,y\n0,1.0,2.0\n1,nan,1.2\n";
  const std::string log2 = dir / "agent2.log";
  EXPECT_EQ(RunAgentExpectingRefusal(run_dir, log2), 2);
  const std::string said2 = testing::ReadWhole(log2);
  EXPECT_NE(said2.find("landmarks.csv:3: field 'x'"), std::string::npos) << said2;
}

}  // namespace
}  // namespace fleetloc
