// fleetctl calibrate: chessboard photographs of a raw downward camera → the `raw` block of
// camera.json (K, dist, H_ground; docs/formats.md). Prints a JSON summary on stdout.
#include <spdlog/spdlog.h>

#include <iostream>
#include <nlohmann/json.hpp>

#include "calibration/camera_calibration.h"
#include "commands.h"
#include "run_io/run.h"

namespace fleetloc::fleetctl {
namespace {

struct CalibrateArgs {
  std::vector<std::string> images;
  std::string floor_view;
  std::string board = "9x6";
  double square_m = 0.025;
  std::string
      camera;  // rectified model to keep (width, height, resolution, principal point, mount)
  std::string out;
};

Result<cv::Size> ParseBoard(const std::string& text) {
  int w = 0, h = 0;
  char x = 0;
  if (std::sscanf(text.c_str(), "%d%c%d", &w, &x, &h) != 3 || x != 'x' || w < 2 || h < 2) {
    return InvalidInput("--board: '" + text + "' is not COLSxROWS of inner corners (e.g. 9x6)");
  }
  return cv::Size(w, h);
}

Status RunCalibrate(const CalibrateArgs& a) {
  Result<cv::Size> inner = ParseBoard(a.board);
  if (!inner.ok()) return inner.status();
  const calibration::ChessboardSpec board{*inner, a.square_m};
  std::vector<cv::Mat> views;
  for (const std::string& path : a.images) {
    Result<cv::Mat> image = run_io::ReadGrayImage(path);
    if (!image.ok()) return image.status();
    views.push_back(*image);
  }
  Result<cv::Mat> floor = run_io::ReadGrayImage(a.floor_view);
  if (!floor.ok()) return floor.status();
  spdlog::info("calibrate: {} views, board {} inner corners of {} m", views.size(), a.board,
               a.square_m);
  Result<calibration::Intrinsics> intrinsics = calibration::CalibrateIntrinsics(views, board);
  if (!intrinsics.ok()) return InvalidInput("--images: " + intrinsics.status().message());
  Result<cv::Matx33d> H = calibration::GroundHomography(*floor, *intrinsics, board);
  if (!H.ok()) return InvalidInput(a.floor_view + ": " + H.status().message());
  run_io::CameraFile camera;
  if (!a.camera.empty()) {
    Result<run_io::CameraFile> base = run_io::ReadCameraJson(a.camera);
    if (!base.ok()) return base.status();
    camera = *base;
  }
  run_io::RawCamera raw;
  for (int i = 0; i < 9; ++i) {
    raw.K[i] = intrinsics->K.val[i];
    raw.H_ground[i] = H->val[i];
  }
  raw.dist = intrinsics->dist;
  camera.raw = raw;
  FLEETLOC_RETURN_IF_ERROR(run_io::WriteCameraJson(a.out, camera));
  nlohmann::json summary{{"out", a.out},
                         {"views", intrinsics->views},
                         {"images", a.images.size()},
                         {"rms_px", intrinsics->rms_px},
                         {"K", raw.K},
                         {"dist", raw.dist},
                         {"H_ground", raw.H_ground}};
  std::cout << summary.dump(2) << "\n";
  return Status::Ok();
}

}  // namespace

void RegisterCalibrateCommand(CLI::App& app, Status* result) {
  auto a = std::make_shared<CalibrateArgs>();
  CLI::App* cmd = app.add_subcommand(
      "calibrate", "Camera calibration from chessboard images into camera.json's raw block");
  cmd->option_defaults()->always_capture_default();
  cmd->add_option("--images", a->images, "Chessboard views (comma-separated; at least 3 boards)")
      ->required()
      ->delimiter(',');
  cmd->add_option("--floor-view", a->floor_view, "A view of the board lying on the floor")
      ->required();
  cmd->add_option("--board", a->board, "Inner corners, COLSxROWS");
  cmd->add_option("--square", a->square_m, "Square side in metres")->check(CLI::PositiveNumber);
  cmd->add_option("--camera", a->camera,
                  "camera.json whose rectified model to keep (default: 640x480, 0.5 mm/px)");
  cmd->add_option("--out", a->out, "camera.json to write")->required();
  cmd->callback([a, result] { *result = RunCalibrate(*a); });
}

}  // namespace fleetloc::fleetctl
