// The corridor layout (see corridor_scene.h). Walls are 0.5 m thick boxes; every landmark is a
// vertex of some solid's footprint, so it is exactly where the rendered edge meets the floor.
//
//   left wall  (y > W): door A, door B, low cabinet
//   right wall (y < -W): cupboard, door C, alcove; a rail and posters above the floor
//   in the corridor: a pillar and a bin with slanted sides (clutter)
#include "sim/corridor_scene.h"

#include <algorithm>
#include <cmath>
#include <opencv2/core.hpp>
#include <string>

namespace fleetloc::sim {
namespace {

constexpr double kWallThickness = 0.5;
constexpr double kWallHeight = 2.5;
constexpr double kDoorWidth = 0.9;
constexpr double kDoorHeight = 2.1;
constexpr double kDoorRecess = 0.1;  // door leaf behind the wall face
constexpr double kWallAlbedo = 0.72;
constexpr double kDoorLeafAlbedo = 0.6;  // light wood: darker than the wall, brighter than a reveal
constexpr double kStainClearance = 0.3;  // between a stain's rim and any landmark

// Axis-aligned box [x0, x1] × [y0, y1] × [z0, z1].
Solid Box(double x0, double x1, double y0, double y1, double z0, double z1, double albedo) {
  Solid solid;
  solid.albedo = albedo;
  solid.faces = {{Eigen::Vector3d::UnitX(), x1}, {-Eigen::Vector3d::UnitX(), -x0},
                 {Eigen::Vector3d::UnitY(), y1}, {-Eigen::Vector3d::UnitY(), -y0},
                 {Eigen::Vector3d::UnitZ(), z1}, {-Eigen::Vector3d::UnitZ(), -z0}};
  return solid;
}

// A square bin standing on the floor, wider at the top: its silhouette edges are slanted.
Solid Frustum(const Eigen::Vector2d& center, double bottom_half, double top_half, double height,
              double albedo) {
  Solid solid;
  solid.albedo = albedo;
  solid.faces = {{Eigen::Vector3d::UnitZ(), height}, {-Eigen::Vector3d::UnitZ(), 0.0}};
  const double slope = (top_half - bottom_half) / height;  // outward per metre of height
  for (const Eigen::Vector2d& side : {Eigen::Vector2d(1, 0), Eigen::Vector2d(-1, 0),
                                      Eigen::Vector2d(0, 1), Eigen::Vector2d(0, -1)}) {
    // side · (p - center) - slope · z <= bottom_half, normalized.
    const Eigen::Vector3d n(side.x(), side.y(), -slope);
    const double offset = bottom_half + side.dot(center);
    solid.faces.push_back({n / n.norm(), offset / n.norm()});
  }
  return solid;
}

Solid Wall(double x0, double x1, double y0, double y1) {
  Solid wall = Box(x0, x1, y0, y1, 0.0, kWallHeight, kWallAlbedo);
  wall.baseboard = true;
  return wall;
}

class LayoutBuilder {
 public:
  LayoutBuilder(const CorridorSceneOptions& options, CorridorScene* scene)
      : options_(options), scene_(scene), rng_(options.seed), w_(options.width_m / 2) {}

  double Jitter(double x) { return x + rng_.uniform(-options_.jitter_m, options_.jitter_m); }

  void Landmarks(std::initializer_list<Eigen::Vector2d> corners) {
    scene_->landmarks.insert(scene_->landmarks.end(), corners);
  }

  // The end walls close the corridor; their corridor-side vertices are concave corners.
  void EndWalls() {
    const double length = options_.length_m;
    scene_->solids.push_back(Wall(-kWallThickness, 0.0, -w_, w_));
    scene_->solids.push_back(Wall(length, length + kWallThickness, -w_, w_));
    Landmarks({{0.0, -w_}, {0.0, w_}, {length, -w_}, {length, w_}});
  }

  // A side wall from x = -thickness to length + thickness with door openings (start x, width
  // kDoorWidth) and one alcove; `side` is +1 (left) or -1 (right).
  void SideWall(int side, const std::vector<double>& doors, std::optional<double> alcove_x) {
    const double face = side * w_, back = side * (w_ + kWallThickness);
    const double y0 = std::min(face, back), y1 = std::max(face, back);
    std::vector<std::pair<double, double>> gaps;
    for (double x : doors) gaps.emplace_back(x, x + kDoorWidth);
    if (alcove_x) gaps.emplace_back(*alcove_x, *alcove_x + 1.0);
    std::sort(gaps.begin(), gaps.end());
    double x = -kWallThickness;
    for (const auto& [g0, g1] : gaps) {
      scene_->solids.push_back(Wall(x, g0, y0, y1));
      Landmarks({{g0, face}, {g1, face}});
      x = g1;
    }
    scene_->solids.push_back(Wall(x, options_.length_m + kWallThickness, y0, y1));
    for (double door : doors) Door(side, door);
    if (alcove_x) Alcove(side, *alcove_x);
  }

  // A dark door leaf recessed behind the wall face, and the lintel above the opening.
  void Door(int side, double x0) {
    const double x1 = x0 + kDoorWidth, leaf = side * (w_ + kDoorRecess);
    const double leaf_back = side * (w_ + kDoorRecess + 0.05);
    scene_->solids.push_back(Box(x0, x1, std::min(leaf, leaf_back), std::max(leaf, leaf_back), 0,
                                 kDoorHeight, kDoorLeafAlbedo));
    const double face = side * w_, back = side * (w_ + kWallThickness);
    scene_->solids.push_back(Box(x0, x1, std::min(face, back), std::max(face, back), kDoorHeight,
                                 kWallHeight, kWallAlbedo));
    Landmarks({{x0, leaf}, {x1, leaf}});
  }

  // A 1 m wide, 0.35 m deep alcove: its back wall fills the rest of the wall's thickness.
  void Alcove(int side, double x0) {
    const double depth = side * (w_ + 0.35), back = side * (w_ + kWallThickness);
    scene_->solids.push_back(Wall(x0, x0 + 1.0, std::min(depth, back), std::max(depth, back)));
    Landmarks({{x0, depth}, {x0 + 1.0, depth}});
  }

  // A box standing against a wall (or free, for a pillar) whose four footprint corners are
  // landmarks.
  void Furniture(double x0, double x1, double y0, double y1, double height, double albedo) {
    scene_->solids.push_back(Box(x0, x1, y0, y1, 0.0, height, albedo));
    Landmarks({{x0, y0}, {x1, y0}, {x0, y1}, {x1, y1}});
  }

  // Not in the map: posters and a rail that do not reach the floor, a bin with slanted sides.
  void Clutter() {
    const double poster_a = Jitter(5.6), poster_b = Jitter(8.3), bin_x = Jitter(8.0);
    scene_->solids.push_back(Box(poster_a, poster_a + 0.8, w_ - 0.01, w_, 1.0, 1.7, 0.15));
    scene_->solids.push_back(Box(poster_b, poster_b + 0.6, -w_, -w_ + 0.01, 1.2, 1.9, 0.95));
    scene_->solids.push_back(Box(7.6, 10.0, -w_, -w_ + 0.05, 0.85, 0.92, 0.25));
    scene_->solids.push_back(Frustum({bin_x, 0.5}, 0.14, 0.2, 0.65, 0.3));
  }

  // Stains keep clear of the landmarks' edges: a stain across a corner's foot hides it, which
  // no detector can undo (the map fit copes with missing points).
  void Stains() {
    while (static_cast<int>(scene_->stains.size()) < options_.stains) {
      const int surface = rng_.uniform(0, 3);  // floor, left wall, right wall
      const double x = rng_.uniform(0.0, options_.length_m);
      const Eigen::Vector3d center =
          surface == 0 ? Eigen::Vector3d(x, rng_.uniform(-w_, w_), 0.0)
                       : Eigen::Vector3d(x, surface == 1 ? w_ : -w_, rng_.uniform(0.2, 2.2));
      const Stain stain{center, rng_.uniform(0.05, 0.25), rng_.uniform(0.25, 0.6)};
      if (!NearALandmark(stain)) scene_->stains.push_back(stain);
    }
  }

  bool NearALandmark(const Stain& stain) const {
    const Eigen::Vector2d xy = stain.center.head<2>();
    return std::any_of(scene_->landmarks.begin(), scene_->landmarks.end(),
                       [&](const Eigen::Vector2d& l) {
                         return (l - xy).norm() < stain.radius_m + kStainClearance;
                       });
  }

  double half_width() const { return w_; }

 private:
  const CorridorSceneOptions& options_;
  CorridorScene* scene_;
  cv::RNG rng_;
  double w_;
};

}  // namespace

Status Validate(const CorridorSceneOptions& options) {
  if (!(options.length_m >= 16.0)) {
    return InvalidInput("corridor scene: length_m must be >= 16 (the layout's extent)");
  }
  if (!(options.width_m >= 1.5 && options.width_m <= 6.0)) {
    return InvalidInput("corridor scene: width_m must be in [1.5, 6]");
  }
  if (!(options.jitter_m >= 0.0 && options.jitter_m <= 0.45)) {
    return InvalidInput("corridor scene: jitter_m must be in [0, 0.45] (keeps features apart)");
  }
  if (options.stains < 0) return InvalidInput("corridor scene: stains must be >= 0");
  return Status::Ok();
}

CorridorScene BuildCorridorScene(const CorridorSceneOptions& options) {
  FLEETLOC_CHECK(Validate(options).ok());
  CorridorScene scene;
  LayoutBuilder layout(options, &scene);
  const double w = layout.half_width();
  layout.EndWalls();
  const double door_a = layout.Jitter(2.8), door_b = layout.Jitter(9.0);
  const double door_c = layout.Jitter(6.4), alcove = layout.Jitter(11.2);
  layout.SideWall(+1, {door_a, door_b}, std::nullopt);
  layout.SideWall(-1, {door_c}, alcove);
  const double cupboard = layout.Jitter(3.4), cabinet = layout.Jitter(12.6);
  const double pillar = layout.Jitter(14.2);
  layout.Furniture(cupboard, cupboard + 1.2, -w, -w + 0.6, 2.0, 0.3);
  layout.Furniture(cabinet, cabinet + 0.8, w - 0.5, w, 0.9, 0.3);
  layout.Furniture(pillar - 0.15, pillar + 0.15, -0.45, -0.15, kWallHeight, 0.62);
  layout.Clutter();
  layout.Stains();
  return scene;
}

}  // namespace fleetloc::sim
