// fleetctl sim: make a simulated run (docs/formats.md) over a floor given as a mosaic or as an
// image with its resolution. Frames, odometry and truth come from the sim library; the run files
// are written with the io library. Progress goes to stderr, a JSON summary to stdout.
#include <spdlog/spdlog.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "commands.h"
#include "mosaic/tile_store.h"
#include "run_io/run.h"
#include "sim/run_simulator.h"
#include "support/parse_numbers.h"
#include "support/sim_run_writer.h"

namespace fleetloc::fleetctl {
namespace {

namespace fs = std::filesystem;

constexpr int kProgressEvery = 50;  // frames between progress lines
constexpr std::size_t kTileCacheBytes = 256 << 20;

struct SimArgs {
  std::string mosaic;
  std::string image;
  double resolution_m = 0.0;
  std::string origin;  // "X,Y"
  std::string out;
  bool overwrite = false;
  std::string camera;  // camera.json; default: width × height at the floor's resolution
  int width_px = 640;
  int height_px = 480;
  std::string vehicle_id = "sim-1";
  std::string route = "figure8";
  std::string initial_sigma = "0.002,0.002,0.5";  // metres, metres, degrees
  std::string gain = "0.85,1.15";
  std::string bias = "-8,8";
  double speed_m_s = 0.0;  // overrides speed_px_s when given (non-zero)
  double crab_deg = 0.0;
  double frame_jitter_ms = 1.0;
  double odometry_jitter_ms = 0.5;
  double heading_drift_deg_s = 0.2;
  double exposure_ms = 0.0;
  bool odom_at_origin = false;
  bool clean = false;
  sim::SimOptions options;
};

// The floor: an in-memory image or a mosaic file (its level 0), kept alive together.
struct Floor {
  std::shared_ptr<mosaic::TileStore> store;
  std::unique_ptr<mosaic::RasterSource> source;
};

Result<Floor> OpenImageFloor(const SimArgs& args) {
  if (!(args.resolution_m > 0)) {
    return InvalidInput("--resolution must be a positive number of metres per pixel");
  }
  Result<cv::Mat> image = run_io::ReadGrayImage(args.image);
  if (!image.ok()) return image.status();
  geometry::Geotransform geo{0.0, image->rows * args.resolution_m, args.resolution_m};
  if (!args.origin.empty()) {
    Result<std::vector<double>> origin = ParseNumbers(args.origin, 2, "--origin", "X,Y");
    if (!origin.ok()) return origin.status();
    geo.origin_x = (*origin)[0];
    geo.origin_y = (*origin)[1];
  }
  Floor floor;
  floor.source = std::make_unique<mosaic::ImageRasterSource>(std::move(*image), geo);
  return floor;
}

Result<Floor> OpenFloor(const SimArgs& args) {
  if (args.mosaic.empty() == args.image.empty()) {
    return InvalidInput("give the floor as exactly one of --mosaic or --image");
  }
  if (!args.image.empty()) return OpenImageFloor(args);
  if (!args.origin.empty() || args.resolution_m != 0.0) {
    return InvalidInput("--origin and --resolution apply to --image only (a mosaic has its own)");
  }
  Result<std::unique_ptr<mosaic::TileStore>> opened =
      mosaic::TileStore::Open(args.mosaic, mosaic::OpenMode::kReadOnly);
  if (!opened.ok()) return opened.status();
  Floor floor;
  floor.store = std::move(*opened);
  floor.source = std::make_unique<mosaic::MosaicView>(
      floor.store->layout(), mosaic::MakeTileLoader(floor.store),
      std::make_shared<mosaic::TileCache>(kTileCacheBytes));
  return floor;
}

// camera.json when given, else the default camera (principal point at the centre, mounted 0.40 m
// ahead of base_link) at the floor's resolution.
Result<run_io::CameraFile> LoadCamera(const SimArgs& args, double floor_resolution_m) {
  if (!args.camera.empty()) return run_io::ReadCameraJson(args.camera);
  return DefaultSimCamera(args.width_px, args.height_px, floor_resolution_m);
}

// Completes args.options from the options given in other units or as lists.
Status ResolveOptions(SimArgs* args, double floor_resolution_m) {
  sim::SimOptions& o = args->options;
  if (args->route == "figure8") {
    o.route.shape = sim::RouteShape::kFigureEight;
  } else if (args->route == "rectangle") {
    o.route.shape = sim::RouteShape::kRoundedRectangle;
  } else {
    return InvalidInput("--route '" + args->route + "': expected figure8 or rectangle");
  }
  if (args->speed_m_s != 0) o.route.speed_px_s = args->speed_m_s / floor_resolution_m;
  o.route.crab_rad = args->crab_deg * M_PI / 180.0;
  o.timing.frame_jitter_s = args->frame_jitter_ms * 1e-3;
  o.timing.odometry_jitter_s = args->odometry_jitter_ms * 1e-3;
  o.odometry.heading_drift_rad_s = args->heading_drift_deg_s * M_PI / 180.0;
  if (args->odom_at_origin) o.odometry.start_pose = geometry::Pose2{};
  o.render.exposure_s = args->exposure_ms * 1e-3;
  Result<std::vector<double>> sigma =
      ParseNumbers(args->initial_sigma, 3, "--initial-sigma", "SX_M,SY_M,STHETA_DEG");
  Result<std::vector<double>> gain = ParseNumbers(args->gain, 2, "--gain", "MIN,MAX");
  Result<std::vector<double>> bias = ParseNumbers(args->bias, 2, "--bias", "MIN,MAX");
  for (const Status& s : {sigma.status(), gain.status(), bias.status()}) {
    FLEETLOC_RETURN_IF_ERROR(s);
  }
  o.initial_pose.sigma = {(*sigma)[0], (*sigma)[1], (*sigma)[2] * M_PI / 180.0};
  o.render.gain_min = (*gain)[0];
  o.render.gain_max = (*gain)[1];
  o.render.bias_min_dn = (*bias)[0];
  o.render.bias_max_dn = (*bias)[1];
  if (args->clean) o = sim::CleanSimOptions(o);
  return sim::Validate(o);
}

nlohmann::ordered_json SummaryJson(const sim::SimSummary& s, const SimArgs& args,
                                   const FrameTimes& times) {
  const double frames = std::max(1, s.frames);
  return {{"out", args.out},
          {"seed", args.options.seed},
          {"frames", s.frames},
          {"duration_s", s.duration_s},
          {"speed_px_s", s.speed_px_s},
          {"speed_m_s", s.speed_m_s},
          {"distance_m", s.distance_m},
          {"route_length_m", s.route_length_m},
          {"laps", s.laps},
          {"route_margin_m", s.route_margin_m},
          {"overlapping_pairs_fraction", s.overlapping_pairs_fraction},
          {"mean_pair_overlap", s.mean_pair_overlap},
          {"floor_fraction_seen", s.floor_fraction_seen},
          {"min_frame_on_floor", s.min_frame_on_floor},
          {"odometry_drift_m", s.odometry_drift_m},
          {"odometry_drift_rad", s.odometry_drift_rad},
          {"render_ms_per_frame", times.render_ms / frames},
          {"write_wait_ms_per_frame", times.write_wait_ms / frames}};
}

Status RunSim(SimArgs& args) {
  Result<Floor> floor = OpenFloor(args);
  if (!floor.ok()) return floor.status();
  const double floor_resolution_m = floor->source->layout().geo.resolution;
  Result<run_io::CameraFile> camera = LoadCamera(args, floor_resolution_m);
  if (!camera.ok()) return camera.status();
  FLEETLOC_RETURN_IF_ERROR(ResolveOptions(&args, floor_resolution_m));
  Result<std::unique_ptr<sim::RunSimulator>> simulator =
      sim::RunSimulator::Create(floor->source.get(), camera->model, args.options);
  if (!simulator.ok()) return simulator.status();
  const fs::path dir = fs::absolute(args.out);
  FLEETLOC_RETURN_IF_ERROR(PrepareRunDir(dir, args.overwrite));
  FrameTimes times;
  const auto progress = [](int done, int total) {
    if (done % kProgressEvery == 0 || done == total) spdlog::info("sim: {}/{} frames", done, total);
  };
  Result<run_io::Run> run =
      WriteSimulatedRun(**simulator, *camera, dir, args.vehicle_id, progress, &times);
  if (!run.ok()) return run.status();
  std::cout << SummaryJson((*simulator)->summary(), args, times).dump(2) << "\n";
  return Status::Ok();
}

void AddFloorAndOutputOptions(CLI::App* sim, SimArgs* a) {
  sim->add_option("--mosaic", a->mosaic, "Floor: a mosaic file (its level 0)");
  sim->add_option("--image", a->image, "Floor: an image file (read as 8-bit gray)");
  sim->add_option("--resolution", a->resolution_m, "Metres per pixel of --image");
  sim->add_option("--origin", a->origin,
                  "X,Y map coordinates of --image's top-left corner (default 0,height*resolution)");
  sim->add_option("--out", a->out, "Run directory to create")->required();
  sim->add_flag("--overwrite", a->overwrite, "Replace the run files in an existing directory");
  sim->add_option("--camera", a->camera, "camera.json (default: --width x --height, pp centred)");
  sim->add_option("--width", a->width_px, "Frame width without --camera")
      ->check(CLI::Range(8, 16384));
  sim->add_option("--height", a->height_px, "Frame height without --camera")
      ->check(CLI::Range(8, 16384));
  sim->add_option("--vehicle-id", a->vehicle_id, "run.json vehicle_id");
  sim->add_option("--seed", a->options.seed, "Random seed (same seed, same run)");
  sim->add_flag(
      "--clean", a->clean,
      "Everything off: no photometric effects, exact odometry, no jitter or perturbation");
}

void AddMotionOptions(CLI::App* sim, SimArgs* a) {
  sim::SimOptions& o = a->options;
  sim->add_option("--frames", o.timing.frames, "Number of frames");
  sim->add_option("--rate-hz", o.timing.frame_rate_hz, "Frame rate");
  sim->add_option("--odom-rate-hz", o.timing.odometry_rate_hz, "Odometry rate (>= frame rate)");
  sim->add_option("--start-time", o.timing.start_time_s, "Time of the first odometry sample, s");
  sim->add_option("--frame-jitter-ms", a->frame_jitter_ms, "Uniform ± jitter of frame times");
  sim->add_option("--odom-jitter-ms", a->odometry_jitter_ms, "Uniform ± jitter of odometry times");
  sim->add_option("--route", a->route, "figure8 or rectangle");
  sim->add_option("--speed-px-s", o.route.speed_px_s, "Footprint speed, floor pixels per second");
  sim->add_option("--speed-m-s", a->speed_m_s, "Footprint speed in m/s (overrides --speed-px-s)");
  sim->add_option("--speed-variation", o.route.speed_variation_fraction,
                  "Relative sinusoidal speed variation (0..0.9)");
  sim->add_option("--crab-deg", a->crab_deg, "Heading minus direction of travel");
  sim->add_option("--min-floor-overlap", o.route.min_floor_overlap_fraction,
                  "Share of every frame that must lie on the floor");
  sim->add_option("--start-fraction", o.route.start_fraction, "Start point along the route (0..1)");
  sim->add_option(
      "--kidnap-at", o.kidnap.at_s,
      "Kidnap the vehicle this many seconds after the start (frames jump, odometry does not)");
  sim->add_option("--kidnap-jump", o.kidnap.jump_fraction, "How far it is carried, in laps (0..1)");
}

void AddOdometryOptions(CLI::App* sim, SimArgs* a) {
  sim::OdometryOptions& o = a->options.odometry;
  sim->add_option("--odom-scale-error", o.distance_scale_error, "Relative distance error");
  sim->add_option("--odom-turn-error", o.heading_scale_error, "Relative turn error");
  sim->add_option("--odom-drift-deg-s", a->heading_drift_deg_s, "Heading bias, deg/s");
  sim->add_option("--odom-distance-noise", o.distance_noise_m_per_sqrt_m, "m per sqrt(m)");
  sim->add_option("--odom-heading-noise", o.heading_noise_rad_per_sqrt_s, "rad per sqrt(s)");
  sim->add_flag("--odom-at-origin", a->odom_at_origin, "Start odom at (0,0,0), not at truth");
  sim->add_option("--initial-sigma", a->initial_sigma, "SX_M,SY_M,STHETA_DEG of initial_pose");
  sim->add_flag("!--no-initial-perturb", a->options.initial_pose.perturb,
                "initial_pose = truth (sigma still written)");
}

void AddRenderOptions(CLI::App* sim, SimArgs* a) {
  sim::RenderOptions& o = a->options.render;
  sim->add_option("--supersample", o.supersample, "Area-sensor supersampling factor");
  sim->add_option("--floor-grain", o.floor_grain_dn,
                  "Floor-attached pixel noise the mosaic lacks (its capture noise), DN");
  sim->add_option("--dust", o.dust_fraction, "Share of the floor covered by dust and grime");
  sim->add_option("--lighting", o.lighting_amplitude, "Relative amplitude of uneven lighting");
  sim->add_option("--blur-sigma-px", o.blur_sigma_px, "Lens blur (Gaussian sigma)");
  sim->add_option("--exposure-ms", a->exposure_ms, "Exposure time for motion blur (0: none)");
  sim->add_option("--vignetting", o.vignetting_corner_loss, "Brightness lost at the corners");
  sim->add_option("--gain", a->gain, "MIN,MAX per-frame gain");
  sim->add_option("--bias", a->bias, "MIN,MAX per-frame bias, DN");
  sim->add_option("--noise-sigma", o.noise_sigma_dn, "Read noise sigma, DN");
  sim->add_option("--shot-noise", o.shot_noise_dn, "Shot-noise variance per DN of signal");
  sim->add_option("--gamma", o.response_gamma, "Camera response exponent");
  sim->add_option("--s-curve", o.response_s_curve, "Camera response S-curve weight (0..1)");
  sim->add_option(
      "--jpeg-quality", o.jpeg_quality,
      "JPEG-encode each frame at this quality, as a streaming camera (1..100; 0: none)");
}

}  // namespace

void RegisterSimCommand(CLI::App& app, Status* result) {
  auto args = std::make_shared<SimArgs>();
  CLI::App* sim = app.add_subcommand("sim", "Make a simulated run over a floor mosaic or image");
  sim->option_defaults()->always_capture_default();  // --help shows every default
  AddFloorAndOutputOptions(sim, args.get());
  AddMotionOptions(sim, args.get());
  AddOdometryOptions(sim, args.get());
  AddRenderOptions(sim, args.get());
  sim->callback([args, result] { *result = RunSim(*args); });
}

}  // namespace fleetloc::fleetctl
