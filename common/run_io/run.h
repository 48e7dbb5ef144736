// Readers and writers for the files of docs/formats.md: camera.json, a run directory
// (run.json, frames.csv, odometry.csv, truth.csv, the optional forward/) and poses.csv. Every
// reader rejects a file that breaks the contract with a one-line message naming the file, the line
// and the field.
#pragma once

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "base/status.h"
#include "geometry/camera_model.h"
#include "geometry/pose2.h"
#include "mapmatch/forward_camera.h"

namespace fleetloc::run_io {

// The `raw` block of camera.json: an uncalibrated physical camera.
struct RawCamera {
  std::array<double, 9> K{};         // row-major intrinsics
  std::vector<double> dist;          // k1, k2, p1, p2, k3 (OpenCV order; 4, 5, 8, 12 or 14 values)
  std::array<double, 9> H_ground{};  // undistorted pixels → camera_ground metres
};

struct CameraFile {
  geometry::CameraModel model;
  std::optional<RawCamera> raw;
};

struct FrameRef {
  double t = 0.0;
  std::filesystem::path file;  // absolute (resolved against the run directory)
};

// The optional forward (landmark) camera of a run: its `forward/` directory (docs/formats.md,
// docs/forward_camera.md).
struct ForwardStream {
  mapmatch::ForwardCameraParams camera;      // forward/forward_camera.json
  std::vector<FrameRef> frames;              // forward/forward.csv, may be empty
  std::vector<geometry::StampedPose> truth;  // forward/truth.csv (simulated), empty if absent
};

struct Run {
  std::filesystem::path dir;
  std::string vehicle_id;
  CameraFile camera;
  geometry::Pose2 initial_pose;            // base_link in map at the first frame's time
  Eigen::Vector3d initial_sigma{0, 0, 0};  // 1-sigma x, y, theta
  std::vector<FrameRef> frames;
  std::vector<geometry::StampedPose> odometry;  // base_link in odom
  std::vector<geometry::StampedPose> truth;     // base_link in map, empty if absent
  std::optional<ForwardStream> forward;         // when the run has a forward/ directory
};

// One row of poses.csv (docs/formats.md).
struct PoseRecord {
  double t = 0.0;
  geometry::Pose2 pose;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  std::string status;  // tracking | coasting | lost | relocalized
  int inliers = 0;
};

// Every reader below returns NotFound "<file>: not found" for a missing file and InvalidInput
// "<file>[:<line>]: field '<name>': <what>" for a file that breaks the contract; writers write
// atomically (temporary file, then rename) and refuse, with InvalidInput and without writing,
// content their reader would reject (NaN, an unknown status, ...). Angles are wrapped to
// (-pi, pi] on read and on write. The per-table readers are in run_io/run_tables.h.

// camera.json: unknown members are ignored, known ones are checked (forward_camera.json has its
// own reader, run_io/forward_camera_json.h).
Result<CameraFile> ReadCameraJson(const std::filesystem::path& path);
Status WriteCameraJson(const std::filesystem::path& path, const CameraFile& camera);

// Reads and validates a whole run directory (not the images themselves: they are read lazily by
// the tracker with ReadFrame so that a bad image is reported with its file name), with its
// forward/ directory if there is one. frames.csv may have no rows when forward/forward.csv has
// some (a run without downward frames); odometry must cover the frames of both cameras.
Result<Run> ReadRun(const std::filesystem::path& dir);
// Writes run.json, camera.json, frames.csv, odometry.csv and (if non-empty) truth.csv. Frame
// files are written by the caller; FrameRef::file is written relative to the run directory.
Status WriteRun(const Run& run);

// Reads one frame as 8-bit gray; checks its size against the camera (in its header, before it is
// decoded).
Result<cv::Mat> ReadFrame(const FrameRef& frame, const geometry::CameraModel& camera);

// Reads an image file (PNG, JPEG, BMP or binary PNM; 8-bit or 16-bit, gray or colour) as 8-bit
// gray, without a size check beyond `max_pixels` (for raw frames, whose size is the physical
// camera's, and floor images), read from its header before decoding. NotFound "<file>: not found",
// InvalidInput "<file>: ..." for a larger, corrupt or unsupported file.
constexpr long long kMaxImagePixels = 100'000'000;
Result<cv::Mat> ReadGrayImage(const std::filesystem::path& path,
                              long long max_pixels = kMaxImagePixels);

// poses.csv: every number finite, t strictly ascending, variances non-negative, status one of
// the four names, inliers a non-negative integer. Written numbers round-trip exactly.
Result<std::vector<PoseRecord>> ReadPosesCsv(const std::filesystem::path& path);
Status WritePosesCsv(const std::filesystem::path& path, const std::vector<PoseRecord>& poses);

}  // namespace fleetloc::run_io
