// Renders forward-camera images of a CorridorScene by ray casting through every (sub)pixel of the
// distorted image (so the lens distortion is exactly the camera model's), with Lambertian shading,
// an uneven light field, lens blur and the simulator's sensor model; and lists the landmarks whose
// vertical edges the camera sees, as ground truth for landmark detection.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "base/status.h"
#include "geometry/pose2.h"
#include "mapmatch/forward_camera.h"
#include "sim/corridor_scene.h"
#include "sim/sim_options.h"

namespace fleetloc::sim {

struct ForwardRenderOptions {
  int supersample = 2;         // k × k rays per pixel, averaged (anti-aliasing)
  double exposure_dn = 240.0;  // radiance of a white surface under full light, DN
  // Of these only lighting_amplitude, blur_sigma_px and the sensor fields (gain, bias, noise,
  // response) apply; the floor dust and grain fields are for the downward camera.
  RenderOptions photometric = DefaultPhotometric();

  static RenderOptions DefaultPhotometric() {
    RenderOptions options;
    options.lighting_amplitude = 0.25;
    options.blur_sigma_px = 0.6;
    return options;
  }
};

// InvalidInput naming the field.
Status Validate(const ForwardRenderOptions& options);

// A landmark whose vertical edge the camera sees.
struct VisibleLandmark {
  int index = 0;          // into CorridorScene::landmarks
  Eigen::Vector2d map;    // the landmark
  Eigen::Vector2d base;   // the same floor point in base_link
  Eigen::Vector2d pixel;  // its foot in the (distorted) image
  double range_m = 0.0;   // horizontal distance from the camera
  // The weakest radiance difference across the edge over its lowest edge_height_m, without light
  // field, blur or noise: how well the image can show the corner at all.
  double contrast_dn = 0.0;
};

struct VisibilityOptions {
  double margin_px = 10.0;     // the edge lies this far inside the image border
  double edge_height_m = 0.3;  // the edge is seen unoccluded from the floor up to this height
  double occlusion_tolerance_m = 0.02;
};

class ForwardRenderer {
 public:
  // Precomputes the base_link ray of every subpixel (undistortion of the whole image). The options
  // must be valid (checked).
  ForwardRenderer(const mapmatch::ForwardCamera& camera, const ForwardRenderOptions& options);

  // The CV_8UC1 image seen from base_link at `vehicle` (in map); `seed` draws the light field,
  // the sensor gain and bias and the noise.
  cv::Mat Render(const CorridorScene& scene, const geometry::Pose2& vehicle,
                 std::uint64_t seed) const;

  // The landmarks whose foot and edge up to edge_height_m are inside the image and unoccluded,
  // with their edges' contrast.
  std::vector<VisibleLandmark> VisibleLandmarks(const CorridorScene& scene,
                                                const geometry::Pose2& vehicle,
                                                const VisibilityOptions& options = {}) const;

 private:
  // The mean radiance over each pixel's subpixel rays (CV_32FC1, DN).
  cv::Mat Radiance(const CorridorScene& scene, const geometry::Pose2& vehicle) const;
  // Radiance along one map-frame ray (DN), 0 when it escapes.
  double RayRadiance(const CorridorScene& scene, const Eigen::Vector3d& origin,
                     const Eigen::Vector3d& direction) const;
  // VisibleLandmark::contrast_dn of the corner at `base` (base_link), sampled 3 px either side.
  double EdgeContrast(const CorridorScene& scene, const geometry::Pose2& vehicle,
                      const Eigen::Vector2d& base, double height_m) const;

  mapmatch::ForwardCamera camera_;
  ForwardRenderOptions options_;
  std::vector<Eigen::Vector3d> rays_;  // unit base_link directions, subpixel rows in image order
};

}  // namespace fleetloc::sim
