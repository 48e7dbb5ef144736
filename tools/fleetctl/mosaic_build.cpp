// Mapping run → mosaic file: run reading, frame loading, blending rows into the tile store.
#include "mosaic_build.h"

#include <spdlog/spdlog.h>

#include <chrono>
#include <cmath>

#include "mosaic/importer.h"
#include "run_io/run.h"
#include "tracking/odometry_history.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The blended canvas as importer rows, top to bottom.
class BlendedRowReader : public mosaic::GrayRowReader {
 public:
  explicit BlendedRowReader(const mapping::MosaicBlender& blender) : blender_(blender) {
    width_px_ = blender.canvas().width_px;
    height_px_ = blender.canvas().height_px;
  }
  bool streaming() const override { return true; }
  Status ReadRow(std::span<std::uint8_t> row) override {
    blender_.Row(next_row_++, row);
    return Status::Ok();
  }

 private:
  const mapping::MosaicBlender& blender_;
  int next_row_ = 0;
};

// base_link's odometry pose at each frame's time, interpolated as the tracker does.
Result<mapping::MapperInput> MapperInputOf(const run_io::Run& run) {
  tracking::OdometryHistory odometry(1e12, 0.0);
  const std::string odometry_csv = (run.dir / "odometry.csv").string();
  for (const geometry::StampedPose& sample : run.odometry) {
    const Status added = odometry.Add(sample);
    if (!added.ok()) return InvalidInput(odometry_csv + ": " + added.message());
  }
  mapping::MapperInput input;
  input.camera = run.camera.model;
  input.initial_base_in_map = run.initial_pose;
  for (const run_io::FrameRef& frame : run.frames) {
    Result<geometry::Pose2> odom = odometry.At(frame.t);
    if (!odom.ok()) return InvalidInput(odometry_csv + ": " + odom.status().message());
    input.frame_times_s.push_back(frame.t);
    input.odometry.push_back(*odom);
  }
  return input;
}

MappedAccuracy Accuracy(const run_io::Run& run, const std::vector<geometry::Pose2>& cameras) {
  MappedAccuracy a;
  double sum_sq = 0.0, heading_sq = 0.0;
  for (size_t k = 0; k < cameras.size(); ++k) {
    const geometry::Pose2 truth = run.truth[k].pose * run.camera.model.mount;
    const double error_px =
        std::hypot(cameras[k].x - truth.x, cameras[k].y - truth.y) / run.camera.model.resolution_m;
    sum_sq += error_px * error_px;
    a.camera_position_max_px = std::max(a.camera_position_max_px, error_px);
    heading_sq += std::pow(geometry::WrapAngle(cameras[k].theta - truth.theta), 2);
  }
  a.camera_position_rms_px = std::sqrt(sum_sq / cameras.size());
  a.heading_rms_rad = std::sqrt(heading_sq / cameras.size());
  return a;
}

Status Blend(const run_io::Run& run, const std::vector<geometry::Pose2>& cameras,
             mapping::MosaicBlender* blender) {
  const int frames = static_cast<int>(run.frames.size());
  for (int k = 0; k < frames; ++k) {
    Result<cv::Mat> frame = run_io::ReadFrame(run.frames[k], run.camera.model);
    if (!frame.ok()) return frame.status();
    blender->Add(*frame, cameras[k]);
    if ((k + 1) % std::max(1, frames / 10) == 0 || k + 1 == frames) {
      spdlog::info("blended {}/{} frames", k + 1, frames);
    }
  }
  return Status::Ok();
}

Result<mosaic::MosaicLayout> WriteMosaic(const mapping::MosaicBlender& blender,
                                         const std::string& out_db) {
  BlendedRowReader rows(blender);
  mosaic::ImportOptions import;
  import.resolution_m = blender.canvas().geo.resolution;
  import.origin_x_m = blender.canvas().geo.origin_x;
  import.origin_y_m = blender.canvas().geo.origin_y;
  int last_tenth = -1;
  return mosaic::ImportRows(rows, import, out_db, [&last_tenth](int done, int total) {
    const int tenth = static_cast<int>(10LL * done / total);
    if (tenth == last_tenth) return;
    last_tenth = tenth;
    spdlog::info("blending rows into tiles: {}/{}", done, total);
  });
}

}  // namespace

Result<MosaicBuildSummary> BuildMosaicFromRun(const fs::path& run_dir, const std::string& out_db,
                                              const MosaicBuildOptions& options) {
  FLEETLOC_RETURN_IF_ERROR(mapping::Validate(options.mapper));
  FLEETLOC_RETURN_IF_ERROR(mapping::Validate(options.blend));
  FLEETLOC_RETURN_IF_ERROR(mosaic::CheckNewMosaicPath(out_db));
  Result<run_io::Run> run = run_io::ReadRun(run_dir);
  if (!run.ok()) return run.status();
  Result<mapping::MapperInput> input = MapperInputOf(*run);
  if (!input.ok()) return input.status();
  MosaicBuildSummary summary;
  summary.frames = static_cast<int>(run->frames.size());
  auto start = Clock::now();
  const mapping::FrameLoader load = [&run](int k) {
    return run_io::ReadFrame(run->frames.at(k), run->camera.model);
  };
  Result<mapping::MappedRun> mapped = mapping::MapRun(
      *input, load, options.mapper, [](const std::string& line) { spdlog::info("{}", line); });
  if (!mapped.ok()) {
    return Status(mapped.status().code(), run->dir.string() + ": " + mapped.status().message());
  }
  summary.mapped = std::move(*mapped);
  summary.mapping_s = SecondsSince(start);
  if (!run->truth.empty()) summary.accuracy = Accuracy(*run, summary.mapped.camera_in_map);

  Result<mapping::Canvas> canvas =
      mapping::CanvasFor(summary.mapped.camera_in_map, run->camera.model, options.blend);
  if (!canvas.ok())
    return Status(canvas.status().code(), run->dir.string() + ": " + canvas.status().message());
  summary.canvas = *canvas;
  start = Clock::now();
  mapping::MosaicBlender blender(*canvas, run->camera.model, options.blend);
  summary.canvas_bytes = blender.canvas_bytes();
  spdlog::info("blending canvas {} x {} px ({:.1f} MiB of floats)", canvas->width_px,
               canvas->height_px, summary.canvas_bytes / double(1 << 20));
  FLEETLOC_RETURN_IF_ERROR(Blend(*run, summary.mapped.camera_in_map, &blender));
  summary.blending_s = SecondsSince(start);
  start = Clock::now();
  Result<mosaic::MosaicLayout> layout = WriteMosaic(blender, out_db);
  if (!layout.ok()) return layout.status();
  summary.layout = *layout;
  summary.writing_s = SecondsSince(start);
  return summary;
}

nlohmann::ordered_json BuildSummaryJson(const MosaicBuildSummary& s) {
  const mapping::MappedRun& m = s.mapped;
  nlohmann::ordered_json json{
      {"frames", s.frames},
      {"pairs_tried", m.pairs_tried},
      {"pairs_registered", m.pairs_registered},
      {"successive_registered", m.successive_registered},
      {"odometry_bridges", m.odometry_bridges},
      {"loop_candidates", m.loop_candidates},
      {"loop_closures", m.loop_registered - m.loop_pruned},
      {"loop_closures_pruned", m.loop_pruned},
      {"loop_closures_far_from_prediction", m.loop_outside_gate},
      {"solver_iterations", nlohmann::json::array()},
      {"mosaic_px", {s.layout.width_px, s.layout.height_px}},
      {"origin", {s.layout.geo.origin_x, s.layout.geo.origin_y}},
      {"resolution", s.layout.geo.resolution},
      {"levels", s.layout.levels},
      {"canvas_bytes", s.canvas_bytes},
      {"seconds",
       {{"mapping", s.mapping_s}, {"blending", s.blending_s}, {"writing", s.writing_s}}}};
  for (const mapping::PoseGraphSolveSummary& solve : m.solves) {
    json["solver_iterations"].push_back(solve.iterations);
  }
  if (s.accuracy) {
    json["truth"] = {{"camera_position_rms_px", s.accuracy->camera_position_rms_px},
                     {"camera_position_max_px", s.accuracy->camera_position_max_px},
                     {"heading_rms_rad", s.accuracy->heading_rms_rad}};
  }
  return json;
}

}  // namespace fleetloc::fleetctl
