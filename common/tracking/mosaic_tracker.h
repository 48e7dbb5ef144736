// The mosaic tracker cycle (paper 000 §2, docs/architecture.md): one call per camera frame turns
// the frame, its capture time and the odometry pose at that time into base_link's pose in map.
#pragma once

#include <opencv2/core.hpp>
#include <optional>

#include "geometry/camera_model.h"
#include "mosaic/raster_source.h"
#include "tracking/direct_aligner.h"
#include "tracking/feature_selection.h"
#include "tracking/frame_localizer.h"
#include "tracking/frame_pyramid.h"
#include "tracking/internal_estimate.h"
#include "tracking/normalized_mosaic.h"
#include "tracking/pose_update.h"
#include "tracking/template_matcher.h"
#include "tracking/tracker_options.h"

namespace fleetloc::tracking {

class MosaicTracker : public FrameLocalizer {
 public:
  // `mosaic` must outlive the tracker. Options must have passed Validate().
  MosaicTracker(const TrackerOptions& options, const geometry::CameraModel& camera,
                mosaic::RasterSource* mosaic);

  // Starts tracking from base_link's pose in map (with covariance) at the time whose odometry
  // pose is `odom`.
  std::string name() const override { return "fleetloc"; }
  void Reset(const geometry::PoseWithCovariance& base_in_map, const geometry::Pose2& odom) override;

  // One cycle. `frame` is the rectified CV_8UC1 image (camera size), `odom` base_link in odom
  // at time t (interpolated by the caller). Reset() must have been called.
  FrameResult Track(const cv::Mat& frame, double t, const geometry::Pose2& odom) override {
    return Track(frame, t, odom, 0.0);
  }
  // The same with `odom` extrapolated `extrapolated_s` past the newest odometry sample (a live
  // frame that did not wait for odometry): the prediction's covariance grows accordingly.
  FrameResult Track(const cv::Mat& frame, double t, const geometry::Pose2& odom,
                    double extrapolated_s);
  // The odometry pose at the last frame's time t, extrapolated then, is now known: the next
  // prediction starts from it (InternalEstimate::CorrectOdometry).
  void CorrectOdometry(double t, const geometry::Pose2& odom) {
    estimate_.CorrectOdometry(t, odom);
  }

  // Odometry-only step (a frame that could not be read or used): the pose coasts.
  FrameResult Coast(double t, const geometry::Pose2& odom) override;

  // Normalizes at most `max_tiles` of the mosaic tiles a frame at `base_in_map` would search (its
  // footprint grown by the search radius of the pose's covariance, at the levels that radius is
  // searched at) that are not normalized yet: the first frame's first-use work, done ahead a few
  // tiles at a time (e.g. while the vehicle waits for its camera). Tiles not loaded yet are loaded
  // through the raster source. Returns how many it normalized (fewer than max_tiles: all are);
  // the tracker's state is unchanged.
  int WarmUp(const geometry::PoseWithCovariance& base_in_map, int max_tiles);

  // Forgets the normalized tiles computed from `changed` tiles of the mosaic (a new mosaic
  // version changed them): those tiles and their neighbours, whose margins read them.
  void DropTiles(const std::vector<mosaic::TileKey>& changed);

 private:
  // A site with its normalized template at the level it is matched at.
  struct PreparedSite {
    TemplateSite site;
    cv::Mat templ;
  };
  struct Measured {
    std::vector<PreparedSite> sites;
    std::vector<Correspondence> matches;
  };
  int MaxSearchRadius() const;
  int SearchRadius(const geometry::PoseWithCovariance& camera, const Eigen::Vector2d& px) const;
  // Template sizes (level-0 px) of one matching attempt: full resolution and coarse levels.
  struct TemplateScale {
    int size_px = 0;
    int coarse_size_px = 0;
  };
  // `texture`: the half-resolution frame's texture score at the candidate grid.
  std::vector<TemplateSite> ChooseSites(const cv::Mat& texture, const geometry::Pose2& camera,
                                        int radius_px, int template_size_px) const;
  std::vector<PreparedSite> Prepare(const cv::Mat& frame_at_level,
                                    const std::vector<TemplateSite>& sites, int size_px,
                                    int level) const;
  // Matches sites at a pyramid level around `camera`; each site searches its own 3-sigma
  // radius, or fixed_radius_px (level pixels) when > 0, and a site not found there searches
  // retry_radius_px when that is larger.
  Measured MatchSites(const std::vector<PreparedSite>& sites,
                      const geometry::PoseWithCovariance& camera, int fixed_radius_px, int level,
                      int retry_radius_px = 0) const;
  PoseUpdate Update(const geometry::PoseWithCovariance& prior, const Measured& measured,
                    int level) const;
  // Keeps the sites the update kept.
  static std::vector<PreparedSite> Inliers(const Measured& measured, const PoseUpdate& update);
  int FrameSearchRadius(const geometry::PoseWithCovariance& prior) const;
  std::optional<geometry::PoseWithCovariance> MatchTemplates(
      FramePyramid* pyramid, const geometry::PoseWithCovariance& prior, int frame_radius,
      bool weak_first, FrameResult* stats) const;
  std::optional<geometry::PoseWithCovariance> MatchTemplatesAt(
      FramePyramid* pyramid, const cv::Mat& texture, const geometry::PoseWithCovariance& prior,
      int frame_radius, const TemplateScale& scale, FrameResult* stats) const;
  int CoarseLevels(int frame_radius) const;
  void ChooseTemplateSizeAfter(int locked_size_px, bool weak_went_first);
  std::optional<geometry::PoseWithCovariance> AlignDirect(const cv::Mat& frame,
                                                          const geometry::PoseWithCovariance& prior,
                                                          const geometry::Pose2& start,
                                                          bool refine_only,
                                                          FrameResult* stats) const;
  bool WeakDenseFitToPolish(const FrameResult& stats) const;
  bool ToPolish(bool templates_locked, const FrameResult& stats) const;
  static bool PolishesEveryFrame(const TrackerOptions& options,
                                 const geometry::CameraModel& camera);
  bool Agree(const geometry::PoseWithCovariance& a, const geometry::PoseWithCovariance& b) const;
  geometry::PoseWithCovariance Polished(FramePyramid* pyramid,
                                        const geometry::PoseWithCovariance& prior,
                                        const geometry::PoseWithCovariance& fit,
                                        FrameResult* stats);
  std::optional<geometry::PoseWithCovariance> Decide(
      const cv::Mat& frame, const geometry::PoseWithCovariance& prior,
      const std::optional<geometry::PoseWithCovariance>& templates, bool direct_tried,
      FrameResult* stats) const;
  std::optional<geometry::PoseWithCovariance> Measure(FramePyramid* pyramid,
                                                      const geometry::PoseWithCovariance& prior,
                                                      int radius_px, bool* templates_locked,
                                                      FrameResult* stats);
  LockState UpdateLock(const std::optional<geometry::PoseWithCovariance>& posterior,
                       bool beyond_search);
  FrameResult Finish(double t, LockState state);

  TrackerOptions options_;
  geometry::CameraModel camera_;
  mosaic::RasterSource* mosaic_;
  NormalizedMosaic normalized_;
  TemplateMatcher matcher_;
  DirectAligner direct_;
  InternalEstimate estimate_;  // camera_ground in map: the tracker's own estimate
  bool polish_ = false;        // this camera's frames are all polished (PolishesEveryFrame)
  bool polish_dense_ = false;  // and those the dense alignment located (…dense_max_frame_pixels)
  int coasting_frames_ = 0;
  bool direct_first_ = false;       // the last frame locked by dense alignment, not templates
  int frames_since_templates_ = 0;  // frames tracked by dense alignment alone since templates ran
  int template_failures_ = 0;       // frames in a row the templates were tried on and failed
  // Frames the weak-floor template size still goes first for, and the frames in a row the standard
  // size was tried on and failed (ChooseTemplateSizeAfter).
  int weak_first_frames_left_ = 0;
  int standard_template_misses_ = 0;
  // The frame's blur against the mosaic and its residual noise as the polish last estimated them
  // (blur < 0: not yet), and the frames polished since
  // (DirectAlignOptions::view_blur_every_frames).
  PolishModel polish_model_;
  int frames_since_model_ = 0;
  LockState state_ = LockState::kLost;
};

}  // namespace fleetloc::tracking
