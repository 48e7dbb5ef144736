// Global relocalization in the live agent: a map_server process publishes its mosaic's place
// index; a tracker_agent replays a simulated run with no initial pose (--relocalize) in which the
// vehicle is also kidnapped — carried 40 % of its route further at t = 4 s while its odometry
// sees nothing. The agent must find its pose on the first frames, lose lock at the kidnap,
// relocalize within a second and return to tracking, every pose within millimetres of truth.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <nlohmann/json.hpp>

#include "map_server_fixture.h"
#include "published_poses.h"
#include "run_io/run.h"
#include "transport/place_index_channel.h"
#include "transport/vehicle_streams.h"

namespace fleetloc {
namespace {

using testing::Eventually;
constexpr uint32_t kDomain = 89;
constexpr double kKidnapS = 4.0;  // elapsed run time of the kidnap (the run starts at t = 0)

double PositionError(const transport::PoseReport& pose, const geometry::Pose2& truth) {
  return std::hypot(pose.base_in_map.pose.x - truth.x, pose.base_in_map.pose.y - truth.y);
}

double HeadingError(const transport::PoseReport& pose, const geometry::Pose2& truth) {
  return std::abs(geometry::WrapAngle(pose.base_in_map.pose.theta - truth.theta));
}

TEST(AgentRelocalization, StartsWithoutAPoseAndRecoversFromAKidnap) {
  // A real photograph (moss seen from above, 1.28 m x 0.8 m): nothing in it repeats. (A tiling
  // game texture such as rock_dirt_2048 repeats itself exactly, and no single frame can tell
  // which copy it sees.)
  const cv::Mat floor = cv::imread(FLEETLOC_SOURCE_DIR "/deploy/demo/floors/moss_2560x1600.jpg",
                                   cv::IMREAD_GRAYSCALE);
  testing::MapServerFixture server("agent_relocalization", floor, kDomain);
  const std::string run_dir = (server.dir() / "run").string();
  ASSERT_EQ(
      testing::RunFleetctl("sim --mosaic " + server.mosaic_path() +
                           " --frames 60 --seed 3 --kidnap-at 4 --kidnap-jump 0.4 --out " + run_dir)
          .exit_code,
      0);
  Result<run_io::Run> run = run_io::ReadRun(run_dir);
  ASSERT_TRUE(run.ok()) << run.status().message();

  // The map server publishes the index once built (a fraction of a second for this floor).
  transport::Participant& p = server.participant();
  auto index = transport::PlaceIndexReceiver::Create(p);
  ASSERT_TRUE(index.ok());
  std::vector<transport::PlaceIndexBlob> blobs;
  ASSERT_TRUE(Eventually(
      [&] {
        blobs = (*index)->Poll();
        return !blobs.empty();
      },
      30))
      << "no place index published";
  EXPECT_EQ(blobs[0].mosaic_id, server.layout().mosaic_id);

  auto pose_topic =
      transport::Topic<fleetloc_VehiclePose>::Create(p, transport::topics::kVehiclePose);
  auto pose_reader = transport::VehicleStreamReader<fleetloc_VehiclePose>::Create(
      p, *pose_topic, transport::Qos().Reliable().KeepAll());
  const std::string summary_path = (server.dir() / "summary.json").string();
  runtime::ChildProcess agent = testing::StartDaemon(
      "tracker_agent",
      {"--run", run_dir, "--relocalize", "--domain", std::to_string(kDomain), "--vehicle-id",
       "agv-5", "--outbox", (server.dir() / "outbox.db").string(), "--summary", summary_path},
      (server.dir() / "agent.log").string());
  std::vector<transport::PoseReport> published;
  ASSERT_TRUE(Eventually(
      [&] {
        testing::TakePoses(*pose_reader, &published);
        return !agent.Running();
      },
      90));
  EXPECT_EQ(agent.Wait(std::chrono::seconds(1)), 0);
  testing::TakePoses(*pose_reader, &published);

  // Frame by frame: when the agent relocalized (with no prior), and how well it tracked.
  std::vector<double> relocalized_at;
  int tracked_frames = 0;
  for (const geometry::StampedPose& truth : run->truth) {
    const transport::PoseReport* pose = testing::PoseAt(published, truth.t);
    if (pose == nullptr) continue;  // before the first relocalization: nothing to publish
    const bool localized = pose->state == tracking::LockState::kTracking ||
                           pose->state == tracking::LockState::kRelocalized;
    if (pose->state == tracking::LockState::kRelocalized) relocalized_at.push_back(truth.t);
    if (!localized) continue;
    ++tracked_frames;
    EXPECT_LT(PositionError(*pose, truth.pose), 0.002) << "at t=" << truth.t;
    EXPECT_LT(HeadingError(*pose, truth.pose), 0.5 * M_PI / 180) << "at t=" << truth.t;
  }
  // The start: the first frame pose published is localized (the pose of the very first frame may
  // go out before this test's reader is matched, so the summary counts the relocalizations).
  const auto first_frame = std::find_if(
      run->truth.begin(), run->truth.end(),
      [&](const auto& truth) { return testing::PoseAt(published, truth.t) != nullptr; });
  ASSERT_NE(first_frame, run->truth.end()) << "no frame pose published";
  EXPECT_LT(first_frame->t, run->truth[0].t + 0.5) << "the first frames find the pose";
  // The kidnap: relocalized within a second.
  ASSERT_FALSE(relocalized_at.empty());
  EXPECT_GT(relocalized_at.back(), kKidnapS);
  EXPECT_LT(relocalized_at.back(), kKidnapS + 1.0) << "relocalized within a second of the kidnap";
  const double recovered_at = relocalized_at.back();
  // Every frame after the recovery tracks.
  int after_recovery = 0, tracking_after = 0;
  for (const geometry::StampedPose& truth : run->truth) {
    if (truth.t <= recovered_at) continue;
    const transport::PoseReport* pose = testing::PoseAt(published, truth.t);
    ++after_recovery;
    tracking_after += pose != nullptr && pose->state == tracking::LockState::kTracking;
  }
  EXPECT_EQ(tracking_after, after_recovery);
  EXPECT_GT(tracked_frames, 50);

  std::ifstream in(summary_path);
  ASSERT_TRUE(in.good()) << "no summary";
  const nlohmann::json reloc = nlohmann::json::parse(in)["relocalization"];
  EXPECT_EQ(reloc.value("found", 0), 2) << reloc.dump();
  EXPECT_EQ(reloc.value("index_version", 0), 1) << reloc.dump();
  EXPECT_EQ(reloc.value("chunks_rejected", 1), 0) << reloc.dump();
}

}  // namespace
}  // namespace fleetloc
